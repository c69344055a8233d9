"""Synthetic self-affine surfaces: reproducibility, exact rms, exact spectrum (random phase)."""

import numpy as np
import pytest

from roadscan import HeightMap
from roadscan.inpaint import fill_unmeasured
from roadscan.level import level
from roadscan.roughness import area_parameters
from roadscan.spectrum import psd_2d
from roadscan.synth import model_psd, self_affine_surface


def test_reproducible_from_seed():
    a = self_affine_surface(64, seed=5)
    b = self_affine_surface(64, seed=5)
    c = self_affine_surface(64, seed=6)
    assert np.array_equal(a.heights_m, b.heights_m)
    assert not np.allclose(a.heights_m, c.heights_m)


@pytest.mark.parametrize("gauss", [True, False])
def test_rms_exact_and_zero_mean(gauss):
    hm = self_affine_surface(
        128, 96, dx_m=20e-6, hurst=0.6, rms_height_m=0.37e-3, seed=1, gaussian_amplitudes=gauss
    )
    assert hm.shape == (96, 128)
    assert np.sqrt(np.mean(hm.heights_m**2)) == pytest.approx(0.37e-3, rel=1e-12)
    assert abs(hm.heights_m.mean()) < 1e-15


def test_random_phase_periodogram_equals_model_on_every_lattice_point():
    hm = self_affine_surface(
        128,
        dx_m=50e-6,
        hurst=0.7,
        rms_height_m=1e-3,
        q0_per_m=3000,
        q_roll_per_m=6000,
        seed=2,
        gaussian_amplitudes=False,
    )
    m = hm.meta["model"]
    s2 = psd_2d(hm, window_alpha=0.0)
    q = np.hypot(s2.qx_per_m[None, :], s2.qy_per_m[:, None])
    expect = model_psd(q, 0.7, m["prefactor_m4"], m["q0_per_m"], m["q1_per_m"], m["q_roll_per_m"])
    assert np.allclose(s2.C_m4, expect, rtol=1e-9, atol=1e-12 * expect.max())
    # roll-off plateau present
    band = (q > 3100) & (q < 5900)
    assert np.allclose(s2.C_m4[band], expect[band].max(), rtol=1e-9)


def test_analysis_recovers_rms_after_tilt_and_dropouts():
    rms = 0.8e-3
    hm = self_affine_surface(512, dx_m=50e-6, hurst=0.8, rms_height_m=rms, seed=3)
    y, x = np.mgrid[0:512, 0:512] * 50e-6
    tilted = hm.heights_m + 0.02 * x - 0.01 * y + 3e-3
    rng = np.random.default_rng(0)
    bad = rng.random(hm.shape) < 0.03
    for _ in range(60):
        i, j = rng.integers(0, 500, 2)
        bad[i : i + 8, j : j + 8] = True
    damaged = HeightMap(tilted, 50e-6, 50e-6, unmeasured=bad)
    assert damaged.measured_fraction < 0.97
    sq = area_parameters(damaged)["Sq_m"]
    filled, frac = fill_unmeasured(level(damaged))
    sq_filled = np.sqrt(np.mean(level(filled).heights_m ** 2))
    assert frac == pytest.approx(bad.mean())
    assert sq == pytest.approx(rms, rel=0.02)
    assert sq_filled == pytest.approx(rms, rel=0.02)
