"""Benchmark of the spectrum step, ``psd_area`` (window, FFT, |F|^2, angular average), against
the same-FFT floor at 512^2, 1024^2, 2048^2 and 4096^2 (issue 13: at most 1.2x at every size).

The floor is the least any implementation of this step can do with the same transform, run in
the same process on the same levelled heights, interleaved with roadscan (best of N each):

    F = rfft2(h * W)      # psd_area's own FFT for this size: numpy's up to 4 Mpx, scipy's
                          # with every core above (the same pocketfft, threads and dtype)
    P = F.real**2 + F.imag**2
    C_ring = np.bincount(RING, weights=P.ravel())   # RING: cached ring index of every point

with the 2D window ``W`` and the ring index ``RING`` (int64, out-of-range points in a spare bin)
computed once, outside the timing; it does not even weight the points whose mirror image the
half lattice omits, so it is a strict lower bound. roadscan's ``psd_area`` returns the same
angular average (checked here to 1e-10) plus the Spectrum2D (the half lattice; the full
fftshifted map is built only when read).

Also printed: ``level`` (plane fit and subtraction, a separate step) in milliseconds and as a
fraction of the floor, and, if SurfaceTopography is importable, its
``power_spectrum_from_area`` on the same heights (goal: slower than roadscan).

Allocator: both sides allocate and free arrays of 1 to 130 MB on every call. glibc serves
these from fresh ``mmap`` pages or from its heap depending on the history of earlier frees
(its dynamic mmap and trim thresholds), so a candidate can pay 0.5 to 1 ms of page faults per
call that the other, by the luck of its allocation order, does not (measured at 512^2:
floor 3.2 ms, psd_area 4.3 ms; with the thresholds fixed, 1.9 and 2.0 ms). The benchmark
therefore fixes them for the whole process (``mallopt``: mmap threshold 256 MiB, trim
threshold 512 MiB) before measuring, the same for both; ``--default-malloc`` keeps glibc's
defaults.

Run: PYTHONPATH=. .venv/bin/python benchmarks/bench_psd.py [--sizes 512,1024,2048,4096]
[--default-malloc]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from roadscan import spectrum as sp
from roadscan.level import level
from roadscan.synth import self_affine_surface

A_M = 55.4e-6
GOAL = 1.2
REPEATS = {512: 40, 1024: 20, 2048: 9, 4096: 5}


def make_floor(hm, window_alpha=0.25, rings_per_decade=20):
    """The floor for this grid: window and ring index precomputed; returns a callable."""
    ny, nx = hm.shape
    dx, dy = hm.dx_m, hm.dy_m
    W, w2 = sp.window_2d(ny, nx, window_alpha)
    qx = 2 * np.pi * np.fft.rfftfreq(nx, dx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, dy)
    q_min, q_max = 2 * np.pi / max(nx * dx, ny * dy), np.pi / max(dx, dy)
    edges = sp._ring_edges(q_min, q_max, rings_per_decade)
    n = edges.size - 1
    ring = sp._ring_index(np.hypot(qx[None, :], qy[:, None]).ravel(), q_min, q_max, n)
    ring[ring < 0] = n  # the spare bin
    scale = (dx * dy) ** 2 / ((2 * np.pi) ** 2 * nx * dx * ny * dy * w2)
    h = hm.heights_m
    fft = sp.fft_backend(h.size)  # the FFT psd_area uses for this size

    def floor():
        F = fft.rfft2(h * W)
        P = F.real**2 + F.imag**2
        return np.bincount(ring, weights=P.ravel(), minlength=n + 1)[:n] * scale

    return floor


def best_times(fns, repeat):
    """Interleaved runs (background load hits every candidate alike): best and median [s]."""
    for fn in fns:
        fn()  # warm up: FFT plans, ring caches
    times = [[] for _ in fns]
    for _ in range(repeat):
        for fn, ts in zip(fns, times):
            t = time.perf_counter()
            fn()
            ts.append(time.perf_counter() - t)
    return [(min(ts), float(np.median(ts))) for ts in times]


def check_same(hm):
    """psd_area's angular average against the full-lattice one of psd_2d (independent path)."""
    s, _ = sp.psd_area(hm)
    a = sp.angular_average(sp.psd_2d(hm))
    assert np.array_equal(s.count, a.count) and np.allclose(s.C_m4, a.C_m4, rtol=1e-10)


def _fix_malloc():
    """Fixed glibc mmap/trim thresholds for this process (see the module docstring)."""
    import ctypes
    import ctypes.util

    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3
        ok = libc.mallopt(M_MMAP_THRESHOLD, 256 << 20) and libc.mallopt(M_TRIM_THRESHOLD, 512 << 20)
    except (OSError, AttributeError):
        ok = 0
    return (
        "glibc mmap threshold 256 MiB, trim threshold 512 MiB (same for floor and psd_area)"
        if ok
        else "mallopt not available: the platform's defaults"
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="512,1024,2048,4096")
    ap.add_argument(
        "--default-malloc",
        action="store_true",
        help="keep glibc's dynamic mmap/trim thresholds (see the module docstring)",
    )
    args = ap.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",")]
    print("allocator:", "glibc defaults" if args.default_malloc else _fix_malloc())
    print(
        f"psd_area against the same-FFT floor (psd_area's own FFT for each size: numpy.fft up to "
        f"{sp.NUMPY_FFT_MAX_POINTS} points, scipy.fft workers={sp._WORKERS} above; float64, "
        "window and ring index cached); best of N interleaved, median in brackets"
    )
    print(
        f"{'size':>6} {'N':>3} {'floor ms':>16} {'psd_area ms':>16} {'ratio':>6} "
        f"{'level ms':>14} {'level/floor':>11}"
    )
    rows = []
    for n in sizes:
        raw = self_affine_surface(n, dx_m=A_M, hurst=0.86, rms_height_m=0.5e-3, seed=0)
        x = np.linspace(0.0, 1.0, n)
        raw = raw.with_heights(raw.heights_m + 1e-4 + 2e-4 * x[None, :])  # offset and tilt
        hm = level(raw)
        if n <= 1024:
            check_same(hm)
        floor = make_floor(hm)
        rep = REPEATS.get(n, 3)
        (tf, mf), (tp, mp), (tl, ml) = best_times(
            [floor, lambda hm=hm: sp.psd_area(hm), lambda raw=raw: level(raw)], rep
        )
        ratio = tp / tf
        rows.append((n, ratio, tl / tf))
        print(
            f"{n:>6} {rep:>3} {tf * 1e3:8.1f} ({mf * 1e3:5.1f}) {tp * 1e3:8.1f} ({mp * 1e3:5.1f}) "
            f"{ratio:6.2f} {tl * 1e3:6.1f} ({ml * 1e3:5.1f}) {tl / tf:11.2f}"
        )
    for n, ratio, lvl in rows:
        print(
            f"RATIO | psd_area / same-FFT floor, {n}^2 | {ratio:.2f} | <= {GOAL} | "
            f"{'PASS' if ratio <= GOAL else 'FAIL'} | level adds {lvl:.2f}x the floor"
        )
    try:
        from SurfaceTopography import Topography
    except ImportError:
        print("SurfaceTopography not installed: no comparison with power_spectrum_from_area")
        return
    n = min(max(sizes), 2048)
    hm = level(self_affine_surface(n, dx_m=A_M, hurst=0.86, rms_height_m=0.5e-3, seed=0))
    topo = Topography(hm.heights_m, physical_sizes=(n * A_M, n * A_M))
    (tp, _), (ts, _) = best_times(
        [lambda: sp.psd_area(hm), lambda: topo.power_spectrum_from_area()], REPEATS.get(n, 3)
    )
    print(
        f"SurfaceTopography power_spectrum_from_area at {n}^2: {ts * 1e3:.1f} ms, roadscan {tp * 1e3:.1f} ms"
    )
    print(
        f"RATIO | psd_area / SurfaceTopography, {n}^2 | {tp / ts:.2f} | < 1 | "
        f"{'PASS' if tp < ts else 'FAIL'} | power_spectrum_from_area on the same heights"
    )


if __name__ == "__main__":
    main()
