"""Held-out errors of a fitted candidate (20 or more measured speeds).

With ``CV_BELOW`` (20) or more points, every third point (indices 1, 4, 7, ...) is held out and
never used in a fit. With fewer, held-out errors of four or five training points cannot carry a
verdict: the diagnosis compares the explanations by their Bayesian evidence instead
(:mod:`.search_few`, :mod:`.few`); :func:`holdout` then marks the points ``cv`` (few)
and trains on all of them.

Shrink: 1 - gap_heldout / baseline gap_heldout, with a 5-95 % bootstrap interval over the
held-out points (the same resamples for every candidate, so intervals are paired; Efron &
Tibshirani 1993, *An introduction to the bootstrap*, ch. 13). Score: held-out rms times
(1 + k / n_train) OCCAM^k (a penalty for free parameters).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pipelines.diagnosis.fit.fitting import at_bound

__all__ = ["Holdout", "holdout", "heldout_mask", "evaluate", "boot_shrink", "CV_BELOW"]

CV_BELOW = 20
N_BOOT = 1000
OCCAM = 1.08
HELDOUT_EVERY = 3


def heldout_mask(n, every=HELDOUT_EVERY):
    """Deterministic held-out subset: indices 1, 1 + every, ... (the end points stay in training).

    Parameters
    ----------
    n : int
        Number of measured points (in speed order).
    every : int, optional
        Index step between held-out points (default 3: a third held out).

    Returns
    -------
    ndarray of bool, shape (n,)
        True at the held-out indices 1, 1 + every, ... below n - 1.
    """
    m = np.zeros(n, bool)
    m[1 : n - 1 : every] = True
    return m


@dataclass
class Holdout:
    """How the points are held out (see module docstring).

    Attributes
    ----------
    cv : bool
        Few points (fewer than ``CV_BELOW``: compared by evidence, every point trains) or a
        fixed held-out third.
    train, held : ndarray of bool
        Training and held-out points.
    n_train : int
        Number of training points of one fit (n when ``cv``).
    boot : ndarray of int, shape (1000, n_held)
        Bootstrap resamples: indices into the held-out residuals, drawn with seed 0 (the same for
        every candidate, so shrink intervals are paired).
    """

    cv: bool
    train: np.ndarray  # rows of the reported fit
    held: np.ndarray  # rows whose residuals score a candidate
    n_train: int  # training rows of one fit
    boot: np.ndarray  # (N_BOOT, n_held) resample indices into the held-out residuals

    @property
    def description(self):
        if self.cv:
            return f"none: {self.train.size} measured speeds are compared by Bayesian evidence"
        return "every third point (indices 1, 4, 7, ...), never used in a fit"


def holdout(n):
    """The :class:`Holdout` of ``n`` measured points.

    Parameters
    ----------
    n : int
        Number of measured points.

    Returns
    -------
    Holdout
        Below ``CV_BELOW`` (20) points ``cv`` is True and every point both trains and is scored.
    """
    if n < CV_BELOW:
        train = np.ones(n, bool)
        held = np.ones(n, bool)
        n_held, n_train = n, n
    else:
        train = ~heldout_mask(n)
        held = ~train
        n_held, n_train = int(held.sum()), int(train.sum())
    boot = np.random.default_rng(0).integers(0, n_held, size=(N_BOOT, n_held))
    return Holdout(n < CV_BELOW, train, held, n_train, boot)


def boot_shrink(r_num, r_den, boot):
    """5-95 % bootstrap interval of 1 - rms(r_num) / rms(r_den) over paired resamples.

    Parameters
    ----------
    r_num, r_den : ndarray
        Residuals with and without the effect.
    boot : ndarray of int, shape (n_boot, n_held)
        Resample indices into both residual arrays (e.g. :attr:`Holdout.boot`).

    Returns
    -------
    tuple of float
        (5th, 95th percentile) of the shrink; (nan, nan) when no resample has a nonzero baseline.
    """
    num = np.sqrt(np.mean(r_num[boot] ** 2, axis=1))
    den = np.sqrt(np.mean(r_den[boot] ** 2, axis=1))
    sb = 1.0 - num / np.where(den > 0, den, np.nan)
    sb = sb[np.isfinite(sb)]
    if not sb.size:
        return (float("nan"), float("nan"))
    return (float(np.percentile(sb, 5)), float(np.percentile(sb, 95)))


def evaluate(c, ctx, real_mu, ho, r0_held):
    """Fill in the held-out residuals, gap, shrink, interval, score, at_bound and plausibility of
    candidate ``c`` (fitted on ``ho.train``); ``r0_held``: the baseline's held-out residuals.

    Parameters
    ----------
    c : Candidate
        Fitted on ``ho.train``; filled in place.
    ctx : FrictionContext
        The context it was fitted on (bounds, no-effect values and plausibility checks).
    real_mu : ndarray, shape (n,)
        Measured mu at every row.
    ho : Holdout
        The hold-out scheme; a few-points one (``ho.cv``) raises ValueError.
    r0_held : ndarray
        The baseline's log10(measured / simulated mu) at the held-out rows.

    Returns
    -------
    Candidate
        ``c`` itself.
    """
    if ho.cv:
        raise ValueError("fewer than 20 points are compared by evidence (search_few), not held out")
    y = np.log10(real_mu)
    c.at_bound = at_bound(ctx, c.effects, c.params)
    bad = []
    for e, p in zip(c.effects, c.params):
        for name, why in e.implausible(ctx, p, real_mu):
            bad.append((name if len(c.effects) == 1 else f"{e.name}.{name}", why))
    c.implausible = [b[0] for b in bad]
    c.implausible_why = [b[1] for b in bad]
    c.r_held = (y - np.log10(c.pred))[ho.held]
    c.score = c.gap_heldout * (1.0 + c.k / ho.n_train) * OCCAM**c.k
    g_ho = float(np.sqrt(np.mean(r0_held**2)))
    c.shrink = 1.0 - c.gap_heldout / g_ho if g_ho > 0 else float("nan")
    c.shrink_interval = boot_shrink(c.r_held, r0_held, ho.boot)
    return c
