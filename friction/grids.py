"""Quadrature grids: the wave-vector grid (uniform in ln q) and the phi rule, plus the
tabulated phi integrals of a rubber.

Phi integrals (docs: Theory). With ``x = q v`` [rad/s] and the rubber at its reference
state, Persson's angular integrals reduce to two functions of x alone,

    m(x) = integral_0^{pi/2} cos(phi) Im E(x cos phi) dphi        [Pa]
    w(x) = integral_0^{pi/2} |E(x cos phi)|^2 dphi                 [Pa^2]

(the integrands are even about phi = 0 and phi = pi, so the 0..2 pi integrals are 4 m and 4 w).
A temperature T only rescales the frequency, ``E(omega, T) = E_ref(omega a)``, so the moduli at
any temperature are ``m(x a)`` and ``w(x a)``: one table per rubber serves every speed,
wave vector and temperature. The table is a cubic spline of (ln x, ln m) and (ln x, ln w).
"""

from __future__ import annotations

import weakref
from itertools import pairwise
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from .rubber import Rubber

__all__ = ["phi_rule", "q_grid", "q_nodes_per_decade", "PhiTable", "phi_table"]


def phi_rule(
    n_gl: int = 8, panels_per_decade: float = 1.0, u_min: float = 1e-8
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gauss-Legendre panels on phi in [0, pi/2], graded geometrically towards phi = pi/2.

    With ``u = pi/2 - phi`` (so ``cos phi = sin u``) the range ``[u_min, pi/2]`` is cut into
    panels of equal width in ln u (``panels_per_decade`` per decade), each integrated with
    ``n_gl`` Gauss-Legendre nodes in ln u; ``[0, u_min]`` gets one ``n_gl``-node panel.
    The grading follows the structure of the integrand near phi = pi/2, where
    ``omega = x cos phi -> 0`` crosses the rubber's relaxation frequencies.

    Returns
    -------
    cos_phi, weights : ndarray, shape (n,)
        Nodes and weights with ``sum w f(phi) ~ integral_0^{pi/2} f dphi``.

    Parameters
    ----------
    n_gl : int, optional
        Gauss-Legendre nodes per panel.
    panels_per_decade : float, optional
        Panels per decade of u = pi/2 - phi.
    u_min : float, optional
        Lower end of the graded range of u [rad].
    """
    t, wt = np.polynomial.legendre.leggauss(int(n_gl))
    lo, hi = np.log(u_min), np.log(np.pi / 2)
    npan = max(1, int(np.ceil((hi - lo) / np.log(10.0) * panels_per_decade)))
    edges = np.linspace(lo, hi, npan + 1)
    a, b = edges[:-1, None], edges[1:, None]
    s = 0.5 * (a + b) + 0.5 * (b - a) * t[None, :]
    u = np.exp(s)
    w = 0.5 * (b - a) * wt[None, :] * u  # du = u ds
    u0 = 0.5 * u_min * (1 + t)
    w0 = 0.5 * u_min * wt
    u = np.concatenate([u0, u.ravel()])
    w = np.concatenate([w0, w.ravel()])
    return np.sin(u), w


def q_nodes_per_decade(tol: float, base: float = 40.0, ref_tol: float = 1e-3, minimum: int = 8) -> int:
    """q nodes per decade for a relative tolerance ``tol`` on mu (second-order rule:
    about 40 per decade at 1e-3, scaling as tol^-1/2; measured in tests).

    Parameters
    ----------
    tol : float
        Relative tolerance wanted on mu.
    base : float, optional
        Nodes per decade at the reference tolerance.
    ref_tol : float, optional
        The reference tolerance.
    minimum : int, optional
        Fewest nodes per decade returned.

    Returns
    -------
    int
        Nodes per decade of ln q.
    """
    return max(minimum, int(np.ceil(base * np.sqrt(ref_tol / tol))))


def q_grid(
    breakpoints_per_m: ArrayLike, nodes_per_decade: float, grade: int = 8
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Nodes uniform in ln q between consecutive breakpoints (all breakpoints are nodes),
    with the first interval graded geometrically towards the lowest q: ``grade`` extra nodes at
    ``s0 + h / 2^k``, k = 1..grade, where G rises from 0 and P has its 1/sqrt(q - q_min)
    shape (keeps the P integration second order).

    Returns ``q`` (n,) [1/m] and ``h`` (n-1,) the interval widths in ln q.

    Parameters
    ----------
    breakpoints_per_m : array_like
        Wave vectors that must be nodes (the band ends, a spectrum's tabulated points) [1/m].
    nodes_per_decade : float
        Nodes per decade between breakpoints.
    grade : int, optional
        Extra nodes graded towards the lowest q (0 for none).

    Returns
    -------
    q : ndarray, shape (n,)
        Nodes [1/m].
    h : ndarray, shape (n - 1,)
        Interval widths in ln q.
    """
    bp = np.sort(np.asarray(breakpoints_per_m, dtype=float).ravel())
    if bp.size and not np.isnan(bp[-1]):  # np.unique's values, without numpy.ma
        bp = bp[np.r_[True, bp[1:] != bp[:-1]]]
    else:
        bp = np.unique(bp)
    parts = []
    for a, b in pairwise(bp):
        n = max(2, int(np.ceil(np.log10(b / a) * nodes_per_decade)))
        parts.append(np.linspace(np.log(a), np.log(b), n + 1)[:-1])
    s = np.concatenate(parts + [[np.log(bp[-1])]])
    if grade and s.size > 1:
        s = np.sort(np.concatenate([s, s[0] + (s[1] - s[0]) * 0.5 ** np.arange(1, grade + 1)]))
    return np.exp(s), np.diff(s)


class _NotAKnotSpline:
    """Cubic interpolating spline with not-a-knot end conditions (the same spline as
    ``scipy.interpolate.CubicSpline``'s default, equal to it to rounding; written here because
    importing ``scipy.interpolate`` costs 0.1 s, which every ``roadscan`` run would pay).

    The slopes s_i at the nodes x_0 < ... < x_{n-1} solve the tridiagonal system of C2
    continuity, for i = 1..n-2 (h_i = x_{i+1} - x_i, d_i = (y_{i+1} - y_i) / h_i)

        h_i s_{i-1} + 2 (h_{i-1} + h_i) s_i + h_{i-1} s_{i+1} = 3 (h_i d_{i-1} + h_{i-1} d_i),

    closed by continuity of the third derivative at x_1 and x_{n-2} (de Boor, *A Practical
    Guide to Splines*, 2001, ch. IV):

        h_1 s_0 + (h_0 + h_1) s_1 = ((h_0 + 2 (h_0 + h_1)) h_1 d_0 + h_0^2 d_1) / (h_0 + h_1)

    and its mirror image at the right end. Each interval is the cubic Hermite polynomial of
    its end values and slopes. Needs n >= 4 nodes.
    """

    def __init__(self, x, y):
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        n = x.size
        if n < 4:
            raise ValueError("the not-a-knot spline needs at least 4 nodes")
        h = np.diff(x)
        d = np.diff(y) / h
        lower = np.empty(n)  # A[i, i-1]
        diag = np.empty(n)  # A[i, i]
        upper = np.empty(n)  # A[i, i+1]
        rhs = np.empty(n)
        lower[1:-1], diag[1:-1], upper[1:-1] = h[1:], 2 * (h[:-1] + h[1:]), h[:-1]
        rhs[1:-1] = 3 * (h[1:] * d[:-1] + h[:-1] * d[1:])
        w0 = x[2] - x[0]
        diag[0], upper[0] = h[1], w0
        rhs[0] = ((h[0] + 2 * w0) * h[1] * d[0] + h[0] ** 2 * d[1]) / w0
        w1 = x[-1] - x[-3]
        diag[-1], lower[-1] = h[-2], w1
        rhs[-1] = (h[-1] ** 2 * d[-2] + (2 * w1 + h[-1]) * h[-2] * d[-1]) / w1
        # Thomas algorithm (the system is diagonally dominant but for its first and last rows,
        # whose eliminations do not pivot in LAPACK's banded LU either)
        diag, upper, rhs, lower = diag.tolist(), upper.tolist(), rhs.tolist(), lower.tolist()
        for i in range(1, n):
            f = lower[i] / diag[i - 1]
            diag[i] -= f * upper[i - 1]
            rhs[i] -= f * rhs[i - 1]
        slope = [0.0] * n
        slope[-1] = rhs[-1] / diag[-1]
        for i in range(n - 2, -1, -1):
            slope[i] = (rhs[i] - upper[i] * slope[i + 1]) / diag[i]
        s = np.array(slope)
        t = (s[:-1] + s[1:] - 2 * d) / h
        self.x, self.slope = x, s
        self.c = np.stack([t / h, (d - s[:-1]) / h - t, s[:-1], y[:-1]])  # c0 u^3 + ... + c3

    def __call__(self, xi):
        """Spline values at ``xi`` (inside [x_0, x_{n-1}]; the end cubics continue outside)."""
        xi = np.asarray(xi, dtype=float)
        i = np.clip(np.searchsorted(self.x, xi, side="right") - 1, 0, self.x.size - 2)
        u = xi - self.x[i]
        c = self.c[:, i]
        return ((c[0] * u + c[1]) * u + c[2]) * u + c[3]

    def ends(self):
        """(value, slope) at the first node, then at the last node."""
        return (self.c[3, 0], self.slope[0], float(self(self.x[-1])), self.slope[-1])


class PhiTable:
    """Spline tables of ``m(x)`` and ``w(x)`` (see module docstring) over ``[x_lo, x_hi]``.

    Nodes are on the lattice ``ln x = k / per_decade * ln 10``; outside the range the tables
    are extended linearly in (ln x, ln m) with the end slopes. ``m`` and ``w`` are returned
    in Pa and Pa^2; Persson's M and W follow as ``4 m / ((1 - nu^2) sigma0)`` and
    ``4 w / ((1 - nu^2) sigma0)^2``.

    Parameters
    ----------
    rubber : rubber model
        Any rubber of :mod:`friction.rubber` (``modulus_ref``).
    k_lo, k_hi : int
        Lattice range of the table: ``ln x = k ln(10) / per_decade``.
    per_decade : int, optional
        Table nodes per decade of x.
    n_gl : int, optional
        Gauss-Legendre nodes per panel of the phi rule.
    panels_per_decade : float, optional
        Panels per decade of the phi rule.
    """

    def __init__(
        self,
        rubber: Rubber,
        k_lo: int,
        k_hi: int,
        per_decade: int = 24,
        n_gl: int = 8,
        panels_per_decade: float = 1.0,
    ) -> None:
        self.rubber, self.k_lo, self.k_hi, self.per_decade = rubber, int(k_lo), int(k_hi), per_decade
        lx = np.arange(self.k_lo, self.k_hi + 1) * (np.log(10.0) / per_decade)
        c, wphi = phi_rule(n_gl, panels_per_decade)
        self.phi_nodes = c.size
        with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
            E = rubber.modulus_ref(np.exp(lx)[:, None] * c[None, :])
            m = (c * E.imag) @ wphi
            w = (E.real**2 + E.imag**2) @ wphi
        m = np.where(np.isfinite(m), m, 0.0)
        w = np.where(np.isfinite(w), w, np.finfo(float).max)
        tiny = 1e-300
        self._lx = lx
        self._lm = _NotAKnotSpline(lx, np.log(np.maximum(m, tiny)))
        self._lw = _NotAKnotSpline(lx, np.log(np.maximum(w, tiny)))
        self._ends = [f.ends() for f in (self._lm, self._lw)]

    def covers(self, k_lo: int, k_hi: int) -> bool:
        """Whether the table spans the lattice range [k_lo, k_hi]."""
        return self.k_lo <= k_lo and k_hi <= self.k_hi

    def __call__(self, x: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(m, w)`` at ``x = q v a`` [rad/s] (any shape, x > 0)."""
        lx = np.log(np.maximum(x, 1e-300))  # x = 0 (a shift factor that underflowed) stays finite
        lo, hi = self._lx[0], self._lx[-1]
        lxc = np.clip(lx, lo, hi)
        out = []
        for f, (y0, d0, y1, d1) in zip((self._lm, self._lw), self._ends):
            y = f(lxc)
            y = np.where(lx < lo, y0 + d0 * (lx - lo), y)
            y = np.where(lx > hi, y1 + d1 * (lx - hi), y)
            out.append(np.exp(np.clip(y, -700.0, 700.0)))  # no overflow far outside the table
        return out[0], out[1]


#: per rubber: tables by (nodes per decade, first node, last node), at most _KEEP of them
_CACHE: weakref.WeakKeyDictionary[Rubber, dict[tuple[int, int, int], PhiTable]] = weakref.WeakKeyDictionary()
_KEEP = 16


def phi_table(rubber: Rubber, x_min: float, x_max: float, per_decade: int = 24) -> PhiTable:
    """A cached :class:`PhiTable` for ``rubber`` covering ``[x_min, x_max]`` (with margin).

    The table's nodes are a fixed lattice (``per_decade`` a decade) and its ends are the
    requested range widened by three nodes and then out to whole decades, so the table, and
    every value read from it, is a function of the request alone: the same call gives the same
    bits whatever the process computed before (a spline through a range grown by earlier calls
    would not; its not-a-knot ends reach a few nodes in).

    Parameters
    ----------
    rubber : rubber model
        The rubber the table is for (tables are cached per rubber).
    x_min, x_max : float
        Range of ``x = q v aT`` that must be covered [rad/s].
    per_decade : int, optional
        Table nodes per decade.

    Returns
    -------
    PhiTable
        A table covering at least ``[x_min, x_max]``.

    Raises
    ------
    ValueError
        When the range is not finite and positive.
    """
    d = np.log(10.0) / per_decade
    if not (np.isfinite(x_min) and np.isfinite(x_max) and 0 < x_min <= x_max):
        raise ValueError(
            f"reduced frequencies q v aT out of range ({x_min:.3g}..{x_max:.3g} rad/s): "
            "is the temperature far outside the rubber's shift table?"
        )
    k_lo = (int(np.floor(np.log(x_min) / d)) - 3) // per_decade * per_decade
    k_hi = -((-(int(np.ceil(np.log(x_max) / d)) + 3)) // per_decade) * per_decade
    tabs = _CACHE.setdefault(rubber, {})
    key = (per_decade, k_lo, k_hi)
    t = tabs.pop(key, None)
    if t is None:
        t = PhiTable(rubber, k_lo, k_hi, per_decade)
        while len(tabs) >= _KEEP:
            del tabs[next(iter(tabs))]
    tabs[key] = t  # the most recent last
    return t
