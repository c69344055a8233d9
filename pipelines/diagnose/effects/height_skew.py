"""``height_skew`` (surface level): non-Gaussian heights. A synthesis matching both the spectrum
and the height histogram (e.g. rank-transforming the Gaussian twin onto the measured heights)
leaves C(q) nearly unchanged but moves the skewness and kurtosis to the fitted values."""
from . import Effect, Param, register


def _apply(ctx, p, C, st):
    st = st.copy()
    st[ctx.stat_index("skewness")] = p["skewness"]
    st[ctx.stat_index("excess_kurtosis")] = p["excess_kurtosis"]
    return C, st


EFFECT = register(Effect(
    name="height_skew", level="surface",
    params=(Param("skewness", -10.0, 10.0, 0.0, "lin"), Param("excess_kurtosis", -1.5, 200.0, 0.0, "lin")),
    apply_fn=_apply,
    description="height distribution with free skewness and excess kurtosis",
))
