"""``load``: the nominal contact pressure sigma0 differs from the assumed one.

Every row's sigma0 is multiplied by ``sigma0_scale`` (changes P(q) and M(q) in Persson's
theory; mu depends on sigma0 through the contact area, weakly at low load).
"""

from pipelines.diagnosis.effects import Effect, Param, register

EFFECT = register(
    Effect(
        name="load",
        level="friction",
        params=(Param("sigma0_scale", 0.2, 5.0, 1.0, "log"),),
        modify=lambda spec, p, ctx: spec.with_(sigma0_scale=spec.sigma0_scale * p["sigma0_scale"]),
        null=lambda ctx: {"sigma0_scale": 1.0},
        description="nominal pressure scale factor",
    )
)
