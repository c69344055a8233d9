"""``roadscan dry-vs-wet SCAN --out DIR``."""
from __future__ import annotations

from roadscan.errors import InputError

from ..friction_options import add_friction_options, settings_from_args
from ..scan_input import add_scan_options, load_scan
from .rainfill import add_water_options, check_water_options

NAME = "dry-vs-wet"
HELP = "rain-fill a scan and compare PSD and friction mu(v) dry and wet (thesis section 4.4)"


def add_arguments(p):
    p.add_argument("scan", metavar="SCAN", help="area height file")
    p.add_argument("--out", required=True, metavar="DIR")
    add_scan_options(p)
    add_water_options(p)
    from ..analyse_options import add_spectrum_options

    add_spectrum_options(p)        # --window-alpha, --fit-band, --despike, --resolution
    add_friction_options(p)


def run(args):
    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    from ..dry_vs_wet import run_dry_vs_wet

    check_water_options(args)
    check_output_dir(args.out, inputs=[args.scan])
    settings = settings_from_args(args)
    from ..analyse_options import spectrum_kwargs

    sk = spectrum_kwargs(args)
    scan = load_scan(args.scan, args)
    try:
        with atomic_output_dir(args.out, inputs=[args.scan]) as tmp:
            r = run_dry_vs_wet(scan, tmp, settings, connectivity=args.connectivity,
                               max_depth_m=args.max_depth, water_film_m=args.water_film,
                               **sk)
    except InputError as exc:
        if "out" in exc.hint_option or str(exc.path or "").startswith(str(args.out)):
            raise                          # about the output, which it names: not the scan
        raise exc.reworded(args.scan) from None
    from ..units_format import length

    print(f"{args.scan}: wetted {r['wetted_fraction']:.1%}, water {length(r['water_volume_m3_per_m2'])}, "
          f"rms dry {length(r['rms_height_dry_m'])} / wet {length(r['rms_height_wet_m'])} "
          f"-> {args.out}/report.html")
    return 0
