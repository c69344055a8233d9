"""``roadscan friction``: mu(v) from a spectrum and a rubber (Persson's theory).

Outputs: ``--out mu.csv`` with columns ``v_m_per_s,mu,area_fraction`` (A/A0 = P(q1) at each
speed; with ``--flash`` also ``T_flash_max_C``, the hottest flash temperature over all length
scales, then ``T_C_zeta_1``, ``T_C_zeta_max`` and ``T_C_zeta_<z>`` per ``--magnifications``
value), a PNG plot beside it (same stem) and ``<stem>_summary.json`` (inputs, the integration
band, the master-curve frequency coverage and the WLF fit of a shift table). Defaults (docs: Theory
sec 5): sigma0 = 0.2 MPa, nu = 0.5, the thesis rubber at T0 = T_ref, isothermal, speeds 1e-4 to
1e2 m/s at 10 per decade (61 points), the spectrum's own band.
"""
from __future__ import annotations

from ..friction_options import add_friction_options

NAME = "friction"
HELP = "friction coefficient mu(v) and contact area A/A0 from a spectrum (psd.csv or self-affine model) and a rubber"


def add_arguments(p):
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--psd", metavar="FILE", help="psd.csv with header q_per_m,C_m4 [1/m, m^4]")
    src.add_argument("--self-affine", metavar="H=..,h0=..,q0=..,q1=..",
                     help="self-affine model (thesis appendix A): Hurst H, h0 [m], q0, q1 [1/m], "
                          "optional qroll [1/m]")
    add_friction_options(p, master_curve=True, optional=False, q1_help=None)
    p.add_argument("--magnifications", default="", metavar="Z1,Z2,...",
                   help="with --flash: also report T at these magnifications zeta = q/q0")
    p.add_argument("--tol", type=float, default=1e-3, help="relative accuracy target for mu (1e-3)")
    p.add_argument("--out", default="mu.csv", metavar="mu.csv",
                   help="output CSV (PNG and <stem>_summary.json beside it)")


def run(args):
    from ..friction_job import run_friction

    res, v, psd, out = run_friction(args)   # the job (pipelines.friction_job); printed here
    from ..headline import peak_keys, peak_text
    from ..units_format import quantity

    print(f"{out}: {v.size} speeds, {peak_text(**peak_keys(res.v_m_per_s, res.mu))}, "
          f"q {quantity('q_per_m', psd.q_min_per_m)} to {quantity('q_per_m', psd.q1_per_m)}"
          + (f", {res.iterations} iterations, residual {res.residual:.2g} K" if args.flash else ""))
    return 0
