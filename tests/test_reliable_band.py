"""The reliable band of a spectrum (issue 20): leakage at the low end, Nyquist, lateral
resolution and noise floor at the high end, roll-off detection; validated on synthetic surfaces
of known C(q) "measured" by simulated instruments (non-periodic views)."""

import numpy as np
import pytest

from roadscan import level
from roadscan.reliable_band import (
    NYQUIST_FRACTION,
    RESPONSE_MIN,
    gaussian_response,
    leakage_factor,
    reliable_band,
    resolution_limit,
)
from roadscan.rolloff import detect_roll_off
from roadscan.spectrum import psd_area
from roadscan.synth import model_psd
from roadscan.synth_measure import measure_synthetic

H, K, N, DX = 0.8, 1e-20, 128, 1e-5
Q_FOV = 2 * np.pi / (N * DX)


def _measure(seed, n=N, **kw):
    hm = level.level(measure_synthetic(n, DX, H, K, seed=seed, **kw), degree=1)
    spec, _ = psd_area(hm)
    return spec


def _band(spec, n=N, **kw):
    return reliable_band(spec.q_per_m, spec.C_m4, spec.count, n * DX, DX, **kw)


def _log_ratio(spec, ks, q_roll=None):
    k = spec.q_per_m / Q_FOV
    truth = model_psd(spec.q_per_m, H, K, q_roll_per_m=q_roll)
    return np.interp(ks, k, np.log(spec.C_m4 / truth))


def test_leakage_factor_table():
    assert leakage_factor(2.0) == 4.0 and leakage_factor(5.0) == leakage_factor(4.0) <= 15.0
    assert 8.0 <= leakage_factor(2 + 2 * 0.8) <= 15.0  # steep: 8-15 x 2 pi / L
    assert leakage_factor(3.0) < leakage_factor(3.6) < leakage_factor(4.0)


def test_low_end_leakage_biases_below_and_not_above():
    """Mean over seeds of log(C / truth): biased upwards at 3-5 x 2 pi / L (the window leaks the
    modes longer than the view), within 12 % from the band's lo on."""
    ks_low = np.array([3.0, 4.0, 5.0])
    lows, ins, los = [], [], []
    for seed in range(10):
        spec = _measure(seed)
        rb = _band(spec)
        los.append(rb.lo_per_m / Q_FOV)
        lows.append(_log_ratio(spec, ks_low))
        ks_in = np.geomspace(rb.lo_per_m / Q_FOV, 0.5 * N / 2, 6)
        ins.append(_log_ratio(spec, ks_in))
    assert np.exp(np.mean(lows)) > 1.2
    assert abs(np.exp(np.mean(ins)) - 1) < 0.12
    assert all(8 <= k <= 15 for k in los)
    assert rb.lo_reason.startswith("field of view")


def test_roll_off_found_and_sets_lo_without_false_positives():
    q_roll = 6 * Q_FOV
    found = []
    for seed in range(4):
        spec = _measure(seed, q_roll_per_m=q_roll)
        rb = _band(spec)
        found.append(rb.q_roll_per_m)
        assert rb.lo_reason.startswith("roll-off")
        assert rb.lo_per_m < leakage_factor(-rb.slope) * Q_FOV
    assert all(f is not None and abs(np.log(f / q_roll)) < np.log(1.35) for f in found)
    none = [_band(_measure(100 + s)).q_roll_per_m for s in range(6)]
    assert none.count(None) >= 5


def test_detect_roll_off_on_a_broken_line():
    q = np.geomspace(100, 1e5, 60)
    slope, icpt = -3.6, 0.0
    C = 10 ** (icpt + slope * np.log10(np.maximum(q, 1000.0)))
    r = detect_roll_off(q, C, np.full(q.size, 1000), slope, icpt, 30.0, 1e5)
    assert r == pytest.approx(1000.0, rel=0.15)
    C2 = 10 ** (icpt + slope * np.log10(q))
    assert detect_roll_off(q, C2, np.full(q.size, 1000), slope, icpt, 30.0, 1e5) is None


def test_high_end_is_nyquist_fraction_without_noise_or_blur():
    spec = _measure(3, oversample=1)  # no folding: the spectrum holds to Nyquist
    rb = _band(spec)
    assert rb.hi_per_m == pytest.approx(NYQUIST_FRACTION * np.pi / DX)
    assert rb.hi_reason.startswith("Nyquist")


def test_high_end_at_lateral_resolution():
    res = 2.5 * DX
    spec = _measure(4, resolution_m=res, n=256)
    rb = _band(spec, n=256, resolution_m=res)
    assert rb.hi_reason.startswith("lateral resolution")
    assert rb.hi_per_m == pytest.approx(resolution_limit(res))
    assert gaussian_response(rb.hi_per_m, res) == pytest.approx(RESPONSE_MIN)
    assert rb.hi_per_m < 2 * np.pi / res  # before the 50 % wavelength
    sel = (spec.q_per_m >= rb.lo_per_m) & (spec.q_per_m <= rb.hi_per_m)
    ratio = spec.C_m4[sel] / model_psd(spec.q_per_m[sel], H, K)
    assert ratio.min() > RESPONSE_MIN**2 * 0.85  # attenuation still small


@pytest.mark.parametrize("at", [0.3, 0.6])
def test_high_end_before_white_noise_dominates(at):
    """White noise whose C equals the surface's at ``at`` x Nyquist: the band ends where the
    noise is still under a third of the signal."""
    q_eq = at * np.pi / DX
    c_noise = K * q_eq ** (-2 * (H + 1))
    sigma = np.sqrt(c_noise * (2 * np.pi) ** 2 / DX**2)  # C_white = sigma^2 dx dy / (2 pi)^2
    for seed in (5, 6):
        spec = _measure(seed, noise_rms_m=sigma, oversample=1)
        rb = _band(spec)
        assert rb.hi_reason.startswith("noise floor")
        share = c_noise / model_psd(rb.hi_per_m, H, K)
        assert share < 1 / 3
        assert rb.hi_per_m > 0.25 * q_eq  # and not absurdly early


def test_profile_spectrum_band():
    """A line profile's 1D spectrum: the slope is 1 + 2H, so the window leaks less."""
    from roadscan.heightmap import Profile
    from roadscan.spectrum import psd_profile

    hm = measure_synthetic(512, DX, H, K, seed=7, pad=2, oversample=1)
    profs = [level.level(Profile(row.copy(), DX, name="p"), degree=1) for row in hm.heights_m[::16]]
    _q, _C1, spec = psd_profile(profs)
    C1b = np.asarray(spec.meta["C1_binned_m3"])
    rb = reliable_band(spec.q_per_m, C1b, spec.count, profs[0].length_m, DX)
    assert rb.slope == pytest.approx(-(1 + 2 * H), abs=0.45)
    q_fov = 2 * np.pi / profs[0].length_m
    assert 4 * q_fov <= rb.lo_per_m <= 9 * q_fov


def test_coarse_sample_roll_off_14_mm():
    """sample_scans/coarse_asphalt.x3p was made with a roll-off at 14 mm (sample_scans/README)."""
    from pathlib import Path

    from roadscan import inpaint
    from roadscan.io import read

    hm = read(Path(__file__).resolve().parents[1] / "sample_scans" / "coarse_asphalt.x3p")
    filled, _ = inpaint.fill_unmeasured(level.level(hm, degree=1))
    spec, _ = psd_area(filled)
    rb = reliable_band(spec.q_per_m, spec.C_m4, spec.count, min(hm.size_m), max(hm.dx_m, hm.dy_m))
    assert rb.q_roll_per_m is not None
    assert 2 * np.pi / rb.q_roll_per_m == pytest.approx(14e-3, rel=0.15)
    assert rb.lo_reason.startswith("roll-off")


def test_resolution_from_the_flag_or_the_file_metadata(tmp_path):
    """analyse --resolution ends the band at the 80 % response; without the flag the file's
    instrument metadata gives it (pipelines.chain.reliable)."""
    import json
    from pathlib import Path

    from pipelines.chain.reliable import resolution_of, scan_band
    from pipelines.cli.app import main

    sample = Path(__file__).resolve().parents[1] / "sample_scans" / "coarse_asphalt.x3p"
    assert (
        main(
            [
                "analyse",
                str(sample),
                "--out",
                str(tmp_path / "o"),
                "--no-figures",
                "--no-friction",
                "--resolution",
                "2e-4",
            ]
        )
        == 0
    )
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert s["reliable_band_reasons"]["hi"].startswith("lateral resolution")
    assert s["reliable_band_per_m"][1] == pytest.approx(resolution_limit(2e-4))
    hm = measure_synthetic(N, DX, H, K, seed=8)
    hm.meta["instrument"] = {"lateral_resolution_m": 3 * DX}
    assert resolution_of(hm) == (3 * DX, "file metadata")
    assert resolution_of(hm, 1e-5) == (1e-5, "given")
    spec, _ = psd_area(level.level(hm, degree=1))
    rb = scan_band(hm, spec)
    assert rb.limits["resolution"] == pytest.approx(resolution_limit(3 * DX))
