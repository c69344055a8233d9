"""``flash_temperature``: frictional heating of the rubber at each length scale (Persson 2006;
thesis chapter 3; docs: Theory), which the isothermal model lacks.

The engine's self-consistent flash-temperature model replaces the isothermal one. Free
parameters: zeta_m = q_m / q0, the magnification of the macro-asperity contact spots
(Persson 2006: 2 < zeta_m < 5; the bounds are a little wider), and ``heat_scale``, a factor on the
heat source (``friction.mu_flash(heat_scale=...)``): the temperature rise scales with the
frictional heat over the rubber's heat capacity and conductivity, which a measurement's rubber
need not share with the model's defaults. heat_scale -> 1e-3 is no effect (a temperature rise a
thousand times smaller: the isothermal model within 1e-3), so the fit can always fall back on
the baseline. Physical: heat_scale within a factor 3 of 1 (``plausible``). The effect is expensive (about
0.02-0.3 s per curve), so the search spends few evaluations on it.
"""

from pipelines.diagnosis.effects import Effect, Param, register

#: heating within this factor of the model's own is physical (rubber's heat capacity and
#: conductivity uncertain by about that much)
HEAT_FACTOR = 3.0


def _plausible(ctx, p, real_mu):
    h = p["heat_scale"]
    if h <= 1.01e-3:  # the no-effect limit
        return []
    if not (1 / HEAT_FACTOR <= h <= HEAT_FACTOR):
        return [
            (
                "heat_scale",
                f"heat_scale {h:.3g} is not within a factor {HEAT_FACTOR:g} of the model's heating",
            )
        ]
    return []


def _modify(spec, p, ctx):
    flash = dict(spec.flash or {})
    flash["zeta_m"] = p["zeta_m"]
    flash["heat_scale"] = p["heat_scale"]
    return spec.with_(flash=flash)


EFFECT = register(
    Effect(
        name="flash_temperature",
        level="friction",
        params=(Param("zeta_m", 1.5, 8.0, 3.0, "log"), Param("heat_scale", 1e-3, 10.0, 1.0, "log")),
        modify=_modify,
        cost=10.0,
        null=lambda ctx: {"zeta_m": 3.0, "heat_scale": 1e-3},
        plausible=_plausible,
        physical=lambda ctx, mu: {"heat_scale": (1 / HEAT_FACTOR, HEAT_FACTOR)},
        description="self-consistent flash temperature (Persson 2006), zeta_m and heat-source scale free",
    )
)
