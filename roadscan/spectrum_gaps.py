"""Gaps of a merged spectrum: grid bins inside the union of the inputs' reliable bands that no
input measures, found, bridged and given the bands' own ends
(:func:`roadscan.spectrum_merge.merge_spectra`).

A gap is bridged in ln C against ln q from the covered rows within 0.5 decade on either side
(inverse-variance weights from each row's 5-95 % band): by one power law, or, when the lower
side is flatter than the upper by over :data:`BRIDGE_BEND` in slope (a roll-off inside the gap
that no input found), by the lower of the two sides' power laws (Persson's plateau then power
law, each side extrapolated until they meet). Rows of the gap's own segment (between bends)
are preferred: the plateau under a roll-off says nothing of the slope above it.

Reference: Sanner et al., Surf. Topogr.: Metrol. Prop. 10, 035014 (2022), doi:10.1088/2051-672X/
ac860a (merging the spectra of several instruments); Persson, Tribol. Lett. 63, 42 (2016).
"""

from __future__ import annotations

import numpy as np

from .spectrum_agreement import Z95

__all__ = ["bridge", "find_gaps", "gap_edges", "BRIDGE_BEND"]

#: a gap whose lower side is flatter than its upper side by more than this (log-log slope) is
#: bridged by the lower of the two sides' power laws (a roll-off), not by one line
BRIDGE_BEND = 1.0


def _line(X, y, w):
    """Weighted least-squares line y = c0 + c1 X -> (c0, c1, weighted rms residual) or None
    (fewer than 2 points, or all at one X)."""
    if X.size < 2 or np.ptp(X) <= 0:
        return None
    A = np.column_stack([np.ones(X.size), X])
    sw = np.sqrt(w)
    coef, *_ = np.linalg.lstsq(A * sw[:, None], y * sw, rcond=None)
    return coef[0], coef[1], float(np.sqrt(np.sum(w * (y - A @ coef) ** 2) / np.sum(w)))


def bridge(gap, q, lnC, d_lo, d_hi, covered, seg=None, reach=0.5):
    """Fill the rows of one gap in place from the covered rows within ``reach`` decades on
    either side (inverse-variance weights from each row's band, so that a band end's tolerated
    bias weighs less; only rows of the gap's own segment when two or more are there: the
    plateau under a roll-off says nothing of the slope above it).

    A power law is fitted on each side. When the lower side is flatter by over
    :data:`BRIDGE_BEND` in slope (a roll-off in or beside the gap, found by no input), the
    bridge is the lower of the two power laws (Persson's plateau-then-power-law, each side
    extrapolated until they meet); else one power law is fitted to both sides. The band there
    is the widest of the edges' with the fit's rms residual added.
    """
    x = np.log10(q)
    lo, hi = np.log10(gap["q_from_per_m"]), np.log10(gap["q_to_per_m"])
    inside = (x > lo + 1e-12) & (x < hi - 1e-12)
    near = covered & (((x <= lo + 1e-12) & (x >= lo - reach)) | ((x >= hi - 1e-12) & (x <= hi + reach)))
    if seg is not None and inside.any():
        own = near & (seg == seg[np.argmax(inside)])
        if own.sum() >= 2:
            near = own
    sigma = (d_lo + d_hi) / (2 * Z95)
    w = 1.0 / np.maximum(sigma, 1e-6) ** 2
    X = np.log(q)
    below, above = near & (x <= lo + 1e-12), near & (x >= hi - 1e-12)
    f_lo, f_hi = _line(X[below], lnC[below], w[below]), _line(X[above], lnC[above], w[above])
    if f_lo is not None and f_hi is not None and f_lo[1] - f_hi[1] > BRIDGE_BEND:
        lnC[inside] = np.minimum(f_lo[0] + f_lo[1] * X[inside], f_hi[0] + f_hi[1] * X[inside])
        resid = max(f_lo[2], f_hi[2])
        how = (
            f"the lower of the power laws fitted on either side within {reach:g} decade "
            f"(C ~ q^{f_lo[1]:.2f} below, q^{f_hi[1]:.2f} above: a bend)"
        )
    else:
        c0, c1, resid = _line(X[near], lnC[near], w[near])
        lnC[inside] = c0 + c1 * X[inside]
        how = f"a power law C ~ q^{c1:.2f} fitted to the rows within {reach:g} decade on either side"
    d_lo[inside] = np.hypot(np.max(d_lo[near]), Z95 * resid)
    d_hi[inside] = np.hypot(np.max(d_hi[near]), Z95 * resid)
    gap["bridged_by"] = how


def find_gaps(covered, q):
    """Runs of uncovered bins -> [{q_from_per_m, q_to_per_m, factor, rows}] (the reliable
    rows on either side)."""
    out = []
    i = 0
    while i < covered.size:
        if covered[i]:
            i += 1
            continue
        j = i
        while not covered[j]:
            j += 1
        a, b = float(q[i - 1]), float(q[j])
        out.append(
            {
                "q_from_per_m": a,
                "q_to_per_m": b,
                "factor": b / a,
                "rows": int(j - i),
                "_bridged": (float(q[i]), float(q[j - 1])),
            }
        )
        i = j
    return out


def gap_edges(gaps, lows, highs):
    """Each gap's ends moved from the rows beside it to the reliable bands' own ends: from the
    highest band top below its bridged bins to the lowest band start above them (rows pool
    several rings, so their q lies inside the bands)."""
    for g in gaps:
        first, last = g.pop("_bridged")  # bridged bins lie outside every band
        below = [h for h in highs if h < first]
        above = [lo for lo in lows if lo > last]
        if below and above:
            g["q_from_per_m"], g["q_to_per_m"] = max(below), min(above)
            g["factor"] = g["q_to_per_m"] / g["q_from_per_m"]
