"""``roadscan rain-fill SCAN --out DIR``: fill a scan's cavities with water.

The job and its files are :mod:`pipelines.rain_fill` (``wet.npy``, ``depth.npy``, ``wet.npz``,
``depth.npz``, ``rainfill.json``); ``--no-level`` fills the heights as read.
"""
from __future__ import annotations

from pathlib import Path

from ..scan_input import add_scan_options, load_scan

NAME = "rain-fill"
HELP = "fill a scan's depressions with water (imfill; optional depth cap or water film)"


def add_arguments(p):
    p.add_argument("scan", metavar="SCAN", help="area height file")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    add_scan_options(p)
    add_water_options(p)
    p.add_argument("--no-level", action="store_true",
                   help="fill the heights as read (default: remove the least-squares plane first)")


def add_water_options(p):
    """``--connectivity 4|8`` and ``--max-depth M`` / ``--water-film M`` (docs: Theory)."""
    p.add_argument("--connectivity", type=int, choices=(4, 8), default=4,
                   help="connectivity of the fill (default 4, as Matlab's imfill)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--max-depth", type=float, default=None, metavar="M",
                   help="water at most this deep above each depression's lowest point [m]")
    g.add_argument("--water-film", type=float, default=None, metavar="M",
                   help="water available per area [m^3/m^2 = m]; fills to the smallest depth cap holding it")


def check_water_options(args):
    """``--max-depth`` / ``--water-film`` checked (:func:`pipelines.rain_fill.check_water`)."""
    from ..rain_fill import check_water

    check_water(args.max_depth, args.water_film)


def run(args):
    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    from ..rain_fill import rain_fill_scan, write_rain_fill
    from ..units_format import length

    check_water_options(args)
    check_output_dir(args.out, inputs=[args.scan])
    scan, r = rain_fill_scan(load_scan(args.scan, args), connectivity=args.connectivity,
                             max_depth_m=args.max_depth, water_film_m=args.water_film,
                             level=not args.no_level, path=args.scan)
    final = Path(args.out)
    with atomic_output_dir(final, inputs=[args.scan]) as out:
        write_rain_fill(out, scan, r, args.scan, levelled=not args.no_level)
    cap = (f", at most {length(args.max_depth)} deep" if args.max_depth is not None else
           f", {length(args.water_film)} of water per area offered (the depressions hold "
           f"{length(r.meta['capacity_m3_per_m2'])})" if args.water_film is not None else "")
    print(f"{args.scan}: {r.connectivity}-connected fill{cap}, wetted {r.wetted_fraction:.1%}, "
          f"water {length(r.water_volume_m3_per_m2)} deep on average (volume per area) -> {final}")
    return 0
