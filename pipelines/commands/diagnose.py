"""``roadscan diagnose``: the sim-to-real gap.

Friction level: ``roadscan diagnose --measured MU.csv (--scan FILE | --psd FILE)
[--rubber FILE.toml | --master-curve MC.csv --shift-table aT.csv [--reference-temperature C]]
[--sigma0 0.3MPa] [--nu NU] [--q0 Q] [--q1 Q] [--contact-gamma G] [--extrapolate hold|powerlaw]
[--temperature C] [--noise RMS] [--validate OTHER.csv] --out DIR``. The band, nu, the pressure
that enters P(q), the master curve's frequency coverage (one warning line beyond a decade of
extrapolation) and the WLF fit of a shift table go into diagnosis.json as in ``roadscan friction``.
Surface level: ``roadscan diagnose --scan FILE --out DIR``.
Writes DIR/diagnosis.json and DIR/report.html (see :mod:`pipelines.diagnose`).
"""
from __future__ import annotations

import sys

from ..friction_options import add_friction_options
from ..scan_input import add_scan_options

NAME = "diagnose"
HELP = "sim-to-real gap: where model and measurement disagree, which unmodelled effect, how much it closes"


def add_arguments(p):
    p.add_argument("--measured", metavar="MU.csv", default=None,
                   help="measured mu(v): CSV v_m_per_s,mu[,T0_C,sigma0_Pa,condition] (friction level); "
                        "without it the scan itself is diagnosed (surface level)")
    p.add_argument("--scan", metavar="FILE", default=None, help="height file (area scan or line profile)")
    p.add_argument("--psd", metavar="FILE", default=None, help="spectrum CSV q_per_m,C_m4 (instead of --scan)")
    add_friction_options(p, master_curve=True, sliding=False, optional=False, q1_help=None)
    p.add_argument("--noise", type=float, default=None, metavar="RMS",
                   help="measurement noise as rms of log10 (default: estimated from the data)")
    p.add_argument("--validate", metavar="OTHER.csv", default=None,
                   help="a separate measurement predicted by the corrected model without refitting")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument("--uncertain", default=None, metavar="KEY=LO:HI,...",
                   help="inputs known only within a range, calibrated on the training points: q1=LO:HI [1/m] "
                        "(q1=known: q1 fixed), sigma0=LO:HI (units as --sigma0), psd_scale=LO:HI (factor on C(q)), "
                        "temperature=LO:HI [C]; any subset")
    p.add_argument("--measurements", metavar="M.csv", default=None,
                   help="several measurements at once: CSV measured,rubber,label[,temperature_C,sigma0_Pa] "
                        "(paths relative to M.csv); q1, psd_scale and sigma0 shared")
    add_scan_options(p)
    p.set_defaults(sigma0=None)   # None: not given (the default 0.2MPa is then listed as assumed)


def _say(msg):
    print(msg, file=sys.stderr)


def run(args):
    from ..diagnose.job import run_diagnosis

    return run_diagnosis(args, _report, _say)


def _report(data, out):
    v = data["verdict"]
    eff = v["effect"] if not isinstance(v["effect"], list) else "+".join(v["effect"])
    print(f"{data['level']} level: baseline gap {data['baseline_gap']:.4g}, noise {data['noise']:.4g}; "
          f"verdict: {eff or 'null'}" + (f" (held-out shrink {v['shrink']:.0%})" if v.get("shrink") is not None else ""))
    print(f"wrote {out}/diagnosis.json and {out}/report.html")


