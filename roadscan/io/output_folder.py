"""Which folder an output run may replace as a whole (:func:`roadscan.io.atomic.atomic_output_dir`
swaps a complete new set in for the old one, so whatever else the folder held would be lost).

Refused, with one line: a path that is a file or lies below one; the current folder, the home
folder, a parent of the current folder or a filesystem root; a folder holding one of the run's
inputs; a non-empty folder that holds no earlier roadscan output; an earlier output folder that
also holds a file of a kind no roadscan run writes (a user's notes or photo put beside it).
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError

__all__ = ["check_output_dir", "OUTPUT_MARKERS", "OUTPUT_SUFFIXES"]

#: files whose presence marks a folder as an earlier roadscan output (safe to replace)
OUTPUT_MARKERS = (
    "summary.json",
    "report.html",
    "rainfill.json",
    "summary.csv",
    "mu.csv",
    "psd.csv",
    "compare.csv",
    "diagnosis.json",
    "wet.npy",
)


def check_output_dir(target, option="out", inputs=()):
    """Refuse an output folder that cannot or must not be (re)placed, with one line.

    Refused: a path that is an existing file; a path below a file; an existing non-empty folder
    that holds no earlier roadscan output (it would be replaced as a whole); the current
    folder, the home folder or a filesystem root; a folder that contains one of ``inputs``.
    ``option`` is the keyword of the option naming the folder (named in the messages:
    :class:`roadscan.errors.InputError`).

    Parameters
    ----------
    target : str or Path
        The output folder.
    option : str, optional
        Option name used in the message.
    inputs : iterable of path, optional
        The command's inputs.

    Returns
    -------
    None
        Raises :class:`roadscan.InputError` when refused.
    """
    label = "{" + option + "}"
    target = Path(target)
    if str(target).strip() == "":
        raise InputError(None, hint_option=option, problem=f"{label}: empty folder name")
    for parent in [target, *target.parents]:
        if parent.exists() and not parent.is_dir():
            what = "is an existing file" if parent == target else f"is below the file {parent}"
            raise InputError(None, hint_option=option, problem=f"{label} {target}: {what}, need a folder")
    resolved = target.resolve()
    if (
        resolved in (Path.cwd().resolve(), Path.home().resolve())
        or resolved == resolved.parent
        or resolved in Path.cwd().resolve().parents
    ):
        raise InputError(
            None,
            hint_option=option,
            problem=f"{label} {target}: the whole folder would be replaced; name a new "
            f"or earlier output folder",
        )
    for inp in inputs:
        try:
            Path(inp).resolve().relative_to(resolved)
        except ValueError:
            continue
        raise InputError(
            None,
            hint_option=option,
            problem=f"{label} {target}: contains the input {inp}; name another folder",
        )
    if target.is_dir():
        entries = [p.name for p in target.iterdir()]
        if (
            entries
            and not any(m in entries for m in OUTPUT_MARKERS)
            and not any((target / e / m).exists() for e in entries for m in OUTPUT_MARKERS)
        ):
            raise InputError(
                None,
                hint_option=option,
                problem=f"{label} {target}: folder exists, is not empty and holds no "
                f"earlier roadscan output; name a new folder",
            )
        foreign = _foreign_file(target)
        if foreign is not None:
            raise InputError(
                None,
                hint_option=option,
                problem=f"{label} {target}: holds {foreign}, which no roadscan run writes; "
                f"replacing the folder would lose it: move it or name another folder",
            )


#: what roadscan writes into an output folder (a folder holding anything else is not replaced)
OUTPUT_SUFFIXES = (".json", ".csv", ".png", ".html", ".npy", ".npz", ".parquet")


def _foreign_file(folder, depth=2):
    """The first visible file below ``folder`` (``depth`` levels) whose kind roadscan never writes
    into an output folder (a user's notes or photo beside an earlier run), else None."""
    try:
        entries = sorted(Path(folder).iterdir())
    except OSError:
        return None
    for p in entries:
        if p.name.startswith("."):
            continue
        if p.is_dir() and not p.is_symlink():
            if depth > 1:
                found = _foreign_file(p, depth - 1)
                if found is not None:
                    return found
        elif p.suffix.lower() not in OUTPUT_SUFFIXES:
            return p
    return None
