"""Mean interfacial separation and contact pressure from Persson's contact mechanics.

Persson's relation between the mean separation u of two surfaces and the pressure p pressing
them together (Persson, Phys. Rev. Lett. 99, 125502 (2007)), written with the engine's own
G(q) (:func:`friction.isothermal.contact_state`, at pressure sigma0)::

    u(p) = sqrt(pi) int_{q0}^{q1} dq q^2 C(q) w(q) J(p / (2 sigma0 sqrt(G(q))))
    w(q) = (pi int_{q0}^{q} dq' q'^3 C(q'))^(-1/2)
    J(y) = int_y^inf (dx / x) [gamma + 3 (1 - gamma) erf(x)^2] exp(-x^2)

(Persson's inner integral over p' with x = w p' / E*; for an elastic solid
``1 / (2 sqrt(G)) = w sigma0 / E*``, so the engine's G, which holds the rubber's modulus at the
sliding frequencies, stands for E*). The contact pressure ``p_cont(u)`` is its inverse: the part
of the load the asperity contact carries when the surfaces are u apart (the rest is carried by
the water between them). u is measured from the mean plane of the rough surface: the volume
of the gap per nominal area.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..contact import cumulative_G, erf

__all__ = ["SEPARATION_GAMMA", "J_function", "contact_pressure", "mean_separation"]

#: Persson's gamma in u(p), ~0.4 (Persson, PRL 99, 125502 (2007); Yang & Persson, J. Phys.:
#: Condens. Matter 20, 215214 (2008), doi:10.1088/0953-8984/20/21/215214)
SEPARATION_GAMMA = 0.4


@lru_cache(maxsize=4)
def _J_table(gamma):
    """ln y nodes and J(y) on them (y from 1e-12 to 7), by the trapezoid rule in ln x."""
    lx = np.linspace(np.log(1e-12), np.log(7.0), 4001)
    x = np.exp(lx)
    f = (gamma + 3.0 * (1.0 - gamma) * erf(x) ** 2) * np.exp(-x * x)  # dx/x = d ln x
    seg = 0.5 * (f[1:] + f[:-1]) * np.diff(lx)
    J = np.concatenate([np.cumsum(seg[::-1])[::-1], [0.0]])
    return lx, J


def J_function(y, gamma=SEPARATION_GAMMA):
    """``J(y) = int_y^inf dx/x [gamma + 3(1 - gamma) erf(x)^2] exp(-x^2)`` (elementwise).

    J falls from ``-gamma ln y`` (y -> 0) to 0 (tabulated to y = 7, where it is below 1e-22).

    Parameters
    ----------
    y : array_like
        Argument, >= 0 (0 gives +inf, inf gives 0).
    gamma : float, optional
        Persson's gamma.

    Returns
    -------
    ndarray
        J(y), shaped like ``y``.
    """
    lx, J = _J_table(float(gamma))
    y = np.asarray(y, dtype=float)
    with np.errstate(divide="ignore"):
        ly = np.log(np.maximum(y, 0.0))
    small = ly < lx[0]
    out = np.interp(np.clip(ly, lx[0], lx[-1]), lx, J, right=0.0)
    out = np.where(ly >= lx[-1], 0.0, out)
    # below the table: J(y) = J(y0) + gamma ln(y0 / y) (the erf term is negligible there)
    return np.where(small, J[0] + gamma * (lx[0] - ly), out)


def mean_separation(q_per_m, C_m4, G, sigma0_Pa, p_Pa, gamma=SEPARATION_GAMMA):
    """Persson's mean separation u(p) [m] at pressures ``p_Pa`` for every speed (row) of G.

    Parameters
    ----------
    q_per_m : ndarray, shape (nq,)
        Wave vectors of the engine's grid [1/m], uniform or not in ln q.
    C_m4 : ndarray, shape (nq,)
        Spectrum there [m^4].
    G : ndarray, shape (nv, nq)
        Persson's G(q) at the nominal pressure ``sigma0_Pa`` (``FrictionResult.G``).
    sigma0_Pa : float or ndarray, shape (nv,)
        The pressure G was computed at [Pa].
    p_Pa : array_like, shape (np,)
        Pressures carried by the contact [Pa].
    gamma : float, optional
        Persson's gamma of u(p) (:data:`SEPARATION_GAMMA`).

    Returns
    -------
    ndarray, shape (nv, np)
        Mean separation [m] (decreasing in p).

    References
    ----------
    B.N.J. Persson, "Relation between interfacial separation and load: a general theory of
    contact mechanics", Phys. Rev. Lett. 99, 125502 (2007), doi:10.1103/PhysRevLett.99.125502.
    """
    q = np.asarray(q_per_m, dtype=float)
    C = np.asarray(C_m4, dtype=float)
    G = np.atleast_2d(np.asarray(G, dtype=float))
    p = np.atleast_1d(np.asarray(p_Pa, dtype=float))
    s = np.diff(np.log(q))
    I3 = cumulative_G(q**4 * C, s)  # int_{q0}^{q} q'^3 C dq'
    with np.errstate(divide="ignore"):
        w = np.where(I3 > 0, 1.0 / np.sqrt(np.pi * np.maximum(I3, 1e-300)), 0.0)
        a = np.where(
            G > 0, 1.0 / (2.0 * np.reshape(sigma0_Pa, (-1, 1)) * np.sqrt(np.maximum(G, 1e-300))), np.inf
        )  # (nv, nq): y = p a
    ws = np.zeros(q.size)  # trapezoid weights in ln q
    ws[:-1] += 0.5 * s
    ws[1:] += 0.5 * s
    kern = np.sqrt(np.pi) * ws * q**3 * C * w  # (nq,)
    y = p[None, :, None] * a[:, None, :]  # (nv, np, nq)
    return np.einsum("vpq,q->vp", J_function(y, gamma), kern)


def contact_pressure(u_m, u_table, p_table):
    """Inverse of :func:`mean_separation` for one speed: the contact pressure [Pa] at mean
    separation(s) ``u_m``, interpolated in (u, ln p); 0 beyond the table's largest separation,
    the table's largest pressure below its smallest.

    Parameters
    ----------
    u_m : array_like
        Mean separations [m].
    u_table : ndarray, shape (np,)
        u(p) at ``p_table`` (decreasing).
    p_table : ndarray, shape (np,)
        Increasing pressures [Pa].

    Returns
    -------
    ndarray
        p_cont [Pa], shaped like ``u_m``.
    """
    u = np.asarray(u_m, dtype=float)
    ut, lp = u_table[::-1], np.log(p_table[::-1])  # increasing u
    out = np.exp(np.interp(u, ut, lp))
    return np.where(u > ut[-1], 0.0, out)
