"""``height_skew`` (surface level): non-Gaussian heights. A synthesis matching both the spectrum
and the height histogram (the Gaussian twin rank-transformed onto a gamma law of moment skewness
``skewness``, :func:`pipelines.diagnosis.surface.twin.skewed`) keeps the ordering of heights, so C(q)
changes little, but moves the blocks' L-skewness and L-kurtosis and the rain-fill response (deep
narrow valleys hold water differently). Both are tabulated on the skewed twins over a grid of
skewness values and interpolated; ``dtau4`` adds to the L-kurtosis (tails heavier or lighter than
the gamma law's). skewness = 0, dtau4 = 0 is the twin (no effect)."""

import numpy as np

from pipelines.diagnosis.effects import Effect, Param, register


def _apply(ctx, p, pred):
    t = ctx.skew_table
    s = p["skewness"]
    h = np.array([np.interp(s, t["s"], t["height"][:, j]) for j in range(t["height"].shape[1])])
    h[1] += p["dtau4"]
    out = dict(pred, height=h)
    if "rain" in pred and t.get("rain") is not None:
        out["rain"] = pred["rain"] + np.array(
            [np.interp(s, t["s"], t["rain"][:, j]) for j in range(t["rain"].shape[1])]
        )
    return out


EFFECT = register(
    Effect(
        name="height_skew",
        level="surface",
        params=(Param("skewness", -3.0, 3.0, 0.0, "lin"), Param("dtau4", -0.15, 0.3, 0.0, "lin")),
        apply_fn=_apply,
        null=lambda ctx: {"skewness": 0.0, "dtau4": 0.0},
        description="height distribution: gamma-law skewness and an L-kurtosis change",
    )
)
