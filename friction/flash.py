"""Persson's flash-temperature model (Persson 2006; thesis eqs 3.1 to 3.7; DESIGN.md sec 5).

The rubber heats at every length scale:

    T_q = T0 + integral_0^inf dq' g(q, q') f(q')
    g(q, q') = (1/pi) int_0^inf dk (1 - exp(-D k^2 t0)) / (D k^2)
               * 4 q' / (k^2 + 4 q'^2) * 4 q^2 / (k^2 + 4 q^2)                  [s]
    f(q') = v q'^4 C(q') P(q') / (rho c_v P(q_m))
            * int_0^{2pi} dphi cos(phi) Im E(q' v cos phi, T_q') / (1 - nu^2)    [K m/s]

with ``D = lambda/(rho c_v)``, ``t0 = R / v``, ``R = (a + b P(q_m)^c) / q_m``, ``q_m = zeta_m q0``.
The moduli in f, in mu and in G (hence P) are taken at T_q:
``E(omega, T_q) = E_ref(omega * 10**log10_shift(T_q))``.

Numerics. The k integral is a trapezoid rule in ln k (spectrally accurate: the integrand is
analytic in ln k and decays at both ends), so the heat kernel factorises,
``sum_q' g f = sum_k B(k, q) w_k F(k, t0) sum_q' A(k, q') f(q') dq'``: two matrix products for
all velocities at once. The q' integral uses the exact-P weights of :func:`p_weights`.
The self-consistent T_q (all speeds at once) is found by a damped fixed-point iteration with
Anderson acceleration (per speed, memory 6), safeguarded by restarts; the iteration count and
the final residual ``max |Phi(T) - T|`` [K] are reported, and a RuntimeError is raised if it
does not converge.
"""
from __future__ import annotations

import numpy as np

from .grids import phi_table, q_grid, q_nodes_per_decade
from .isothermal import _breakpoints, _check, contact_state
from .result import FrictionResult
from .rubber import log10_shift

__all__ = ["mu_flash", "heat_kernel"]


def k_rule(k_lo, k_hi, per_decade=8):
    """Trapezoid nodes and weights in ln k on [k_lo, k_hi]: ``int dk F ~ sum w_k F(k_k)``."""
    n = int(np.ceil(np.log10(k_hi / k_lo) * per_decade)) + 1
    lk = np.linspace(np.log(k_lo), np.log(k_hi), n)
    k = np.exp(lk)
    w = np.full(n, lk[1] - lk[0]) * k
    w[0] *= 0.5
    w[-1] *= 0.5
    return k, w


def heat_kernel(q_per_m, qp_per_m, D_m2_s, t0_s, per_decade=8):
    """The kernel g(q, q') [s] of the flash temperature, by the ln-k trapezoid rule
    (used by :func:`mu_flash` in factorised form; exposed for tests)."""
    q = np.atleast_1d(np.asarray(q_per_m, float))
    qp = np.atleast_1d(np.asarray(qp_per_m, float))
    s = D_m2_s * t0_s
    klo = 1e-5 * min(2 * q.min(), 2 * qp.min(), 1 / np.sqrt(s))
    khi = 1e3 * 2 * max(q.max(), qp.max())
    k, wk = k_rule(klo, khi, per_decade)
    F = -np.expm1(-s * k * k) / (D_m2_s * k * k) / np.pi
    A = 4 * qp[None, :] / (k[:, None] ** 2 + 4 * qp[None, :] ** 2)
    B = 4 * q[None, :] ** 2 / (k[:, None] ** 2 + 4 * q[None, :] ** 2)
    return (B * (wk * F)[:, None]).T @ A


def _anderson_step(X, R, T, r, beta, reg=1e-10):
    """One Anderson (type II) update per row. X, R: (nv, m, nq) histories of iterates and
    residuals (differences computed here); T, r: (nv, nq) current iterate and residual."""
    dX = np.diff(X, axis=1)
    dR = np.diff(R, axis=1)
    Mtx = dR @ dR.transpose(0, 2, 1)
    scale = np.trace(Mtx, axis1=1, axis2=2)[:, None, None] + 1e-300
    Mtx = Mtx + (reg * scale + 1e-300) * np.eye(Mtx.shape[1])[None]
    rhs = dR @ r[:, :, None]
    gam = np.linalg.solve(Mtx, rhs)[:, :, 0]
    return T + beta * r - np.einsum("vm,vmq->vq", gam, dX + beta[:, :, None] * dR)


def mu_flash(psd, rubber, v_m_per_s, sigma0_Pa=0.2e6, nu=0.5, T0_C=None, zeta_m=3.0,
             asperity_abc=(0.0, 2 * np.sqrt(np.pi), 0.5), tol=1e-3, wlf_form="relative",
             max_iter=400, beta=0.5, memory=6):
    """Kinetic friction with flash heating, solved self-consistently for T_q at every speed.

    Parameters
    ----------
    psd, rubber, v_m_per_s, sigma0_Pa, nu, T0_C, wlf_form : as :func:`mu_isothermal`.
    zeta_m : float, macro-asperity magnification, ``q_m = zeta_m q0`` (2 < zeta_m < 5).
    asperity_abc : (a, b, c), ``R = (a + b P(q_m)^c) / q_m`` [m]; the default
        (0, 2 sqrt(pi), 1/2) means spots at areal density (q_m/2pi)^2 covering P(q_m).
        (a, b, c) = (R q_m, 0, 0) fixes R.
    tol : relative accuracy target (sets the q grid, ~40 nodes/decade at 1e-3); the fixed point
        is converged to ``max |Phi(T) - T| <= 1e-2 tol max(1 K, max(T - T0))``.
    max_iter, beta, memory : solver controls (iterations, damping, Anderson memory).

    Returns
    -------
    FrictionResult with ``T_q_C`` (nv, nq), ``iterations`` and ``residual`` [K];
    ``meta['R_m']`` (nv,) the macro-asperity radius.

    Raises
    ------
    RuntimeError if the fixed point is not reached within ``max_iter`` iterations.
    """
    v = _check(psd, v_m_per_s, sigma0_Pa, nu)
    T0 = rubber.T_ref_C if T0_C is None else float(T0_C)
    th = rubber.thermal
    D = th.diffusivity_m2_s
    rc = th.heat_capacity_J_m3K
    q_m = zeta_m * psd.q0_per_m
    if not (psd.q_min_per_m <= q_m <= psd.q1_per_m):
        raise ValueError("q_m = zeta_m q0 must lie inside the spectrum's band")
    q, h = q_grid(_breakpoints(psd, [q_m]), q_nodes_per_decade(tol))
    im = int(np.argmin(np.abs(np.log(q / q_m))))
    C = psd.C(q)
    a_, b_, c_ = asperity_abc
    s_fac = (1.0 - nu * nu)

    # heat kernel factors on a k grid wide enough for every speed and every R <= R_max
    R_max = (a_ + b_) / q_m
    s_max = D * R_max / v.min()
    klo = 1e-5 * min(2 * q[0], 1 / np.sqrt(s_max))
    khi = 1e3 * 2 * q[-1]
    k, wk = k_rule(klo, khi)
    A = 4 * q[:, None] / (k[None, :] ** 2 + 4 * q[:, None] ** 2) * q[:, None]  # (nq, nk), incl. dq = q ds
    B = 4 * q[None, :] ** 2 / (k[:, None] ** 2 + 4 * q[None, :] ** 2)            # (nk, nq)
    k2 = k * k
    pre = (v[:, None] * q ** 4 * C) * 4.0 / (rc * s_fac)                        # (nv, nq)

    x0 = v[:, None] * q[None, :]
    lo_shift = float(np.min(log10_shift(rubber, np.array([T0, T0 + 2000.0]), wlf_form, T0)))
    hi_shift = float(np.max(log10_shift(rubber, np.array([T0, T0 + 2000.0]), wlf_form, T0)))
    tab = phi_table(rubber, x0.min() * 10 ** lo_shift, x0.max() * 10 ** hi_shift)

    def state(T):
        a = 10.0 ** log10_shift(rubber, T, wlf_form, T0)
        m, w = tab(x0 * a)
        G, P, wP, fmu = contact_state(q, h, C, m, w, sigma0_Pa, nu)
        return m, G, P, wP, fmu

    def phi_map(T):
        m, G, P, wP, fmu = state(T)
        Pm = P[:, im]
        R = (a_ + b_ * Pm ** c_) / q_m
        s = D * R / v
        F = -np.expm1(-s[:, None] * k2[None, :]) / (D * k2[None, :]) / np.pi  # (nv, nk)
        u = wP * pre * m / Pm[:, None]                                         # (nv, nq)
        Tn = T0 + ((u @ A) * (F * wk)) @ B
        return Tn, R

    T = np.full((v.size, q.size), T0)
    hist_X, hist_R = [], []
    beta_v = np.full(v.size, float(beta))
    prev = np.full(v.size, np.inf)
    it, res = 0, np.inf
    converged = False
    for it in range(1, max_iter + 1):
        Tn, R = phi_map(T)
        r = Tn - T
        res_rows = np.max(np.abs(r), axis=1)
        res = float(res_rows.max())
        if res <= 1e-2 * tol * max(1.0, float(np.max(Tn - T0))):
            converged = True
            T = Tn
            break
        # safeguard per speed: a growing residual means the accelerated step overshot (the map
        # is steeply decreasing at high speed): drop that row's history and damp harder.
        bad = res_rows > prev
        beta_v = np.where(bad, np.maximum(beta_v * 0.5, 1.0 / 64), np.minimum(beta_v * 1.25, beta))
        prev = res_rows
        for X, Rr in zip(hist_X, hist_R):
            X[bad], Rr[bad] = T[bad], r[bad]
        hist_X.append(T.copy())
        hist_R.append(r.copy())
        if len(hist_X) > memory + 1:
            hist_X.pop(0)
            hist_R.pop(0)
        bcol = beta_v[:, None]
        if len(hist_X) >= 2:
            Tnew = _anderson_step(np.stack(hist_X, 1), np.stack(hist_R, 1), T, r, bcol)
        else:
            Tnew = T + bcol * r
        T = np.clip(Tnew, T0, T0 + 1e4)
    if not converged:
        raise RuntimeError(f"flash temperature did not converge: residual {res:.3g} K after {it} iterations")
    m, G, P, wP, fmu = state(T)
    mu = 0.5 * np.sum(wP * fmu, axis=-1)
    meta = dict(model="flash", sigma0_Pa=sigma0_Pa, nu=nu, T0_C=T0, tol=tol, wlf_form=wlf_form,
                q0_per_m=psd.q0_per_m, zeta_m=zeta_m, q_m_per_m=q_m, asperity_abc=tuple(asperity_abc),
                R_m=R, q_nodes=q.size, k_nodes=k.size, phi_nodes=tab.phi_nodes,
                thermal=th)
    return FrictionResult(v, mu, q, P, G, T, it, res, meta)
