"""Self-affine fit: Hurst recovery, dropouts, model form (h0, band rms), roll-off, extension."""

import numpy as np
import pytest

from roadscan import HeightMap, Spectrum
from roadscan.fit import detect_band, extend_spectrum, fit_self_affine
from roadscan.inpaint import fill_unmeasured
from roadscan.level import level
from roadscan.spectrum import psd_area
from roadscan.synth import self_affine_surface


@pytest.mark.parametrize("hurst", [0.3, 0.5, 0.7, 0.9])
def test_hurst_recovered_1024(hurst):
    hm = self_affine_surface(1024, dx_m=50e-6, hurst=hurst, rms_height_m=1e-3, seed=int(hurst * 10))
    s, _ = psd_area(level(hm))
    fit = fit_self_affine(s)
    lo, hi = fit.fit_band_per_m
    assert hi / lo > 10  # a real band was found
    assert abs(fit.hurst - hurst) < 0.03
    assert 0 < fit.hurst_stderr < 0.03
    assert fit.q_roll_per_m is None  # pure power law: no roll-off


def _with_dropouts(hm, fraction, seed=0):
    rng = np.random.default_rng(seed)
    bad = rng.random(hm.shape) < fraction / 2
    n_blobs = int(fraction / 2 * hm.heights_m.size / 25)
    for i, j in rng.integers(0, min(hm.shape) - 5, (n_blobs, 2)):
        bad[i : i + 5, j : j + 5] = True
    return HeightMap(hm.heights_m, hm.dx_m, hm.dy_m, unmeasured=bad)


def test_dropouts_do_not_bias_hurst():
    hm = self_affine_surface(512, dx_m=50e-6, hurst=0.7, rms_height_m=1e-3, seed=21)
    ref = fit_self_affine(psd_area(level(hm))[0])
    damaged = _with_dropouts(hm, 0.05)
    assert 0.04 < 1 - damaged.measured_fraction < 0.06
    filled, _ = fill_unmeasured(level(damaged))
    fit = fit_self_affine(psd_area(level(filled))[0], band=ref.fit_band_per_m)
    assert abs(fit.hurst - ref.hurst) < 0.03
    assert abs(fit.hurst - 0.7) < 0.03


def _model_spectrum(H, h0, q0, q1, q_low, noise=0.0, n=200):
    q = np.logspace(np.log10(q_low), np.log10(q1), n)
    C = (H / (2 * np.pi)) * (h0 / q0) ** 2 * (np.maximum(q, q0) / q0) ** (-2 * (H + 1)) + noise
    return Spectrum(q, C, kind="model")


def test_model_form_h0_band_rms_and_roll_off():
    H, h0, q0, q1 = 0.8, 5e-4, 2000.0, 2e5
    s = _model_spectrum(H, h0, q0, q1, q_low=200.0)
    fit = fit_self_affine(s)
    assert fit.hurst == pytest.approx(H, abs=1e-6)
    assert fit.q_roll_per_m == pytest.approx(q0, rel=0.02)
    assert fit.h0_m == pytest.approx(h0, rel=0.02)
    # DESIGN sec 2: 2 pi int_{q0}^{q1} q C dq = h0^2/2 (1 - (q1/q0)^-2H)
    qq = np.logspace(np.log10(fit.q0_per_m), np.log10(fit.q1_per_m), 20001)
    numeric = np.sqrt(2 * np.pi * np.trapezoid(qq * fit.model_C(qq), qq))
    assert fit.band_rms_m == pytest.approx(numeric, rel=1e-4)
    assert fit.model_C(100.0) == pytest.approx(fit.C_at_q0_m4)  # plateau below q0


def test_band_excludes_roll_off_and_noise_floor():
    H, h0, q0, q1 = 0.6, 5e-4, 2000.0, 1e6
    clean = _model_spectrum(H, h0, q0, q1, q_low=100.0)
    floor = clean.C_m4[np.searchsorted(clean.q_per_m, 1e5)]
    s = Spectrum(clean.q_per_m, clean.C_m4 + floor, kind="model")
    lo, hi = detect_band(s)
    assert q0 < lo < 2 * q0
    assert 2e4 < hi < 1e5
    fit = fit_self_affine(s)
    assert abs(fit.hurst - H) < 0.03


def test_extension_continues_the_power_law():
    hm = self_affine_surface(256, dx_m=55.4e-6, hurst=0.85, rms_height_m=1e-3, seed=2)
    s, _ = psd_area(hm)
    fit = fit_self_affine(s)
    ext = extend_spectrum(s, fit, 6e5)
    assert ext.kind == "extended" and ext.q_max_per_m == pytest.approx(6e5)
    n = s.q_per_m.size
    assert np.array_equal(ext.C_m4[:n], s.C_m4)
    q_new = ext.q_per_m[n:]
    assert np.all(np.diff(ext.q_per_m) > 0)
    slope = np.polyfit(np.log(q_new), np.log(ext.C_m4[n:]), 1)[0]
    assert slope == pytest.approx(-2 * (fit.hurst + 1), rel=1e-9)
    assert np.all(ext.count[n:] == 0)
    assert 18 <= q_new.size / np.log10(6e5 / s.q_max_per_m) <= 22


def test_a_fit_band_wider_than_the_spectrum_is_the_spectrum_range():
    """Fuzz finding: --fit-band=1e-300,1e4 was recorded as given and the fitted line drawn from
    1e-300 1/m overflowed; the band fitted (and reported) is the part the spectrum covers, and
    the fit equals the one over exactly that range."""
    q = np.logspace(3, 5, 41)
    C = 1e-18 * (q / 1e3) ** (-2 * (1 + 0.8))
    sp = Spectrum(q, C)
    wide = fit_self_affine(sp, band=(1e-300, 1e300))
    exact = fit_self_affine(sp, band=(q[0], q[-1]))
    assert wide.fit_band_per_m == pytest.approx((q[0], q[-1]))
    assert wide.hurst == exact.hurst and wide.h0_m == exact.h0_m
    with np.errstate(all="raise"):
        wide.model_C(np.array(wide.fit_band_per_m))
