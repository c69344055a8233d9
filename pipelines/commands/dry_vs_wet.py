"""``roadscan dry-vs-wet SCAN --out DIR``."""
from __future__ import annotations

from roadscan.errors import InputError

from ..dry_vs_wet import run_dry_vs_wet
from ..friction_options import add_friction_options, settings_from_args
from ..scan_input import add_scan_options, load_scan

NAME = "dry-vs-wet"
HELP = "rain-fill a scan and compare PSD and friction mu(v) dry and wet (thesis section 4.4)"


def add_arguments(p):
    p.add_argument("scan", metavar="SCAN", help="area height file")
    p.add_argument("--out", required=True, metavar="DIR")
    add_scan_options(p)
    p.add_argument("--connectivity", type=int, choices=(4, 8), default=4,
                   help="connectivity of the fill (default 4, as Matlab's imfill)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--max-depth", type=float, default=None, metavar="M",
                   help="limit water to this depth above each depression's lowest point [m]")
    g.add_argument("--water-film", type=float, default=None, metavar="M",
                   help="limit water to this volume per area [m^3/m^2 = m]")
    add_friction_options(p)


def run(args):
    for flag, val in (("--max-depth", args.max_depth), ("--water-film", args.water_film)):
        if val is not None and not val >= 0:
            raise InputError(None, f"{flag} {val}: must be a non-negative length in metres")
    settings = settings_from_args(args)
    scan = load_scan(args.scan, args)
    try:
        r = run_dry_vs_wet(scan, args.out, settings, connectivity=args.connectivity,
                           max_depth_m=args.max_depth, water_film_m=args.water_film)
    except InputError as exc:
        raise InputError(args.scan, exc.problem) from None
    except ValueError as exc:
        raise InputError(args.scan, str(exc)) from None
    print(f"{args.scan}: wetted {r['wetted_fraction']:.1%}, water {r['water_volume_m3_per_m2'] * 1e3:.3g} mm, "
          f"rms dry {r['rms_height_dry_m'] * 1e6:.1f} um / wet {r['rms_height_wet_m'] * 1e6:.1f} um "
          f"-> {args.out}/report.html")
    return 0
