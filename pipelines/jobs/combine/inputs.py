"""The inputs of ``roadscan combine``: height files given one by one, or a manifest CSV.

A manifest is a CSV file whose header holds the column ``file`` and optionally
``spacing_m`` [m] (``DX`` or ``DX;DY``: a comma would split the cell), ``units``
(``m, mm, um, nm``), ``resolution_m`` [m] (the lateral resolution: the wavelength the
instrument passes at 50 % amplitude) and ``label``; relative paths are relative to the
manifest's folder. An empty cell means "not given" (the file's own metadata or the
command-line option then applies). Every problem is one line naming the manifest and the row.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from roadscan.errors import InputError

__all__ = ["CombineInput", "MANIFEST_COLUMNS", "collect_inputs", "is_manifest", "add_combine_options"]

#: columns a manifest may have (``file`` required)
MANIFEST_COLUMNS = ("file", "spacing_m", "units", "resolution_m", "label")
_UNITS = ("m", "mm", "um", "nm")


@dataclass(frozen=True)
class CombineInput:
    """One measurement to combine: its file and what the manifest or the options say of it.

    Attributes
    ----------
    path : Path
        The file.
    label : str
        Its label.
    spacing : str or None
        Spacing [m].
    units : str or None
        Height unit.
    resolution_m : float or None
        Lateral resolution [m].
    origin : str or None
        Manifest it came from.
    """

    path: Path
    label: str
    spacing: str | None = None  # as ``--spacing`` takes it: "DX" or "DX,DY" [m]
    units: str | None = None
    resolution_m: float | None = None
    origin: str | None = None  # the manifest and row it came from, for messages


def _header(path):
    """The first non-blank, non-comment line of a .csv file split at commas, or None."""
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as f:
            for _, line in zip(range(50), f):
                if line.strip() and not line.lstrip().startswith("#"):
                    return [c.strip().lower() for c in line.strip().split(",")]
    except OSError:
        return None
    return None


def is_manifest(path):
    """True for a ``.csv`` file whose header names the column ``file`` (a height table never
    does).

    Parameters
    ----------
    path : str or Path
        A file.

    Returns
    -------
    bool
    """
    path = Path(path)
    if path.suffix.lower() != ".csv" or not path.is_file():
        return False
    head = _header(path)
    return bool(head) and "file" in head


def _positive(text, what, where):
    try:
        v = float(text)
    except ValueError:
        raise InputError(where, f"{what} {text!r} is not a number") from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(where, f"{what} {text!r} must be a positive length in metres")
    if v > 10.0:
        raise InputError(where, f"{what} {text!r} is over 10 m: metres expected (e.g. 5e-6)")
    return v


def _resolution(text, where):
    """A manifest's ``resolution_m`` [m], bounded as ``--resolution`` is
    (:func:`roadscan.resolution.resolution_problem`)."""
    from roadscan.resolution import resolution_problem

    v = _positive(text, "resolution_m", where)
    why = resolution_problem(v)
    if why:
        raise InputError(where, f"resolution_m {text!r}: {why}")
    return v


def _read_manifest(path, default_resolution):
    from pipelines.output.csv_files import read_csv_rows

    head, rows = read_csv_rows(path, "a header file[,spacing_m,units,resolution_m,label]")
    head = [h.lower() for h in head]
    unknown = [h for h in head if h not in MANIFEST_COLUMNS]
    if unknown:
        raise InputError(
            path, f"unknown manifest column {unknown[0]!r} (allowed: {','.join(MANIFEST_COLUMNS)})"
        )
    if len(set(head)) != len(head):
        raise InputError(path, "a manifest column appears twice")
    if not rows:
        raise InputError(path, "manifest lists no file")
    col = {h: i for i, h in enumerate(head)}
    out = []
    for k, row in enumerate(rows, start=2):
        where = f"{path} row {k}"
        if len(row) != len(head):
            raise InputError(
                where,
                f"{len(row)} cells for {len(head)} columns (a spacing DX;DY takes a semicolon, not a comma)",
            )
        cell = {h: row[i] for h, i in col.items()}
        if not cell["file"]:
            raise InputError(where, "empty file cell")
        f = Path(cell["file"])
        f = f if f.is_absolute() else path.parent / f
        spacing = cell.get("spacing_m") or None
        if spacing:
            parts = [p for p in spacing.replace(";", " ").split()]
            if len(parts) not in (1, 2):
                raise InputError(where, f"spacing_m {spacing!r}: give DX or DX;DY in metres")
            spacing = ",".join(repr(_positive(p, "spacing_m", where)) for p in parts)
        units = cell.get("units") or None
        if units is not None and units not in _UNITS:
            raise InputError(where, f"units {units!r} not one of {', '.join(_UNITS)}")
        res = cell.get("resolution_m") or None
        res = _resolution(res, where) if res else default_resolution
        out.append(CombineInput(f, cell.get("label") or f.stem, spacing, units, res, where))
    return out


def collect_inputs(items, spacing=None, units=None, resolution_m=None):
    """The measurements named by ``items`` (files and manifests, in order).

    ``spacing``, ``units``, ``resolution_m`` (the command-line options) apply to files given
    directly and fill a manifest's empty cells. Labels are made unique (``name``, ``name-2``).
    Raises :class:`InputError` (one line naming the file) for a missing file, a manifest
    naming itself or another manifest, and every bad cell.

    Parameters
    ----------
    items : iterable of str
        Files and manifests.
    spacing, units : str, optional
        Command-line defaults.
    resolution_m : float, optional
        Command-line resolution [m].

    Returns
    -------
    list of CombineInput
    """
    found = []
    for item in items:
        p = Path(item)
        if not p.exists():
            raise InputError(p, "no such file")
        if p.is_dir():
            raise InputError(p, "is a directory, expected a height file or a manifest CSV")
        if is_manifest(p):
            for e in _read_manifest(p, resolution_m):
                if not e.path.exists():
                    raise InputError(e.path, f"no such file (listed in {e.origin})")
                if is_manifest(e.path):
                    raise InputError(e.origin, f"{e.path} is a manifest: list height files")
                found.append(
                    CombineInput(
                        e.path, e.label, e.spacing or spacing, e.units or units, e.resolution_m, e.origin
                    )
                )
        else:
            found.append(CombineInput(p, p.stem, spacing, units, resolution_m, None))
    seen = {}
    unique = []
    for e in found:
        n = seen.get(e.label, 0) + 1
        seen[e.label] = n
        label = e.label if n == 1 else f"{e.label}-{n}"
        unique.append(CombineInput(e.path, label, e.spacing, e.units, e.resolution_m, e.origin))
    return unique


def add_combine_options(p):
    """Every option of ``roadscan combine`` but its inputs and ``--out``: ``--resolution``,
    ``--no-figures`` and how a scan is read.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser to extend.

    Returns
    -------
    None
    """
    from pipelines.settings.scan_input import add_scan_options

    p.add_argument(
        "--resolution",
        type=float,
        default=None,
        metavar="M",
        help="lateral resolution [m] (wavelength passed at 50 %% amplitude) of inputs "
        "given on the command line whose file does not carry one",
    )
    p.add_argument("--no-figures", action="store_true", help="skip combine.png")
    add_scan_options(p)
