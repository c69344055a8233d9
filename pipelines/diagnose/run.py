"""The friction-level diagnosis from inputs to files: compose measured curve, context, search,
band map, validation and the report."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from . import gap as gapmod
from .bandmap import band_map
from .model import FrictionContext, simulate
from .search import diagnose_friction, predict

__all__ = ["validate", "run_friction"]


def validate(ctx, d, other_curve):
    """Predict a separate measurement with the corrected model, no refitting.

    Returns dict(gap_before, gap_after, v, mu, pred) (gap_after = baseline when no verdict).
    """
    vctx = FrictionContext.from_measured(other_curve, ctx.base, scan=ctx.scan, spectrum=ctx.spectrum,
                                         fit=ctx.fit, inputs=ctx.inputs)
    vctx.cache = ctx.cache
    base = simulate(ctx.base, vctx)
    pred = predict(vctx, d.best.effects, d.best.params) if d.best is not None else base
    return dict(gap_before=gapmod.gap(other_curve.mu, base), gap_after=gapmod.gap(other_curve.mu, pred),
                v=other_curve.v_m_per_s, mu=other_curve.mu, pred=pred)


def run_friction(curve, ctx, out_dir, noise=None, other=None, log=None, report=True, extra=None):
    """Diagnose ``curve`` (MeasuredCurve) on ``ctx``; write DIR/diagnosis.json and report.html.

    ``extra``: a dict of run settings added to the JSON (the command's band, nu, rubber checks).

    Returns the JSON dict.
    """
    from .. import report as rep
    from .report import friction_json, write_friction_report

    d = diagnose_friction(ctx, curve.mu, noise=noise, log=log)
    where = gapmod.gap_by_band(curve.v_m_per_s, curve.mu, d.baseline_mu, d.noise)
    bands = [(w["v_min_m_per_s"], w["v_max_m_per_s"]) for w in where]
    T0 = ctx.T0_C[np.isfinite(ctx.T0_C)]
    bm, bm_curves = band_map(ctx.base, bands, sigma0_Pa=float(np.median(ctx.sigma0_Pa)),
                             T0_C=float(np.median(T0)) if T0.size else None)
    val = validate(ctx, d, other) if other is not None else None
    data = friction_json(d, where, bm, val)
    data.update(extra or {})
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rep.write_json(out_dir / "diagnosis.json", data)
    if report:
        write_friction_report(out_dir, curve, d, data, where, bm_curves, val)
    return data
