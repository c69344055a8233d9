"""``temperature_offset``: the rubber's background temperature T0 differs from the assumed one.

Every row's T0 is shifted by ``dT_C`` [K]; through the WLF shift (docs: Theory,
E(w, T) = E_ref(w aT(T)/aT(T_ref))) this moves mu(v) along the speed axis. Physical: T0 + dT inside the
rubber's shift table (when it has one; outside it the master curve is extrapolated).
"""

import numpy as np

from pipelines.diagnosis.effects import Effect, Param, register, temperature_extrapolated


def _T0(ctx):
    T = ctx.T0_C[np.isfinite(ctx.T0_C)]
    return float(np.median(T)) if T.size else float(ctx.base.rubber.T_ref_C)


def _physical(ctx, real_mu):
    """dT keeping T0 + dT inside the shift table (no limit for a WLF shift)."""
    T = getattr(getattr(ctx.base.rubber, "shift", None), "T_C", None)
    if T is None or not np.size(T):
        return {}
    return {"dT_C": (float(np.min(T)) - _T0(ctx), float(np.max(T)) - _T0(ctx))}


def _plausible(ctx, p, real_mu):
    T = ctx.T0_C[np.isfinite(ctx.T0_C)]
    T0 = float(np.median(T)) if T.size else float(ctx.base.rubber.T_ref_C)
    why = temperature_extrapolated(ctx, T0 + p["dT_C"])
    return [("dT_C", why)] if why else []


EFFECT = register(
    Effect(
        name="temperature_offset",
        level="friction",
        params=(Param("dT_C", -30.0, 30.0, 0.0, "lin"),),
        modify=lambda spec, p, ctx: spec.with_(T0_shift_C=spec.T0_shift_C + p["dT_C"]),
        null=lambda ctx: {"dT_C": 0.0},
        plausible=_plausible,
        physical=_physical,
        description="background temperature offset dT [K] (WLF shift along the speed axis)",
    )
)
