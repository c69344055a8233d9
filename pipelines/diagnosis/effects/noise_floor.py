"""``noise_floor`` (surface level): instrument noise (a white floor C_n added to C) and/or optical
smoothing (C multiplied by exp(-(q/q_c)^2)) at high wave vectors. C_n = floor_rel x the twin's
C at the highest ring, q_c = q_c_rel x the highest ring's q; floor_rel -> 1e-4 with q_c_rel = 20
is no effect (below 1e-4 decade)."""

import numpy as np

from pipelines.diagnosis.effects import Effect, Param, register


def _apply(ctx, p, pred):
    q = ctx.ring_q
    s = pred["spec_rings"]
    Cn = 10.0 ** ctx.twin_rings[-1] * p["floor_rel"]
    qc = q[-1] * p["q_c_rel"]
    C = 10.0**s * np.exp(-((q / qc) ** 2)) + Cn
    return dict(pred, spec_rings=np.log10(C))


EFFECT = register(
    Effect(
        name="noise_floor",
        level="surface",
        params=(Param("floor_rel", 1e-4, 1e3, 1e-2, "log"), Param("q_c_rel", 0.05, 20.0, 10.0, "log")),
        apply_fn=_apply,
        null=lambda ctx: {"floor_rel": 1e-4, "q_c_rel": 20.0},
        description="white floor C_n = floor_rel x C_twin(q_max) plus "
        "Gaussian smoothing cut-off q_c = q_c_rel x q_max",
    )
)
