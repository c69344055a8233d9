"""``roadscan stitch``: overlapping tiles into one height map (thesis section 4.1).

    roadscan stitch MANIFEST.csv --out OUT.x3p [--spacing DX[,DY]] [--units U]
    roadscan stitch TILE... --grid ROWSxCOLS --overlap FRACTION --out OUT.x3p

The manifest is a CSV with header ``file,x_m,y_m`` (tile file relative to the manifest, nominal
position [m] of its first sample; x along columns, y along rows). With ``--grid`` the tiles are
given in row-major order and their nominal positions follow from the tile size, the spacing and
the nominal overlap fraction. The output format follows the extension of ``--out`` (``.x3p``,
``.npy`` metres with NaN unmeasured, ``.npz``, ``.tif``). The residual height mismatch of every
overlap is printed and written beside the output as ``<stem>_overlaps.csv``.
"""

from __future__ import annotations

from pathlib import Path

from pipelines.settings.scan_input import add_scan_options

NAME = "stitch"
HELP = "stitch overlapping tiles (manifest CSV or --grid) into one height map"


def add_arguments(p):
    p.add_argument(
        "inputs",
        nargs="+",
        metavar="MANIFEST_OR_TILE",
        help="a manifest CSV (file,x_m,y_m), or the tile files with --grid",
    )
    p.add_argument(
        "--out",
        required=True,
        metavar="FILE",
        help="output height file; format from the extension (.x3p, .npy, .npz, .tif)",
    )
    p.add_argument(
        "--grid",
        metavar="ROWSxCOLS",
        default=None,
        help="tiles given in row-major order on a ROWS x COLS grid",
    )
    p.add_argument(
        "--overlap",
        type=float,
        default=None,
        metavar="FRACTION",
        help="nominal overlap fraction of neighbouring tiles (with --grid)",
    )
    p.add_argument(
        "--max-shift",
        type=int,
        default=20,
        metavar="PX",
        help="largest nominal position error searched, in samples (default 20)",
    )
    p.add_argument(
        "--blend",
        choices=("feather", "average"),
        default="feather",
        help="blending of overlaps (default feather)",
    )
    add_scan_options(p)


def run(args):
    from pipelines.jobs.stitching import stitch_files
    from pipelines.output.units import length

    out = Path(args.out)
    if not out.suffix:
        out = out.with_suffix(".x3p")
    res = stitch_files(args, out)
    hm = res.heightmap
    names = res.meta["tile_names"]
    print(f"{'tile i':>24} {'tile j':>24} {'points':>8} {'rms mismatch':>14} {'shift [px]':>16}")
    for o in res.overlaps:
        flag = "" if o["registered"] else "  (not registered: nominal kept)"
        print(
            f"{Path(names[o['i']]).name:>24} {Path(names[o['j']]).name:>24} {o['n_points']:>8d} "
            f"{length(o['rms_mismatch_m']):>14} {o['shift_px'][0]:>7.2f},{o['shift_px'][1]:>7.2f}{flag}"
        )
    print(
        f"wrote {out}: {hm.ny} x {hm.nx} points at {length(hm.dx_m)} x "
        f"{length(hm.dy_m)} from {len(res.meta['tile_names'])} tiles, "
        f"{hm.measured_fraction:.1%} measured"
    )
    return 0
