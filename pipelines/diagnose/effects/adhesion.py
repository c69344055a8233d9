"""``adhesion``: an extra contribution at low speed that the viscoelastic theory lacks.

mu_adh(v) = A / (1 + (v / v_c)^n): a plateau A [-] at low speed falling off above a
characteristic speed v_c [m/s] with exponent n (a simple form of the bond-breaking term of
Persson's later work; the exponent lets it fall gently or steeply).
"""
import numpy as np

from . import Effect, Param, register


def _modify(spec, p, ctx):
    A, vc, n = p["amplitude"], p["v_c_m_per_s"], p["exponent"]

    def mu_adh(v):
        return A / (1.0 + (np.asarray(v, float) / vc) ** n)

    return spec.with_(additive=spec.additive + (mu_adh,))


EFFECT = register(Effect(
    name="adhesion", level="friction",
    params=(Param("amplitude", 1e-3, 3.0, 0.05, "log"),
            Param("v_c_m_per_s", 1e-7, 30.0, 1e-3, "log"),
            Param("exponent", 0.5, 3.0, 1.0, "log")),
    modify=_modify,
    description="additive mu_adh = A / (1 + (v/v_c)^n)",
))
