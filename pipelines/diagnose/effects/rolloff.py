"""``rolloff`` (surface level): the spectrum flattens below a roll-off wave vector q_r (the
usual extension for real surfaces, DESIGN.md sec 2): C(q) = C(q_r) for q < q_r, which a pure
power law lacks. Parameter: q_r relative to the lowest wave vector of a block; 1 is no effect."""
import numpy as np

from . import Effect, Param, register


def _apply(ctx, p, pred):
    q = ctx.ring_q
    s = pred["spec_rings"]
    qr = q[0] * p["q_roll_rel"]
    at = np.interp(np.log(qr), np.log(q), s)
    return dict(pred, spec_rings=np.where(q < qr, at, s))


EFFECT = register(Effect(
    name="rolloff", level="surface", params=(Param("q_roll_rel", 1.0, 100.0, 3.0, "log"),),
    apply_fn=_apply, null=lambda ctx: {"q_roll_rel": 1.0},
    description="flat spectrum below q_r = q_roll_rel x lowest q of a block",
))
