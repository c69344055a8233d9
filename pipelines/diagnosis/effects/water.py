"""``water``: water in the road's cavities (thesis section 4.4, docs: Theory).

Sliding rubber seals the cavities and "feels" the rain-filled surface: the wet rows use the
spectrum of the rain-filled scan with a limited water film w = ``fill_fraction`` x the full
capacity of the depressions (``roadscan.rain.rain_fill``, 4-connectivity). Needs the scan.
Wet spectra are precomputed at a few fill fractions; between them log C is interpolated
linearly in log(fraction), down to the dry spectrum at ``DRY_FRACTION`` (no effect).
"""

import numpy as np

from pipelines.diagnosis.effects import Effect, Param, register

FRACTIONS = (0.01, 0.03, 0.1, 0.25, 0.5, 0.75, 1.0)
#: below this fill fraction the wet spectrum is the dry one (no effect, reachable)
DRY_FRACTION = 1e-3


def _prepare(ctx):
    from roadscan.rain import rain_fill
    from roadscan.spectrum import psd_area

    hm = ctx.scan
    if hm is None or not hasattr(hm, "ny"):
        return "needs an area scan (--scan of a height map)"
    full = rain_fill(hm)
    cap = float(full.meta.get("capacity_m3_per_m2", full.water_volume_m3_per_m2))
    if not cap > 0:
        return "the scan has no closed depressions to hold water"
    psd = ctx.base.psd
    q = np.geomspace(psd.q_min_per_m, psd.q1_per_m, 200)
    dry_spec = ctx.spectrum if ctx.spectrum is not None else psd_area(hm)[0]
    dry = np.interp(np.log(q), np.log(dry_spec.q_per_m), np.log(np.maximum(dry_spec.C_m4, 1e-300)))
    logC = []
    for f in FRACTIONS:
        rf = full if f >= 1.0 else rain_fill(hm, water_film_m=f * cap)
        spec, _ = psd_area(rf.wet)
        wet = np.interp(np.log(q), np.log(spec.q_per_m), np.log(np.maximum(spec.C_m4, 1e-300)))
        logC.append(wet - dry)  # log ratio wet/dry, applied to the baseline spectrum
    ctx.cache["water"] = dict(q=q, log_ratio=np.array(logC), capacity_m=cap)
    return None


def wet_psd(ctx, psd, fraction):
    """The baseline spectrum times the interpolated wet/dry ratio at ``fraction`` of capacity."""
    from friction.psd import TabulatedPSD

    c = ctx.cache["water"]
    lf = np.log((DRY_FRACTION,) + FRACTIONS)
    table = np.vstack([np.zeros_like(c["log_ratio"][0]), c["log_ratio"]])
    x = np.clip(np.log(fraction), lf[0], lf[-1])
    i = int(np.clip(np.searchsorted(lf, x) - 1, 0, lf.size - 2))
    t = (x - lf[i]) / (lf[i + 1] - lf[i])
    lr = (1 - t) * table[i] + t * table[i + 1]
    q = c["q"]
    C = psd.C(q) * np.exp(lr)
    return TabulatedPSD(q, C, q0_per_m=psd.q0_per_m, q1_per_m=psd.q1_per_m)


EFFECT = register(
    Effect(
        name="water",
        level="friction",
        params=(Param("fill_fraction", DRY_FRACTION, 1.0, 0.3, "log"),),
        null=lambda ctx: {"fill_fraction": DRY_FRACTION},
        modify=lambda spec, p, ctx: spec.with_(wet_psd=wet_psd(ctx, spec.psd, p["fill_fraction"])),
        requires=frozenset({"scan"}),
        prepare=_prepare,
        description="cavities filled with a water film (fraction of the depressions' capacity)",
    )
)
