"""``contact_correction``: Persson's later factor S(q) = gamma + (1 - gamma) P(q)^2 in the
integrand of mu (Persson 2006, J. Phys.: Condens. Matter 18, 7789), which the thesis model
lacks (S = 1). gamma is fitted over its whole physical range (0, 1]; Persson uses about 0.45,
and gamma = 1 is the thesis model.
"""

from pipelines.diagnosis.effects import Effect, Param, register

EFFECT = register(
    Effect(
        name="contact_correction",
        level="friction",
        params=(Param("contact_gamma", 0.02, 1.0, 0.5, "lin"),),
        modify=lambda spec, p, ctx: spec.with_(contact_gamma=p["contact_gamma"]),
        null=lambda ctx: {"contact_gamma": 1.0},
        description="S(q) = gamma + (1 - gamma) P^2 factor in mu",
    )
)
