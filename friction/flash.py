"""Persson's flash-temperature model (Persson 2006, J. Phys.: Condens. Matter 18, 7789,
doi:10.1088/0953-8984/18/32/025; thesis eqs 3.1 to 3.7).

The rubber heats at every length scale::

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
The self-consistent T_q is found for every speed side by side (:func:`_solve_flash`): a damped
fixed point with an adaptive damping per speed (cut when successive residuals oppose, grown
along aligned ones) and Anderson acceleration (Walker & Ni 2011) once that speed's residual
falls steadily; a converged speed leaves the active set, so the cost follows the hard speeds
only. On the thesis's flash-temperature parameter set it takes about 20 map evaluations for 50 speeds over
1e-8..1e4 m/s (the damped loop it replaced took 572; benchmarks/bench_friction.py). The
iteration count and the final residual ``max |Phi(T) - T|`` [K] are reported, and a
:class:`FlashConvergenceError` (a RuntimeError, one line) is raised if it does not converge.
"""

from __future__ import annotations

import numpy as np

from ._flash_errors import FlashBandError, FlashConvergenceError
from .contact import contact_S
from .grids import phi_table, q_grid, q_nodes_per_decade
from .isothermal import _breakpoints, _check, contact_state
from .result import FrictionResult
from .rubber import log10_shift

__all__ = ["mu_flash", "heat_kernel", "FlashConvergenceError", "FlashBandError", "T_RISE_MAX_K", "ZETA_M"]

#: Flash temperature rises T_q - T0 [K] the viscoelastic tables are built for; the iterates are
#: kept in [T0, T0 + 1e4 K]. A solve that fails after reaching rises above this is reported as
#: runaway heating (rubber is destroyed long before), not as a numerical failure.
T_RISE_MAX_K = 2000.0
#: default macro-asperity magnification of :func:`mu_flash`, q_m = ZETA_M q0 (2 < zeta_m < 5)
ZETA_M = 3.0
#: default (a, b, c) of the hot spots' radius R = (a + b P(q_m)^c) / q_m [m]: (0, 2 sqrt(pi), 1/2)
ASPERITY_ABC = (0.0, 2 * float(np.sqrt(np.pi)), 0.5)


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
    (used by :func:`mu_flash` in factorised form; exposed for tests).

    Parameters
    ----------
    q_per_m : array_like
        Wave vectors q where the temperature is wanted [1/m].
    qp_per_m : array_like
        Source wave vectors q' [1/m].
    D_m2_s : float
        Thermal diffusivity lambda / (rho c_v) of the rubber [m^2/s].
    t0_s : float
        Contact time R / v of a macro-asperity [s].
    per_decade : int, optional
        Nodes per decade of the trapezoid rule in ln k.

    Returns
    -------
    ndarray, shape (len(q), len(q'))
        g(q, q') [s].

    References
    ----------
    B.N.J. Persson, J. Phys.: Condens. Matter 18, 7789 (2006), doi:10.1088/0953-8984/18/32/025.
    """
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
    """One Anderson (type II) update per row (Walker & Ni 2011, eq. 2.1 with damping beta).

    X, R : (n, m, nq) histories of iterates and residuals ``Phi(X) - X`` (oldest first, the
    current pair last); T, r : (n, nq) current iterate and residual; beta : (n,) damping.
    Minimises ``|r - dR gamma|`` (Tikhonov-regularised at ``reg`` x the trace, so that repeated
    entries are harmless) and returns ``T + beta r - (dX + beta dR) gamma``.
    """
    dX = np.diff(X, axis=1)
    dR = np.diff(R, axis=1)
    Mtx = dR @ dR.transpose(0, 2, 1)
    scale = np.trace(Mtx, axis1=1, axis2=2)[:, None, None] + 1e-300
    Mtx = Mtx + (reg * scale + 1e-300) * np.eye(Mtx.shape[1])[None]
    rhs = dR @ r[:, :, None]
    gam = np.linalg.solve(Mtx, rhs)[:, :, 0]
    b = np.asarray(beta, dtype=float).reshape(-1, 1)
    return T + b * r - np.einsum("vm,vmq->vq", gam, dX + b[:, :, None] * dR)


def _solve_flash(
    phi_map,
    nv,
    nq,
    T0,
    tol,
    max_iter,
    beta,
    memory,
    v=None,
    osc=-0.3,
    cut=0.5,
    recover=1.25,
    T_cap=1e4,
    max_stretch=np.inf,
    enter=2,
    near=0.3,
    reg=1e-10,
    align=0.9,
    beta_max=1.0,
):
    """Self-consistent T_q at every speed: damped fixed point with Anderson acceleration.

    The speeds are independent problems ``T = Phi(T)`` (rows of T, nq unknowns each), solved
    side by side; a row leaves the active set (and costs nothing more) once
    ``max_q |Phi(T) - T| <= 1e-2 tol max(1 K, max_q (Phi(T) - T0))``, and its T is the last
    ``Phi(T)``. Per row:

    - Anderson mixing (type II, memory ``memory``) on the damped map ``T + beta (Phi(T) - T)``.
      Near the solution Phi is strongly *decreasing* in T at high speed (hotter rubber is softer
      and dissipates less), with Jacobian eigenvalues down to about -2 on the reference set: the
      damped map contracts only for beta < 2/3, and Anderson removes the slow modes.
    - Oscillation guard: when two successive residuals point in opposite directions
      (cosine < ``osc``) the row is overshooting (a 2-cycle of the undamped map, docs: Theory):
      its history is dropped and its beta cut by ``cut`` (down to 1/64); otherwise beta recovers
      by ``recover`` per step up to ``beta``. A residual that merely grows (the runaway region
      between T0 and the solution, where heating rises with T) is not an oscillation and does not
      cut beta: cutting there only slows the climb.
    - Iterates are kept in [T0, T0 + T_cap].

    Returns (T, R, iterations, residual): T (nv, nq) [C], R (nv,) [m] from the last map
    evaluation of each row, the largest number of map evaluations any row needed, and the
    largest final residual [K]. Raises FlashConvergenceError after ``max_iter`` evaluations.
    """
    m = max(int(memory), 1)
    beta_max = max(beta, beta_max)
    T = np.full((nv, nq), float(T0))
    T_out = np.empty((nv, nq))
    R_out = np.empty(nv)
    res_out = np.zeros(nv)
    act = np.arange(nv)
    HX = np.zeros((nv, m + 1, nq))
    HR = np.zeros((nv, m + 1, nq))
    nh = np.zeros(nv, dtype=int)
    r_prev = np.zeros((nv, nq))
    rr_prev = np.full(nv, np.inf)
    calm = np.zeros(nv, dtype=int)
    bv = np.full(nv, float(beta))
    ceil = np.full(nv, float(beta_max))
    capped = np.zeros(nv, dtype=bool)  # the row's iterate went above T0 + T_RISE_MAX_K
    rr = np.zeros(0)
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 - the count is returned after the loop
        Ta = T[act]
        Tn, R = phi_map(Ta, act)
        if not np.all(np.isfinite(Tn)):
            bad = act[~np.all(np.isfinite(Tn), axis=1)]
            speeds = "" if v is None else f" at v = {_speeds(v[bad])} m/s"
            raise FlashConvergenceError(f"flash temperature: the heat balance is not finite{speeds}")
        r = Tn - Ta
        rr = np.max(np.abs(r), axis=1)
        rise = np.maximum(1.0, np.max(Tn - T0, axis=1))
        done = rr <= 1e-2 * tol * rise
        if done.any():
            rows = act[done]
            T_out[rows], R_out[rows], res_out[rows] = Tn[done], R[done], rr[done]
            if done.all():
                break
            keep = np.flatnonzero(~done)
            k = keep.size
            for arr in (HX, HR, nh, r_prev, rr_prev, calm, bv, ceil, capped):
                arr[:k] = arr[keep]
            act, Ta, r, rr, rise = act[keep], Ta[keep], r[keep], rr[keep], rise[keep]
        k = act.size
        hx, hr, n, rp, rrp, cm, b, cl = (
            HX[:k],
            HR[:k],
            nh[:k],
            r_prev[:k],
            rr_prev[:k],
            calm[:k],
            bv[:k],
            ceil[:k],
        )
        cos = np.sum(r * rp, axis=1) / (np.sqrt(np.sum(r * r, axis=1) * np.sum(rp * rp, axis=1)) + 1e-300)
        oscil = cos < osc
        aligned = cos > align
        # an oscillating row lowers its own ceiling for good (so that beta cannot climb back
        # into the cycle), then beta grows again only along aligned residuals, up to that ceiling
        cl[:] = np.where(oscil, np.maximum(0.75 * b, 1.0 / 64), cl)
        b[:] = np.where(
            oscil,
            np.maximum(b * cut, 1.0 / 64),
            np.where(aligned, np.minimum(b * recover, cl), np.minimum(b, beta)),
        )
        # Anderson only where the map behaves like a contraction: the residual fell in each of
        # the last `enter` steps and is small against the rise; any growth restarts the history
        cm[:] = np.where(rr < rrp, cm + 1, 0)
        on = (cm >= enter) & (rr <= near * rise) & ~oscil
        n[~on] = 0
        rp[:] = r
        rrp[:] = rr
        full = on & (n == m + 1)
        hx[full, :-1] = hx[full, 1:]
        hr[full, :-1] = hr[full, 1:]
        n[full] -= 1
        idx = np.flatnonzero(on)
        hx[idx, n[idx]] = Ta[idx]
        hr[idx, n[idx]] = r[idx]
        n[idx] += 1
        step = b[:, None] * r  # the damped fixed-point step
        Tnew = Ta + step
        for L in np.unique(n[n >= 2]):
            g = np.flatnonzero(n == L)
            Ta_g = _anderson_step(hx[g, :L], hr[g, :L], Ta[g], r[g], b[g], reg)
            # an extrapolation far longer than the damped step is not trusted: damped step,
            # history dropped
            wild = np.max(np.abs(Ta_g - Ta[g]), axis=1) > max_stretch * np.max(np.abs(step[g]), axis=1)
            Tnew[g[~wild]] = Ta_g[~wild]
            n[g[wild]] = 0
        capped[:k] |= np.max(Tnew, axis=1) > T0 + T_RISE_MAX_K
        T[act] = np.clip(Tnew, T0, T0 + T_cap)
    else:
        k = act.size
        hot = capped[:k]
        if hot.any():
            speeds = "" if v is None else f" at v = {_speeds(v[act[hot]])} m/s"
            raise FlashConvergenceError(
                f"flash temperature runs away{speeds}: no self-consistent solution found, the "
                f"iterates rose more than {T_RISE_MAX_K:g} K above T0 (outside the model's range)"
            )
        speeds = "" if v is None else f" at v = {_speeds(v[act])} m/s"
        raise FlashConvergenceError(
            f"flash temperature did not converge{speeds}: residual {float(rr.max()):.3g} K "
            f"after {it} iterations"
        )
    return T_out, R_out, it, float(res_out.max())


def _speeds(v):
    v = np.asarray(v)
    return ", ".join(f"{x:.3g}" for x in v[:3]) + (f" (and {v.size - 3} more)" if v.size > 3 else "")


def mu_flash(
    psd,
    rubber,
    v_m_per_s,
    sigma0_Pa=0.2e6,
    nu=0.5,
    T0_C=None,
    zeta_m=ZETA_M,
    asperity_abc=ASPERITY_ABC,
    tol=1e-3,
    wlf_form="relative",
    max_iter=400,
    beta=0.5,
    memory=6,
    heat_scale=1.0,
    contact_gamma=None,
):
    """Kinetic friction with flash heating, solved self-consistently for T_q at every speed.

    The rubber at length scale 2 pi / q is at ``T_q = T0 + int_0^inf dq' g(q, q') f(q')``
    (see the module docstring for the kernel g [s] and the heat source f [K m/s]); the moduli in
    mu, P and G are taken at T_q. The fixed point is found by damped, Anderson-accelerated
    iteration over all speeds at once.

    Parameters
    ----------
    psd : SelfAffinePSD or TabulatedPSD
        Surface spectrum C(q) [m^4].
    rubber : StandardLinearSolid, Prony or MasterCurve
        The rubber; its ``thermal`` properties give rho, c_v and lambda.
    v_m_per_s : array_like
        Sliding speeds [m/s].
    sigma0_Pa : float or array_like, optional
        Nominal pressure [Pa] (default 0.2 MPa), or one per speed.
    nu : float, optional
        Poisson's ratio (0.5).
    T0_C : float, optional
        Background temperature [C]; None means ``rubber.T_ref_C``.
    zeta_m : float, optional
        Macro-asperity magnification, ``q_m = zeta_m q0`` (2 < zeta_m < 5; default 3).
    asperity_abc : tuple of float, optional
        (a, b, c) of ``R = (a + b P(q_m)^c) / q_m`` [m]; the default (0, 2 sqrt(pi), 1/2) means
        spots at areal density (q_m / 2 pi)^2 covering P(q_m); (R q_m, 0, 0) fixes R.
    tol : float, optional
        Relative accuracy target; the fixed point is converged to
        ``max |Phi(T) - T| <= 1e-2 tol max(1 K, max(T - T0))``.
    wlf_form : {"relative", "literal"}, optional
        As in :func:`mu_isothermal`.
    max_iter : int, optional
        Map evaluations allowed.
    beta : float, optional
        Initial damping.
    memory : int, optional
        Anderson memory.
    heat_scale : float, optional
        Factor on the heat source (1: the model; 0: no heating, exactly the isothermal result).
    contact_gamma : float, optional
        Persson's gamma of ``S = gamma + (1 - gamma) P^2``, applied to mu and the heat source.

    Returns
    -------
    FrictionResult
        With ``T_q_C`` (nv, nq) [C], ``iterations``, ``residual`` [K] and ``meta['R_m']`` (nv,),
        the macro-asperity radius [m].

    Raises
    ------
    FlashBandError
        A ValueError, when ``zeta_m q0`` lies outside the spectrum's band.
    FlashConvergenceError
        A RuntimeError, when the fixed point is not reached within ``max_iter`` evaluations; its
        one-line message names the speeds ("runs away" when the iterates rose more than
        :data:`T_RISE_MAX_K` above T0).

    References
    ----------
    B.N.J. Persson, "Rubber friction: role of the flash temperature", J. Phys.: Condens. Matter 18,
    7789 (2006), doi:10.1088/0953-8984/18/32/025.
    H.F. Walker, P. Ni, "Anderson acceleration for fixed-point iterations", SIAM J. Numer. Anal.
    49, 1715 (2011), doi:10.1137/10078356X.

    Examples
    --------
    >>> import numpy as np, friction
    >>> psd = friction.SelfAffinePSD(0.8, 6.67e-4, 1500, 6e5)
    >>> hot = friction.mu_flash(psd, friction.thesis_rubber(), np.logspace(-2, 1, 4), sigma0_Pa=0.4e6)
    >>> bool((hot.T_q_C >= 60 - 1e-9).all())
    True
    """
    v = _check(psd, v_m_per_s, sigma0_Pa, nu, contact_gamma)
    if not (np.isfinite(heat_scale) and heat_scale >= 0):
        raise ValueError(f"heat_scale must be a finite number >= 0, got {heat_scale!r}")
    if not (int(max_iter) >= 1):
        raise ValueError(f"max_iter must be >= 1, got {max_iter!r}")
    if not (0 < beta <= 1):
        raise ValueError(f"beta must lie in (0, 1], got {beta!r}")
    sig = sigma0_Pa if np.ndim(sigma0_Pa) == 0 else np.asarray(sigma0_Pa, dtype=float)
    T0 = rubber.T_ref_C if T0_C is None else float(T0_C)
    th = rubber.thermal
    D = th.diffusivity_m2_s
    rc = th.heat_capacity_J_m3K
    q_m = zeta_m * psd.q0_per_m
    if not (psd.q_min_per_m <= q_m <= psd.q1_per_m):
        raise FlashBandError(q_m, psd.q1_per_m, zeta_m)
    q, h = q_grid(_breakpoints(psd, [q_m]), q_nodes_per_decade(tol))
    im = int(np.argmin(np.abs(np.log(q / q_m))))
    C = psd.C(q)
    a_, b_, c_ = asperity_abc
    s_fac = 1.0 - nu * nu

    # heat kernel factors on a k grid wide enough for every speed and every R <= R_max
    R_max = (a_ + b_) / q_m
    s_max = D * R_max / v.min()
    klo = 1e-5 * min(2 * q[0], 1 / np.sqrt(s_max))
    khi = 1e3 * 2 * q[-1]
    k, wk = k_rule(klo, khi)
    A = 4 * q[:, None] / (k[None, :] ** 2 + 4 * q[:, None] ** 2) * q[:, None]  # (nq, nk), incl. dq = q ds
    B = 4 * q[None, :] ** 2 / (k[:, None] ** 2 + 4 * q[None, :] ** 2)  # (nk, nq)
    k2 = k * k
    pre = (v[:, None] * q**4 * C) * (4.0 * heat_scale / (rc * s_fac))  # (nv, nq)

    x0 = v[:, None] * q[None, :]
    span = log10_shift(rubber, np.array([T0, T0 + T_RISE_MAX_K]), wlf_form, T0)
    lo_shift, hi_shift = float(np.clip(np.min(span), -300, 300)), float(np.clip(np.max(span), -300, 300))
    tab = phi_table(rubber, x0.min() * 10**lo_shift, x0.max() * 10**hi_shift)

    def state(T, rows=slice(None)):
        # the clip keeps 10**shift a finite non-zero number where a shift table is extrapolated
        a = 10.0 ** np.clip(log10_shift(rubber, T, wlf_form, T0), -300.0, 300.0)
        m, w = tab(x0[rows] * a)
        G, P, wP, fmu = contact_state(q, h, C, m, w, sig if np.ndim(sig) == 0 else sig[rows], nu)
        S = contact_S(P, contact_gamma)
        return m * S, G, P, wP, fmu * S

    def phi_map(T, rows=slice(None)):
        """Phi(T) on the speeds ``rows`` (T holds those rows only); also R [m] there."""
        m, _G, P, wP, _fmu = state(T, rows)
        Pm = P[:, im]
        R = (a_ + b_ * Pm**c_) / q_m
        s = D * R / v[rows]
        F = -np.expm1(-s[:, None] * k2[None, :]) / (D * k2[None, :]) / np.pi  # (nv, nk)
        u = wP * pre[rows] * m / Pm[:, None]  # (nv, nq)
        Tn = T0 + ((u @ A) * (F * wk)) @ B
        return Tn, R

    T, R, it, res = _solve_flash(phi_map, v.size, q.size, T0, tol, int(max_iter), float(beta), memory, v=v)
    _m, G, P, wP, fmu = state(T)
    mu = 0.5 * np.sum(wP * fmu, axis=-1)
    meta = dict(
        model="flash",
        sigma0_Pa=sigma0_Pa,
        nu=nu,
        T0_C=T0,
        tol=tol,
        wlf_form=wlf_form,
        heat_scale=float(heat_scale),
        contact_gamma=contact_gamma,
        q0_per_m=psd.q0_per_m,
        zeta_m=zeta_m,
        q_m_per_m=q_m,
        asperity_abc=tuple(asperity_abc),
        R_m=R,
        q_nodes=q.size,
        k_nodes=k.size,
        phi_nodes=tab.phi_nodes,
        thermal=th,
    )
    return FrictionResult(v, mu, q, P, G, T, it, res, meta)
