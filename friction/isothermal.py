"""Persson's isothermal friction model (Persson 2001; thesis eqs 2.1 to 2.3; docs: Theory).

    mu(v) = 1/2 integral_{q_min}^{q1} dq q^3 C(q) S(q) P(q) M(q)
    M(q)  = integral_0^{2pi} dphi cos(phi) Im E(q v cos phi) / ((1 - nu^2) sigma0)
    G(q)  = 1/8 integral_{q_min}^{q} dq' q'^3 C(q') W(q'),
    W(q)  = integral_0^{2pi} dphi |E(q v cos phi)|^2 / ((1 - nu^2) sigma0)^2
    P(q)  = erf(1 / (2 sqrt G(q)))

with S = 1 (the thesis) or Persson's later ``S = gamma + (1 - gamma) P^2`` (``contact_gamma``).
The rubber is at the background temperature T0: ``E(omega, T0) = E_ref(omega a)`` with
``a = aT(T0)/aT(T_ref)`` ("relative", default) or the thesis's literal eq 3.7 (see
:func:`friction.rubber.log10_shift`).

Numerics: nodes uniform in ln q (count per decade from ``tol``), the phi integrals from a
per-rubber spline table of x = q v a (see :mod:`friction.grids`), G integrated exactly for
piecewise power laws, and P integrated exactly over each interval (:func:`p_weights`).
"""

from __future__ import annotations

import numpy as np

from .contact import contact_S, cumulative_G, p_weights
from .grids import phi_table, q_grid, q_nodes_per_decade
from .result import FrictionResult
from .rubber import log10_shift

__all__ = ["mu_isothermal", "contact_state"]


def _check(psd, v, sigma0_Pa, nu, contact_gamma=None):
    v = np.atleast_1d(np.asarray(v, dtype=float))
    if v.ndim != 1 or not np.all(np.isfinite(v)) or np.any(v <= 0):
        raise ValueError("velocities must be a 1D array of positive finite speeds [m/s]")
    sig = np.asarray(sigma0_Pa, dtype=float)
    if sig.ndim > 1 or (sig.ndim == 1 and sig.shape != v.shape) or not np.all(sig > 0):
        raise ValueError("sigma0_Pa must be positive (a number, or one per speed)")
    if not (-1 < nu < 1):
        raise ValueError("nu must lie in (-1, 1)")
    if contact_gamma is not None and not (np.isfinite(contact_gamma) and 0 <= contact_gamma <= 1):
        raise ValueError(f"contact_gamma must lie in [0, 1], got {contact_gamma!r}")
    return v


def _breakpoints(psd, extra=()):
    bp = [psd.q_min_per_m, psd.q1_per_m]
    if psd.q0_per_m > psd.q_min_per_m:
        bp.append(psd.q0_per_m)
    bp += [q for q in extra if psd.q_min_per_m < q < psd.q1_per_m]
    return bp


def contact_state(q, h, C, m, w, sigma0_Pa, nu):
    """G, P and the P-integration weights on a (nv, nq) grid from tabulated m, w.

    Parameters
    ----------
    q : ndarray, shape (nq,)
        Wave vectors [1/m].
    h : ndarray, shape (nq - 1,)
        Interval widths in ln q.
    C : ndarray, shape (nq,)
        Spectrum at ``q`` [m^4].
    m, w : ndarray, shape (nv, nq)
        Tabulated quarter-range phi integrals (:class:`friction.grids.PhiTable`) [Pa, Pa^2].
    sigma0_Pa : float or ndarray, shape (nv,)
        Nominal pressure [Pa], one for all speeds or one per speed (row).
    nu : float
        Poisson's ratio.

    Returns
    -------
    G, P, wP : ndarray, shape (nv, nq)
        Persson's G(q), the contact area P(q) and the exact-P quadrature weights.
    dissipation : ndarray, shape (nv, nq)
        ``q^4 C M`` without P, ready for the weights.
    """
    s = (1.0 - nu * nu) * sigma0_Pa
    if np.ndim(s):  # one pressure per speed: a column against the (nv, nq) tables
        s = np.asarray(s, dtype=float)[:, None]
    q4C = q**4 * C
    g = q4C * (4.0 * w / (s * s)) / 8.0
    G = cumulative_G(g, h)
    wP, P = p_weights(G, h)
    return G, P, wP, q4C * (4.0 * m / s)


def mu_isothermal(
    psd,
    rubber,
    v_m_per_s,
    sigma0_Pa=0.2e6,
    nu=0.5,
    T0_C=None,
    tol=1e-3,
    contact_gamma=None,
    wlf_form="relative",
):
    """Isothermal kinetic friction mu(v) by Persson's theory.

    With ``s = (1 - nu^2) sigma0`` and the rubber's modulus E(omega) at the background
    temperature::

        mu(v) = 1/2 int_{q0}^{q1} dq q^3 C(q) S(q) P(q) M(q)
        M(q)  = int_0^{2 pi} dphi cos(phi) Im E(q v cos phi) / s
        P(q)  = erf(1 / (2 sqrt(G(q)))),  G(q) = 1/8 int_{q0}^{q} dq' q'^3 C(q') W(q')
        W(q)  = int_0^{2 pi} dphi |E(q v cos phi)|^2 / s^2

    integrated in ln q with P integrated exactly over each interval.

    Parameters
    ----------
    psd : SelfAffinePSD or TabulatedPSD
        Surface spectrum C(q) [m^4] (Persson's normalisation); integrated from
        ``psd.q_min_per_m`` to ``psd.q1_per_m``.
    rubber : StandardLinearSolid, Prony or MasterCurve
        The rubber, with its reference temperature and shift.
    v_m_per_s : array_like
        Sliding speeds [m/s].
    sigma0_Pa : float or array_like, optional
        Nominal pressure [Pa] (default 0.2 MPa); an array gives one pressure per speed (the
        wet model's contact pressure, :mod:`friction.wet`).
    nu : float, optional
        Poisson's ratio (0.5).
    T0_C : float, optional
        Background temperature [C]; None means ``rubber.T_ref_C``.
    tol : float, optional
        Relative accuracy target for mu; sets the q grid (about 40 nodes per decade at 1e-3).
    contact_gamma : float, optional
        Persson's gamma of ``S = gamma + (1 - gamma) P^2``; None for S = 1.
    wlf_form : {"relative", "literal"}, optional
        Temperature shift ``E_ref(omega aT(T) / aT(T_ref))`` (default) or the thesis's eq 3.7.

    Returns
    -------
    FrictionResult
        ``mu`` (nv,), ``P`` and ``G`` (nv, nq) on ``q_per_m``; ``T_q_C`` is None.

    References
    ----------
    B.N.J. Persson, "Theory of rubber friction and contact mechanics", J. Chem. Phys. 115, 3840
    (2001), doi:10.1063/1.1388626.

    Examples
    --------
    >>> import numpy as np, friction
    >>> psd = friction.SelfAffinePSD(0.85, 5e-4, 2000, 2e5)
    >>> r = friction.mu_isothermal(psd, friction.thesis_rubber(), np.logspace(-4, 2, 7))
    >>> r.mu.shape
    (7,)
    """
    v = _check(psd, v_m_per_s, sigma0_Pa, nu, contact_gamma)
    T0 = rubber.T_ref_C if T0_C is None else float(T0_C)
    a = 10.0 ** float(log10_shift(rubber, T0, wlf_form, T0))
    q, h = q_grid(_breakpoints(psd), q_nodes_per_decade(tol))
    C = psd.C(q)
    x = (v[:, None] * a) * q[None, :]
    tab = phi_table(rubber, x.min(), x.max())
    m, w = tab(x)
    G, P, wP, f = contact_state(q, h, C, m, w, sigma0_Pa, nu)
    f = f * contact_S(P, contact_gamma)
    mu = 0.5 * np.sum(wP * f, axis=-1)
    meta = dict(
        model="isothermal",
        sigma0_Pa=sigma0_Pa,
        nu=nu,
        T0_C=T0,
        tol=tol,
        contact_gamma=contact_gamma,
        wlf_form=wlf_form,
        q0_per_m=psd.q0_per_m,
        q_nodes=q.size,
        phi_nodes=tab.phi_nodes,
        log10_shift=float(np.log10(a)),
    )
    return FrictionResult(v, mu, q, P, G, None, 0, 0.0, meta)
