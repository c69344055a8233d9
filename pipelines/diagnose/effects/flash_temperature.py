"""``flash_temperature``: frictional heating of the rubber at each length scale (Persson 2006;
thesis chapter 3; DESIGN.md sec 5), which the isothermal model lacks.

The engine's self-consistent flash-temperature model replaces the isothermal one. Free
parameters: zeta_m = q_m / q0, the magnification of the macro-asperity contact spots
(DESIGN.md: 2 < zeta_m < 5; the bounds are a little wider), and ``R_scale``, a factor on the
macro-asperity radius R = R_scale (a + b P(q_m)^c) / q_m with the engine's default (a, b, c) =
(0, 2 sqrt(pi), 1/2), which sets the heating time R / v (the heating depends strongly on R,
DESIGN.md sec 7). The effect is expensive (about 0.02-0.3 s per curve), so the search spends
few evaluations on it.
"""
import numpy as np

from . import Effect, Param, register

B_DEFAULT = 2.0 * np.sqrt(np.pi)


def _modify(spec, p, ctx):
    flash = dict(spec.flash or {})
    flash["zeta_m"] = p["zeta_m"]
    flash["asperity_abc"] = (0.0, B_DEFAULT * p["R_scale"], 0.5)
    return spec.with_(flash=flash)


EFFECT = register(Effect(
    name="flash_temperature", level="friction",
    params=(Param("zeta_m", 1.5, 8.0, 3.0, "log"), Param("R_scale", 0.2, 5.0, 1.0, "log")),
    modify=_modify, cost=10.0,
    description="self-consistent flash temperature (Persson 2006), zeta_m and contact-spot size free",
))
