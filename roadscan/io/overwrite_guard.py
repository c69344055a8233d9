"""No command ever writes over one of its inputs.

Two complementary checks, both one-line :class:`~roadscan.errors.InputError` refusals (the
CLI's exit code 2):

- :func:`refuse_overwrite` (before any work): every output path against every input path a
  command names (flags and positional arguments, manifests, a rubber TOML...). Two paths are
  the same file when ``os.path.samefile`` says so (symbolic and hard links included) or when
  their fully resolved paths are equal; an input *inside* an output folder is refused too (the
  folder is replaced as a whole).
- :func:`reads_tracked` / :func:`check_not_read` (at the moment of writing): while a command
  runs, every file the process opens for reading is recorded with a Python audit hook
  (:pep:`578`, event ``open``), and the atomic writers of :mod:`roadscan.io.atomic` refuse to
  rename a finished output onto any of them. This covers inputs that no flag names: the tiles
  of a stitch manifest, the master curve and shift table a rubber TOML points to, the PSD of
  ``friction``. The temporary output is deleted, nothing is lost.

Files of the Python installation (modules, shared libraries) and of ``/proc``, ``/sys`` and
``/dev`` are not recorded.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading

from ..errors import InputError

__all__ = [
    "refuse_overwrite",
    "same_path",
    "inside",
    "reads_tracked",
    "check_not_read",
    "tracked_reads",
    "untracked",
]

_LOCK = threading.Lock()
_READS = None  # set of absolute paths read while tracking, or None when not tracking
_HOOKED = False
_SKIP_SUFFIXES = (".py", ".pyc", ".so", ".pyd", ".pth", ".mo")


def _skip_roots():
    roots = {sys.prefix, sys.base_prefix, sys.exec_prefix, "/proc", "/sys", "/dev"}
    return tuple(os.path.join(os.path.abspath(r), "") for r in roots if r)


_ROOTS = _skip_roots()


_SUSPENDED = threading.local()  # .on: this thread's reads are not recorded (untracked)


def _audit(event, args):
    if event != "open" or _READS is None or getattr(_SUSPENDED, "on", False):
        return
    try:
        path, mode, flags = args
        if isinstance(path, int) or path is None:
            return
        if isinstance(mode, str):
            reading = "r" in mode or "+" in mode
        else:
            reading = (int(flags or 0) & os.O_ACCMODE) != os.O_WRONLY
        if not reading:
            return
        p = os.path.abspath(os.fsdecode(path))
        if p.endswith(_SKIP_SUFFIXES) or p.startswith(_ROOTS):
            return
        _READS.add(p)
    except Exception:  # noqa: BLE001 - an audit hook must never break the program
        return


@contextlib.contextmanager
def reads_tracked():
    """Record every file opened for reading inside the block (see the module docstring).

    Nesting is allowed; the outermost block starts and ends the record.

    Parameters
    ----------
    None

    Yields
    ------
    None

    Returns
    -------
    contextlib.AbstractContextManager
        Use with ``with``.
    """
    global _READS, _HOOKED
    with _LOCK:
        if not _HOOKED:
            sys.addaudithook(_audit)
            _HOOKED = True
        outer = _READS is None
        if outer:
            _READS = set()
    try:
        yield
    finally:
        if outer:
            _READS = None


@contextlib.contextmanager
def untracked():
    """Inside the block, files this thread opens are not recorded by :func:`reads_tracked`:
    a command looking at its own earlier output to recognise it (the header of a campaign's
    ``campaign.csv`` before ``--resume``) has not read an input, and may replace that output.

    Parameters
    ----------
    None

    Yields
    ------
    None

    Returns
    -------
    contextlib.AbstractContextManager
        Use with ``with``.
    """
    before = getattr(_SUSPENDED, "on", False)
    _SUSPENDED.on = True
    try:
        yield
    finally:
        _SUSPENDED.on = before


def tracked_reads():
    """The files read so far in the current :func:`reads_tracked` block (empty outside one).

    Parameters
    ----------
    None

    Returns
    -------
    set of str
        Paths read.
    """
    reads = _READS
    return set() if reads is None else set(reads)


def same_path(a, b):
    """True when ``a`` and ``b`` are the same file: ``samefile`` (links) or equal resolved paths.

    Parameters
    ----------
    a, b : str or Path
        Two paths.

    Returns
    -------
    bool
    """
    try:
        if os.path.exists(a) and os.path.exists(b) and os.path.samefile(a, b):
            return True
    except OSError:
        pass
    try:
        return os.path.realpath(a) == os.path.realpath(b)
    except (OSError, ValueError):
        return False


def inside(path, folder):
    """True when ``path`` (resolved) lies inside ``folder`` (resolved), at any depth.

    Parameters
    ----------
    path, folder : str or Path
        The paths.

    Returns
    -------
    bool
    """
    try:
        p, f = os.path.realpath(path), os.path.realpath(folder)
    except (OSError, ValueError):
        return False
    return p != f and p.startswith(os.path.join(f, ""))


def refuse_overwrite(outputs, inputs, option="out"):
    """Raise :class:`InputError` when an output would replace an input.

    Parameters
    ----------
    outputs : iterable of (path or (path, is_folder))
        Paths the command writes. A folder output (replaced as a whole) also refuses the inputs
        inside it.
    inputs : iterable of paths
        Every path the command reads (missing ones are skipped: their readers report them).
    option : str
        The keyword of the option naming the outputs, for the message.

    The message is one line: ``{out} OUT: is the input IN; name another output``
    (:class:`roadscan.errors.InputError` names the option).

    Returns
    -------
    None
    """
    inputs = [str(i) for i in inputs if i is not None and str(i) != ""]
    for out in outputs:
        folder = False
        if isinstance(out, tuple):
            out, folder = out
        if out is None or str(out) == "":
            continue
        out = str(out)
        for inp in inputs:
            if same_path(out, inp):
                raise InputError(
                    None,
                    hint_option=option,
                    problem=f"{{{option}}} {out}: is the input file {inp}; name another output "
                    f"(an input is never written over)",
                )
            if folder and inside(inp, out):
                raise InputError(
                    None,
                    hint_option=option,
                    problem=f"{{{option}}} {out}: contains the input {inp}; name another "
                    f"folder (an input is never written over)",
                )


def check_not_read(targets, option="out", exclude=None):
    """Refuse to replace a file this command has read (inside :func:`reads_tracked`).

    ``targets`` are final output paths (files or folders); ``exclude`` a temporary folder whose
    own files do not count (an output read back while it was being built). ``option``: the
    keyword of the option naming the outputs (None: they are called "output").

    Parameters
    ----------
    targets : iterable of path
        Output paths.
    option : str, optional
        Option naming the outputs, for the message.
    exclude : str or Path, optional
        A temporary folder whose files do not count.

    Returns
    -------
    None
    """
    label = "output" if option is None else "{" + option + "}"
    reads = _READS
    if not reads:
        return
    reads = list(reads)
    if exclude is not None:
        reads = [r for r in reads if not (same_path(r, exclude) or inside(r, exclude))]
    for t in targets:
        t = str(t)
        for r in reads:
            if not os.path.lexists(r):
                continue
            if same_path(t, r) or (os.path.isdir(t) and inside(r, t)):
                raise InputError(
                    None,
                    hint_option=option,
                    problem=f"{label} {t}: would replace the input {r}, "
                    f"which this command read; name another output",
                )
