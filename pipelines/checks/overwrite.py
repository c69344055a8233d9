"""Every command's inputs and outputs from its parsed options, checked before any work: an
output never replaces an input; an output below an existing file, a broken or looping symbolic
link given as an input and a device, pipe or socket given as an input are one-line input errors.

The parsed options are read generically (every string option that names an existing path is an
input; ``--out`` and convert's ``OUT`` are the outputs), so a new command or flag is covered
without listing it here. What no option names (the tiles of a stitch manifest, the data files of
a rubber TOML) is caught when the output is written: :mod:`roadscan.io.overwrite_guard`
records the files a command reads and the atomic writers refuse to replace them.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from roadscan.errors import InputError
from roadscan.io.overwrite_guard import refuse_overwrite

__all__ = ["command_inputs", "command_outputs", "check_command_paths", "check_link"]

#: options that name outputs, and how the message calls them
OUTPUT_OPTIONS = {"out": "--out", "output": "OUT"}

#: commands whose --out is a folder replaced as a whole (an input inside it is refused too;
#: batch adds to its folder, and checks each of its outputs itself)
FOLDER_COMMANDS = {"analyse", "compare", "rain-fill", "dry-vs-wet", "diagnose", "combine"}

_NOT_PATHS = {"command", "_run", "debug", "rubber_command"}


def _strings(value):
    if isinstance(value, (str, os.PathLike)):
        return [os.fspath(value)]
    if isinstance(value, (list, tuple)):
        return [os.fspath(v) for v in value if isinstance(v, (str, os.PathLike))]
    return []


def command_inputs(args):
    """Every option value of ``args`` (an argparse namespace) that names an existing path
    (a dangling or looping link included), outputs excepted.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    list of str
    """
    found = []
    for key, value in vars(args).items():
        if key in OUTPUT_OPTIONS or key in _NOT_PATHS or key.startswith("_"):
            continue
        for s in _strings(value):
            if s and os.path.lexists(s):
                found.append(s)
    return found


def command_outputs(args, keys=False):
    """``[(path, is_folder, flag)]`` of the outputs ``args`` names (``keys``: with the option's
    keyword as a fourth item).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.
    keys : bool, optional
        Add the option keyword.

    Returns
    -------
    list of tuple
    """
    folder = getattr(args, "command", None) in FOLDER_COMMANDS
    outs = [
        (os.fspath(v), folder, flag, key)
        for key, flag in OUTPUT_OPTIONS.items()
        if isinstance((v := getattr(args, key, None)), (str, os.PathLike))
    ]
    for out, _, flag, _ in outs:
        if not out.strip():
            raise InputError(None, f"{flag}: empty name; name a file or folder")
    return outs if keys else [o[:3] for o in outs]


def check_link(path):
    """Refuse (one line) an input that is a symbolic link loop or a dangling link.

    Parameters
    ----------
    path : str or Path
        An input.

    Returns
    -------
    None
    """
    if not os.path.islink(path):
        return
    try:
        os.stat(path)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise InputError(path, "is a symbolic link loop") from None
        target = os.readlink(path)
        raise InputError(
            path, f"is a broken symbolic link (to {target}: {exc.strerror or 'not found'})"
        ) from None


_KINDS = (
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISFIFO, "a named pipe (FIFO)"),
    (stat.S_ISSOCK, "a socket"),
)


def check_kind(path, advice="save the data to a file first"):
    """Refuse (one line) an input that is a device, a pipe or a socket: ``/dev/zero`` never
    ends, a FIFO blocks until someone writes; roadscan reads files (and never replaces a
    device node by one: ``advice`` for an output)."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return  # missing or unreadable: the reader says so
    for test, what in _KINDS:
        if test(mode):
            raise InputError(path, f"is {what}, not a file: {advice}")


def check_command_paths(args):
    """The checks of the module docstring on a parsed command line; InputError (exit 2).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    None
    """
    inputs = command_inputs(args)
    for inp in inputs:
        check_link(inp)
        check_kind(inp)
    for out, folder, flag, key in command_outputs(args, keys=True):
        if os.path.islink(out):
            try:
                os.stat(out)
            except OSError as exc:
                if exc.errno == errno.ELOOP:
                    raise InputError(
                        None, f"{flag} {out}: is a symbolic link loop; name another output"
                    ) from None
        try:
            check_kind(out, "name a file or folder")  # /dev/full, a FIFO: never replaced
        except InputError as exc:
            raise InputError(None, f"{flag} {exc}") from None
        for parent in Path(out).parents:  # every output, before any work
            if parent.is_file():
                raise InputError(None, f"{flag} {out}: is below the file {parent}, need a folder")
        try:
            refuse_overwrite([(out, folder)], inputs, option=key)
        except InputError as exc:  # named as this command names it (a flag or OUT)
            raise InputError(None, exc.render(lambda _key, flag=flag: flag)) from None
