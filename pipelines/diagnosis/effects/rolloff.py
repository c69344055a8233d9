"""``rolloff`` (surface level): the spectrum flattens below a roll-off wave vector q_r (the
usual extension for real surfaces, docs: Theory): C(q) = C(q_r) for q < q_r, which a pure
power law lacks. Applied to the twin's ring spectrum as the ratio of the rolled-off to the pure
law, log10 C -> log10 C - 2 (H + 1) log10(q_r / q) for q < q_r (H the twin's Hurst exponent),
so that what levelling and the window do to the lowest rings of the twin stays in the
prediction. Parameter: q_r relative to the lowest wave vector of a block; 1 is no effect."""

import numpy as np

from pipelines.diagnosis.effects import Effect, Param, register


def _apply(ctx, p, pred):
    q = ctx.ring_q
    qr = q[0] * p["q_roll_rel"]
    drop = 2.0 * (float(ctx.fit.hurst) + 1.0) * np.log10(np.minimum(q / qr, 1.0))
    return dict(pred, spec_rings=pred["spec_rings"] + drop)


EFFECT = register(
    Effect(
        name="rolloff",
        level="surface",
        params=(Param("q_roll_rel", 1.0, 100.0, 3.0, "log"),),
        apply_fn=_apply,
        null=lambda ctx: {"q_roll_rel": 1.0},
        description="flat spectrum below q_r = q_roll_rel x lowest q of a block",
    )
)
