"""ISO 13473-4 third-octave texture levels (roadscan.texture_spectrum, issue 21)."""

from pathlib import Path

import numpy as np
import pytest
from conftest import _shared_dir

from roadscan.heightmap import HeightMap, Profile
from roadscan.texture_spectrum import (
    MIN_BINS,
    MIN_SAMPLES_PER_WAVELENGTH,
    NOMINAL_MM,
    texture_spectrum,
    third_octave_bands,
)

CAPTIF = (_shared_dir() or Path("/nonexistent")) / "data" / "profiles" / "captif"


def _expected(A):
    return 20 * np.log10(A / (np.sqrt(2) * 1e-6))


def test_band_definition():
    nom, c, lo, hi = third_octave_bands()
    assert len(NOMINAL_MM) == 31 and nom[0] == 0.5 and nom[-1] == 500
    k = np.arange(-3, 28)
    assert np.allclose(c, 10.0 ** (k / 10) * 1e-3, rtol=1e-12)
    assert np.allclose(lo, c * 10 ** (-1 / 20)) and np.allclose(hi, c * 10 ** (1 / 20))
    assert np.allclose(hi[:-1], lo[1:])  # contiguous bands
    assert np.all(np.abs(nom * 1e-3 / c - 1) < 0.02)  # nominal labels near the exact centres


def test_sines_at_nominal_centres():
    dx, n = 0.05e-3, 40000  # 2 m profile
    x = np.arange(n) * dx
    rng = np.random.default_rng(4)
    amps = {1.0: 0.5e-3, 2.5: 0.7e-3, 8: 1.0e-3, 31.5: 0.8e-3, 80: 1.0e-3}
    z = (
        sum(A * np.sin(2 * np.pi * x / (lam * 1e-3) + rng.uniform(0, 2 * np.pi)) for lam, A in amps.items())
        + 3e-4 * x / x[-1]
    )  # plus a tilt
    ts = texture_spectrum(Profile(z, dx))
    got = dict(zip(ts.nominal_mm, ts.level_dB))
    for lam, A in amps.items():
        assert abs(got[lam] - _expected(A)) < 0.5, (lam, got[lam], _expected(A))
    floor = min(got[lam] for lam in amps)
    others = [v for k, v in got.items() if k not in amps]
    assert others and max(others) < floor - 10
    assert 100 in got and 125 not in got  # 2 m: lambda_hi <= L / 15.4


def test_longest_resolved_band_keeps_a_centred_sine():
    dx = 0.1e-3
    for n in (6000, 9500, 17000, 31000):
        x = np.arange(n) * dx
        lam = texture_spectrum(Profile(np.sin(x * 1e3), dx)).nominal_mm[-1]
        ts = texture_spectrum(Profile(1e-3 * np.sin(2 * np.pi * x / (lam * 1e-3) + 0.7), dx))
        assert ts.nominal_mm[-1] == lam
        assert abs(ts.level_dB[-1] - _expected(1e-3)) < 0.1
        assert ts.level_dB[-2] < ts.level_dB[-1] - 10


def test_resolved_band_limits():
    dx, n = 0.2e-3, 2000  # 400 mm at 0.2 mm
    ts = texture_spectrum(Profile(np.random.default_rng(0).normal(size=n) * 1e-4, dx))
    L = n * dx
    assert np.all(ts.lo_m >= MIN_SAMPLES_PER_WAVELENGTH * dx * (1 - 1e-9))
    assert np.all((1 / ts.lo_m - 1 / ts.hi_m) * L >= MIN_BINS * (1 - 1e-9))
    _, c, lo, hi = third_octave_bands()
    assert ts.lo_m[0] / dx < MIN_SAMPLES_PER_WAVELENGTH * 10**0.1  # the next finer is not
    nxt = np.searchsorted(c, ts.centre_m[-1] * 1.01)
    assert (1 / lo[nxt] - 1 / hi[nxt]) * L < MIN_BINS


def _ideal_bandpass_levels(z, dx, lo, hi):
    """Straightforward reference for a periodic profile (no leakage, so no window nor detrend):
    rectangular FFT, keep the band's bins, inverse FFT, rms in the space domain."""
    n = z.size
    Z = np.fft.rfft(z)
    f = np.fft.rfftfreq(n, dx)
    out = []
    for a, b in zip(lo, hi):
        keep = (f >= 1 / b) & (f < 1 / a)
        out.append(20 * np.log10(np.sqrt(np.mean(np.fft.irfft(Z * keep, n) ** 2)) / 1e-6))
    return np.array(out)


def test_matches_ideal_fft_bandpass_on_random_rough_profiles():
    """Periodic random profiles with a red spectrum. The Hann window mixes neighbouring bins of
    random phase, so a band of N FFT bins scatters about 4.3 / sqrt(N) dB around the exact
    band rms (0.11 dB at N = 1500, 1 dB at N = 19): each band within 15 / sqrt(N) dB, and no
    bias, the mean difference over 16 profiles within 0.5 dB where N >= 10."""
    dx, n = 0.05e-3, 2**16
    f = np.fft.rfftfreq(n, dx)
    amp = np.zeros(f.size)
    amp[1:] = f[1:] ** -1.4  # red, self-affine-like spectrum
    diffs = []
    for seed in range(16):
        rng = np.random.default_rng(seed)
        z = np.fft.irfft(amp * np.exp(2j * np.pi * rng.uniform(size=f.size)), n)
        z *= 3e-4 / z.std()
        ts = texture_spectrum(Profile(z, dx))
        diffs.append(ts.level_dB - _ideal_bandpass_levels(z, dx, ts.lo_m, ts.hi_m))
    diffs = np.array(diffs)
    bins = (1 / ts.lo_m - 1 / ts.hi_m) * n * dx
    assert np.all(np.abs(diffs) < 15 / np.sqrt(bins))
    assert np.max(np.abs(diffs[:, bins >= 10].mean(axis=0))) < 0.5


def test_area_lines_along_driving_direction_and_mean_of_squares():
    dx, nx, ny = 0.1e-3, 4000, 6
    x = np.arange(nx) * dx
    A = np.array([0.1, 0.2, 0.3, 0.1, 0.2, 0.3]) * 1e-3
    h = A[:, None] * np.sin(2 * np.pi * x / 10e-3)[None, :]
    hm = HeightMap(h, dx, dx)
    tx = texture_spectrum(hm, direction="x")
    lvl = dict(zip(tx.nominal_mm, tx.level_dB))
    assert abs(lvl[10] - 10 * np.log10(np.mean(A**2) / 2 / 1e-12)) < 0.1
    ty = texture_spectrum(hm.with_heights(h.T.copy(), np.zeros((nx, ny), bool)), direction="y")
    assert np.allclose(ty.level_dB, tx.level_dB, atol=1e-9)
    with pytest.raises(ValueError):
        texture_spectrum(hm, direction="z")


def test_dropouts_filled_linearly():
    dx, n = 0.05e-3, 30000
    x = np.arange(n) * dx
    z = 0.5e-3 * np.sin(2 * np.pi * x / 5e-3)
    rng = np.random.default_rng(3)
    bad = np.zeros(n, bool)
    for s in rng.integers(0, n - 20, 60):
        bad[s : s + 10] = True  # 2 % in 0.5 mm gaps
    ts = texture_spectrum(Profile(z, dx, unmeasured=bad))
    lvl = dict(zip(ts.nominal_mm, ts.level_dB))
    assert abs(lvl[5] - _expected(0.5e-3)) < 0.5
    assert "dropouts filled" in ts.note
    assert np.all(np.isfinite(ts.level_dB))


def _welch_levels(z, dx, lo, hi):
    """Independent estimate: scipy.signal.welch (Hann segments of half the profile, 50 % overlap,
    linear detrend per segment), density integrated over each band with the trapezoid rule."""
    from scipy.signal import welch

    f, p = welch(z, fs=1 / dx, window="hann", nperseg=z.size // 2, detrend="linear", scaling="density")
    out = []
    for a, b in zip(lo, hi):
        fa, fb = 1 / b, 1 / a
        inside = (f > fa) & (f < fb)
        ff = np.r_[fa, f[inside], fb]
        pp = np.r_[np.interp(fa, f, p), p[inside], np.interp(fb, f, p)]
        out.append(10 * np.log10(np.trapezoid(pp, ff) / 1e-12))
    return np.array(out)


@pytest.mark.skipif(not CAPTIF.is_dir(), reason="CAPTIF profiles not available")
@pytest.mark.parametrize("station", [0, 1, 10])
def test_captif_levels_match_welch(station):
    from roadscan.io import read
    from roadscan.trim import road_section

    prof = road_section(read(CAPTIF / f"20211011_aylesbury_dec_station_{station}.dat"))
    ts = texture_spectrum(prof)
    sel = (ts.nominal_mm >= 2) & (ts.nominal_mm <= 50)
    assert sel.sum() == 15
    z = prof.heights_m.copy()
    good = np.isfinite(z)
    idx = np.arange(z.size)
    z[~good] = np.interp(idx[~good], idx[good], z[good])
    ref = _welch_levels(z, prof.dx_m, ts.lo_m[sel], ts.hi_m[sel])
    assert np.max(np.abs(ts.level_dB[sel] - ref)) < 1.5
    assert np.all(ts.level_dB[sel] > 20)  # macrotexture: tens of dB re 1 um


def test_vectorised_line_fill_equals_np_interp():
    from roadscan.texture_spectrum import _fill_lines

    rng = np.random.default_rng(0)
    z = rng.normal(size=(40, 150))
    z[rng.random(z.shape) < 0.3] = np.nan
    z[3] = np.nan  # no data: stays NaN (the line is skipped)
    z[4, :50] = np.nan  # leading and trailing gaps: held at the nearest value
    z[5, -30:] = np.nan
    f = _fill_lines(z)
    x = np.arange(z.shape[1])
    for i in range(z.shape[0]):
        good = np.isfinite(z[i])
        if good.any():
            assert np.allclose(f[i], np.interp(x, x[good], z[i, good]), rtol=1e-12, atol=0)
        else:
            assert np.isnan(f[i]).all()
