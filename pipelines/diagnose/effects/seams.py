"""``seams`` (surface level): stitching seams, steps or tilt residue along the scan's lattice
axes put power exactly on the axes of the 2D spectrum (qx = 0, qy = 0); the lattice-axis
excess (log10 of axis over beside-axis power, see :mod:`pipelines.diagnose.blocks`) rises by
log10(``axis_excess``) over the twin's; 1 is no effect. Needs an area scan."""
import numpy as np

from . import Effect, Param, register


def _apply(ctx, p, pred):
    return dict(pred, seams=pred["seams"] + np.log10(p["axis_excess"]))


EFFECT = register(Effect(
    name="seams", level="surface", requires=frozenset({"area"}),
    params=(Param("axis_excess", 1.0, 1000.0, 2.0, "log"),),
    apply_fn=_apply, null=lambda ctx: {"axis_excess": 1.0},
    description="excess power on the lattice axes (seams, steps, stitching residue)",
))
