"""Benchmark of the whole spectrum step (level, window, FFT, angular average) on the thesis's
grid, 1088 x 978 points, as a ratio to a bare floor run in the same process: numpy rfft2 of the
raw heights plus a ring average by np.bincount (no levelling, no window, no 2D map).
Goal: ratio <= 1.5. If SurfaceTopography is importable, also the ratio to its
power_spectrum_from_area (goal: faster).

Run: .venv/bin/python benchmarks/bench_psd.py
"""
import time

import numpy as np

from roadscan.level import level
from roadscan.spectrum import psd_area
from roadscan.synth import self_affine_surface

NY, NX, A_M = 1088, 978, 55.4e-6
REPEAT = 15


def floor_step(h, dx, dy, rings_per_decade=20):
    ny, nx = h.shape
    F = np.fft.rfft2(h)
    P = (F.real**2 + F.imag**2) * (dx * dy) ** 2 / ((2 * np.pi) ** 2 * nx * dx * ny * dy)
    qx = 2 * np.pi * np.fft.rfftfreq(nx, dx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, dy)
    q = np.hypot(qx[None, :], qy[:, None])
    q_min, q_max = 2 * np.pi / max(nx * dx, ny * dy), np.pi / max(dx, dy)
    n = int(np.ceil(rings_per_decade * np.log10(q_max / q_min)))
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.floor(np.log(q / q_min) / np.log(q_max / q_min) * n).astype(np.int64).ravel()
    ok = (r >= 0) & (r < n)
    cnt = np.bincount(r[ok], minlength=n)
    csum = np.bincount(r[ok], weights=P.ravel()[ok], minlength=n)
    keep = cnt > 0
    return csum[keep] / cnt[keep]


def ours(hm):
    return psd_area(level(hm, 1))


def best_times(fns, repeat=REPEAT):
    """Run the candidates interleaved (so background load hits them alike); best and median."""
    for fn in fns:
        fn()                                        # warm up (plans, caches)
    times = [[] for _ in fns]
    for _ in range(repeat):
        for fn, ts in zip(fns, times):
            t = time.perf_counter()
            fn()
            ts.append(time.perf_counter() - t)
    return [(min(ts), float(np.median(ts))) for ts in times]


def main():
    hm = self_affine_surface(NX, NY, dx_m=A_M, hurst=0.86, rms_height_m=0.5e-3, seed=0)
    h = hm.heights_m + 1e-4                          # an offset: ours levels it, the floor not
    hm = hm.with_heights(h)
    (t_floor, m_floor), (t_ours, m_ours) = best_times(
        [lambda: floor_step(h, A_M, A_M), lambda: ours(hm)])
    print(f"grid {NY} x {NX}; best of {REPEAT} (median in brackets)")
    print(f"floor  numpy rfft2 + bincount ring average : {t_floor * 1e3:7.1f} ms ({m_floor * 1e3:.1f})")
    print(f"roadscan level + psd_area (window, 2D map): {t_ours * 1e3:7.1f} ms ({m_ours * 1e3:.1f})")
    print(f"ratio roadscan / floor = {t_ours / t_floor:.2f} (goal <= 1.5)")
    try:
        from SurfaceTopography import Topography
    except ImportError:
        print("SurfaceTopography not installed: no comparison with power_spectrum_from_area")
        return
    topo = Topography(h, physical_sizes=(NY * A_M, NX * A_M))
    (t_st, m_st), = best_times([lambda: topo.power_spectrum_from_area()])
    print(f"SurfaceTopography power_spectrum_from_area : {t_st * 1e3:7.1f} ms ({m_st * 1e3:.1f})")
    print(f"ratio roadscan / SurfaceTopography = {t_ours / t_st:.2f} (goal < 1)")


if __name__ == "__main__":
    main()
