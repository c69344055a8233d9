"""``roadscan rubber master RAW.csv --reference-temperature T --out rubber.toml``: raw DMA
frequency sweeps -> master curve; the job and its files are :mod:`pipelines.jobs.rubber_master`.
"""

from __future__ import annotations

import sys
from pathlib import Path

from pipelines.output.units import sig3

NAME = "rubber"
HELP = "rubber data tools: 'rubber master RAW.csv' builds a master curve from raw DMA sweeps"


def add_arguments(p):
    sub = p.add_subparsers(dest="rubber_command", metavar="ACTION")
    sub.required = True
    m = sub.add_parser(
        "master",
        help="raw DMA frequency sweeps -> master curve, shift table, WLF, Prony",
        description="Time-temperature superposition of raw DMA frequency sweeps "
        "(columns f, E_stor, E_loss, T with units; optional Set).",
    )
    m.add_argument(
        "raw",
        metavar="RAW.csv",
        help="raw sweeps: f [Hz], E_stor, E_loss, T [C] (+ units line), optional Set",
    )
    m.add_argument(
        "--reference-temperature",
        type=float,
        required=True,
        metavar="C",
        help="reference temperature T_ref of the master curve [C] (within the sweeps' range)",
    )
    m.add_argument(
        "--out", required=True, metavar="rubber.toml", help="rubber TOML to write (data files beside it)"
    )
    m.add_argument(
        "--prony-per-decade",
        type=float,
        default=1.5,
        metavar="N",
        help="Prony terms per decade of the master curve (default 1.5)",
    )


def run(args):
    from pipelines.jobs.rubber_master import build_rubber_master

    out = Path(args.out)
    res = build_rubber_master(args.raw, args.reference_temperature, out, args.prony_per_decade)
    m, w, p, stem = res.master, res.wlf, res.prony, out.stem
    trend = sum(i["method"] == "trend" for i in res.sweep_info)
    print(
        f"{out}: master curve at {res.T_ref_C:g} °C from {len(res.T_sweep_C)} sweeps, "
        f"{m.f_Hz[0]:.3g}..{m.f_Hz[-1]:.3g} Hz; WLF C1 {sig3(w.C1)}, C2 {sig3(w.C2_K)} K, "
        f"rms {res.wlf_rms_decades:.2f} decades; Prony {p.E_i_Pa.size} terms"
    )
    if res.wlf_rms_decades > 0.5:
        print(
            f"note: WLF describes this shift table poorly (rms {res.wlf_rms_decades:.2f} decades, max "
            f"{res.wlf_max_decades:.2f}); runs use the table itself, not the WLF fit",
            file=sys.stderr,
        )
    if trend:
        print(
            f"note: {trend} sweep(s) too flat to shift by overlap (plateau); their shift continues "
            f"the trend of their neighbours (see {stem}_master.json)",
            file=sys.stderr,
        )
    return 0
