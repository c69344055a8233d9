"""``seams`` (surface level): stitching seams, steps or tilt residue: straight discontinuities
along the scan's lattice axes. The blocks' line-score entry (log10 of the largest over the
median line score, :func:`pipelines.diagnosis.surface.blocks.seam_score`) rises by
log10(``line_score_ratio``) over the twin's; 1 is no effect. Needs an area scan."""

import numpy as np

from pipelines.diagnosis.effects import Effect, Param, register


def _apply(ctx, p, pred):
    return dict(pred, seams=pred["seams"] + np.log10(p["line_score_ratio"]))


EFFECT = register(
    Effect(
        name="seams",
        level="surface",
        requires=frozenset({"area"}),
        params=(Param("line_score_ratio", 1.0, 1e6, 10.0, "log"),),
        apply_fn=_apply,
        null=lambda ctx: {"line_score_ratio": 1.0},
        description="straight discontinuities along the lattice axes (seams, steps, stitching residue)",
    )
)
