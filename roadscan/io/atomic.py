"""Write-then-rename, so that a failed or killed run never leaves a half-written output.

Two levels:

- :func:`atomic_path` (one file): the data go to a hidden temporary file beside the target,
  which is renamed onto it only when complete. The temporary file gets the permissions a
  normally created file would (``0o666 & ~umask``), not ``mkstemp``'s 0600.
- :func:`atomic_output_dir` (a whole output folder): every file of a run is written into a
  hidden temporary folder beside the target (``.<name>.roadscan-tmp-XXXX``), which is swapped
  in only when the whole set is complete. After ``kill -9`` at any moment the target holds
  either the complete old set or the complete new set, never a mix, and no temporary file
  lives inside it. Temporary and set-aside folders left in the parent by a killed run are
  removed by the next run on the same target (an old set that was set aside but not yet
  replaced is put back first).

The swap uses Linux ``renameat2(RENAME_EXCHANGE)`` (one atomic step: the old set moves to the
temporary name, then is deleted). Where that is unavailable the old folder is renamed aside,
the new one renamed in, and the old one deleted; a kill between the two renames leaves the
target missing for an instant, and the next run restores the old set before doing anything.

Every writer here writes *through* a symbolic link (the file or folder it points to is
replaced, the link stays), names the final file in "No space left on device" and other write
errors, and refuses to replace a file the running command has read
(:mod:`roadscan.io.overwrite_guard`). Two runs writing the same target at once both finish:
each locks its own temporary folder (``flock``), so the other's clean-up leaves it alone, and
the target ends up holding one complete set, the last one swapped in.

The one-file level (:func:`atomic_path` and its writers, :func:`through_link`,
:func:`final_name`) lives in ``roadscan.io._atomic_file`` and is re-exported here.
"""

from __future__ import annotations

import contextlib
import errno
import os
import random
import shutil
import string
import time
from pathlib import Path

from ..errors import InputError
from ._atomic_file import (
    _dir_mode,
    _named,
    atomic_path,
    atomic_save_npy,
    atomic_write_bytes,
    atomic_write_text,
    file_mode,
    final_name,
    through_link,
)
from .folder_swap import OLD_TAG, TMP_TAG, _hold, _in_use, _leftovers, _swap_in, recover_output_dir
from .output_folder import OUTPUT_MARKERS, OUTPUT_SUFFIXES, check_output_dir  # noqa: F401 (re-exported)
from .overwrite_guard import check_not_read

__all__ = [
    "atomic_path",
    "atomic_write_text",
    "atomic_write_bytes",
    "atomic_save_npy",
    "atomic_output_dir",
    "atomic_file_set",
    "check_output_dir",
    "file_mode",
    "TMP_TAG",
    "OLD_TAG",
    "through_link",
    "final_name",
]


# ---------------------------------------------------------------------------- output folders


def _make_folder(folder, target, option):
    """Create ``folder`` (the output's parent) or raise a one-line InputError naming ``target``."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(
            None, f"{{{option}}} {target}: cannot create the folder ({exc.strerror or exc})", option
        ) from None


class _Temporary:
    """A new hidden temporary folder for ``target`` inside ``folder`` and the lock that holds it
    (a concurrent run's clean-up leaves a held folder alone).

    Its path is known before the folder exists (:attr:`path`), so that a stop signal arriving
    at any moment after :meth:`make` is entered (the folder made, not yet returned) still finds
    it for the clean-up: :meth:`remove` deletes it if it was made."""

    def __init__(self):
        self.path = None
        self.lock = None
        self._made = False

    def make(self, folder, target, option):

        letters = string.ascii_lowercase + string.digits
        for _ in range(100):
            self.path = Path(folder) / f".{target.name}{TMP_TAG}{''.join(random.choices(letters, k=8))}"
            try:
                self._made = True  # before the folder exists: see the class docstring
                os.mkdir(self.path, 0o700)
            except FileExistsError:  # another run's: never ours to remove
                self._made = False
                continue
            except OSError as exc:
                self._made = False
                raise InputError(
                    None, f"{{{option}}} {target}: cannot write there ({exc.strerror or exc})", option
                ) from None
            self.lock = _hold(self.path)
            return self.path
        raise InputError(None, f"{{{option}}} {target}: cannot make a temporary folder there", option)

    def remove(self, remove_tree):
        if self._made and self.path is not None:
            remove_tree(self.path)

    def release(self):
        if self.lock is not None:
            os.close(self.lock)
            self.lock = None


def _remove_tree(folder, waits=(0.05, 0.2, 0.5)):
    """Delete ``folder``; again after a short wait while a writer still finishing a file there
    (a figure helper process drawing into a run that was stopped) makes it reappear."""
    shutil.rmtree(folder, ignore_errors=True)
    for wait in waits:
        if not os.path.lexists(folder):
            return
        time.sleep(wait)
        shutil.rmtree(folder, ignore_errors=True)


@contextlib.contextmanager
def atomic_output_dir(target, option="out", inputs=()):
    """Build a whole output folder in a temporary folder beside ``target``; swap it in at the end.

    Parameters
    ----------
    target : str or Path
        The output folder. It may be missing (created), empty, or hold an earlier roadscan run
        (replaced as a whole). See :func:`check_output_dir` for what is refused.
    option : str
        The keyword of the option naming the folder, for error messages.
    inputs : sequence of paths
        Input files of the run (a folder holding one of them is refused).

    Yields
    ------
    Path
        The temporary folder: write every output file there (plain writes are fine).

    On an exception (including ``KeyboardInterrupt``) the temporary folder is deleted and the
    target is left as it was. On success the target holds exactly the files written.

    Returns
    -------
    contextlib.AbstractContextManager
        Use with ``with``; the block receives the temporary folder.
    """
    target = through_link(Path(target))  # a link to a folder: the folder it points to
    check_output_dir(target, option, inputs)
    parent = target.parent
    _make_folder(parent, target, option)
    recover_output_dir(target)
    held = _Temporary()
    try:
        tmp = held.make(parent, target, option)
        os.chmod(tmp, _dir_mode())
        yield tmp
        check_not_read([target], option=option, exclude=tmp)
        _swap_in(tmp, target)
    except BaseException as exc:
        held.remove(_remove_tree)
        if isinstance(exc, OSError):
            raise _named(exc, target) from None
        raise
    finally:
        held.release()


@contextlib.contextmanager
def atomic_file_set(target, option="out"):
    """Write a set of sibling files (``mu.csv`` with ``mu_summary.json`` and ``mu.png``; a
    stitched map with its overlaps table; a rubber TOML with its data files) all or none.

    Parameters
    ----------
    target : str or Path
        The set's main file; the set lives in its folder.
    option : str
        The keyword of the option naming it, for error messages.

    Yields
    ------
    Path
        A hidden temporary folder beside the files (``.<name>.roadscan-tmp-XXXX``): write every
        file of the set there under its final name (relative references between them work).

    On success each file is renamed into the target's folder (replacing files of the same
    names; other files there are left alone), after checking that none of the names is a
    folder. On an exception (``KeyboardInterrupt`` included) the temporary folder is deleted,
    folders created for the set are removed and nothing else changes. A killed run leaves only
    the hidden folder, which the next run on the same target removes.

    Returns
    -------
    contextlib.AbstractContextManager
        Use with ``with``; the block receives the temporary folder of the set.
    """
    target = Path(target)
    folder = target.parent
    if target.is_dir():
        raise InputError(None, f"{{{option}}} {target}: is a folder, need a file name", option)
    for parent in [folder, *folder.parents]:
        if parent.exists() and not parent.is_dir():
            raise InputError(
                None, f"{{{option}}} {target}: is below the file {parent}, need a folder", option
            )
    created = [p for p in [folder, *folder.parents] if not p.exists()]
    _make_folder(folder, target, option)
    for old in _leftovers(target, TMP_TAG):
        if not _in_use(old):
            shutil.rmtree(old, ignore_errors=True)
    held = _Temporary()
    tmp = None
    try:
        tmp = held.make(folder, target, option)
        os.chmod(tmp, _dir_mode())
        yield tmp
        files = sorted(tmp.iterdir())
        dests = [through_link(folder / p.name) for p in files]  # a link: where it points
        busy = [d for d in dests if d.is_dir()]
        if busy:
            raise InputError(
                None, f"{{{option}}} {target}: {busy[0]} is a folder, cannot write the file", option
            )
        check_not_read(dests, option=option, exclude=tmp)
        for p, dest in zip(files, dests):
            _place(p, dest)
        os.rmdir(tmp)
    except BaseException as exc:
        held.remove(lambda path: shutil.rmtree(path, ignore_errors=True))
        for d in created:  # deepest first
            with contextlib.suppress(OSError):
                d.rmdir()
        if isinstance(exc, OSError) and not isinstance(exc, InputError):
            name = getattr(exc, "filename", None)
            # a file of the set: named where it goes
            if name and tmp is not None and Path(name).parent in (tmp, final_name(tmp)):
                exc = OSError(exc.errno, exc.strerror or str(exc), str(folder / Path(name).name))
            raise _named(exc, target) from None
        raise
    finally:
        held.release()


def _place(src, dest):
    """Rename ``src`` onto ``dest``; across file systems (a link pointing elsewhere) copy to a
    temporary file beside ``dest`` first, then rename."""
    try:
        os.replace(src, dest)
    except OSError as exc:
        if exc.errno != errno.EXDEV:
            raise
        with atomic_path(dest) as tmp:
            shutil.copyfile(src, tmp)
