"""``roadscan friction``: mu(v) from a spectrum and a rubber (Persson's theory).

Outputs: ``--out mu.csv`` with columns ``v_m_per_s,mu,area_fraction`` (A/A0 = P(q1) at each
speed; with ``--flash`` also ``T_flash_max_C``, the hottest flash temperature over all length
scales, then ``T_C_zeta_1``, ``T_C_zeta_max`` and ``T_C_zeta_<z>`` per ``--magnifications``
value), a PNG plot beside it (same stem) and ``<stem>_summary.json`` (inputs, the integration
band, the master-curve frequency coverage and the WLF fit of a shift table). Defaults (docs: Theory
sec 5): sigma0 = 0.2 MPa, nu = 0.5, the thesis rubber at T0 = T_ref, isothermal, speeds 1e-4 to
1e2 m/s at 10 per decade (61 points), the spectrum's own band. The command parses, calls
:func:`pipelines.friction` and prints one line from the summary it returns.
"""

from __future__ import annotations

from pathlib import Path

from pipelines.jobs.friction_call import add_friction_command_options

NAME = "friction"
HELP = (
    "friction coefficient mu(v) and contact area A/A0 from "
    "a spectrum (psd.csv or self-affine model) and a rubber"
)


def add_arguments(p):
    add_friction_command_options(p)  # spectrum, rubber, contact, speeds (pipelines.friction's too)
    p.add_argument(
        "--out", default="mu.csv", metavar="mu.csv", help="output CSV (PNG and <stem>_summary.json beside it)"
    )


def run(args):
    from pipelines.jobs.friction_call import friction
    from pipelines.output.headline import peak_text
    from pipelines.output.units import quantity
    from pipelines.settings.keywords import keywords_of

    s = friction(args.out, **keywords_of(args, friction))
    band = s["band"]
    print(
        f"{Path(args.out)}: {len(s['extrapolated_share'])} speeds, "
        f"{peak_text(s['mu_peak'], s['v_peak_m_per_s'], s['peak_at_edge'], s['peak_note'])}, "
        f"q {quantity('q_per_m', band['q0_per_m'])} to {quantity('q_per_m', band['q1_per_m'])}"
        + (f", hottest flash {s['T_flash_max_C']:.4g} °C" if args.flash else "")
    )
    return 0
