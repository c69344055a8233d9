"""2D and 1D PSD: normalisation (Parseval), invariances, units, DESIGN.md sec 7 numbers, 1D->2D."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from roadscan import HeightMap, Profile, Spectrum2D
from roadscan.fit import fit_self_affine
from roadscan.level import level
from roadscan.spectrum import angular_average, anisotropy, psd_2d, psd_area, psd_profile, window_2d
from roadscan.synth import model_psd, self_affine_surface

A_M = 50e-6


@pytest.fixture(scope="module")
def gauss512():
    return self_affine_surface(512, dx_m=A_M, hurst=0.7, rms_height_m=1e-3, seed=11)


@pytest.fixture(scope="module")
def rect():
    return self_affine_surface(96, 80, dx_m=40e-6, dy_m=30e-6, hurst=0.6, rms_height_m=1e-3, seed=4)


@pytest.fixture(scope="module")
def design_surface():
    """DESIGN.md sec 7 'Surfaces': random phase, 1024^2, a = 50 um, H = 0.8, q0 = 2000 1/m."""
    return self_affine_surface(
        1024, dx_m=A_M, hurst=0.8, rms_height_m=1e-3, q0_per_m=2000, seed=7, gaussian_amplitudes=False
    )


@pytest.mark.parametrize("alpha", [0.0, 0.25, 1.0])
def test_parseval_on_2d_map(rect, alpha):
    s2 = psd_2d(rect, window_alpha=alpha)
    w, w2 = window_2d(*rect.shape, alpha)
    Lx, Ly = rect.size_m
    lhs = s2.C_m4.sum() * (2 * np.pi) ** 2 / (Lx * Ly)
    rhs = np.mean((w * rect.heights_m) ** 2) / w2
    assert lhs == pytest.approx(rhs, rel=1e-12)


def test_window_power_of_tukey_025():
    assert window_2d(1024, 1024, 0.25)[1] == pytest.approx(0.7105, abs=2e-4)


def test_angular_average_of_map_equals_psd_area(rect):
    s, s2 = psd_area(rect)
    a = angular_average(psd_2d(rect))
    assert np.array_equal(a.count, s.count)
    assert np.allclose(a.C_m4, s.C_m4, rtol=1e-12)
    assert np.allclose(a.q_per_m, s.q_per_m, rtol=1e-12)
    assert np.allclose(s2.C_m4, psd_2d(rect).C_m4, rtol=1e-12)
    Lx, Ly = rect.size_m
    assert s.q_per_m[0] >= 2 * np.pi / max(Lx, Ly) * (1 - 1e-12)
    assert s.q_per_m[-1] <= np.pi / 40e-6 * (1 + 1e-12)
    assert np.all(s.count > 0) and s.kind == "area"
    assert s.meta["window_alpha"] == 0.25 and "normalisation" in s.meta


def test_unfilled_map_is_refused():
    h = np.ones((8, 8))
    h[2, 3] = np.nan
    with pytest.raises(ValueError, match="fill"):
        psd_2d(HeightMap(h, 1e-5, 1e-5))


@settings(max_examples=15, deadline=None)
@given(sy=st.integers(0, 79), sx=st.integers(0, 95), offset=st.floats(-1e-2, 1e-2))
def test_periodic_shift_and_offset_invariance(rect, sy, sx, offset):
    ref = psd_2d(rect, window_alpha=0.0).C_m4
    moved = rect.with_heights(np.roll(rect.heights_m, (sy, sx), axis=(0, 1)) + offset)
    C = psd_2d(moved, window_alpha=0.0).C_m4
    nz = np.ones_like(C, dtype=bool)
    nz[C.shape[0] // 2, C.shape[1] // 2] = False  # q = 0 carries the offset
    assert np.allclose(C[nz], ref[nz], rtol=1e-9, atol=1e-12 * ref.max())
    # with the default window, levelling removes any offset exactly
    s_ref, _ = psd_area(level(rect))
    s_off, _ = psd_area(level(rect.with_heights(rect.heights_m + offset)))
    assert np.allclose(s_off.C_m4, s_ref.C_m4, rtol=1e-8)


def test_rotation_by_90_degrees(gauss512):
    s, _ = psd_area(gauss512)
    r, _ = psd_area(gauss512.with_heights(np.rot90(gauss512.heights_m)))
    assert np.allclose(r.C_m4, s.C_m4, rtol=1e-10)


def test_mm_and_m_give_the_same_spectrum(rect):
    s_m, _ = psd_area(rect)
    in_mm = HeightMap(rect.heights_m * 1e3, rect.dx_m * 1e3, rect.dy_m * 1e3)
    s_mm, _ = psd_area(in_mm)
    assert np.allclose(s_mm.q_per_m * 1e3, s_m.q_per_m, rtol=1e-12)  # 1/mm -> 1/m
    assert np.allclose(s_mm.C_m4 * 1e-12, s_m.C_m4, rtol=1e-10)  # mm^4 -> m^4


def test_design_surface_numbers(design_surface):
    """C within ~2 % on [3 q0, q1/3], H within 0.007; without window correction 29 % low."""
    hm = design_surface
    m = hm.meta["model"]
    s, s2 = psd_area(hm)
    q_lat = np.hypot(s2.qx_per_m[None, :], s2.qy_per_m[:, None])
    model_map = model_psd(q_lat, 0.8, m["prefactor_m4"], m["q0_per_m"], m["q1_per_m"])
    expect = angular_average(Spectrum2D(s2.qx_per_m, s2.qy_per_m, model_map, meta=s2.meta))
    q1 = m["q1_per_m"]
    sel = (s.q_per_m >= 3 * 2000) & (s.q_per_m <= q1 / 3)
    ratio = s.C_m4[sel] / expect.C_m4[sel]
    assert np.max(np.abs(ratio - 1)) < 0.03
    assert np.mean(np.abs(ratio - 1)) < 0.01
    fit = fit_self_affine(s, band=(3 * 2000, q1 / 3))
    assert abs(fit.hurst - 0.8) < 0.007
    uncorrected = ratio * s2.meta["window_mean_square"]
    assert np.mean(uncorrected) == pytest.approx(0.71, abs=0.02)  # 29 % low


def test_profile_psd_parseval_and_units():
    rng = np.random.default_rng(0)
    h = np.cumsum(rng.standard_normal(4096)) * 1e-6
    h -= h.mean()
    p = Profile(h, 1e-4)
    q, C1, spec = psd_profile(p, window_alpha=0.0, hurst=0.5)
    assert 2 * np.sum(C1) * (q[1] - q[0]) == pytest.approx(np.mean(h**2), rel=1e-10)
    assert spec.kind == "profile" and "Abel" in spec.meta["conversion"]
    _, C1mm, _ = psd_profile(Profile(h * 1e3, 0.1), window_alpha=0.0, hurst=0.5)
    assert np.allclose(C1mm * 1e-9, C1, rtol=1e-10)  # mm^3 -> m^3


def test_profiles_to_2d_random_phase_exact_conversion():
    """Rows of a random-phase surface (no window): the power-law Abel inversion of C1 gives
    the 2D ring spectrum within 3 % over the middle of the band."""
    for H in (0.4, 0.8):
        g = self_affine_surface(512, dx_m=A_M, hurst=H, rms_height_m=1e-3, seed=1, gaussian_amplitudes=False)
        sa, _ = psd_area(g, window_alpha=0.0)
        _, _, sp = psd_profile(g, window_alpha=0.0)
        assert abs(sp.meta["conversion_hurst"] - H) < 0.03
        C = np.interp(np.log(sa.q_per_m), np.log(sp.q_per_m), sp.C_m4)
        sel = (sa.q_per_m > 8 * sa.q_per_m[0]) & (sa.q_per_m < sa.q_per_m[-1] / 8)
        assert np.max(np.abs(C[sel] / sa.C_m4[sel] - 1)) < 0.03


def test_profiles_to_2d_gaussian_default_window(gauss512):
    """Gaussian surface, default window: 1D->2D within 15 % of the 2D spectrum (mid band, on
    average over rings; single rings scatter)."""
    sa, _ = psd_area(gauss512)
    profiles = [Profile(r, A_M) for r in gauss512.heights_m[::2]]
    _, _, sp = psd_profile(profiles)
    C = np.interp(np.log(sa.q_per_m), np.log(sp.q_per_m), sp.C_m4)
    sel = (sa.q_per_m > 10 * sa.q_per_m[0]) & (sa.q_per_m < sa.q_per_m[-1] / 4)
    r = C[sel] / sa.C_m4[sel]
    assert abs(np.mean(r) - 1) < 0.15
    assert np.median(np.abs(r - 1)) < 0.15


def test_anisotropy(gauss512):
    iso = anisotropy(psd_2d(gauss512))
    assert iso["power_ratio_x_to_y"] == pytest.approx(1.0, abs=0.1)
    assert iso["anisotropy_index"] < 0.1
    ridges = gauss512.with_heights(np.tile(gauss512.heights_m[0], (512, 1)))  # varies along x only
    a = anisotropy(psd_2d(ridges))
    assert a["power_ratio_x_to_y"] > 5 and a["anisotropy_index"] > 0.5
    assert min(a["dominant_direction_deg"], 180 - a["dominant_direction_deg"]) < 1.0
    assert sum(a["sector_power_fraction"]) == pytest.approx(1.0)


@pytest.mark.parametrize("shape", [(80, 96), (77, 101)])
def test_half_lattice_map_central_part_and_anisotropy(shape):
    """psd_area keeps the rfft half lattice (issue 13/14): the full map built on demand, its
    central part read without it, and the anisotropy from the half lattice all equal the
    same quantities computed on the full fftshifted map."""
    ny, nx = shape
    g = self_affine_surface(nx, ny, dx_m=40e-6, dy_m=30e-6, hurst=0.6, rms_height_m=1e-3, seed=2)
    ridges = g.with_heights(np.tile(g.heights_m[0], (ny, 1)) + 0.1 * g.heights_m)
    _, s2 = psd_area(ridges)
    full = Spectrum2D(s2.qx_per_m, s2.qy_per_m, s2.C_m4.copy(), meta=s2.meta)
    _, lazy = psd_area(ridges)
    qlim = 0.3 * np.abs(s2.qx_per_m).max()
    qx, qy, C = lazy.central(qlim)
    ix, iy = np.abs(s2.qx_per_m) <= qlim, np.abs(s2.qy_per_m) <= qlim
    assert np.array_equal(C, full.C_m4[np.ix_(iy, ix)])
    assert np.array_equal(qx, s2.qx_per_m[ix]) and np.array_equal(qy, s2.qy_per_m[iy])
    a, b = anisotropy(lazy), anisotropy(full)
    assert a["power_ratio_x_to_y"] > 2  # the ridges are seen
    for k in ("power_ratio_x_to_y", "dominant_direction_deg", "anisotropy_index"):
        assert a[k] == pytest.approx(b[k], rel=1e-10, abs=1e-12)
    assert np.allclose(a["sector_power_fraction"], b["sector_power_fraction"], rtol=0, atol=1e-12)


def test_psd_area_with_fill_values_equals_filled_map():
    """psd_area(levelled, fill_values=...) reads the map as filled without a filled copy."""
    from roadscan.inpaint import fill_unmeasured, unmeasured_fill

    g = self_affine_surface(128, 96, dx_m=A_M, hurst=0.7, rms_height_m=1e-3, seed=3)
    bad = np.zeros(g.shape, bool)
    bad[10:14, 20:30] = bad[60, :] = bad[90:, 5] = True
    hm = level(HeightMap(g.heights_m, A_M, A_M, unmeasured=bad))
    s_ref, m_ref = psd_area(fill_unmeasured(hm)[0])
    s, m = psd_area(hm, fill_values=unmeasured_fill(hm))
    assert np.array_equal(s.count, s_ref.count)
    assert np.allclose(s.C_m4, s_ref.C_m4, rtol=1e-12)
    assert np.allclose(m.C_m4, m_ref.C_m4, rtol=1e-12, atol=0)
    with pytest.raises(ValueError, match="fill_values"):
        psd_area(hm, fill_values=np.zeros(3))


def test_numpy_and_scipy_fft_paths_agree(monkeypatch):
    """psd_area and psd_profile use numpy's FFT for small data (no scipy import) and
    scipy's on every core above NUMPY_FFT_MAX_POINTS: the same spectra to round-off, through
    one band and through several (the in-place column FFT of scipy's path)."""
    import roadscan.fft_backends as fb
    import roadscan.spectrum as sp
    from roadscan.synth import self_affine_surface

    hm = self_affine_surface(300, dx_m=5e-5, hurst=0.8, rms_height_m=3e-4, seed=4)
    assert sp.fft_backend(10).name == "numpy.fft" and "scipy" in sp.fft_backend(1 << 23).name
    results = {}
    for limit in (1 << 22, 0):
        monkeypatch.setattr(fb, "NUMPY_FFT_MAX_POINTS", limit)  # its home (issue 23)
        for band in (1 << 30, 1 << 14):  # one band; 1 row ... bands
            monkeypatch.setattr(sp, "_FFT_BAND_BYTES", band)
            s, s2 = sp.psd_area(hm)
            results[limit, band] = (s.C_m4, s2.half.P)
    ref_C, ref_P = results[1 << 22, 1 << 30]
    for C, P in results.values():
        assert np.allclose(C, ref_C, rtol=1e-12, atol=0)
        assert np.allclose(P, ref_P, rtol=1e-10, atol=1e-12 * ref_P.max())
