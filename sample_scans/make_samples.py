"""Regenerate the sample scans shipped in this folder (deterministic: fixed seeds).

Run from the repository root:  python sample_scans/make_samples.py

Every sample is synthetic: a Gaussian self-affine field from :func:`roadscan.synth.self_affine_surface`
turned asphalt-like by a monotone transform that deepens the cavities (negative skew, as on a
real asphalt whose rounded aggregate tops stand above narrow voids), with the defects of a real
optical scan added: a tilt, a height offset, and unmeasured points clustered in the deepest
cavities (where an optical profiler loses the reflection) plus scattered dropouts.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import x3pio
from scipy import ndimage

from roadscan.synth import self_affine_surface

HERE = Path(__file__).resolve().parent


def asphalt_like(nx, ny, dx_m, hurst, rms_m, q_roll, seed, skew_strength=0.3):
    g = self_affine_surface(nx, ny, dx_m=dx_m, hurst=hurst, rms_height_m=1.0, q_roll_per_m=q_roll, seed=seed)
    z = g.heights_m / g.heights_m.std()
    h = -np.expm1(-skew_strength * z) / skew_strength  # deep voids, rounded tops
    h -= h.mean()
    return h * (rms_m / h.std())


def add_scan_defects(
    h, dx_m, seed, slope=(2.0e-3, -1.2e-3), offset_m=12e-3, deep_fraction=0.015, speck_fraction=0.008
):
    rng = np.random.default_rng(seed + 1000)
    ny, nx = h.shape
    y, x = np.mgrid[0:ny, 0:nx] * dx_m
    out = h + slope[0] * x + slope[1] * y + offset_m
    deep = h < np.quantile(h, deep_fraction)
    deep = ndimage.binary_dilation(deep, iterations=1)
    specks = rng.random(h.shape) < speck_fraction
    out[deep | specks] = np.nan
    return out


def write_x3p_float32(path, heights_m, dx_m, dy_m):
    x3pio.write(str(path), heights_m.astype(np.float32), x_scale=dx_m, y_scale=dy_m, z_type="F")


def main():
    # 1. the thesis-like scan: 978 x 1088 points at 55.4 um (about 54 x 60 mm), H about 0.86
    a = 55.4e-6
    h = asphalt_like(978, 1088, a, hurst=0.86, rms_m=0.45e-3, q_roll=2 * np.pi / 6e-3, seed=2008)
    write_x3p_float32(HERE / "asphalt.x3p", add_scan_defects(h, a, seed=2008), a, a)

    # 2. a coarser-aggregate surface for the comparison example: 640 x 640 at 80 um (51 mm)
    b = 80e-6
    hc = asphalt_like(
        640, 640, b, hurst=0.75, rms_m=1.0e-3, q_roll=2 * np.pi / 14e-3, seed=16, skew_strength=0.45
    )
    write_x3p_float32(
        HERE / "coarse_asphalt.x3p", add_scan_defects(hc, b, seed=16, slope=(-1e-3, 0.5e-3)), b, b
    )

    # 3. overlapping tiles of one asphalt-like surface: 2 x 3 tiles of 320 x 320, 64 px overlap,
    #    each with its own height offset and tilt (stage and levelling errors), and nominal
    #    positions that are off by a few pixels (stage error), as a manifest file,x_m,y_m
    tiles_dir = HERE / "tiles"
    tiles_dir.mkdir(exist_ok=True)
    full = asphalt_like(
        3 * 256 + 64, 2 * 256 + 64, a, hurst=0.86, rms_m=0.45e-3, q_roll=2 * np.pi / 6e-3, seed=7
    )
    rng = np.random.default_rng(7)
    rows = []
    for r in range(2):
        for c in range(3):
            y0, x0 = 256 * r, 256 * c
            t = full[y0 : y0 + 320, x0 : x0 + 320].copy()
            yy, xx = np.mgrid[0:320, 0:320] * a
            t += rng.normal(0, 0.3e-3) + rng.normal(0, 1e-3) * xx + rng.normal(0, 1e-3) * yy
            t[rng.random(t.shape) < 0.005] = np.nan
            name = f"tile_r{r}_c{c}.npz"
            np.savez_compressed(tiles_dir / name, heights=t.astype(np.float32), dx=a, dy=a)
            ex, ey = rng.integers(-4, 5, size=2)
            rows.append((f"tiles/{name}", (x0 + ex) * a, (y0 + ey) * a))
    with open(HERE / "tiles_manifest.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["file", "x_m", "y_m"])
        for f, x, y in rows:
            w.writerow([f, f"{x:.7g}", f"{y:.7g}"])
    np.save(tiles_dir.parent / "tiles_truth.npy", full.astype(np.float32))


if __name__ == "__main__":
    main()
