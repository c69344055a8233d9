"""The ``roadscan convert`` job: a height file read by :func:`roadscan.io.read` written in another
format (``.x3p``: ISO 25178-72, float64 metres, NaN unmeasured, instrument metadata and a
comment naming the source in Record2; ``.npy``: heights [m] only; ``.npz``: heights, dx, dy,
unmeasured; ``.tif``/``.tiff``: float64 metres, spacing in tags), chosen by the output's
extension; heights, unmeasured points and spacing bit for bit (float64), or rounded to
float32 on request. The file appears only when complete.
"""

from __future__ import annotations

from pathlib import Path

from roadscan.errors import InputError

__all__ = ["OUTPUTS", "convert_file"]

#: output extensions and what they keep
OUTPUTS = {
    ".x3p": "X3P, float64 metres, spacing, unmeasured points and instrument metadata",
    ".npy": "heights [m] only (NaN unmeasured; the spacing is not stored)",
    ".npz": "heights [m], dx, dy, unmeasured",
    ".tif": "float64 metres, spacing in tags and description",
    ".tiff": "float64 metres, spacing in tags and description",
}


def _check_output(inp, out):
    ext = out.suffix.lower()
    if out.is_dir():
        raise InputError(out, "is a folder: name the output file")
    if ext not in OUTPUTS:
        raise InputError(out, f"cannot write {ext or '(no extension)'!r}: use .x3p, .npy, .npz or .tif")
    if not out.parent.is_dir():
        raise InputError(out, f"folder {out.parent} does not exist")
    try:
        same = out.exists() and out.resolve() == Path(inp).resolve()
    except OSError:
        same = False
    if same:
        raise InputError(out, "is the input file: name another output")


def _source_note(inp, scan):
    meta = scan.meta
    inst = meta.get("instrument") if isinstance(meta.get("instrument"), dict) else {}
    what = inst.get("format") or meta.get("format") or Path(inp).suffix.lstrip(".")
    by = f", read by {inst['reader']}" if inst.get("reader") else ""
    return f"converted by roadscan from {Path(inp).name} ({what}{by})"


def convert_file(inp, out, read_options, units=None, float32=False):
    """Read ``inp`` (with ``read_options``: :func:`pipelines.settings.scan_input.read_options`), check
    its heights' plausibility, write ``out``; returns the scan read.

    Parameters
    ----------
    inp : str or Path
        Input height file.
    out : str or Path
        Output file (format by extension).
    read_options : dict
        Keyword arguments of :func:`roadscan.io.read`.
    units : str, optional
        Height unit of the input.
    float32 : bool, optional
        Store float32 heights.

    Returns
    -------
    HeightMap or Profile
        The scan read.
    """
    from roadscan.heightmap import HeightMap
    from roadscan.io import read, write
    from roadscan.plausibility import check_plausible

    inp, out = Path(inp), Path(out)
    if not inp.exists():
        raise InputError(inp, "no such file")
    if inp.is_dir():
        raise InputError(inp, "is a directory, expected a height file")
    _check_output(inp, out)
    if read_options.get("spacing") is not None:
        from pipelines.checks.validate import check_spacing_option

        check_spacing_option(read_options["spacing"])
    scan = read(inp, **read_options)
    check_plausible(scan, inp, units)  # a units slip is not converted
    ext = out.suffix.lower()
    if ext in (".tif", ".tiff") and not isinstance(scan, HeightMap):
        raise InputError(inp, "is a line profile: TIFF holds area scans; use .x3p, .npy or .npz")
    options = {"dtype": "float32" if float32 else "float64"}
    if ext == ".x3p":
        options["comment"] = _source_note(inp, scan)
    write(out, scan, **options)
    return scan
