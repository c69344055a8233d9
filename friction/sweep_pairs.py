"""The shift between two DMA frequency sweeps, the building block of time-temperature
superposition (:mod:`friction.mastercurve`).

Sweeps are grouped by temperature (:func:`group_sweeps`); a pair's relative shift
(:func:`pair_shift`) is estimated at three modulus levels spanning the two sweeps' common
range, from E' fitted by a power law with an offset (:func:`fit_power_offset`) and from E'' by
straight lines in log-log, weighted by ``slope^2 / residual^2``, then refined by overlaying
quadratic fits where the sweeps overlap by a decade or more (J.D. Ferry, *Viscoelastic
Properties of Polymers*, 3rd ed., Wiley 1980, ch. 11).

Units: f in Hz, moduli in Pa, temperatures in C, shifts as decimal logarithms.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["group_sweeps", "fit_power_offset", "pair_shift"]


def group_sweeps(
    T_C: ArrayLike, set_id: ArrayLike | None = None, gap_C: float = 2.0
) -> tuple[NDArray[np.float64], list[NDArray[np.intp]]]:
    """Indices of the rows of each isothermal sweep, ordered by temperature.

    With ``set_id`` the rows are grouped by it; otherwise rows whose temperatures, sorted, lie
    within ``gap_C`` of their neighbour form one sweep. Returns (T_mean (n,), list of index arrays).

    Parameters
    ----------
    T_C : array_like
        Temperature of every row [C].
    set_id : array_like, optional
        Sweep label of every row.
    gap_C : float, optional
        Largest temperature step inside one sweep [C].

    Returns
    -------
    T_mean : ndarray, shape (n,)
        Mean temperature of each sweep [C], ascending.
    groups : list of ndarray
        Row indices of each sweep.
    """
    T = np.asarray(T_C, dtype=float)
    if set_id is not None:
        sid = np.asarray(set_id)
        keys = np.unique(sid)
        groups = [np.flatnonzero(sid == k) for k in keys]
    else:
        o = np.argsort(T, kind="stable")
        cut = np.flatnonzero(np.diff(T[o]) > gap_C) + 1
        groups = [np.sort(g) for g in np.split(o, cut)]
    Tm = np.array([T[g].mean() for g in groups])
    order = np.argsort(Tm)
    return Tm[order], [groups[i] for i in order]


def fit_power_offset(
    f: ArrayLike, y: ArrayLike, b_max: float = 2.0, nb: int = 801
) -> tuple[float, float, float, float]:
    """Least-squares fit ``y = a f^b + e`` (a power law with an offset, in linear modulus).

    For each exponent b on a grid in [-b_max, b_max] the model is linear in (a, e) and solved in
    closed form; the best grid b is refined with a bounded scalar minimisation. Returns
    (a, b, e, rms residual).

    Parameters
    ----------
    f : array_like
        Frequencies [Hz], positive.
    y : array_like
        Values to fit (a modulus [Pa]).
    b_max : float, optional
        Largest |exponent| searched.
    nb : int, optional
        Exponents on the first grid.

    Returns
    -------
    a : float
        Amplitude at the geometric-mean frequency.
    b : float
        Exponent.
    e : float
        Offset.
    rms : float
        Rms residual, in the units of ``y``.
    """
    from scipy.optimize import minimize_scalar

    f, y = np.asarray(f, float), np.asarray(y, float)
    lf = np.log(f / np.exp(np.mean(np.log(f))))  # centred: a is the value at the mean f

    def solve(b):
        b = np.atleast_1d(b)
        X = np.exp(b[:, None] * lf[None, :])  # (nb, n)
        n = f.size
        sx, sy, sxx, sxy = X.sum(1), y.sum(), (X * X).sum(1), X @ y
        den = n * sxx - sx * sx
        den = np.where(np.abs(den) > 1e-300, den, np.nan)
        a = (n * sxy - sx * sy) / den
        e = (sy - a * sx) / n
        r = y[None, :] - a[:, None] * X - e[:, None]
        return a, e, np.sqrt(np.mean(r * r, axis=1))

    bs = np.linspace(-b_max, b_max, nb)
    bs = bs[np.abs(bs) > 1e-9]
    _, _, rms = solve(bs)
    i = int(np.nanargmin(rms))
    db = bs[1] - bs[0]
    opt = minimize_scalar(
        lambda b: float(solve(b)[2][0]),
        bounds=(bs[i] - db, bs[i] + db),
        method="bounded",
        options={"xatol": 1e-6},
    )
    b = float(opt.x) if opt.fun <= rms[i] else float(bs[i])
    a, e, r = solve(b)
    scale = np.exp(-b * np.mean(np.log(f)))  # back to y = a' f^b + e
    return float(a[0] * scale), b, float(e[0]), float(r[0])


def _inverse(y, a, b, e):
    """f at which ``a f^b + e = y`` (NaN where there is none)."""
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return ((np.asarray(y, float) - e) / a) ** (1.0 / b)


def _loglog_line(x, y):
    """Straight line y = c + m x in (log f, log E) -> (m, c, rms residual [decades])."""
    m, c = np.polyfit(x, y, 1)
    r = y - (c + m * x)
    return float(m), float(c), float(np.sqrt(np.mean(r * r)))


def _levels(ya, yb):
    """Three levels spanning the common range of two value sets (or the gap between them)."""
    lo, hi = max(np.min(ya), np.min(yb)), min(np.max(ya), np.max(yb))
    if lo > hi:
        lo, hi = hi, lo
    return np.array([lo, 0.5 * (lo + hi), hi])


def _storage_shift(f_a, E_a, f_b, E_b):
    """Shift from the storage moduli fitted by ``E' = c f^b + e`` (None if not defined)."""
    pa, pb = fit_power_offset(f_a, E_a), fit_power_offset(f_b, E_b)
    y = _levels(E_a, E_b)
    xa, xb = _inverse(y, *pa[:3]), _inverse(y, *pb[:3])
    ok = np.isfinite(xa) & np.isfinite(xb) & (xa > 0) & (xb > 0)
    return float(np.mean(np.log10(xa[ok]) - np.log10(xb[ok]))) if np.any(ok) else None


def _line_shift(xa, ya, xb, yb):
    """(shift, weight) from straight log-log lines; weight = slope^2 / residual^2 (inverse
    variance of the shift; 0 when the slopes differ in sign)."""
    ma, ca, ra = _loglog_line(xa, ya)
    mb, cb, rb = _loglog_line(xb, yb)
    if ma * mb <= 0:
        return 0.0, 0.0
    y = _levels(ya, yb)
    s = float(np.mean((y - ca) / ma - (y - cb) / mb))
    noise = max(ra, 1e-4) ** 2 + max(rb, 1e-4) ** 2
    return s, min(ma * ma, mb * mb) / noise


def _overlap_shift(xa, Ya, xb, Yb, s0, min_overlap=1.0, span=1.5):
    """Refine a shift by overlaying quadratic fits of the sweeps in (log f, log E).

    Each modulus k of each sweep is fitted by a quadratic in log f (smooths scatter, keeps the
    curvature a straight line misses); the shift minimises
    ``sum_k w_k mean_x (Qa_k(x) - Qb_k(x - s))^2`` over the common log-f window, with
    ``w_k = 1 / (residual_a^2 + residual_b^2)``. Searched within ``s0 +- span`` decades where
    the window is at least ``min_overlap`` decades wide. Returns the shift or None (no overlap).
    """
    from scipy.optimize import minimize_scalar

    ca = [np.polyfit(xa, y, 2) for y in Ya]
    cb = [np.polyfit(xb, y, 2) for y in Yb]
    ra = [np.sqrt(np.mean((np.polyval(c, xa) - y) ** 2)) for c, y in zip(ca, Ya)]
    rb = [np.sqrt(np.mean((np.polyval(c, xb) - y) ** 2)) for c, y in zip(cb, Yb)]
    w = [1.0 / (max(a, 1e-3) ** 2 + max(b, 1e-3) ** 2) for a, b in zip(ra, rb)]
    lo_s = max(s0 - span, xa.min() - xb.max() + min_overlap)
    hi_s = min(s0 + span, xa.max() - xb.min() - min_overlap)
    if not lo_s < s0 < hi_s:  # the first estimate leaves too little overlap: keep it
        return None
    t = np.linspace(0.0, 1.0, 41)

    def cost(s):
        lo, hi = max(xa.min(), xb.min() + s), min(xa.max(), xb.max() + s)
        x = lo + (hi - lo) * t
        return sum(
            wk * np.mean((np.polyval(a, x) - np.polyval(b, x - s)) ** 2) for wk, a, b in zip(w, ca, cb)
        )

    grid = np.linspace(lo_s, hi_s, 61)
    i = int(np.argmin([cost(g) for g in grid]))
    d = grid[1] - grid[0]
    opt = minimize_scalar(
        cost,
        bounds=(grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)] + 1e-12 * d),
        method="bounded",
        options={"xatol": 1e-4},
    )
    return float(opt.x)


def pair_shift(
    f_a: NDArray[np.float64],
    E1_a: NDArray[np.float64],
    E2_a: NDArray[np.float64],
    f_b: NDArray[np.float64],
    E1_b: NDArray[np.float64],
    E2_b: NDArray[np.float64],
) -> tuple[float, dict[str, Any]]:
    """log10 of the factor by which sweep b's frequencies are multiplied to overlay sweep a.

    Two estimates: from the storage modulus (both sweeps fitted by ``E' = c f^b + e``,
    :func:`fit_power_offset`; the mean of ``log10 f_a(E') - log10 f_b(E')`` at three levels
    spanning the sweeps' common E' range, or the gap between their ranges) and from the loss
    modulus (straight lines in log-log, same three-level rule). They are averaged with weights
    ``slope^2 / residual^2`` of log-log line fits (the inverse variance of a horizontal shift):
    where E' is flat (glassy plateau) the loss modulus leads, where E'' is curved or scattered
    (near its peak, instrument resonances) the storage modulus does.

    Returns (shift, dict with both estimates and weights).

    Parameters
    ----------
    f_a, E1_a, E2_a : ndarray
        Frequencies [Hz], storage and loss moduli [Pa] of sweep a.
    f_b, E1_b, E2_b : ndarray
        The same for sweep b.

    Returns
    -------
    shift : float
        log10 of the frequency factor moving sweep b onto sweep a.
    info : dict
        ``storage``, ``loss`` (the two estimates), ``w_storage``, ``w_loss`` (their weights),
        ``first`` and ``overlap``.

    Raises
    ------
    ValueError
        When neither modulus varies with frequency.
    """
    xa, xb = np.log10(f_a), np.log10(f_b)
    s_line, w1 = _line_shift(xa, np.log10(E1_a), xb, np.log10(E1_b))
    s1 = _storage_shift(f_a, E1_a, f_b, E1_b) if w1 > 0 else None
    if s1 is None:
        s1 = s_line
    s2, w2 = _line_shift(xa, np.log10(E2_a), xb, np.log10(E2_b))
    if w1 + w2 == 0:
        raise ValueError(
            "neither E' nor E'' of two neighbouring sweeps changes with frequency "
            "consistently: no shift can be determined"
        )
    s0 = (w1 * s1 + w2 * s2) / (w1 + w2)
    s = _overlap_shift(xa, [np.log10(E1_a), np.log10(E2_a)], xb, [np.log10(E1_b), np.log10(E2_b)], s0)
    return (s0 if s is None else s), dict(storage=s1, loss=s2, w_storage=w1, w_loss=w2, first=s0, overlap=s)
