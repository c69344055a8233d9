"""``roadscan rain-fill SCAN --out DIR``: fill a scan's cavities with water.

Parses, calls :func:`pipelines.rain_fill` and prints one line; the job and its files are
:mod:`pipelines.jobs.rain_fill` (``wet.npy``, ``depth.npy``, ``wet.npz``, ``depth.npz``,
``rainfill.json``); ``--no-level`` fills the heights as read.
"""

from __future__ import annotations

from pathlib import Path

from pipelines.settings.water import add_rain_fill_options

NAME = "rain-fill"
HELP = "fill a scan's depressions with water (imfill; optional depth cap or water film)"


def add_arguments(p):
    p.add_argument("scan", metavar="SCAN", help="area height file")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    add_rain_fill_options(p)  # scan, water, --no-level (pipelines.rain_fill's too)


def run(args):
    from pipelines.jobs.rain_fill import rain_fill
    from pipelines.output.units import length
    from pipelines.settings.keywords import keywords_of

    r = rain_fill(args.scan, args.out, **keywords_of(args, rain_fill))
    cap = (
        f", at most {length(args.max_depth)} deep"
        if args.max_depth is not None
        else f", {length(args.water_film)} of water per area offered (the depressions hold "
        f"{length(r['capacity_m3_per_m2'])})"
        if args.water_film is not None
        else ""
    )
    print(
        f"{args.scan}: {r['connectivity']}-connected fill{cap}, wetted {r['wetted_fraction']:.1%}, "
        f"water {length(r['water_volume_m3_per_m2'])} deep on average (volume per area) -> {Path(args.out)}"
    )
    return 0
