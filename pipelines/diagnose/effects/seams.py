"""``seams`` (surface level): stitching seams, steps or tilt residue put excess power on the
lattice axes of the 2D spectrum (qx = 0, qy = 0) and add long-wavelength power (a low-q excess
C x (1 + a (q_lo/q)^2) from a residual plane or step). Needs an area scan."""
import numpy as np

from . import Effect, Param, register


def _apply(ctx, p, C, st):
    st = st.copy()
    st[ctx.stat_index("log10_axis_excess")] = np.log10(p["axis_excess"])
    C = C * (1.0 + p["low_q_excess"] * (ctx.q[0] / ctx.q) ** 2)
    return C, st


EFFECT = register(Effect(
    name="seams", level="surface", requires=frozenset({"area"}),
    params=(Param("axis_excess", 1.0, 100.0, 2.0, "log"), Param("low_q_excess", 1e-3, 100.0, 0.1, "log")),
    apply_fn=_apply,
    description="excess power on the lattice axes and at the lowest wave vectors",
))
