"""``flash_temperature``: frictional heating of the rubber at each length scale (Persson 2006;
thesis chapter 3; DESIGN.md sec 5), which the isothermal model lacks.

The engine's self-consistent flash-temperature model replaces the isothermal one; the free
parameter is zeta_m = q_m / q0, the magnification of the macro-asperity contact spots whose
size sets the heating time R / v (DESIGN.md: 2 < zeta_m < 5; the bounds are a little wider).
The effect is expensive (about 0.3 s per curve), so the search spends few evaluations on it.
"""
from . import Effect, Param, register


def _modify(spec, p, ctx):
    flash = dict(spec.flash or {})
    flash["zeta_m"] = p["zeta_m"]
    return spec.with_(flash=flash)


EFFECT = register(Effect(
    name="flash_temperature", level="friction",
    params=(Param("zeta_m", 1.5, 8.0, 3.0, "log"),),
    modify=_modify, cost=10.0,
    description="self-consistent flash temperature (Persson 2006), zeta_m free",
))
