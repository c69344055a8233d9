"""``roadscan convert IN OUT``: hand a scan to someone with other software.

Any file :func:`roadscan.io.read` reads (an instrument's own format, X3P, text, TIFF...) is
written as ``.x3p`` (ISO 25178-72: float64 metres, NaN unmeasured, and in Record2 the
instrument, acquisition date, objective and a comment naming the source), ``.npy`` (heights [m]
only: the spacing is not stored), ``.npz`` (``heights``, ``dx``, ``dy``, ``unmeasured``) or
``.tif``/``.tiff`` (float64 metres, spacing in tags and description), chosen by OUT's
extension. Heights, unmeasured points and spacing are written as read, bit for bit (float64;
``--float32`` halves the file and rounds the heights). The file appears only when complete
(:func:`roadscan.io.atomic.atomic_path`); ``--spacing``, ``--units`` and ``--max-pixels`` act
as in ``roadscan analyse``.
"""
from __future__ import annotations

from pathlib import Path

from roadscan.errors import InputError

from ..scan_input import add_scan_options

NAME = "convert"
HELP = "convert a height file (instrument formats, X3P, text, TIFF...) to .x3p, .npy, .npz or .tif"

#: output extensions and what they keep
OUTPUTS = {
    ".x3p": "X3P, float64 metres, spacing, unmeasured points and instrument metadata",
    ".npy": "heights [m] only (NaN unmeasured; the spacing is not stored)",
    ".npz": "heights [m], dx, dy, unmeasured",
    ".tif": "float64 metres, spacing in tags and description",
    ".tiff": "float64 metres, spacing in tags and description",
}


def add_arguments(p):
    p.add_argument("input", metavar="IN", help="height file in any format roadscan reads")
    p.add_argument("output", metavar="OUT", help="output file: .x3p, .npy, .npz or .tif (by extension)")
    add_scan_options(p)
    p.add_argument("--float32", action="store_true",
                   help="store heights as float32 (half the size; heights rounded to 7 digits)")


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


def run(args):
    from roadscan.heightmap import HeightMap
    from roadscan.io import read, write

    inp, out = Path(args.input), Path(args.output)
    if not inp.exists():
        raise InputError(inp, "no such file")
    if inp.is_dir():
        raise InputError(inp, "is a directory, expected a height file")
    _check_output(inp, out)
    if args.spacing is not None:
        from ..validate import check_spacing_option

        check_spacing_option(args.spacing)
    from ..scan_input import read_options

    from roadscan.plausibility import check_plausible

    scan = read(inp, **read_options(args))
    check_plausible(scan, inp, args.units)   # a units slip is not converted
    ext = out.suffix.lower()
    if ext in (".tif", ".tiff") and not isinstance(scan, HeightMap):
        raise InputError(inp, "is a line profile: TIFF holds area scans; use .x3p, .npy or .npz")
    options = {"dtype": "float32" if args.float32 else "float64"}
    if ext == ".x3p":
        options["comment"] = _source_note(inp, scan)
    write(out, scan, **options)
    shape = " x ".join(str(n) for n in scan.heights_m.shape)
    from ..units_format import length
    spacing = length(scan.dx_m) if not isinstance(scan, HeightMap) else \
        f"{length(scan.dx_m)} x {length(scan.dy_m)}"
    undefined = int(scan.unmeasured.sum())
    note = (f"; spacing not stored in .npy: pass --spacing {scan.dx_m:.6g}"
            + ("" if not isinstance(scan, HeightMap) or scan.dy_m == scan.dx_m else f",{scan.dy_m:.6g}")
            + " when reading it") if ext == ".npy" else ""
    print(f"{inp} -> {out}: {shape} points at {spacing}, {undefined} unmeasured{note}")
    return 0
