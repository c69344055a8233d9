"""``roadscan diagnose``: the sim-to-real gap.

Friction level: ``roadscan diagnose --measured MU.csv (--scan FILE | --psd FILE)
[--rubber FILE.toml | --master-curve MC.csv --shift-table aT.csv [--reference-temperature C]]
[--sigma0 0.3MPa] [--nu NU] [--q0 Q] [--q1 Q] [--contact-gamma G] [--extrapolate hold|powerlaw]
[--temperature C] [--noise RMS] [--validate OTHER.csv] --out DIR``. The band, nu, the pressure
that enters P(q), the master curve's frequency coverage (one warning line beyond a decade of
extrapolation) and the WLF fit of a shift table go into diagnosis.json as in ``roadscan friction``.
Surface level: ``roadscan diagnose --scan FILE --out DIR``.
Writes DIR/diagnosis.json and DIR/report.html (see :mod:`pipelines.diagnosis`). The command
parses, calls :func:`pipelines.diagnose` and prints.
"""

from __future__ import annotations

from pipelines.diagnosis.job import add_diagnose_options

NAME = "diagnose"
HELP = "sim-to-real gap: where model and measurement disagree, which unmodelled effect, how much it closes"


def add_arguments(p):
    add_diagnose_options(p)  # every option but --out (pipelines.diagnose's too)
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")


def run(args):
    from pipelines.diagnosis.job import diagnose
    from pipelines.settings.keywords import keywords_of

    data = diagnose(args.out, **keywords_of(args, diagnose))
    if "measurements" in data and "joint" in data:  # several measurements
        for label, m in data["measurements"].items():
            v = m["verdict"]
            eff = v["effect"] if not isinstance(v["effect"], list) else "+".join(v["effect"])
            print(
                f"{label}: verdict {eff or ('inconclusive' if v['inconclusive'] else 'null')}"
                + (f" ({v['confidence']})" if v.get("confidence") else "")
            )
    else:
        _report(data)
    print(f"wrote {args.out}/diagnosis.json and {args.out}/report.html")
    return 0


def _report(data):
    v = data["verdict"]
    eff = v["effect"] if not isinstance(v["effect"], list) else "+".join(v["effect"])
    print(
        f"{data['level']} level: baseline gap {data['baseline_gap']:.4g}, noise {data['noise']:.4g}; "
        f"verdict: {eff or 'null'}"
        + (f" (held-out shrink {v['shrink']:.0%})" if v.get("shrink") is not None else "")
    )
