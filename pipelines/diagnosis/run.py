"""The friction-level diagnosis from inputs to files: compose measured curve, context, search,
band map, validation and the report."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pipelines.diagnosis import gap as gapmod
from pipelines.diagnosis.model import FrictionContext, simulate
from pipelines.diagnosis.report.bandmap import band_map
from pipelines.diagnosis.verdict.search import diagnose_friction, predict

__all__ = ["validate", "run_friction", "diagnose_curve"]


def _provenance(data, d, ctx, inputs):
    """``inputs`` (provenance, :mod:`pipelines.diagnosis.report.provenance`) and
    ``engine_settings.sigma0_Pa`` of the JSON."""
    from pipelines.diagnosis.report.provenance import inputs_json

    data["inputs"] = inputs_json(ctx, d, inputs)
    es = data.setdefault("engine_settings", {})
    es["sigma0_Pa"] = data["inputs"]["sigma0_Pa"]


def validate(ctx, d, other_curve):
    """Predict a separate measurement with the corrected model, no refitting.

    Returns dict(gap_before, gap_after, v, mu, pred) (gap_after = baseline when no verdict).

    Parameters
    ----------
    ctx : FrictionContext
        The diagnosed context: its baseline spec, scan, spectrum and inputs are reused.
    d : Diagnosis
        The diagnosis whose named candidate (``d.best``, with its fitted parameters) predicts.
    other_curve : MeasuredCurve
        The separate measurement.

    Returns
    -------
    dict
        gap_before, gap_after (rms log10 of measured / baseline and / corrected mu), v [m/s], mu,
        pred (the corrected model's mu at the other curve's rows).
    """
    vctx = FrictionContext.from_measured(
        other_curve, ctx.base, scan=ctx.scan, spectrum=ctx.spectrum, fit=ctx.fit, inputs=ctx.inputs
    )
    vctx.cache = ctx.cache
    base = simulate(ctx.base, vctx)
    pred = predict(vctx, d.best.effects, d.best.params) if d.best is not None else base
    return dict(
        gap_before=gapmod.gap(other_curve.mu, base),
        gap_after=gapmod.gap(other_curve.mu, pred),
        v=other_curve.v_m_per_s,
        mu=other_curve.mu,
        pred=pred,
    )


def diagnose_curve(curve, ctx, noise=None, log=None, uncertain=None):
    """The diagnosis of one curve with its where-table and band map (computed first: where mu is
    carried by the cut-off, q1 is uncertain by default). Returns (Diagnosis, where, bm, bm_curves).

    Parameters
    ----------
    curve : MeasuredCurve
        The measured mu(v) with each row's T0 [C] and sigma0 [Pa].
    ctx : FrictionContext
        The rows of ``curve`` with the baseline spec (``build_context``).
    noise : float, optional
        Noise [rms log10] (estimated when None).
    log : callable, optional
        Called with one progress line (str) per step; None: silent.
    uncertain : dict, optional
        Input name -> :class:`fit.calibration.Uncertain` (``--uncertain``); None: nothing given.

    Returns
    -------
    d : Diagnosis
        The diagnosis.
    where : list of dict
        :func:`gap.gap_by_band` of the baseline per decade of speed.
    bm : list of dict
        :func:`report.bandmap.band_map` rows: the wave vectors carrying mu in each band.
    bm_curves : tuple
        (q [1/m], dmu/dln q per band, band-centre speeds [m/s]) for the band-map figure.
    """
    bands = [(a, b) for a, b, _ in gapmod.decade_bands(curve.v_m_per_s)]
    T0 = ctx.T0_C[np.isfinite(ctx.T0_C)]
    from pipelines.diagnosis.fit.calibration import apply_known

    bm, bm_curves = band_map(
        apply_known(ctx, uncertain or {}),
        bands,
        sigma0_Pa=float(np.median(ctx.sigma0_Pa)),
        T0_C=float(np.median(T0)) if T0.size else None,
    )
    carried = any(b["carried_by_cutoff"] for b in bm)
    d = diagnose_friction(ctx, curve.mu, noise=noise, log=log, uncertain=uncertain, carried=carried)
    where = gapmod.gap_by_band(curve.v_m_per_s, curve.mu, d.baseline_mu, d.noise)
    return d, where, bm, bm_curves


def run_friction(
    curve,
    ctx,
    out_dir,
    noise=None,
    other=None,
    log=None,
    report=True,
    extra=None,
    uncertain=None,
    inputs=None,
):
    """Diagnose ``curve`` (MeasuredCurve) on ``ctx``; write DIR/diagnosis.json and report.html.

    ``extra``: a dict of run settings added to the JSON (the command's band, nu, rubber checks).
    ``uncertain``: dict key -> calibration.Uncertain; ``inputs``: provenance
    (:mod:`pipelines.diagnosis.report.provenance`).

    Returns the JSON dict.

    Parameters
    ----------
    curve : MeasuredCurve
        The measured mu(v) with each row's T0 [C] and sigma0 [Pa].
    ctx : FrictionContext
        The rows of ``curve`` with the baseline spec (``build_context``).
    out_dir : str or Path
        Folder written (created if missing): diagnosis.json and, with ``report``, report.html.
    noise : float, optional
        rms log10 noise of the measurement (``--noise``); None: estimated from the curve.
    other : MeasuredCurve, optional
        ``--validate`` measurement.
    log : callable, optional
        Called with one progress line (str) per step; None: silent.
    report : bool, optional
        Whether to write report.html and its figures too (default True).
    extra : dict, optional
        Run settings for the JSON.
    uncertain : dict, optional
        Input name -> :class:`fit.calibration.Uncertain` (``--uncertain``); None: nothing given.
    inputs : dict, optional
        Provenance hints (:func:`run_command.provenance_hints`); None: judged from the data alone.

    Returns
    -------
    dict
        The content written to ``diagnosis.json``.
    """
    from pipelines.diagnosis.report.single import friction_json, write_friction_report
    from pipelines.output import report as rep

    d, where, bm, bm_curves = diagnose_curve(curve, ctx, noise=noise, log=log, uncertain=uncertain)
    val = validate(ctx, d, other) if other is not None else None
    data = friction_json(d, where, bm, val)
    data.update(extra or {})
    _provenance(data, d, ctx, inputs)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rep.write_json(out_dir / "diagnosis.json", data)
    if report:
        write_friction_report(out_dir, curve, d, data, where, bm_curves, val)
    return data
