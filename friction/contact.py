"""Contact mechanics of Persson's theory: G(q), P(q) and integrals against P.

``G(q) = 1/8 integral_{q_min}^{q} dq' q'^3 C(q') W(q')``, ``P(q) = erf(1 / (2 sqrt G))``
(Persson 2001; thesis eqs 2.2, 2.3; docs: Theory). All integrals are in s = ln q.

Near the lower end G grows linearly from 0 and P falls like 1/sqrt(q - q_min) at high speed:
sampling P at the nodes (trapezoid) overestimates mu badly. :func:`p_weights` integrates P
exactly on each interval, taking G linear in s there and the smooth co-factor linear too.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["cumulative_G", "contact_P", "contact_S", "p_weights"]

_SQPI = np.sqrt(np.pi)
#: from this many values in one call the error function comes from ``scipy.special`` (compiled,
#: vectorised); below it from :func:`math.erf` element by element, which spares a friction curve
#: (a few thousand values per call) the 0.1 s import of ``scipy.special``. The choice depends on
#: the call's size only, never on what the process did before, so the same input gives the same
#: bits in every command and every process (the two differ in the last ulp for 10 % of values).
_SCIPY_FROM = 200_000


def _erf_pair(x, complement):
    """``erf(x)`` (or ``erfc(x)`` when ``complement``), float64, shaped like ``x``.

    The C library's erf/erfc (:func:`math.erf`, C99) for small arrays; ``scipy.special`` (Cephes)
    for large ones (the choice depends only on ``x.size``). W.J. Cody, Math. Comp. 23, 631 (1969) gives the
    rational approximations both follow.
    """
    x = np.asarray(x, dtype=float)
    if x.size >= _SCIPY_FROM:
        from scipy import special

        return special.erfc(x) if complement else special.erf(x)
    f = math.erfc if complement else math.erf  # over a list: a quarter faster than np.frompyfunc
    return np.fromiter(map(f, x.ravel().tolist()), dtype=float, count=x.size).reshape(x.shape)


def erf(x: ArrayLike) -> NDArray[np.float64]:
    """The error function ``erf(x) = 2/sqrt(pi) int_0^x exp(-t^2) dt``, elementwise, float64."""
    return _erf_pair(x, False)


def erfc(x: ArrayLike) -> NDArray[np.float64]:
    """The complementary error function ``erfc(x) = 1 - erf(x)``, elementwise, float64."""
    return _erf_pair(x, True)


def cumulative_G(g: NDArray[np.float64], h: NDArray[np.float64]) -> NDArray[np.float64]:
    """Cumulative integral of a positive integrand ``g`` (..., n) over s with steps ``h`` (n-1,).

    Each interval is integrated exactly for g a power of q (linear in (s, ln g)):
    ``h (g_b - g_a) / ln(g_b / g_a)``, falling back to the trapezoid when ``g_b ~ g_a`` or
    a value is zero. Returns G (..., n) with ``G[..., 0] = 0``.

    Parameters
    ----------
    g : ndarray, shape (..., n)
        Positive integrand on the nodes, uniform or not in s (here s = ln q).
    h : ndarray, shape (n - 1,)
        Widths of the intervals between consecutive nodes in s.

    Returns
    -------
    ndarray, shape (..., n)
        The cumulative integral, ``G[..., 0] = 0``.
    """
    ga, gb = g[..., :-1], g[..., 1:]
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.log(gb / ga)
        seg = np.where(np.abs(r) > 1e-6, (gb - ga) / r, 0.5 * (ga + gb))
    seg = np.where((ga > 0) & (gb > 0) & np.isfinite(seg), seg, 0.5 * (ga + gb)) * h
    out = np.zeros(g.shape)
    np.cumsum(seg, axis=-1, out=out[..., 1:])
    return out


def contact_P(G: ArrayLike) -> NDArray[np.float64]:
    """``P = erf(1 / (2 sqrt G))`` with P(0) = 1: the fraction of the nominal area in contact.

    Parameters
    ----------
    G : array_like
        Persson's G(q), dimensionless, >= 0.

    Returns
    -------
    ndarray
        P(q), the relative contact area at magnification q / q0, shaped like ``G``.

    References
    ----------
    B.N.J. Persson, J. Chem. Phys. 115, 3840 (2001), doi:10.1063/1.1388626.
    """
    G = np.asarray(G, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(G > 0, erf(0.5 / np.sqrt(np.maximum(G, 1e-300))), 1.0)


def contact_S(P: ArrayLike, gamma: float | None = None) -> NDArray[np.float64] | float:
    """Persson's correction of the dissipation integrand, ``S(q) = gamma + (1 - gamma) P(q)^2``.

    It multiplies ``q^3 C(q) P(q) M(q)`` in mu (and, in the flash model, the heat source):
    ``mu = 1/2 int q^3 C S P M dq`` (Persson, J. Phys.: Condens. Matter 18 (2006) 7789; Lorenz et
    al., EPL 103 (2013) 24003, gamma ~ 0.45 to 0.75); G and P are unchanged. ``gamma=None``
    means S = 1 (the thesis). Returns an array shaped like P (or the scalar 1.0).

    Parameters
    ----------
    P : array_like
        The relative contact area P(q).
    gamma : float or None, optional
        Persson's gamma, 0 <= gamma <= 1; None for no correction.

    Returns
    -------
    ndarray or float
        S(q), shaped like ``P``, or 1.0 when ``gamma`` is None.

    References
    ----------
    B.N.J. Persson, J. Phys.: Condens. Matter 18, 7789 (2006), doi:10.1088/0953-8984/18/32/025.
    B. Lorenz et al., EPL 103, 24003 (2013), doi:10.1209/0295-5075/103/24003.
    """
    if gamma is None:
        return 1.0
    return gamma + (1.0 - gamma) * np.asarray(P) ** 2


def _FK(G):
    """Antiderivatives of P and of G P over G, minus their G=0 limits, at once (one erf and
    one erfc of the same argument): ``F = int_0^G P dG'`` and ``K = int_0^G G' P dG'``. Also
    returns P itself, ``erf(1 / (2 sqrt G))`` (1 at G = 0)."""
    G = np.asarray(G, dtype=float)
    sg = np.sqrt(G)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        u = np.where(G > 0, 0.5 / np.where(G > 0, sg, 1.0), np.inf)
        e = np.exp(-u * u)
        E, Ec = erf(u), erfc(u)
        F = G * E + (sg * e / _SQPI - 0.5 * Ec)
        K = 0.5 * G * G * E + e * (2 * G * sg - sg) / (12 * _SQPI) + Ec / 24.0
    return F, K, np.where(G > 0, E, 1.0)


def p_weights(G: ArrayLike, h: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Weights ``w`` (..., n) with ``integral f(s) P(s) ds ~ sum_i w_i f_i`` for f linear on
    each interval and P = erf(1/(2 sqrt G)) with G linear in s on each interval.

    On an interval with ``G(t) = G_a + t dG``, t in [0, 1], the moments
    ``A0 = int P dt``, ``A1 = int t P dt`` come from closed-form antiderivatives of P and G P;
    where ``dG`` is small compared with ``G_a`` (P smooth there) Simpson's rule is used instead
    (avoids cancellation). Returns the weights and P at the nodes.

    Parameters
    ----------
    G : array_like, shape (..., n)
        Persson's G(q) on the nodes (non-decreasing along the last axis).
    h : array_like, shape (n - 1,)
        Interval widths in s = ln q.

    Returns
    -------
    w : ndarray, shape (..., n)
        Quadrature weights for ``integral f P ds``.
    P : ndarray, shape (..., n)
        P at the nodes.
    """
    G = np.asarray(G, dtype=float)
    h = np.asarray(h, dtype=float)
    Ga, Gb = G[..., :-1], G[..., 1:]
    dG = Gb - Ga
    # F, K and P at the nodes from one erf and one erfc of the nodes' argument (the interval
    # ends share them), P at the midpoints from one more erf
    F, K, P = _FK(G)
    Pa, Pb = P[..., :-1], P[..., 1:]
    Pm = contact_P(0.5 * (Ga + Gb))
    A0 = (Pa + 4 * Pm + Pb) / 6.0
    A1 = (2 * Pm + Pb) / 6.0
    exact = dG > 0.05 * Ga
    if np.any(exact):
        ga, dg = Ga[exact], dG[exact]
        Fa, Fb = F[..., :-1][exact], F[..., 1:][exact]
        a0 = (Fb - Fa) / dg
        a1 = ((K[..., 1:][exact] - K[..., :-1][exact]) - ga * (Fb - Fa)) / (dg * dg)
        A0[exact], A1[exact] = a0, a1
    w = np.zeros(G.shape)
    w[..., :-1] += h * (A0 - A1)
    w[..., 1:] += h * A1
    return w, P
