"""Swapping a finished output folder in for the old one, and the locks that protect a run's
temporary folders (:func:`roadscan.io.atomic.atomic_output_dir` uses them).

The swap is Linux ``renameat2(RENAME_EXCHANGE)`` (one atomic step, ``man 2 rename``); where
that is unavailable the old folder is renamed aside, the new one renamed in and the old one
deleted, and :func:`recover_output_dir` puts an old set back when a run was killed between the
two renames. A run holds its temporary folder with ``flock`` so that another run's clean-up
leaves it alone.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import errno
import fcntl
import os
import shutil
import tempfile
from pathlib import Path

__all__ = ["TMP_TAG", "OLD_TAG", "recover_output_dir"]

#: marker in the names of temporary output folders (``.<target>.roadscan-tmp-XXXX``)
TMP_TAG = ".roadscan-tmp-"
#: marker of an old output folder set aside during a swap (``.<target>.roadscan-old-XXXX``)
OLD_TAG = ".roadscan-old-"

_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _renameat2():
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return None
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    fn.restype = ctypes.c_int
    return fn


_RENAMEAT2 = _renameat2()


def _exchange(a, b):
    """Atomically swap two existing paths; False when the system cannot."""
    if _RENAMEAT2 is None:
        return False
    rc = _RENAMEAT2(_AT_FDCWD, os.fsencode(str(a)), _AT_FDCWD, os.fsencode(str(b)), _RENAME_EXCHANGE)
    return rc == 0


def _leftovers(target, tag):
    prefix = f".{target.name}{tag}"
    try:
        return [p for p in target.parent.iterdir() if p.name.startswith(prefix)]
    except OSError:
        return []


def recover_output_dir(target):
    """Clean what a killed run left beside ``target``: put back an old set that was set aside
    (when the target is missing), then delete temporary and set-aside folders.

    Parameters
    ----------
    target : str or Path
        The output folder.

    Returns
    -------
    None
    """
    target = Path(target)
    olds = _leftovers(target, OLD_TAG)
    if olds and not os.path.lexists(target):
        os.rename(olds[0], target)
        olds = olds[1:]
    for p in olds + _leftovers(target, TMP_TAG):
        if not _in_use(p):  # another run writing there now: leave it
            shutil.rmtree(p, ignore_errors=True)


def _hold(folder):
    """Lock ``folder`` (``flock``, released when the descriptor closes or the process dies):
    a concurrent run's clean-up then knows it is being written, not left by a killed run."""
    fd = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
    except OSError:
        pass
    return fd


def _in_use(folder):
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return False
    except BlockingIOError:
        return True
    except OSError:
        return False
    finally:
        os.close(fd)


def _swap_in(tmp, target):
    if not os.path.lexists(target):
        try:
            os.rename(tmp, target)
            return
        except OSError as exc:  # a concurrent run put its set there first
            if exc.errno not in (errno.ENOTEMPTY, errno.EEXIST):
                raise
    if _exchange(tmp, target):  # tmp now holds the old set
        shutil.rmtree(tmp, ignore_errors=True)
        return
    old = Path(tempfile.mkdtemp(prefix=f".{target.name}{OLD_TAG}", dir=target.parent))
    os.rmdir(old)
    os.rename(target, old)
    os.rename(tmp, target)
    shutil.rmtree(old, ignore_errors=True)
