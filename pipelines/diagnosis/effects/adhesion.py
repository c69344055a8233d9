"""``adhesion``: an extra contribution at low speed that the viscoelastic theory lacks.

The adhesive (bond-breaking) shear stress of Persson's later work is a bell in log v
(tau_f(v) ~ exp(-c log^2(v / v*))); measured data often show only its falling side. The
effect covers both with

    mu_adh(v) = A exp(-1/2 (min(log10(v / v_c), 0) / w)^2) / (1 + (v / v_c)^n),

a rise of width w [decades] below the peak speed v_c [m/s] (w large: a plateau at low speed)
and a fall with exponent n above it; A [-] is the peak amplitude. Physical: A below the largest
measured mu (an additive term cannot exceed the total it is part of).
"""

import numpy as np

from pipelines.diagnosis.effects import Effect, Param, register


def adhesion_mu(v, amplitude, v_c_m_per_s, exponent, rise_decades):
    """mu_adh(v) of the module docstring (vectorised over v [m/s])."""
    x = np.asarray(v, float) / v_c_m_per_s
    below = np.minimum(np.log10(x), 0.0) / rise_decades
    return amplitude * np.exp(-0.5 * below * below) / (1.0 + x**exponent)


def _modify(spec, p, ctx):
    def mu_adh(v):
        return adhesion_mu(v, p["amplitude"], p["v_c_m_per_s"], p["exponent"], p["rise_decades"])

    return spec.with_(additive=spec.additive + (mu_adh,))


def _plausible(ctx, p, real_mu):
    top = float(np.max(real_mu))
    if p["amplitude"] > top:
        return [("amplitude", f"amplitude {p['amplitude']:.3g} exceeds the largest measured mu {top:.3g}")]
    return []


EFFECT = register(
    Effect(
        name="adhesion",
        level="friction",
        params=(
            Param("amplitude", 1e-6, 3.0, 0.05, "log"),
            Param("v_c_m_per_s", 1e-8, 30.0, 1e-3, "log"),
            Param("exponent", 0.3, 6.0, 1.0, "log"),
            Param("rise_decades", 0.2, 20.0, 20.0, "log"),
        ),
        modify=_modify,
        plausible=_plausible,
        physical=lambda ctx, mu: {"amplitude": (1e-6, float(np.max(mu)))},
        null=lambda ctx: {"amplitude": 1e-6, "v_c_m_per_s": 1e-3, "exponent": 1.0, "rise_decades": 20.0},
        description="additive bell in log v: rise of width w below v_c, fall (v/v_c)^-n above",
    )
)
