"""Checks of a merged spectrum against itself: inputs that disagree where both measure, and
rows whose 5-95 % band their neighbours contradict (used by
:func:`roadscan.spectrum_merge.merge_spectra`).

Two measurements of one surface agree within their scatter: a ring's periodogram mean over k
degrees of freedom is C chi2_k / k, so ln C scatters by about sqrt(2 / k) (Jacobs, Junge,
Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017), sec. 3). A difference between two
inputs well beyond that, over the rows both measure, says they are not one surface (or one
carries a unit or calibration error); a row far off the line through its neighbours says its
band is too narrow.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["disagreements", "widen_outliers", "DISAGREE_SIGMAS", "DISAGREE_FACTOR", "NEIGHBOUR_REACH", "Z95"]

#: one-sided 95 % point of the standard normal
Z95 = 1.6448536269514722

#: decades either side of a row whose rows predict it (:func:`widen_outliers`)
NEIGHBOUR_REACH = 0.3


def widen_outliers(
    q: NDArray[np.float64],
    lnC: NDArray[np.float64],
    d_lo: NDArray[np.float64],
    d_hi: NDArray[np.float64],
    covered: NDArray[np.bool_],
    seg: NDArray[np.integer[Any]],
) -> list[float]:
    """Widen, in place, the band of each measured row that excludes what its neighbours say
    -> [q of each row widened].

    The neighbours are the measured rows of its segment within :data:`NEIGHBOUR_REACH` decade
    (at least one on each side, or three on one side); the line ln C = a + b ln q through them
    (weights 1 / sigma^2, sigma the row's band half-width over 1.645) predicts the row with a
    standard error se. While some prediction lies beyond its row's band by more than 1.645 se,
    the worst such row (in units of se) has its band widened to reach it, and the others are
    tested again (its widened band then weighs less in theirs): a row is not given with a band
    that its neighbours, and through them the other inputs, contradict.

    Parameters
    ----------
    q : ndarray
        Row wave vectors [1/m].
    lnC : ndarray
        ln C of each row.
    d_lo, d_hi : ndarray
        Lower and upper band of each row in ln C (widened in place).
    covered : ndarray of bool
        Rows some source measures.
    seg : ndarray of int
        Segment of each row (rows are not compared across a bend).

    Returns
    -------
    list of float
        Wave vectors [1/m] of the rows widened.
    """
    x = np.log(q)
    out = []
    for _ in range(int(covered.sum())):
        sig = (d_lo + d_hi) / (2 * Z95)
        worst = None
        for i in np.flatnonzero(covered):
            near = covered & (seg == seg[i]) & (np.abs(x - x[i]) <= NEIGHBOUR_REACH * np.log(10))
            near[i] = False
            below, above = int(np.sum(near & (x < x[i]))), int(np.sum(near & (x > x[i])))
            if not ((below and above) or max(below, above) >= 3) or near.sum() < 2:
                continue
            w = 1.0 / np.maximum(sig[near], 1e-6) ** 2
            xm = np.sum(w * x[near]) / np.sum(w)
            sxx = np.sum(w * (x[near] - xm) ** 2)
            ym = np.sum(w * lnC[near]) / np.sum(w)
            b = np.sum(w * (x[near] - xm) * (lnC[near] - ym)) / sxx if sxx > 0 else 0.0
            pred = ym + b * (x[i] - xm)
            se = np.sqrt(1.0 / np.sum(w) + ((x[i] - xm) ** 2 / sxx if sxx > 0 else 0.0))
            miss = max(lnC[i] - d_lo[i] - pred, pred - lnC[i] - d_hi[i]) / se
            if miss > Z95 and (worst is None or miss > worst[0]):
                worst = (miss, i, pred)
        if worst is None:
            break
        _, i, pred = worst
        if pred < lnC[i]:
            d_lo[i] = lnC[i] - pred
        else:
            d_hi[i] = pred - lnC[i]
        out.append(float(q[i]))
    return sorted(out)


#: two sources disagree when the mean ratio of their C over the rows both measure is beyond
#: this many standard deviations of it and beyond DISAGREE_FACTOR
DISAGREE_SIGMAS = 3.0
DISAGREE_FACTOR = 1.25


def disagreements(
    row: NDArray[np.integer[Any]],
    source: NDArray[np.integer[Any]],
    count: NDArray[np.float64],
    dof: NDArray[np.float64],
    C: NDArray[np.float64],
    edge: NDArray[np.bool_],
    q_row: NDArray[np.float64],
    labels: Sequence[str],
) -> list[dict[str, Any]]:
    """Pairs of sources whose C disagree where both measure: [{labels, factor, q_from_per_m,
    q_to_per_m, rows, sigma_ln}].

    In each row both sources measure, each source's C is the count-weighted mean of its rings
    (moved to the row's q) and ln C scatters by sqrt(2 / k), k its degrees of freedom there. The
    difference d = ln C_a - ln C_b is averaged over the rows with weights 1 / (2 / k_a + 2 / k_b)
    into D; its variance is the larger of the weights' and the rows' own scatter of d, plus
    the bias each band tolerates at its ends (``edge``: ln(1 + b)^2, taken as 1.645 standard
    deviations; it does not average out). ``factor`` is exp|D| >= 1, the C of the first label
    over that of the second (the higher first), reported when
    |D| > :data:`DISAGREE_SIGMAS` standard deviations and exp|D| > :data:`DISAGREE_FACTOR`: two
    measurements of one surface agree within their scatter (Jacobs, Junge, Pastewka 2017,
    sec. 3: a ring's periodogram mean is chi-square distributed).

    Parameters
    ----------
    row : ndarray of int
    source : ndarray of int
    count, dof : ndarray
    C : ndarray
    edge : ndarray of bool
    q_row : ndarray
    labels : list of str

    Returns
    -------
    list of dict
    """
    S = len(labels)
    nb = int(row.max()) + 1
    key = row * S + source

    def per(v):
        return np.bincount(key, v, nb * S).reshape(nb, S)

    N = per(count)
    have = N > 0
    Ns = np.where(have, N, 1.0)
    lnC = np.log(np.maximum(per(count * C) / Ns, 1e-300))
    k = np.maximum(per(dof), 1e-9)
    e = per(count * edge) / Ns
    out = []
    for a in range(S):
        for b in range(a + 1, S):
            both = have[:, a] & have[:, b]
            m = int(both.sum())
            if not m:
                continue
            d = lnC[both, a] - lnC[both, b]
            w = 1.0 / (2.0 / k[both, a] + 2.0 / k[both, b])
            D = float(np.sum(w * d) / np.sum(w))
            var = 1.0 / np.sum(w)
            if m > 1:
                var = max(var, float(np.sum(w * (d - D) ** 2) / np.sum(w) / (m - 1)))
            var += float(np.mean(e[both, a] + e[both, b])) / Z95**2
            sd = float(np.sqrt(var))
            if abs(D) > DISAGREE_SIGMAS * sd and abs(D) > np.log(DISAGREE_FACTOR):
                qs = q_row[:nb][both]
                hi_, lo_ = (a, b) if D > 0 else (b, a)  # the higher C first: factor > 1
                out.append(
                    {
                        "labels": [labels[hi_], labels[lo_]],
                        "factor": float(np.exp(abs(D))),
                        "q_from_per_m": float(qs.min()),
                        "q_to_per_m": float(qs.max()),
                        "rows": m,
                        "sigma_ln": sd,
                    }
                )
    return out
