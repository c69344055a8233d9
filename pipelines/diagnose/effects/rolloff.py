"""``rolloff`` (surface level): the spectrum flattens below a roll-off wave vector q_r (the
usual extension for real surfaces, DESIGN.md sec 2): C(q) = C(q_r) for q < q_r, which a pure
power law lacks. Parameter: q_r relative to the lowest measured q."""
import numpy as np

from . import Effect, Param, register


def _apply(ctx, p, C, st):
    qr = ctx.q[0] * p["q_roll_rel"]
    C_at = np.exp(np.interp(np.log(qr), np.log(ctx.q), np.log(C)))
    return np.where(ctx.q < qr, C_at, C), st


EFFECT = register(Effect(
    name="rolloff", level="surface", params=(Param("q_roll_rel", 1.0, 100.0, 3.0, "log"),),
    apply_fn=_apply,
    description="flat spectrum below q_r = q_roll_rel x lowest q",
))
