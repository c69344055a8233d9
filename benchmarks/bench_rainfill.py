"""Benchmark: full rain fill (roadscan.rain.rain_fill) against scikit-image's reconstruction.

On a 1088 x 978 self-affine scan (the thesis's measured grid, spacing 55.4 um) with a little
white noise (so that it has many small pits, as real scans do), times

- the baseline: ``skimage.morphology.reconstruction(seed, h, method="erosion", footprint=cross)``
  on the same seed as imfill (border heights, maximum inside);
- roadscan's ``rain_fill(hm)`` (4-connected full fill, plus depth map, wetted fraction, volume);

in the same process, best of several repeats, and prints the ratio (goal: at most 1.2).
Usage: ``python benchmarks/bench_rainfill.py [--repeats N] [--dropouts FRACTION]``.
"""
from __future__ import annotations

import argparse
import time

import numpy as np
from skimage.morphology import reconstruction

from roadscan.heightmap import HeightMap
from roadscan.rain import footprint, rain_fill


def scan(ny=1088, nx=978, dx=55.4e-6, hurst=0.86, rms=0.5e-3, seed=0):
    rng = np.random.default_rng(seed)
    qy = np.fft.fftfreq(ny)[:, None]
    qx = np.fft.fftfreq(nx)[None, :]
    q = np.hypot(qx, qy)
    q[0, 0] = 1.0
    amp = q ** (-(hurst + 1.0))
    amp[0, 0] = 0.0
    h = np.fft.ifft2(amp * np.exp(2j * np.pi * rng.random((ny, nx)))).real
    h = rms * (h - h.mean()) / h.std()
    h += 0.01 * rms * rng.standard_normal(h.shape)
    return HeightMap(h, dx, dx, name="bench")


def best_of(fn, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--dropouts", type=float, default=0.0,
                    help="fraction of points made unmeasured in roadscan's run (default 0)")
    a = ap.parse_args(argv)
    hm = scan()
    h = hm.heights_m
    seed = np.full_like(h, h.max())
    seed[0], seed[-1], seed[:, 0], seed[:, -1] = h[0], h[-1], h[:, 0], h[:, -1]
    fp = footprint(4)
    t_ref, ref = best_of(lambda: reconstruction(seed, h, method="erosion", footprint=fp), a.repeats)
    run_hm = hm
    if a.dropouts > 0:
        bad = np.random.default_rng(1).random(h.shape) < a.dropouts
        run_hm = hm.with_heights(np.where(bad, np.nan, h), unmeasured=bad)
    t_rs, res = best_of(lambda: rain_fill(run_hm), a.repeats)
    if a.dropouts == 0:
        assert np.array_equal(res.wet.heights_m, ref), "rain_fill differs from skimage"
    print(f"scan {h.shape[0]} x {h.shape[1]}, connectivity 4, dropouts {a.dropouts:g}")
    print(f"wetted fraction {res.wetted_fraction:.4f}, "
          f"water volume {res.water_volume_m3_per_m2 * 1e6:.2f} um (m^3/m^2 x 1e6)")
    print(f"skimage reconstruction: {t_ref * 1e3:8.1f} ms (best of {a.repeats})")
    print(f"roadscan rain_fill:     {t_rs * 1e3:8.1f} ms (best of {a.repeats})")
    print(f"ratio roadscan / skimage: {t_rs / t_ref:.3f} (goal <= 1.2)")


if __name__ == "__main__":
    main()
