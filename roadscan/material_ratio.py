"""The material-ratio (Abbott-Firestone) curve and its functional figures.

Areal: the ISO 25178-2 Sk family (``Sk_m``, ``Spk_m``, ``Svk_m``, ``Smr1_pct``, ``Smr2_pct``)
and volumes (``Vmp_m3_per_m2``, ``Vmc_m3_per_m2``, ``Vvc_m3_per_m2``, ``Vvv_m3_per_m2``).
Profile: the ISO 21920-2 counterparts (``Rk_m``, ``Rpk_m``, ``Rvk_m``, ``Rmr1_pct``,
``Rmr2_pct``) and ``Rmr_pct`` (material ratio at the mean line).

The curve is built from a fine histogram of the heights (:data:`N_BINS` bins between the lowest
and the highest height, heights uniform inside a bin): one pass over the map, no sort. Its
height resolution is Sz / N_BINS (about Sq / 1000 on a Gaussian surface), far below the
tolerance of the figures it feeds.

Heights in metres; material ratios in percent; volumes per unit area in m^3/m^2 (= m).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "MaterialRatioCurve",
    "material_ratio_curve",
    "equivalent_line",
    "functional_parameters",
    "volume_parameters",
    "areal_material_parameters",
    "profile_material_parameters",
    "N_BINS",
]

#: histogram bins of the material-ratio curve
N_BINS = 1 << 14
#: material-ratio grid step of the inverse curve [%]
MR_STEP_PCT = 0.01
#: heights binned at a time (cache-sized buffers)
_BLOCK = 1 << 16


class MaterialRatioCurve:
    """The areal material ratio Smr(c) and its inverse c(mr) of measured heights ``z`` [m].

    Smr(c) = 100 x (share of the heights above c) [%] (ISO 25178-2:2012, 3.1.7); the inverse
    c(mr) [m] is tabulated on ``mr_pct`` = 0, 0.01, ..., 100 %.

    Parameters
    ----------
    z : array_like
        Heights [m].
    n_bins : int, optional
        Histogram bins of the curve.
    """

    def __init__(self, z, n_bins=N_BINS):
        z = np.asarray(z, dtype=np.float64).ravel()
        lo, hi = _min_max(z)
        n = int(z.size)
        finite_only = not (np.isfinite(lo) and np.isfinite(hi))  # NaN or inf: left out,
        if finite_only:  # block by block (no copy)
            lo, hi, n = _min_max_finite(z)
        if n < 2:
            raise ValueError("a material-ratio curve needs at least two measured heights")
        self.z_min_m, self.z_max_m, self.n = lo, hi, n
        span = hi - lo
        if span <= 0:
            self.edges_m = np.array([lo, lo + 1e-30])
            self.above = np.array([100.0, 0.0])
        else:
            counts = _bin_counts(z, lo, span, n_bins, finite_only)
            self.edges_m = lo + span * np.arange(n_bins + 1) / n_bins
            # share above each edge, from the top: 0 % at the highest height, 100 % at the lowest
            self.above = 100.0 * np.r_[n, n - np.cumsum(counts)] / n
        self.mr_pct = np.linspace(0.0, 100.0, int(round(100 / MR_STEP_PCT)) + 1)
        # c(mr): the edges run upwards while 'above' runs downwards
        self.c_m = np.interp(self.mr_pct, self.above[::-1], self.edges_m[::-1])

    def ratio_at(self, c_m):
        """Smr(c) [%]: share of the heights above the height ``c_m`` [m]."""
        return np.interp(c_m, self.edges_m, self.above)

    def height_at(self, mr_pct):
        """c(mr) [m]: the height above which ``mr_pct`` % of the heights lie."""
        return np.interp(mr_pct, self.mr_pct, self.c_m)


def _min_max(z):
    """(min, max) of the 1D array ``z`` (NaN if it holds a NaN; NaN, NaN if empty), block by
    block: each block is read from memory once for both."""
    if z.size <= _BLOCK:
        return (float(z.min()), float(z.max())) if z.size else (np.nan, np.nan)
    lo, hi = np.inf, -np.inf
    for b in range(0, z.size, _BLOCK):
        blk = z[b : b + _BLOCK]
        lo, hi = np.minimum(lo, blk.min()), np.maximum(hi, blk.max())  # NaN propagates
    return float(lo), float(hi)


def _min_max_finite(z):
    """(min, max, count) of the finite values of the 1D array ``z``, block by block (no
    full-size copy); (nan, nan, 0) when none is finite."""
    lo, hi, n = np.inf, -np.inf, 0
    for b in range(0, z.size, _BLOCK):
        blk = z[b : b + _BLOCK]
        blk = blk[np.isfinite(blk)]
        if blk.size:
            lo, hi, n = min(lo, float(blk.min())), max(hi, float(blk.max())), n + blk.size
    return (lo, hi, n) if n else (np.nan, np.nan, 0)


def _bin_counts(z, lo, span, n_bins, finite_only=False):
    """Heights of the 1D array ``z`` per bin k = floor((z - lo) n_bins / span), the top
    height (k = n_bins) in the last bin (``finite_only``: its non-finite values left out);
    block by block through cache-sized buffers (the same arithmetic as on the whole array,
    without its three full-size temporaries)."""
    scale = n_bins / span
    counts = np.zeros(n_bins + 1, np.intp)
    t = np.empty(min(_BLOCK, z.size))
    k = np.empty(t.size, np.intp)
    for b in range(0, z.size, _BLOCK):
        blk = z[b : b + _BLOCK]
        if finite_only:
            blk = blk[np.isfinite(blk)]
        tb, kb = t[: blk.size], k[: blk.size]
        np.subtract(blk, lo, out=tb)
        tb *= scale
        kb[...] = tb  # truncation = floor (tb >= 0)
        counts += np.bincount(kb, minlength=n_bins + 1)
    counts[n_bins - 1] += counts[n_bins]  # tb <= n_bins (1 + eps) < n_bins + 1
    return counts[:n_bins]


def material_ratio_curve(z, n_bins=N_BINS):
    """:class:`MaterialRatioCurve` of the finite heights in ``z`` [m].

    Parameters
    ----------
    z : array_like
        Heights [m]; non-finite values are ignored.
    n_bins : int, optional
        Histogram bins.

    Returns
    -------
    MaterialRatioCurve

    References
    ----------
    ISO 25178-2:2012, 3.1.7.
    """
    return MaterialRatioCurve(z, n_bins)


def _integral(mr, c, lo, hi):
    """Trapezoid integral of c(mr) d(mr) over [lo, hi] % [m %]."""
    if hi <= lo:
        return 0.0
    inside = (mr > lo) & (mr < hi)
    x = np.r_[lo, mr[inside], hi]
    y = np.r_[np.interp(lo, mr, c), c[inside], np.interp(hi, mr, c)]
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


def equivalent_line(curve, window_pct=40.0):
    """The equivalent straight line of the material-ratio curve (ISO 13565-2:1996;
    ISO 25178-2:2012, Annex B).

    The central region is located by the secant of ``window_pct`` = 40 % material-ratio width
    with the smallest gradient: slope(a) = (c(a) - c(a + 40)) / 40, a in [0, 60] %, a* its
    argmin. The secant only places the region: the line is the least-squares fit, in the
    height direction, of the curve's points c(mr_j) with a* <= mr_j <= a* + 40 (the tabulated
    curve, points evenly spaced in mr as the sorted heights are): c_eq(mr) = c0 + s (mr - m0),
    s = sum (mr_j - m0) (c_j - c0) / sum (mr_j - m0)^2, m0 and c0 the means of the points.

    Parameters
    ----------
    curve : MaterialRatioCurve
        The material-ratio curve.
    window_pct : float
        Width of the central region [%] (40 in the standards).

    Returns
    -------
    top_m, bottom_m : float
        c_eq(0) and c_eq(100) [m]: the line's heights at 0 % and 100 % material ratio.
    start_pct : float
        a*, where the central region starts [%].
    """
    mr, c = curve.mr_pct, curve.c_m
    k = int(round(window_pct / MR_STEP_PCT))
    slope = (c[:-k] - c[k:]) / window_pct  # >= 0: c falls with mr
    i = int(np.argmin(slope))
    m, h = mr[i : i + k + 1], c[i : i + k + 1]
    m0, c0 = float(m.mean()), float(h.mean())
    dm = m - m0
    s = float(np.dot(dm, h - c0) / np.dot(dm, dm))  # <= 0 [m per %]
    return c0 - s * m0, c0 + s * (100.0 - m0), float(mr[i])


def functional_parameters(curve, window_pct=40.0):
    """The Sk family of ISO 25178-2:2012 (4.5 and Annex B; construction of ISO 13565-2:1996).

    With the equivalent straight line c_eq of :func:`equivalent_line` (least-squares line of
    the central 40 % of the curve, the region placed by the flattest 40 % secant):

    - Sk = c_eq(0) - c_eq(100) [m], the core height;
    - Smr1 = Smr(c_eq(0)), Smr2 = Smr(c_eq(100)) [%]: where the curve crosses the heights of
      the line's ends (0 % when c_eq(0) is above the highest height, 100 % when c_eq(100) is
      below the lowest);
    - Spk = 2 A1 / Smr1 with A1 = integral_0^Smr1 (c(mr) - c_eq(0)) dmr (peak area; Spk is the
      height of the triangle of that area over [0, Smr1]) [m];
    - Svk = 2 A2 / (100 - Smr2) with A2 = integral_Smr2^100 (c_eq(100) - c(mr)) dmr [m].

    Parameters
    ----------
    curve : MaterialRatioCurve
        The material-ratio curve.
    window_pct : float
        Width of the central region [%] (40 in the standards).

    Returns
    -------
    dict
        Keys ``Sk_m``, ``Spk_m``, ``Svk_m``, ``Smr1_pct``, ``Smr2_pct``.
    """
    mr, c = curve.mr_pct, curve.c_m
    if curve.z_max_m <= curve.z_min_m:  # flat: no core, no peaks, no dales
        return {"Sk_m": 0.0, "Spk_m": 0.0, "Svk_m": 0.0, "Smr1_pct": 0.0, "Smr2_pct": 100.0}
    top, bottom, _ = equivalent_line(curve, window_pct)
    smr1 = float(np.clip(curve.ratio_at(top), 0.0, 100.0))
    smr2 = float(np.clip(curve.ratio_at(bottom), 0.0, 100.0))
    a1 = _integral(mr, c - top, 0.0, smr1)
    a2 = -_integral(mr, c - bottom, smr2, 100.0)
    spk = 2.0 * a1 / smr1 if smr1 > 0 else 0.0
    svk = 2.0 * a2 / (100.0 - smr2) if smr2 < 100 else 0.0
    return {
        "Sk_m": top - bottom,
        "Spk_m": max(spk, 0.0),
        "Svk_m": max(svk, 0.0),
        "Smr1_pct": smr1,
        "Smr2_pct": smr2,
    }


def volume_parameters(curve, p_pct=10.0, q_pct=80.0):
    """Volume parameters of ISO 25178-2:2012 (section 4.4), per unit area [m^3/m^2].

    Vm(mr) = (1/100) integral_0^mr (c(m) - c(mr)) dm (material above the level c(mr)),
    Vv(mr) = (1/100) integral_mr^100 (c(mr) - c(m)) dm (void below it); with p = 10 %,
    q = 80 %: Vmp = Vm(p), Vmc = Vm(q) - Vm(p), Vvc = Vv(p) - Vv(q), Vvv = Vv(q).

    Returns
    -------
    dict
        Keys ``Vmp_m3_per_m2``, ``Vmc_m3_per_m2``, ``Vvc_m3_per_m2``, ``Vvv_m3_per_m2``.

    Parameters
    ----------
    curve : MaterialRatioCurve
        The material ratio curve.
    p_pct, q_pct : float, optional
        Material ratios p and q [%].
    """
    mr, c = curve.mr_pct, curve.c_m
    if curve.z_max_m <= curve.z_min_m:
        return dict.fromkeys(("Vmp_m3_per_m2", "Vmc_m3_per_m2", "Vvc_m3_per_m2", "Vvv_m3_per_m2"), 0.0)

    def vm(x):
        return _integral(mr, c - curve.height_at(x), 0.0, x) / 100.0

    def vv(x):
        return -_integral(mr, c - curve.height_at(x), x, 100.0) / 100.0

    vmp, vmq, vvp, vvq = vm(p_pct), vm(q_pct), vv(p_pct), vv(q_pct)
    return {
        "Vmp_m3_per_m2": vmp,
        "Vmc_m3_per_m2": vmq - vmp,
        "Vvc_m3_per_m2": vvp - vvq,
        "Vvv_m3_per_m2": vvq,
    }


def areal_material_parameters(z):
    """Sk family and volumes (:func:`functional_parameters`, :func:`volume_parameters`) of the
    measured heights ``z`` [m] of a levelled (S-L or S-F) surface; NaN points are ignored.

    Parameters
    ----------
    z : array_like
        Levelled heights [m].

    Returns
    -------
    dict
        Sk, Spk, Svk, Smr1, Smr2 and the volume parameters.

    References
    ----------
    ISO 25178-2:2012, 4.4 and 4.5; ISO 13565-2.
    """
    curve = MaterialRatioCurve(z)
    return {**functional_parameters(curve), **volume_parameters(curve)}


def profile_material_parameters(z):
    """ISO 21920-2:2021 material-ratio figures of a levelled profile's heights ``z`` [m].

    The Rk family (Rk, Rpk, Rvk, Rmr1, Rmr2) is the construction of :func:`functional_parameters`
    on the profile's material-ratio curve Rmr(c) (ISO 21920-2 section 4.5.3, ISO 13565-2);
    ``Rmr_pct`` = Rmr(0), the material ratio at the mean line [%].

    Returns
    -------
    dict
        Keys ``Rk_m``, ``Rpk_m``, ``Rvk_m``, ``Rmr1_pct``, ``Rmr2_pct``, ``Rmr_pct``.

    Parameters
    ----------
    z : array_like
        Levelled profile heights [m].
    """
    curve = MaterialRatioCurve(z)
    f = functional_parameters(curve)
    return {
        "Rk_m": f["Sk_m"],
        "Rpk_m": f["Spk_m"],
        "Rvk_m": f["Svk_m"],
        "Rmr1_pct": f["Smr1_pct"],
        "Rmr2_pct": f["Smr2_pct"],
        "Rmr_pct": float(curve.ratio_at(0.0)),
    }
