"""Roll-off detection: where a self-affine spectrum bends into a flatter low-q part.

Below the roll-off wave vector q_r the spectrum of a road surface stops rising with the
wavelength (the aggregate size: a plateau in Persson's model). With the self-affine line
y(x) = a + s x fitted over the band (x = log10 q, y = log10 C), the low end is modelled as a
broken line

    y(x) = a + s x                          x >= x_r
    y(x) = a + s x_r + s_low (x - x_r)      x <  x_r,   s / 2 < s_low <= 0.5,

whose free parameters are the knee x_r (searched over the rings) and the low slope s_low
(weighted least squares through the knee). Each ring's weight is its number of lattice points
n: the variance of log10 of a mean of n/2 independent exponential periodogram values is about
0.19 / (n / 2) (Gaussian surface). A roll-off is declared when the broken line explains the
low rings far better than the straight one (weighted residual sum of squares at most half, and
a chi-square drop above :data:`MIN_CHI2_DROP`), the rings below the knee lie on (weighted)
average at least ``min_deficit`` decades under the extended line, and the knee is at least
:data:`MIN_KNEE_FOV` x 2 pi / L: below that, the Tukey window's leakage and the levelling bend
every steep spectrum alike (checked on non-periodic crops of synthetic surfaces without
roll-off: none found; see ``tests/test_reliable_band.py``).

This replaces the older median test in :func:`roadscan.fit.fit_self_affine`, which missed
the coarse sample's 14 mm roll-off (3.7 x 2 pi / L: most rings under the fitted band were
already on the line, so their median deficit was small).

Reference: Persson, Tribol. Lett. 63, 42 (2016) (roll-off of road spectra); Jacobs, Junge,
Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017), sec. 4.
"""

from __future__ import annotations

import numpy as np

__all__ = ["detect_roll_off", "MIN_KNEE_FOV", "MIN_CHI2_DROP"]

#: a knee below this many 2 pi / L is not a roll-off the scan can show
MIN_KNEE_FOV = 2.5
#: least drop of the weighted chi-square (two parameters searched, rings correlated by the window)
MIN_CHI2_DROP = 25.0
#: variance of log10 of one exponential variable: (pi^2 / 6) / ln(10)^2
_VAR_LOG10_EXP = np.pi**2 / 6 / np.log(10) ** 2


def detect_roll_off(q_per_m, C_m4, count, slope, intercept, q_fov_per_m, q_hi_per_m, min_deficit=0.3):
    """The roll-off wave vector [1/m] of a spectrum, or None.

    Parameters
    ----------
    q_per_m, C_m4 : arrays
        The spectrum (rings, increasing q); rings with C <= 0 are ignored.
    count : array or None
        Lattice points per ring (None: every ring weighs alike, chi-square test skipped).
    slope, intercept : float
        The self-affine line log10 C = intercept + slope log10 q fitted over the band.
    q_fov_per_m : float
        2 pi / L of the scan (L its field of view) [1/m].
    q_hi_per_m : float
        Highest wave vector to compare the models on (the top of the fitted band) [1/m].
    min_deficit : float
        Least mean depth [decades] of the rings below the knee under the extended line.

    Returns
    -------
    float or None
        q_r, where the broken line's two parts meet.
    """
    q = np.asarray(q_per_m, float)
    C = np.asarray(C_m4, float)
    n = np.ones_like(q) if count is None else np.asarray(count, float)
    ok = (C > 0) & np.isfinite(C) & (q > 0) & (q <= q_hi_per_m * (1 + 1e-9)) & (n > 0)
    q, C, n = q[ok], C[ok], n[ok]
    if q.size < 5 or not slope < 0:
        return None
    x, y = np.log10(q), np.log10(C)
    d = y - (intercept + slope * x)  # > 0 above the line, < 0 below
    var = _VAR_LOG10_EXP / np.maximum(n / 2.0, 1.0)
    w = 1.0 / var
    chi0 = np.sum(w * d * d)
    best = None
    for j in np.flatnonzero(q >= MIN_KNEE_FOV * q_fov_per_m):
        below = np.arange(j)
        if below.size < 2:
            continue
        dx = x[below] - x[j]  # < 0
        wb = w[below]
        b = np.sum(wb * d[below] * dx) / np.sum(wb * dx * dx)  # s_low - slope
        b = float(np.clip(b, -slope / 2.0, 0.5 - slope))  # s_low in (s/2, 0.5]
        r_below = d[below] - b * dx
        chi = np.sum(wb * r_below**2) + np.sum(w[j:] * d[j:] ** 2)
        deficit = -np.sum(wb * b * dx) / np.sum(wb)  # mean depth of the model under the line
        if best is None or chi < best[0]:
            best = (chi, j, b, deficit)
    if best is None:
        return None
    chi, j, b, deficit = best
    if not b > -slope / 2.0 * (1 + 1e-6):  # clipped: not flatter than s / 2
        return None
    if deficit < min_deficit or chi > 0.5 * chi0:
        return None
    if count is not None and chi0 - chi < MIN_CHI2_DROP:
        return None
    # the knee between rings: where the low part's own line (slope s_low, level fitted to the
    # rings below the knee) meets the self-affine line, kept between the knee ring and the one below
    s_low = slope + b
    below = slice(0, j)
    c_low = np.sum(w[below] * (y[below] - s_low * x[below])) / np.sum(w[below])
    x_knee = (c_low - intercept) / (slope - s_low)
    x_knee = float(np.clip(x_knee, x[j - 1], x[j]))
    return float(10**x_knee)
