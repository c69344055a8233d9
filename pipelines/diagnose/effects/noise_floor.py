"""``noise_floor`` (surface level): instrument noise (a white floor C_n added to C) and/or optical
smoothing (C multiplied by exp(-(q/q_c)^2)) at high wave vectors."""
import numpy as np

from . import Effect, Param, register


def _apply(ctx, p, C, st):
    Cn = ctx.C_twin[-1] * p["floor_rel"]
    qc = ctx.q[-1] * p["q_c_rel"]
    return C * np.exp(-(ctx.q / qc) ** 2) + Cn, st


EFFECT = register(Effect(
    name="noise_floor", level="surface",
    params=(Param("floor_rel", 1e-3, 1e3, 1e-2, "log"), Param("q_c_rel", 0.05, 20.0, 10.0, "log")),
    apply_fn=_apply,
    description="white floor C_n = floor_rel x C_twin(q_max) plus Gaussian smoothing cut-off q_c = q_c_rel x q_max",
))
