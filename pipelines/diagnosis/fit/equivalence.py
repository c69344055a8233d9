"""Equivalent explanations are one explanation: an effect that, within the data's precision, does
what an uncertain input does beyond its range is that input's calibration, not a finding.

The test: the calibration alone, with every uncertain input's range continued beyond its ends
by half its width (:func:`extended_ranges`), is fitted on the same rows, started from the effect fit's own
calibrated inputs. When its best fit reproduces the effect's fit to within the noise (its log-likelihood,
Student-t as in :mod:`.evidence`, lower by at most ``EQUIV_NATS``), the two explanations cannot be told apart
from these data: fine roughness beyond q1 and a larger q1, a load and a wrong sigma0, a
temperature offset and a shift of the master curve are the same curve.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

__all__ = ["EQUIV_NATS", "extended_ranges", "equivalence"]

EQUIV_NATS = 2.0
#: the least continuation of a range on each side: a factor (log-scaled inputs) or kelvins
MIN_FACTOR = 1.5
MIN_KELVIN = 5.0


def extended_ranges(ranges, free):
    """The free uncertain ranges continued beyond each end by half their width (in log for q1,
    sigma0 and the spectrum's level; at least a factor ``MIN_FACTOR`` or ``MIN_KELVIN``).

    Parameters
    ----------
    ranges : dict
        key -> calibration.Uncertain.
    free : dict
        key -> (lo, hi), the fitted ranges.

    Returns
    -------
    dict
        key -> Uncertain with the continued range.
    """
    out = {}
    for k, (lo, hi) in free.items():
        if k == "temperature":
            d = max(0.5 * (hi - lo), MIN_KELVIN)
            lo2, hi2 = lo - d, hi + d
        else:
            f = max(float(np.sqrt(hi / lo)), MIN_FACTOR)
            lo2, hi2 = lo / f, hi * f
        if k == "psd_scale":
            hi2 = min(hi2, 1e6)
        out[k] = replace(ranges[k], lo=lo2, hi=hi2)
    return out


def equivalence(ctx, real_mu, cand, ranges, free, noise, rows=None):
    """Whether the calibration with extended ranges reproduces candidate ``cand``'s fit.

    ``ranges``: key -> Uncertain; ``free``: key -> (lo, hi), the fitted ranges; ``rows``: the
    rows compared (default every row). Returns None without uncertain inputs, else dict(
    equivalent, dloglik (effect fit minus extended calibration, nats), inputs (the uncertain
    inputs the extended fit moves beyond their ranges), calibrated (their fitted values)).

    Parameters
    ----------
    ctx : FrictionContext
        The context ``cand`` was fitted on.
    real_mu : ndarray, shape (n,)
        Measured mu at every row.
    cand : Candidate
        The effect's fit (with or without the calibration); its calibrated inputs start the fit.
    ranges : dict
        Input name -> :class:`calibration.Uncertain`.
    free : dict
        Input name -> (lo, hi), the fitted ranges in SI (temperature in C); empty: returns None.
    noise : float
        rms of log10(measured / simulated mu) of the measurement (at least the evidence's floor).
    rows : ndarray of bool, shape (n,), optional
        Rows fitted and compared; None: every row.

    Returns
    -------
    dict or None
        equivalent (bool), dloglik [nats], inputs (names moved beyond their ranges), calibrated
        (input name -> fitted value) and fit (the extended calibration's Candidate).
    """
    from pipelines.diagnosis.fit.calibration import PARAM, calibration_effect
    from pipelines.diagnosis.fit.evidence import loglik, noise_scale
    from pipelines.diagnosis.fit.fitting import fit_candidate

    if not free:
        return None
    ext = extended_ranges(ranges, free)
    cal_x = calibration_effect(ctx, ext)
    if cal_x is None:
        return None
    y = np.log10(np.asarray(real_mu, float))
    rows = np.ones(y.size, bool) if rows is None else rows
    starts = []
    for e, p in zip(cand.effects, cand.params):
        if e.name == "calibration":
            starts.append(
                [{pp.name: float(np.clip(p.get(pp.name, pp.init), pp.lo, pp.hi)) for pp in cal_x.params}]
            )
    fit = fit_candidate(ctx, real_mu, (cal_x,), rows, extra_starts=starts, cache={})
    s = noise_scale(noise)
    n = int(rows.sum())
    r_c = (y - np.log10(cand.pred))[rows]
    r_x = (y - np.log10(fit.pred))[rows]
    dll = loglik(float(r_c @ r_c), n, s) - loglik(float(r_x @ r_x), n, s)
    inv = {v: k for k, v in PARAM.items()}
    outside = []
    for pp in cal_x.params:
        k = inv[pp.name]
        lo, hi = free[k]
        x = fit.params[0][pp.name]
        if pp.scale == "lin":
            beyond = x < lo - 1e-3 * (hi - lo) or x > hi + 1e-3 * (hi - lo)
        else:
            beyond = x < lo * (1 - 1e-3) or x > hi * (1 + 1e-3)
        if beyond:
            outside.append(k)
    return dict(
        equivalent=bool(dll <= EQUIV_NATS),
        dloglik=float(dll),
        inputs=outside,
        calibrated={inv[k]: float(x) for k, x in fit.params[0].items()},
        fit=fit,
    )
