"""Curves the report draws over the whole speed range (not only at the measured speeds): the
baseline model, the model within the uncertain inputs' ranges (a band), and the corrected model.

The dense grid has ``N_DENSE`` log-spaced speeds from the lowest to the highest measured speed,
at the median measured temperature and pressure (dry rows unless every row is wet). Band: the
envelope of the model with each uncertain input at either end of its range (the others nominal)
and with all of them at their low and at their high ends (mu is monotonic in q1, sigma0 and the
spectrum's level; in temperature it is not, hence the single-input ends too).
"""

from __future__ import annotations

import numpy as np

from pipelines.diagnosis.model import FrictionContext, simulate

__all__ = ["dense_context", "report_curves"]

N_DENSE = 40


def dense_context(ctx, n=N_DENSE):
    """A :class:`FrictionContext` on ``n`` log-spaced speeds over ``ctx``'s measured range.

    Parameters
    ----------
    ctx : FrictionContext
        The measured context: its speed range, baseline spec, inputs and cache are reused.
    n : int, optional
        Number of speeds (default 40).

    Returns
    -------
    FrictionContext
        Rows at the median T0 [C] (NaN: T_ref) and median sigma0 [Pa]; wet only if every row is.
    """
    v = np.geomspace(float(ctx.v_m_per_s.min()), float(ctx.v_m_per_s.max()), n)
    T = ctx.T0_C[np.isfinite(ctx.T0_C)]
    T0 = float(np.median(T)) if T.size else np.nan
    wet = bool(np.all(ctx.wet)) and ctx.n > 0
    return FrictionContext(
        v,
        np.full(n, T0),
        np.full(n, float(np.median(ctx.sigma0_Pa))),
        np.full(n, wet),
        ctx.base,
        ctx.scan,
        ctx.spectrum,
        ctx.fit,
        ctx.inputs,
        ctx.cache,
    )


def _safe(fn):
    try:
        out = np.asarray(fn(), float)
        return out if np.all(np.isfinite(out)) else None
    except (ValueError, ArithmeticError, RuntimeError):
        return None


def report_curves(ctx, d, n=N_DENSE):
    """dict(v, base, corrected (or None), band_lo, band_hi (or None)) on the dense grid of ``ctx``
    for the :class:`search.Diagnosis` ``d``.

    Parameters
    ----------
    ctx : FrictionContext
        The diagnosed context (``d.ctx``); :func:`dense_context` spreads it over ``n`` speeds.
    d : Diagnosis
        The diagnosis: its named candidate gives the corrected curve, its ranges the band.
    n : int, optional
        Number of speeds (default 40).

    Returns
    -------
    dict
        v [m/s] and mu arrays of shape (n,): base, corrected (None without a named candidate or
        on a failed evaluation), band_lo/band_hi (envelope of the baseline over the ends of the
        uncertain ranges; None without them).
    """
    from pipelines.diagnosis.fit.calibration import calibration_effect
    from pipelines.diagnosis.fit.fitting import predict

    dc = dense_context(ctx, n)
    base = _safe(lambda: simulate(ctx.base, dc))
    corrected = None
    if d.best is not None:
        corrected = _safe(lambda: predict(dc, d.best.effects, d.best.params))
    lo = hi = None
    cal = calibration_effect(ctx, d.uncertain) if d.uncertain else None
    if cal is not None and base is not None:
        ends = []
        names = [p.name for p in cal.params]
        nominal = {p.name: p.init for p in cal.params}
        for p in cal.params:
            for x in (p.lo, p.hi):
                ends.append(dict(nominal, **{p.name: x}))
        ends.append({p.name: p.lo for p in cal.params})
        ends.append({p.name: p.hi for p in cal.params})
        curves = [
            c
            for c in (_safe(lambda e=e: simulate(cal.modify(ctx.base, e, dc), dc)) for e in ends)
            if c is not None
        ]
        if curves and names:
            allc = np.vstack(curves + [base])
            lo, hi = allc.min(axis=0), allc.max(axis=0)
    return dict(v=dc.v_m_per_s, base=base, corrected=corrected, band_lo=lo, band_hi=hi)
