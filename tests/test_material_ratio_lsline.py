"""The Sk family with the least-squares equivalent line (ISO 13565-2; ISO 25178-2 Annex B):
against material-ratio curves known in closed form and against a second implementation
written here from the sorted heights (numpy.polyfit), on plateau, ridged and asphalt-like
surfaces."""

import numpy as np
import pytest
from scipy.ndimage import gaussian_filter

from roadscan.material_ratio import (
    areal_material_parameters,
    equivalent_line,
    material_ratio_curve,
    profile_material_parameters,
)

# a piecewise-linear material-ratio curve c(mr) [mm]: steep peaks (0-20 %), a flat plateau
# (20-50 %), deep dales (50-100 %)
KNOTS_MR = np.array([0.0, 20.0, 50.0, 100.0])
KNOTS_C = np.array([3.0, 1.0, 0.7, -4.0])


def _curve(mr):
    return np.interp(mr, KNOTS_MR, KNOTS_C)


def _ratio(c):
    """Smr(c) [%] of the piecewise-linear curve (its inverse)."""
    return np.interp(c, KNOTS_C[::-1], KNOTS_MR[::-1])


def _heights_of_the_curve(n, seed):
    """Heights whose material-ratio curve is c(mr): c(100 U) with U uniform (inverse transform)."""
    return _curve(100.0 * np.random.default_rng(seed).random(n))


def test_uniform_heights_give_a_linear_curve_and_an_exact_line():
    """Heights uniform in [-1, 1] mm: c(mr) = 1 - 2 mr / 100 mm is its own equivalent line:
    Sk = 2 mm, Smr1 = 0, Smr2 = 100, no peak nor dale areas."""
    z = np.random.default_rng(1).uniform(-1e-3, 1e-3, 2_000_000)
    f = areal_material_parameters(z)
    assert f["Sk_m"] == pytest.approx(2e-3, rel=3e-3)
    assert f["Smr1_pct"] < 0.2 and f["Smr2_pct"] > 99.8
    assert f["Spk_m"] < 1e-6 and f["Svk_m"] < 1e-6


def test_kinked_curve_line_is_the_least_squares_fit_not_the_secant():
    """For the piecewise-linear curve the flattest 40 % secant is the one over [20, 60] %
    (its drop 1.36 - 0.006 a falls on [10, 20] and -0.44 + 0.084 a rises on [20, 50]); the
    line is the least-squares line of c over [20, 60] (the normal equations of the exact
    curve, sampled a million times), not the secant (Sk 3.1 mm)."""
    m = np.linspace(20.0, 60.0, 1_000_001)
    slope, icpt = np.polyfit(m, _curve(m), 1)
    top, bottom = icpt, icpt + 100.0 * slope
    secant_sk = (_curve(20.0) - _curve(60.0)) * 100.0 / 40.0
    assert abs((top - bottom) / secant_sk - 1) > 0.2  # the two constructions differ
    smr1, smr2 = _ratio(top), _ratio(bottom)
    mr = np.linspace(0.0, 100.0, 2_000_001)
    step = mr[1] - mr[0]
    a1 = np.sum(np.clip(_curve(mr) - top, 0, None)) * step
    a2 = np.sum(np.clip(bottom - _curve(mr), 0, None)) * step
    z = _heights_of_the_curve(2_000_000, seed=2) * 1e-3
    f = areal_material_parameters(z)
    assert f["Sk_m"] == pytest.approx((top - bottom) * 1e-3, rel=0.01)
    assert f["Smr1_pct"] == pytest.approx(smr1, abs=0.3)
    assert f["Smr2_pct"] == pytest.approx(smr2, abs=0.3)
    assert f["Spk_m"] == pytest.approx(2 * a1 / smr1 * 1e-3, rel=0.02)
    assert f["Svk_m"] == pytest.approx(2 * a2 / (100 - smr2) * 1e-3, rel=0.02)
    t, b, start = equivalent_line(material_ratio_curve(z))
    assert start == pytest.approx(20.0, abs=0.5)
    assert (t, b) == pytest.approx((top * 1e-3, bottom * 1e-3), rel=0.01)
    # the profile construction (ISO 13565-2's Rk) is the same on a profile's heights
    r = profile_material_parameters(z[:400_000])
    assert r["Rk_m"] == pytest.approx((top - bottom) * 1e-3, rel=0.02)
    assert r["Rmr2_pct"] == pytest.approx(smr2, abs=0.5)


def _sk_sorted(z, window=40.0):
    """A second implementation: the material-ratio curve as the heights sorted downwards at
    mr_i = 100 (i + 1/2) / n, the flattest secant over k = 0.4 n points, numpy.polyfit of
    those points, ratios by counting, areas by summing the heights beyond the line."""
    z = np.ravel(z)
    z = np.sort(z[np.isfinite(z)])[::-1]
    n = z.size
    mr = 100.0 * (np.arange(n) + 0.5) / n
    k = int(round(window / 100.0 * n))
    i = int(np.argmin(z[:-k] - z[k:]))
    slope, icpt = np.polyfit(mr[i : i + k], z[i : i + k], 1)
    top, bottom = icpt, icpt + 100.0 * slope
    smr1 = 100.0 * np.count_nonzero(z > top) / n
    smr2 = 100.0 * np.count_nonzero(z > bottom) / n
    a1 = 100.0 / n * np.sum(np.clip(z - top, 0, None))
    a2 = 100.0 / n * np.sum(np.clip(bottom - z, 0, None))
    return {
        "Sk_m": top - bottom,
        "Spk_m": 2 * a1 / smr1 if smr1 else 0.0,
        "Svk_m": 2 * a2 / (100 - smr2) if smr2 < 100 else 0.0,
        "Smr1_pct": smr1,
        "Smr2_pct": smr2,
    }


def _field(seed, sigma, shape=(768, 768)):
    g = gaussian_filter(np.random.default_rng(seed).normal(size=shape), sigma)
    return g / g.std()


def _plateau():
    """Plateau-honed: fine 2 um roughness on a plateau, cut by dales 50 um per unit of a
    coarse field below 0.3 (about 62 % of the area: the central 40 % straddles the plateau's
    edge, where the secant's Sk is 1.4 times the line's and its Smr2 4.5 points off)."""
    return 2e-6 * _field(11, 1.5) + np.minimum(_field(12, 6) - 0.3, 0.0) * 50e-6


def _ridged():
    """Sharp crests: -|g| of a smooth Gaussian field, 0.1 mm."""
    return -np.abs(_field(13, 4)) * 1e-4


def _asphalt_like():
    """Asphalt-like: a self-affine field (H = 0.8, rolled off at 3 mm) with negatively skewed
    heights (rounded aggregate tops, deep narrow voids), 0.5 mm rms; NaN dropouts."""
    from roadscan.synth import self_affine_surface

    h = self_affine_surface(
        512, 512, dx_m=1e-4, hurst=0.8, rms_height_m=1.0, q_roll_per_m=2 * np.pi / 3e-3, seed=5
    ).heights_m
    z = -np.expm1(-0.8 * (h - h.mean()) / h.std())
    z = 0.5e-3 * (z - z.mean()) / z.std()
    z[::37, ::11] = np.nan
    return z


@pytest.mark.parametrize("make", [_plateau, _ridged, _asphalt_like], ids=["plateau", "ridged", "asphalt"])
def test_sk_family_agrees_with_a_sorted_height_implementation(make):
    """Within 5 % (Sk, Spk, Svk; absolute when the reference is below 1 % of Sk) and within
    1.5 points of material ratio (Smr1, Smr2)."""
    z = make()
    got, ref = areal_material_parameters(z), _sk_sorted(z)
    for key in ("Sk_m", "Spk_m", "Svk_m"):
        tol = max(0.05 * ref[key], 0.01 * 0.05 * ref["Sk_m"])
        assert abs(got[key] - ref[key]) <= tol, (key, got[key], ref[key])
    for key in ("Smr1_pct", "Smr2_pct"):
        assert got[key] == pytest.approx(ref[key], abs=1.5), key
    assert ref["Svk_m"] > 0.1 * ref["Sk_m"]  # every surface has dales


def test_sample_asphalt_agrees_with_the_sorted_height_implementation():
    """The shipped asphalt scan (levelled by a plane fit here) with both implementations."""
    from roadscan.io import read

    h = read("sample_scans/asphalt.x3p").heights_m
    yy, xx = np.mgrid[0 : h.shape[0], 0 : h.shape[1]]
    ok = np.isfinite(h)
    a = np.column_stack([np.ones(ok.sum()), xx[ok], yy[ok]])
    coef = np.linalg.lstsq(a, h[ok], rcond=None)[0]
    z = h - (coef[0] + coef[1] * xx + coef[2] * yy)
    got, ref = areal_material_parameters(z), _sk_sorted(z)
    for key in ("Sk_m", "Spk_m", "Svk_m"):
        assert got[key] == pytest.approx(ref[key], rel=0.05), key
    for key in ("Smr1_pct", "Smr2_pct"):
        assert got[key] == pytest.approx(ref[key], abs=1.5), key
