"""``roadscan rain-fill SCAN --out DIR``: fill a scan's cavities with water (thesis sec. 4.4).

Writes ``wet.npy`` (wet surface [m], NaN where unmeasured), ``depth.npy`` (water depth [m], 0
where dry, NaN where unmeasured), the same two maps with their spacing as ``wet.npz`` and
``depth.npz`` (``heights``, ``dx``, ``dy`` [m], ``unmeasured``: ``roadscan analyse out/wet.npz``
needs no ``--spacing``) and ``rainfill.json`` (``dx_m``, ``dy_m`` too). The scan is levelled (least-squares
plane removed) first unless ``--no-level``: water settles relative to gravity, and a scan's tilt
is the instrument's, not the road's. Unmeasured points are transparent (they neither hold nor
block water; see :mod:`roadscan.rain`).
"""
from __future__ import annotations

import json
from pathlib import Path

from roadscan.errors import InputError

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
    import numpy as np

    for flag, val in (("--max-depth", args.max_depth), ("--water-film", args.water_film)):
        if val is not None and not (np.isfinite(val) and val >= 0):
            raise InputError(None, f"{flag} {val}: must be a non-negative length in metres")


def run(args):
    from roadscan.heightmap import HeightMap
    from roadscan.io.atomic import atomic_save_npy, atomic_write_text
    from roadscan.rain import rain_fill

    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    check_water_options(args)
    check_output_dir(args.out, inputs=[args.scan])
    scan = load_scan(args.scan, args)
    if not isinstance(scan, HeightMap):
        raise InputError(args.scan, "rain-fill needs an area scan (a height map), not a line profile")
    if not args.no_level:
        from roadscan import level
        scan = level.level(scan, degree=1)
    r = rain_fill(scan, connectivity=args.connectivity, max_depth_m=args.max_depth,
                  water_film_m=args.water_film)
    final = Path(args.out)
    with atomic_output_dir(final, inputs=[args.scan]) as out:
        _write(out, args, scan, r)
    from ..units_format import length

    cap = (f", at most {length(args.max_depth)} deep" if args.max_depth is not None else
           f", {length(args.water_film)} of water per area offered (the depressions hold "
           f"{length(r.meta['capacity_m3_per_m2'])})" if args.water_film is not None else "")
    print(f"{args.scan}: {r.connectivity}-connected fill{cap}, wetted {r.wetted_fraction:.1%}, "
          f"water {length(r.water_volume_m3_per_m2)} deep on average (volume per area) -> {final}")
    return 0


def _write(out, args, scan, r):
    from roadscan.io.atomic import atomic_save_npy, atomic_write_text

    from roadscan.io import write

    atomic_save_npy(out / "wet.npy", r.wet.heights_m)
    atomic_save_npy(out / "depth.npy", r.depth_m)
    # the same maps with their spacing (heights, dx, dy, unmeasured): read back by roadscan or
    # numpy without --spacing
    write(out / "wet.npz", r.wet)
    write(out / "depth.npz", r.wet.with_heights(r.depth_m, name="depth"))
    summary = {
        "scan": str(args.scan),
        "wetted_fraction": r.wetted_fraction,
        "water_volume_m3_per_m2": r.water_volume_m3_per_m2,
        "connectivity": r.connectivity,
        "max_depth_m": r.meta["max_depth_m"],
        "water_film_m": r.meta["water_film_m"],
        "capacity_m3_per_m2": r.meta["capacity_m3_per_m2"],
        "all_depressions_full": r.meta["all_full"],
        "measured_fraction": r.meta["measured_fraction"],
        "levelled": not args.no_level,
        "dx_m": scan.dx_m,
        "dy_m": scan.dy_m,
        "unmeasured_points": r.meta["unmeasured_policy"],
        "files": {"wet.npy": "wet surface [m], NaN unmeasured (no spacing: dx_m, dy_m above)",
                  "depth.npy": "water depth [m], 0 dry, NaN unmeasured (no spacing: dx_m, dy_m above)",
                  "wet.npz": "wet surface with its spacing: heights [m], dx, dy [m], unmeasured",
                  "depth.npz": "water depth with its spacing: heights [m], dx, dy [m], unmeasured"},
    }
    from ..scan_input import read_record

    summary.update(read_record(scan))          # how the file was read
    from ..validate import warnings_list

    if warnings_list():
        summary["warnings"] = warnings_list()
    atomic_write_text(out / "rainfill.json", json.dumps(summary, indent=2) + "\n")
