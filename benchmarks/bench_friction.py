"""Speed of the friction engine against independent formulations run in the same process.

Isothermal: against a straightforward loop implementation (the thesis's method: Python loops
over velocities and wave vectors, phi integral per (v, q)) on the same q grid and phi rule.
Targets (issue 3): mu(v) at 100 speeds at 0.1 % accuracy < 30 ms and >= 20x the loop.

Flash (issue 13): ``mu_flash`` against a formulation of the flash model written here from the
equations of DESIGN.md section 5 (its own q points with a sqrt-graded rule for the P(q)
singularity, graded Gauss-Legendre panels in phi, a Gauss-Legendre k rule for the heat kernel)
solved by a plain damped fixed point to a tight residual (1e-9 of the rise). Printed per case:
the engine's iterations and time; the iterations and time the plain damped fixed point needs to
reach the engine's own residual criterion (``max |Phi(T) - T| <= 1e-5 max(1 K, rise)`` at
tol 1e-3); the agreement of mu and of the temperature rises at zeta = 1 and zeta_max; and the
engine's previous solver (the loop before issue 13, kept below as a baseline on the engine's map)
with its iterations and time. Targets: at most 60 iterations for 50 speeds over 1e-8..1e4 m/s,
at most 100 over 1e2..1e4 m/s, at most half the previous solver's time.

Run:  .venv/bin/python benchmarks/bench_friction.py [--quick]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from scipy.special import erf

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import friction.flash as _flash
from friction import SelfAffinePSD, StandardLinearSolid, mu_flash, mu_isothermal, thesis_rubber
from friction.grids import phi_rule


def loop_isothermal(psd, rubber, v, q, sigma0=0.2e6, nu=0.5):
    """Reference loop: for each v, for each q: phi integrals (vectorised over phi only), G by
    the trapezoid rule in ln q, P at the node, mu by the trapezoid rule with P averaged over
    each interval by Simpson's rule on G (so that it converges like the fast path)."""
    c, wphi = phi_rule()
    s = (1 - nu * nu) * sigma0
    out = []
    for vv in v:
        G_prev, g_prev, f_prev, P_prev = 0.0, None, None, 1.0
        mu = 0.0
        for i, qq in enumerate(q):
            E = rubber.modulus_ref(qq * vv * c)
            M = 4 * np.dot(c * E.imag, wphi) / s
            W = 4 * np.dot(np.abs(E) ** 2, wphi) / s**2
            Cq = psd.C(qq)
            g = qq**4 * Cq * W / 8
            f = qq**4 * Cq * M
            if i == 0:
                G, P = 0.0, 1.0
            else:
                h = np.log(qq / q[i - 1])
                G = G_prev + 0.5 * h * (g + g_prev)
                P = erf(0.5 / np.sqrt(G))
                Pm = erf(0.5 / np.sqrt(0.5 * (G + G_prev))) if G + G_prev > 0 else 1.0
                mu += 0.5 * h * 0.5 * (f_prev + f) * (P_prev + 4 * Pm + P) / 6
            G_prev, g_prev, f_prev, P_prev = G, g, f, P
        out.append(mu)
    return np.array(out)


# ----------------------------------------------------------------------------- flash reference
def _gl(n):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1), 0.5 * w  # nodes and weights on (0, 1)


SQRT_PI = float(np.sqrt(np.pi))


def flash_reference(
    psd,
    rubber,
    v,
    sigma0=0.4e6,
    nu=0.5,
    zeta_m=3.0,
    abc=(0.0, 2 * SQRT_PI, 0.5),
    per_decade=32,
    beta=0.3,
    rtol=1e-9,
    engine_rtol=1e-5,
    max_iter=4000,
):
    """The flash model of DESIGN.md sec 5 written from the equations, solved by a plain damped
    fixed point ``T <- T + beta (Phi(T) - T)`` until ``max|Phi(T) - T| <= rtol max(1 K, rise)``.

    q: intervals uniform in ln q (``per_decade``), 4 Gauss points per interval in s with
    ln q = ln q_i + s^2 h (the sqrt grading integrates P ~ 1/sqrt(q - q0) at high speed);
    G is integrated over whole intervals and interpolated linearly in ln q inside them.
    phi: 7 Gauss-Legendre panels of 8 nodes on [0, pi/2], graded towards pi/2.
    k: Gauss-Legendre panels of 8 nodes per decade in ln k.
    Returns mu, T at the q points, the q points, the iterations to reach ``engine_rtol`` and
    ``rtol``, and the time to each.
    """
    t_start = time.perf_counter()
    v = np.asarray(v, float)
    T0 = rubber.T_ref_C
    th = rubber.thermal
    D, rc = th.diffusivity_m2_s, th.rho_kg_m3 * th.c_v_J_kgK
    lo, hi = np.log(psd.q_min_per_m), np.log(psd.q1_per_m)
    n_int = int(np.ceil((hi - lo) / np.log(10) * per_decade))
    h = (hi - lo) / n_int
    s_, ws = _gl(4)
    t_ = s_**2
    xi = lo + h * np.arange(n_int)
    q = np.exp(xi[:, None] + h * t_[None, :]).ravel()  # (nf,)
    wq = (h * 2 * s_ * ws)[None, :] * np.exp(xi[:, None] + h * t_[None, :])
    wq = wq.ravel()  # dq weights
    C = psd.C(q)
    # phi panels graded towards pi/2
    edges = np.pi / 2 * np.concatenate([1 - 0.5 ** np.arange(7), [1.0]])
    xg, wg = _gl(8)
    phi = (edges[:-1, None] + np.diff(edges)[:, None] * xg[None, :]).ravel()
    wphi = (np.diff(edges)[:, None] * wg[None, :]).ravel()
    cphi = np.cos(phi)
    s_fac = 1 - nu * nu
    q_m = zeta_m * psd.q0_per_m
    a_, b_, c_ = abc
    # k rule wide enough for every speed (R <= (a + b) / q_m)
    t0_max = (a_ + b_) / q_m / v.min()
    klo = 1e-4 * min(2 * q[0], 1 / np.sqrt(D * t0_max))
    khi = 1e3 * 2 * q[-1]
    dec = np.arange(np.floor(np.log10(klo)), np.ceil(np.log10(khi)))
    lk = (np.log(10) * (dec[:, None] + xg[None, :])).ravel()
    k = np.exp(lk)
    wk = (np.log(10) * np.ones_like(dec)[:, None] * wg[None, :]).ravel() * k
    A = 4 * q[None, :] / (k[:, None] ** 2 + 4 * q[None, :] ** 2)  # (nk, nf)
    B = 4 * q[None, :] ** 2 / (k[:, None] ** 2 + 4 * q[None, :] ** 2)  # (nk, nf)
    ref_shift = rubber.shift.log10_aT(T0)
    im = np.searchsorted(q, q_m)
    tm = (np.log(q_m) - np.log(q[im - 1])) / (np.log(q[im]) - np.log(q[im - 1]))

    def contact(T):
        a = 10.0 ** (rubber.shift.log10_aT(T) - ref_shift)  # (nv, nf)
        E = rubber.modulus_ref((v[:, None, None] * q[None, :, None] * a[:, :, None]) * cphi[None, None, :])
        m = np.einsum("vqp,p->vq", cphi * E.imag, wphi)  # int_0^pi/2 cos Im E
        w2 = np.einsum("vqp,p->vq", np.abs(E) ** 2, wphi)
        g = q**3 * C * (4 * w2 / (s_fac * sigma0) ** 2) / 8
        # G at the interval ends, then linear in ln q inside each interval
        Gint = np.cumsum((g * wq).reshape(v.size, n_int, 4).sum(-1), axis=1)
        Gn = np.concatenate([np.zeros((v.size, 1)), Gint], axis=1)  # at xi and hi
        G = Gn[:, :-1, None] + (Gn[:, 1:] - Gn[:, :-1])[:, :, None] * t_[None, None, :]
        G = G.reshape(v.size, -1)
        with np.errstate(divide="ignore"):
            P = np.where(G > 0, erf(0.5 / np.sqrt(G)), 1.0)
        return m, P

    def phi_map(T):
        m, P = contact(T)
        Pm = P[:, im - 1] * (1 - tm) + P[:, im] * tm
        R = (a_ + b_ * Pm**c_) / q_m
        t0 = R / v
        F = -np.expm1(-D * k[None, :] ** 2 * t0[:, None]) / (D * k[None, :] ** 2) / np.pi
        f = v[:, None] * q**4 * C * P / (rc * Pm[:, None]) * 4 * m / s_fac  # [K m/s]
        return T0 + ((f * wq) @ A.T * F * wk) @ B, m, P

    T = np.full((v.size, q.size), T0)
    it_engine = t_engine = None
    for it in range(1, max_iter + 1):
        Tn, m, P = phi_map(T)
        res = np.max(np.abs(Tn - T), axis=1)
        rise = np.maximum(1.0, np.max(Tn - T0, axis=1))
        if it_engine is None and np.all(res <= engine_rtol * rise):
            it_engine, t_engine = it, time.perf_counter() - t_start
        if np.all(res <= rtol * rise):
            T = Tn
            break
        T = T + beta * (Tn - T)
    else:
        raise RuntimeError(f"reference flash solver did not converge in {max_iter} iterations")
    m, P = contact(T)
    mu = 0.5 * np.sum(q**3 * C * P * (4 * m / (s_fac * sigma0)) * wq, axis=1)
    return dict(
        mu=mu,
        T=T,
        q=q,
        it_engine=it_engine,
        t_engine=t_engine,
        it_tight=it,
        t_tight=time.perf_counter() - t_start,
    )


def previous_solver(phi_map, nv, nq, T0, tol, max_iter, beta, memory, v=None):
    """The engine's fixed-point loop before issue 13 (global damped Anderson, memory 6, beta
    halved on every residual growth), verbatim in substance, as the time baseline. It runs on
    the engine's own map; its iteration limit is raised so that it finishes."""
    T = np.full((nv, nq), T0)
    hist_X, hist_R = [], []
    beta_v = np.full(nv, 0.5)
    prev = np.full(nv, np.inf)
    rows = np.arange(nv)
    for it in range(1, 5001):
        Tn, R = phi_map(T, rows)
        r = Tn - T
        res_rows = np.max(np.abs(r), axis=1)
        res = float(res_rows.max())
        if res <= 1e-2 * tol * max(1.0, float(np.max(Tn - T0))):
            return Tn, R, it, res
        bad = res_rows > prev
        beta_v = np.where(bad, np.maximum(beta_v * 0.5, 1.0 / 64), np.minimum(beta_v * 1.25, 0.5))
        prev = res_rows
        for X, Rr in zip(hist_X, hist_R):
            X[bad], Rr[bad] = T[bad], r[bad]
        hist_X.append(T.copy())
        hist_R.append(r.copy())
        if len(hist_X) > 7:
            hist_X.pop(0)
            hist_R.pop(0)
        if len(hist_X) >= 2:
            Tnew = _flash._anderson_step(np.stack(hist_X, 1), np.stack(hist_R, 1), T, r, beta_v)
        else:
            Tnew = T + beta_v[:, None] * r
        T = np.clip(Tnew, T0, T0 + 1e4)
    raise RuntimeError("previous solver did not converge in 5000 iterations")


def bench_flash(quick=False):
    rub = thesis_rubber()
    fpsd = SelfAffinePSD(0.8, 6.67e-4, 1500.0, 6e5)  # DESIGN.md sec 6, flash set
    cases = [
        ("1e-8..1e4", -8, 4, 0.4e6, 60),
        ("1e2..1e4", 2, 4, 0.4e6, 100),
        ("1e-8..1e4", -8, 4, 0.2e6, 60),
        ("1e2..1e4", 2, 4, 0.2e6, 100),
    ]
    if quick:
        cases = cases[:2]
    print("flash, 50 speeds, tol 1e-3 (flash PSD of DESIGN.md sec 6: H 0.8, q0 1500, q1/q0 400)")
    print(
        f"{'speeds [m/s]':>12} {'sigma0':>7} | {'engine it':>9} {'ms':>6} | {'previous it':>11} "
        f"{'ms':>6} {'t/prev':>6} | {'plain it':>8} {'ms':>7} {'it tight':>8} | "
        f"{'mu diff':>8} {'dT(1)':>7} {'dT(max)':>7} | goal"
    )
    ok = True
    ratios = []
    for name, lo, hi, s0, goal in cases:
        v = np.logspace(lo, hi, 50)
        t_new, res = best_of(lambda v=v, s0=s0: mu_flash(fpsd, rub, v, sigma0_Pa=s0), n=3)
        saved = _flash._solve_flash
        _flash._solve_flash = previous_solver
        try:
            t_old, old = best_of(lambda v=v, s0=s0: mu_flash(fpsd, rub, v, sigma0_Pa=s0), n=1)
        finally:
            _flash._solve_flash = saved
        ref = flash_reference(fpsd, rub, v, sigma0=s0)
        dmu = np.max(np.abs(res.mu / ref["mu"] - 1))
        zmax = fpsd.q1_per_m / fpsd.q0_per_m
        lq = np.log(ref["q"])
        T1 = np.array([np.interp(np.log(fpsd.q0_per_m), lq, t) for t in ref["T"]])
        Tm = np.array([np.interp(np.log(fpsd.q1_per_m), lq, t) for t in ref["T"]])
        rise = np.maximum(1.0, Tm - 60.0)
        d1 = np.max(np.abs(res.temperature_at(1.0) - T1) / rise)
        dm = np.max(np.abs(res.temperature_at(zmax) - Tm) / rise)
        good = res.iterations <= goal and t_new <= 0.5 * t_old
        ok &= good
        print(
            f"{name:>12} {s0 / 1e6:5.1f}MP | {res.iterations:9d} {t_new * 1e3:6.0f} | "
            f"{old.iterations:11d} {t_old * 1e3:6.0f} {t_new / t_old:6.2f} | "
            f"{ref['it_engine']:8d} {ref['t_engine'] * 1e3:7.0f} {ref['it_tight']:8d} | "
            f"{dmu:8.1e} {d1:7.1e} {dm:7.1e} | <= {goal} it, <= 0.5x: {'OK' if good else 'MISSED'}"
        )
        ratios.append(
            f"RATIO | flash iterations / goal, 50 speeds {name} m/s, {s0 / 1e6:g} MPa | "
            f"{res.iterations / goal:.2f} | <= 1 ({goal} it) | "
            f"{'PASS' if res.iterations <= goal else 'FAIL'} | {res.iterations} it; the plain damped "
            f"fixed point needs {ref['it_engine']} to the same residual; mu within {dmu:.1e} of it"
        )
        ratios.append(
            f"RATIO | flash time / previous solver's, 50 speeds {name} m/s, {s0 / 1e6:g} MPa | "
            f"{t_new / t_old:.2f} | <= 0.5 | {'PASS' if t_new <= 0.5 * t_old else 'FAIL'} | "
            f"{t_new * 1e3:.0f} ms against {t_old * 1e3:.0f} ms ({old.iterations} it)"
        )
    print(
        "  mu diff: max |mu/mu_ref - 1|; dT: max |T - T_ref| / max(1 K, rise at zeta_max), both "
        "against the plain damped fixed point converged to 1e-9 (its own discretisation)"
    )
    print("\n".join(ratios))
    return ok


def best_of(fn, n=5):
    ts = []
    for _ in range(n):
        t = time.perf_counter()
        r = fn()
        ts.append(time.perf_counter() - t)
    return min(ts), r


def main(argv=None):
    ap = argparse.ArgumentParser(description="friction engine benchmark")
    ap.add_argument("--quick", action="store_true", help="only the two 0.4 MPa flash cases")
    quick = ap.parse_args(argv).quick
    psd = SelfAffinePSD(0.85, 5e-4, 2000.0, 2e5)
    v = np.logspace(-8, 4, 100)

    rub_cold = StandardLinearSolid()  # fresh rubber: includes building its phi table
    t = time.perf_counter()
    res = mu_isothermal(psd, rub_cold, v, tol=1e-3)
    t_cold = time.perf_counter() - t
    rub = thesis_rubber()
    t_fast, res = best_of(lambda: mu_isothermal(psd, rub, v, tol=1e-3))
    q = res.q_per_m
    t_loop, mu_loop = best_of(lambda: loop_isothermal(psd, rub, v, q), n=1)
    ref = mu_isothermal(psd, rub, v, tol=1e-5).mu
    print(f"isothermal, 100 speeds, tol 1e-3 ({q.size} q nodes, {res.meta['phi_nodes']} phi nodes)")
    print(
        f"  fast: {t_fast * 1e3:.1f} ms (first call incl. phi table: {t_cold * 1e3:.1f} ms)   "
        f"loop: {t_loop * 1e3:.0f} ms   ratio {t_loop / t_fast:.0f}x"
    )
    print(
        f"  max |mu/mu(tol 1e-5) - 1|: fast {np.max(np.abs(res.mu / ref - 1)):.2e}, "
        f"loop {np.max(np.abs(mu_loop / ref - 1)):.2e}"
    )
    print(
        f"  targets: < 30 ms: {'OK' if t_fast < 0.03 else 'MISSED'}; "
        f">= 20x: {'OK' if t_loop / t_fast >= 20 else 'MISSED'}"
    )
    print(
        f"RATIO | isothermal mu(v), 100 speeds at 0.1 %: engine time / loop reference's | "
        f"{t_fast / t_loop:.3f} | <= 0.05 (20x) | {'PASS' if t_loop / t_fast >= 20 else 'FAIL'} | "
        f"{t_fast * 1e3:.1f} ms against {t_loop * 1e3:.0f} ms; mu within "
        f"{np.max(np.abs(res.mu / ref - 1)):.1e} of tol 1e-5"
    )

    bench_flash(quick=quick)


if __name__ == "__main__":
    main()
