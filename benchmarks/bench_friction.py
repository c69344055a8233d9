"""Speed of the friction engine against a straightforward loop implementation (the thesis's
method: Python loops over velocities and wave vectors, phi integral per (v, q)), run in the same
process on the same q grid and phi rule. Targets (issue 3): isothermal mu(v) at 100 speeds at
0.1 % accuracy < 30 ms and >= 20x the loop; flash model at 50 speeds < 0.5 s.

Run:  .venv/bin/python benchmarks/bench_friction.py
"""
from __future__ import annotations

import time

import numpy as np
from scipy.special import erf

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
            W = 4 * np.dot(np.abs(E) ** 2, wphi) / s ** 2
            Cq = psd.C(qq)
            g = qq ** 4 * Cq * W / 8
            f = qq ** 4 * Cq * M
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


def best_of(fn, n=5):
    ts = []
    for _ in range(n):
        t = time.perf_counter()
        r = fn()
        ts.append(time.perf_counter() - t)
    return min(ts), r


def main():
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
    print(f"  fast: {t_fast * 1e3:.1f} ms (first call incl. phi table: {t_cold * 1e3:.1f} ms)   "
          f"loop: {t_loop * 1e3:.0f} ms   ratio {t_loop / t_fast:.0f}x")
    print(f"  max |mu/mu(tol 1e-5) - 1|: fast {np.max(np.abs(res.mu / ref - 1)):.2e}, "
          f"loop {np.max(np.abs(mu_loop / ref - 1)):.2e}")
    print(f"  targets: < 30 ms: {'OK' if t_fast < 0.03 else 'MISSED'}; "
          f">= 20x: {'OK' if t_loop / t_fast >= 20 else 'MISSED'}")

    fpsd = SelfAffinePSD(0.8, 6.67e-4, 1500.0, 6e5)
    v50 = np.logspace(-8, 2, 50)
    t_fl, fl = best_of(lambda: mu_flash(fpsd, rub, v50, sigma0_Pa=0.4e6), n=3)
    print(f"flash, 50 speeds, tol 1e-3 ({fl.q_per_m.size} q nodes, {fl.meta['k_nodes']} k nodes): "
          f"{t_fl * 1e3:.0f} ms, {fl.iterations} iterations, residual {fl.residual:.2g} K   "
          f"target < 0.5 s: {'OK' if t_fl < 0.5 else 'MISSED'}")


if __name__ == "__main__":
    main()
