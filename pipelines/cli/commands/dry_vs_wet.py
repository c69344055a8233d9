"""``roadscan dry-vs-wet SCAN --out DIR``: parses, calls :func:`pipelines.dry_vs_wet`
(the job and its files: :mod:`pipelines.jobs.dry_vs_wet`) and prints one line."""

from __future__ import annotations

from pipelines.settings.water import add_dry_vs_wet_options

NAME = "dry-vs-wet"
HELP = "rain-fill a scan and compare PSD and friction mu(v) dry and wet (thesis section 4.4)"


def add_arguments(p):
    p.add_argument("scan", metavar="SCAN", help="area height file")
    p.add_argument(
        "--out",
        required=True,
        metavar="DIR",
        help="output directory: comparison.json, report.html, the wet map and the PNG "
        "figures (written all or none)",
    )
    add_dry_vs_wet_options(p)  # scan, water, spectrum and friction (pipelines.dry_vs_wet's too)


def run(args):
    from pipelines.jobs.dry_vs_wet import dry_vs_wet
    from pipelines.output.units import length
    from pipelines.settings.keywords import keywords_of

    r = dry_vs_wet(args.scan, args.out, **keywords_of(args, dry_vs_wet))
    print(
        f"{args.scan}: wetted {r['wetted_fraction']:.1%}, water {length(r['water_volume_m3_per_m2'])}, "
        f"rms dry {length(r['rms_height_dry_m'])} / wet {length(r['rms_height_wet_m'])} "
        f"-> {args.out}/report.html"
    )
    return 0
