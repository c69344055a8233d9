"""``roadscan compare SCAN_A SCAN_B [...] --out DIR``."""
from __future__ import annotations

from roadscan.errors import InputError

from ..friction_options import add_friction_options, settings_from_args
from ..scan_input import add_scan_options, load_scan
from .analyse import _unique_dirs

NAME = "compare"
HELP = "compare surfaces: all spectra and mu(v), where and by how much they differ"


def add_arguments(p):
    p.add_argument("scans", nargs="+", metavar="SCAN", help="two or more height files (the first is the reference)")
    p.add_argument("--out", required=True, metavar="DIR")
    add_scan_options(p)
    from ..analyse_options import add_resolution_option

    add_resolution_option(p)
    add_friction_options(p)


def run(args):
    from ..compare import run_compare

    if len(args.scans) < 2:
        raise InputError(args.scans[0], "compare needs at least two scans")
    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    check_output_dir(args.out, inputs=args.scans)
    settings = settings_from_args(args)
    from ..analyse_options import check_resolution

    res = check_resolution(args.resolution)
    scans = [load_scan(f, args) for f in args.scans]
    names = _unique_dirs(args.scans)
    try:
        with atomic_output_dir(args.out, inputs=args.scans) as tmp:
            r = run_compare(scans, names, tmp, settings, resolution_m=res)
    except ValueError as exc:
        raise InputError(None, str(exc)) from None
    from ..units_format import length

    for n in names:
        print(f"{n}: H = {r[n]['hurst']:.3f}, rms height = {length(r[n]['rms_height_m'])}"
              + (f", peak mu = {r[n]['mu_peak']:.3g}" if r[n].get("mu_peak") else ""))
    print(f"-> {args.out}/report.html")
    return 0
