"""``anisotropy`` (surface level): the texture has a direction (the twin is isotropic). The
signed components (a, b) = (M_xx - M_yy, 2 M_xy) / tr M of the blocks' prewhitened direction
tensor (:func:`pipelines.diagnosis.surface.blocks.anisotropy_components`) become parameters; the index is
hypot(a, b) and the direction atan2(b, a) / 2 from the x axis. The twin's own values (0 on a
symmetric lattice) are no effect. Needs an area scan."""

import numpy as np

from pipelines.diagnosis.effects import Effect, Param, register


def _apply(ctx, p, pred):
    return dict(pred, anisotropy=np.array([p["a_xx_minus_yy"], p["b_xy"]]))


EFFECT = register(
    Effect(
        name="anisotropy",
        level="surface",
        requires=frozenset({"area"}),
        params=(Param("a_xx_minus_yy", -0.98, 0.98, 0.0, "lin"), Param("b_xy", -0.98, 0.98, 0.0, "lin")),
        apply_fn=_apply,
        null=lambda ctx: {
            "a_xx_minus_yy": float(ctx.twin_mean["anisotropy"][0]),
            "b_xy": float(ctx.twin_mean["anisotropy"][1]),
        },
        description="directional texture: signed components of the 2D spectrum's direction tensor "
        "(index = hypot(a, b), direction = atan2(b, a) / 2)",
    )
)
