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

from pipelines.settings.scan_input import add_scan_options

NAME = "convert"
HELP = "convert a height file (instrument formats, X3P, text, TIFF...) to .x3p, .npy, .npz or .tif"


def add_arguments(p):
    p.add_argument("input", metavar="IN", help="height file in any format roadscan reads")
    p.add_argument("output", metavar="OUT", help="output file: .x3p, .npy, .npz or .tif (by extension)")
    add_scan_options(p)
    p.add_argument(
        "--float32",
        action="store_true",
        help="store heights as float32 (half the size; heights rounded to 7 digits)",
    )


def run(args):
    from pipelines.jobs.convert import convert_file
    from pipelines.output.units import length
    from pipelines.settings.scan_input import read_options

    inp, out = Path(args.input), Path(args.output)
    scan = convert_file(inp, out, read_options(args), units=args.units, float32=args.float32)
    ext = out.suffix.lower()
    shape = " x ".join(str(n) for n in scan.heights_m.shape)
    area = getattr(scan, "dy_m", None) is not None
    spacing = f"{length(scan.dx_m)} x {length(scan.dy_m)}" if area else length(scan.dx_m)
    undefined = int(scan.unmeasured.sum())
    note = (
        (
            f"; spacing not stored in .npy: pass --spacing {scan.dx_m:.6g}"
            + ("" if not area or scan.dy_m == scan.dx_m else f",{scan.dy_m:.6g}")
            + " when reading it"
        )
        if ext == ".npy"
        else ""
    )
    print(f"{inp} -> {out}: {shape} points at {spacing}, {undefined} unmeasured{note}")
    return 0
