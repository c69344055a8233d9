"""``anisotropy`` (surface level): the texture has a direction (the twin is isotropic); the
anisotropy index (l1 - l2)/(l1 + l2) of the blocks' 2D spectrum direction tensor becomes a
parameter (the twin's own value is no effect). Needs an area scan."""
import numpy as np

from . import Effect, Param, register


def _apply(ctx, p, pred):
    return dict(pred, anisotropy=np.array([p["anisotropy_index"]]))


EFFECT = register(Effect(
    name="anisotropy", level="surface", requires=frozenset({"area"}),
    params=(Param("anisotropy_index", 0.0, 0.95, 0.1, "lin"),),
    apply_fn=_apply, null=lambda ctx: {"anisotropy_index": float(ctx.twin_mean["anisotropy"][0])},
    description="directional texture (anisotropy index of the 2D spectrum)",
))
