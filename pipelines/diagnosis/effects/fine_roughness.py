"""``fine_roughness``: roughness beyond the scan's resolution (thesis section 4.2: extending q1
from the Nyquist 5.6e4 to 6e5 1/m raised mu by 58 %).

The spectrum's upper cut-off q1 is multiplied by ``q1_factor`` >= 1, continuing C(q) with the
engine's power-law extension (``psd.with_q1``). Physical: q1 at most ``Q1_MAX`` (1e7 1/m, a
wavelength of 0.63 um; finer roughness is below the scale of rubber's filler particles).
"""

from pipelines.diagnosis.effects import Effect, Param, register

Q1_MAX = 1e7


def _plausible(ctx, p, real_mu):
    q1 = ctx.base.psd.q1_per_m * p["q1_factor"]
    return [("q1_factor", f"q1 = {q1:.3g} 1/m is beyond {Q1_MAX:.3g} 1/m")] if q1 > Q1_MAX else []


def _modify(spec, p, ctx):
    psd = spec.psd.with_q1(spec.psd.q1_per_m * p["q1_factor"])
    wet = spec.wet_psd.with_q1(spec.wet_psd.q1_per_m * p["q1_factor"]) if spec.wet_psd is not None else None
    return spec.with_(psd=psd, wet_psd=wet)


EFFECT = register(
    Effect(
        name="fine_roughness",
        level="friction",
        params=(Param("q1_factor", 1.0, 100.0, 3.0, "log"),),
        modify=_modify,
        null=lambda ctx: {"q1_factor": 1.0},
        plausible=_plausible,
        description="upper wave vector q1 multiplied by a factor (power-law continuation)",
    )
)
