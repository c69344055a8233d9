"""ISO 25178-2 material-ratio family, volumes and slopes against analytic surfaces and an
independent implementation (SurfaceTopography's rms gradient)."""

import numpy as np
import pytest
from scipy import integrate
from scipy.stats import norm

from roadscan.heightmap import HeightMap
from roadscan.material_ratio import (
    areal_material_parameters,
    material_ratio_curve,
    profile_material_parameters,
    volume_parameters,
)
from roadscan.roughness import area_parameters


def _ls_line(c_of_mr, lo, hi):
    """Least-squares line of c(mr) over [lo, hi] % by quadrature: (c_eq(0), c_eq(100))."""
    mid = 0.5 * (lo + hi)
    mean = integrate.quad(c_of_mr, lo, hi)[0] / (hi - lo)
    slope = integrate.quad(lambda m: (m - mid) * c_of_mr(m), lo, hi)[0] / (2 * (0.5 * (hi - lo)) ** 3 / 3)
    return mean - slope * mid, mean + slope * (100 - mid)


def test_gaussian_core_height_over_sq():
    """Gaussian heights: c(mr) = Sq Phi^-1(1 - mr); the flattest 40 % secant is centred
    (30..70 %), and the equivalent line is the least-squares line of c over that region
    (ISO 13565-2): its ends, Smr1 = 100 Phi(-c_eq(0) / Sq) and Spk by quadrature."""
    sq = 2e-4
    z = np.random.default_rng(4).normal(scale=sq, size=(1500, 1500))
    f = areal_material_parameters(z)
    top, bottom = _ls_line(lambda m: sq * norm.isf(m / 100), 30.0, 70.0)
    assert f["Sk_m"] == pytest.approx(top - bottom, rel=0.01)
    smr1 = 100 * norm.sf(top / sq)
    assert f["Smr1_pct"] == pytest.approx(smr1, abs=0.3)
    assert f["Smr2_pct"] == pytest.approx(100 - smr1, abs=0.3)
    # Spk from the analytic curve by quadrature (an independent integration)
    a1 = integrate.quad(lambda m: sq * norm.isf(m / 100) - top, 1e-9, smr1)[0]
    assert f["Spk_m"] == pytest.approx(2 * a1 / smr1, rel=0.03)
    assert f["Svk_m"] == pytest.approx(f["Spk_m"], rel=0.05)  # symmetric heights


def test_sine_profile_rk_family():
    """z = sin: c(mr) = cos(pi mr / 100); the flattest 40 % secant starts at 0 or at 60 % (a
    tie, mirror images); the least-squares line of c over [0, 40] lies above c(0) = 1 (c is
    concave there), so Rmr1 = 0, Rmr2 = arccos(c_eq(100)) / pi, and Rvk by quadrature; over
    [60, 100] the mirror image: Rmr2 = 100, Rmr1 = 100 - that, Rpk = that Rvk."""
    x = np.linspace(0, 40 * np.pi, 400001)[:-1]
    r = profile_material_parameters(np.sin(x))
    top, bottom = _ls_line(lambda m: np.cos(np.pi * m / 100), 0.0, 40.0)
    assert top > 1
    assert r["Rk_m"] == pytest.approx(top - bottom, rel=2e-3)
    mr2 = 100 * np.arccos(bottom) / np.pi
    a2 = integrate.quad(lambda m: bottom - np.cos(np.pi * m / 100), mr2, 100)[0]
    if r["Rmr1_pct"] < 50:  # the window [0, 40]
        assert r["Rmr1_pct"] == pytest.approx(0.0, abs=0.05)
        assert r["Rmr2_pct"] == pytest.approx(mr2, abs=0.05)
        assert r["Rvk_m"] == pytest.approx(2 * a2 / (100 - mr2), rel=5e-3)
    else:  # its mirror image [60, 100]
        assert r["Rmr2_pct"] == pytest.approx(100.0, abs=0.05)
        assert r["Rmr1_pct"] == pytest.approx(100 - mr2, abs=0.05)
        assert r["Rpk_m"] == pytest.approx(2 * a2 / (100 - mr2), rel=5e-3)
    assert r["Rmr_pct"] == pytest.approx(50.0, abs=0.05)


def test_plateau_surface():
    """70 % plateau (uniform in [0, 0.1] mm) over 30 % deep valleys (uniform in [-5, 0] mm):
    a piecewise-linear curve whose construction is exact: Sk = 0.1 x 100 / 70 mm, Spk = 0,
    Smr2 = 70 + 30 (Sk - 0.1) / 5, Svk = 5 - (Sk - 0.1) mm."""
    rng = np.random.default_rng(5)
    n = 2_000_000
    z = np.where(rng.random(n) < 0.7, rng.uniform(0, 0.1e-3, n), rng.uniform(-5e-3, 0, n))
    f = areal_material_parameters(z)
    sk = 0.1e-3 * 100 / 70
    assert f["Sk_m"] == pytest.approx(sk, rel=0.03)
    assert f["Spk_m"] < 0.02 * sk
    depth = sk - 0.1e-3  # c_eq(100) below zero
    assert f["Smr2_pct"] == pytest.approx(70 + 30 * depth / 5e-3, abs=0.3)
    assert f["Svk_m"] == pytest.approx(5e-3 - depth, rel=0.01)


def test_volumes_of_uniform_heights():
    """Heights uniform in [-1, 1] mm: c(mr) = 1 - 2 mr / 100 mm, so Vm(p) = p^2 / 1e4 mm and
    Vv(p) = (100 - p)^2 / 1e4 mm: Vmp 0.01, Vmc 0.63, Vvc 0.77, Vvv 0.04 (mm^3/mm^2)."""
    z = np.random.default_rng(6).uniform(-1e-3, 1e-3, 3_000_000)
    v = volume_parameters(material_ratio_curve(z))
    for key, want in (
        ("Vmp_m3_per_m2", 0.01),
        ("Vmc_m3_per_m2", 0.63),
        ("Vvc_m3_per_m2", 0.77),
        ("Vvv_m3_per_m2", 0.04),
    ):
        assert v[key] == pytest.approx(want * 1e-3, rel=0.01), key


def test_material_ratio_ignores_unmeasured():
    z = np.random.default_rng(7).normal(size=(300, 300))
    holes = z.copy()
    holes[::7] = np.nan
    a, b = areal_material_parameters(z[~np.isnan(holes)]), areal_material_parameters(holes)
    assert a == pytest.approx(b)


def test_sdq_matches_surfacetopography():
    """Forward-difference Sdq (ISO 25178-2:2021) equals SurfaceTopography's rms gradient."""
    from scipy.ndimage import gaussian_filter
    from SurfaceTopography import Topography

    z = gaussian_filter(np.random.default_rng(0).normal(size=(256, 300)), 2) * 1e-5
    r = area_parameters(HeightMap(z, 1e-5, 2e-5), level_degree=None)
    t = Topography(z.T, (300e-5, 256 * 2e-5), periodic=False)
    assert r["Sdq"] == pytest.approx(t.rms_gradient(), rel=2e-3)


def test_sdr_exact_on_a_tilted_plane_and_a_sine():
    """A plane of slopes (a, b): every triangle has area (dx dy / 2) sqrt(1 + a^2 + b^2). A sine
    z = A sin(k x) sampled finely: Sdr -> <sqrt(1 + (A k cos)^2)> - 1 (quadrature)."""
    y, x = np.mgrid[0:50, 0:60] * 1e-4
    r = area_parameters(HeightMap(0.3 * x + 0.4 * y, 1e-4, 1e-4), level_degree=None)
    assert r["Sdr"] == pytest.approx(np.sqrt(1 + 0.09 + 0.16) - 1, rel=1e-9)
    assert r["Sdq"] == pytest.approx(0.5, rel=1e-9)
    A, k = 1e-3, 2 * np.pi / 0.01
    y, x = np.mgrid[0:20, 0:4000] * 5e-6
    r = area_parameters(HeightMap(A * np.sin(k * x), 5e-6, 5e-6), level_degree=None)
    want = integrate.quad(lambda t: np.sqrt(1 + (A * k * np.cos(t)) ** 2), 0, 2 * np.pi)[0] / (2 * np.pi) - 1
    assert r["Sdr"] == pytest.approx(want, rel=2e-3)


def test_flat_and_tiny_fields_give_zeros_or_null_with_a_note():
    import warnings

    from roadscan.heightmap import Profile
    from roadscan.iso25178 import texture_parameters

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no division by zero on the way
        f, notes = texture_parameters(HeightMap(np.zeros((20, 20)), 1e-4, 1e-4))
        p, _ = texture_parameters(Profile(np.zeros(10), 1e-4))
    assert f["Sk_m"] == 0 and f["Smr2_pct"] == 100 and f["Vvv_m3_per_m2"] == 0
    assert f["Sal_m"] is None and f["Str"] is None and "flat" in notes["spatial"]
    assert f["Spd_per_m2"] == 0 and "flat" in notes["features"]
    assert p["Rk_m"] == 0 and p["Rpk_m"] == 0
