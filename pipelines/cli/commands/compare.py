"""``roadscan compare SCAN_A SCAN_B [...] --out DIR``."""

from __future__ import annotations

from pipelines.settings.analyse import add_compare_options, unique_stems
from pipelines.settings.friction import settings_from_args
from pipelines.settings.scan_input import load_scan
from roadscan.errors import InputError

NAME = "compare"
HELP = "compare surfaces: all spectra and mu(v), where and by how much they differ"


def add_arguments(p):
    p.add_argument(
        "scans", nargs="+", metavar="SCAN", help="two or more height files (the first is the reference)"
    )
    p.add_argument(
        "--out",
        required=True,
        metavar="DIR",
        help="output directory: comparison.json, report.html and the PNG figures (written all or none)",
    )
    add_compare_options(p)  # scan, spectrum and friction options (pipelines.compare's too)


def run(args):
    from pipelines.jobs.compare import run_compare

    if len(args.scans) < 2:
        raise InputError(args.scans[0], "compare needs at least two scans")
    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    check_output_dir(args.out, inputs=args.scans)
    settings = settings_from_args(args)
    from pipelines.settings.analyse import spectrum_kwargs

    sk = spectrum_kwargs(args)
    scans = [load_scan(f, args) for f in args.scans]
    names = unique_stems(args.scans)
    with atomic_output_dir(args.out, inputs=args.scans) as tmp:
        r = run_compare(scans, names, tmp, settings, figures=not args.no_figures, **sk)
    from pipelines.output.headline import hurst_text, peak_text
    from pipelines.output.units import length

    for n in names:
        e = r[n]
        print(
            f"{n}: H = {hurst_text(e)}, rms height = {length(e['rms_height_m'])}"
            + (
                f", {peak_text(e['mu_peak'], e['v_peak_m_per_s'], e.get('peak_at_edge'), e.get('peak_note'))}"
                if e.get("mu_peak")
                else ""
            )
        )
    print(f"-> {args.out}/report.html")
    return 0
