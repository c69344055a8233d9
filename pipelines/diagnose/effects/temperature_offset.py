"""``temperature_offset``: the rubber's background temperature T0 differs from the assumed one.

Every row's T0 is shifted by ``dT_C`` [K]; through the WLF shift (DESIGN.md sec 4,
E(w, T) = E_ref(w aT(T)/aT(T_ref))) this moves mu(v) along the speed axis.
"""
from . import Effect, Param, register

EFFECT = register(Effect(
    name="temperature_offset", level="friction",
    params=(Param("dT_C", -30.0, 30.0, 0.0, "lin"),),
    modify=lambda spec, p, ctx: spec.with_(T0_shift_C=spec.T0_shift_C + p["dT_C"]),
    null=lambda ctx: {"dT_C": 0.0},
    description="background temperature offset dT [K] (WLF shift along the speed axis)",
))
