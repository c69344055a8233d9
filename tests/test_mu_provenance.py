"""Where mu comes from (issue 20): the extrapolated share per speed, the implausible-mu cause,
the rubber label, believable defaults on the shipped samples and the CAPTIF profiles."""

import csv
import json
from pathlib import Path

import numpy as np
import pytest

import friction
from friction import SelfAffinePSD, TabulatedPSD
from friction.band import integration_band
from pipelines.chain import provenance as mp
from pipelines.cli.app import main

ROOT = Path(__file__).resolve().parents[1]


def _mu(psd, v):
    return friction.mu_isothermal(psd, friction.thesis_rubber(), v).mu


def test_extrapolated_share_matches_the_model_cut_at_the_last_measured_q():
    """A table sampled from a power law up to q_m and extended to q1 by its own tail: the share
    equals 1 - mu(model to q_m) / mu(model to q1) computed on the model itself."""
    v = np.logspace(-3, 1, 9)
    model = SelfAffinePSD(0.8, 2e-4, 500.0, 1e6)
    q_m = 3e4
    q = np.geomspace(500.0, q_m, 80)
    table = TabulatedPSD(q, model.C(q))
    ext, _ = integration_band(table, None, 3e5)
    share = mp.extrapolated_share(ext, _mu(ext, v), q_m, lambda p: _mu(p, v))
    expect = 1 - _mu(model.with_q1(q_m), v) / _mu(model.with_q1(3e5), v)
    np.testing.assert_allclose(share, expect, atol=0.02)
    assert np.all(share > 0.2) and np.all(share < 1)
    ext2, _ = integration_band(table, None, 1e5)
    share2 = mp.extrapolated_share(ext2, _mu(ext2, v), q_m, lambda p: _mu(p, v))
    assert np.all(share2 < share)  # less extension, less share
    assert np.all(mp.extrapolated_share(table, _mu(table, v), q_m, None) == 0)
    assert np.all(mp.extrapolated_share(model, _mu(model, v), None, None) == 0)


def test_rms_slope_of_a_power_law():
    """sqrt(2 pi int q^3 C dq) for C = K q^-2(1+H): analytic."""
    H, h0, q0, q1 = 0.8, 1e-4, 1e3, 1e5
    psd = SelfAffinePSD(H, h0, q0, q1)
    K = psd.C(q0) * q0 ** (2 * (1 + H))
    expect = np.sqrt(2 * np.pi * K * (q1 ** (2 - 2 * H) - q0 ** (2 - 2 * H)) / (2 - 2 * H))
    assert mp.rms_slope(psd) == pytest.approx(expect, rel=1e-3)


@pytest.mark.parametrize(
    "kw, words",
    [
        ({"rms_height_m": 0.5}, ["units", "--units"]),
        ({"share_at_peak": 0.6}, ["cut-off", "--q1"]),
        ({"slope": 2.5, "q1_per_m": 1e5}, ["band", "--q1"]),
        ({}, ["rubber", "--rubber"]),
    ],
)
def test_implausible_cause_names_cause_and_flag(kw, words):
    line = mp.implausible_cause(6.0, **kw)
    assert "\n" not in line and all(w in line for w in words)
    assert mp.implausible_cause(1.2, **kw) is None
    assert "below" in mp.implausible_cause(0.1, default_rubber=True)


def test_rubber_label_names_rubber_temperature_pressure():
    lab = mp.rubber_label(None, 0.2e6, None)
    assert "thesis" in lab and "60" in lab and "0.2 MPa" in lab


def _analyse(path, out, *extra):
    assert main(["analyse", str(path), "--out", str(out), "--no-figures", *extra]) == 0
    return json.loads((out / "summary.json").read_text())


@pytest.mark.parametrize("name", ["asphalt.x3p", "coarse_asphalt.x3p"])
def test_shipped_samples_give_believable_mu(tmp_path, name):
    s = _analyse(ROOT / "sample_scans" / name, tmp_path / "o")
    f = s["friction"]
    assert 0.3 <= f["mu_peak"] <= 3.0
    assert "thesis" in f["rubber"] and "MPa" in f["rubber"]
    lo, hi = s["reliable_band_per_m"]
    assert set(s["reliable_band_reasons"]) == {"lo", "hi"}
    assert f["q0_per_m"] >= lo * (1 - 1e-6) and f["q1_per_m"] <= hi * (1 + 1e-6)
    assert s["fit_band_per_m"][1] <= hi * (1 + 1e-6)
    if name == "coarse_asphalt.x3p":  # made with a 14 mm roll-off
        assert 2 * np.pi / s["q_roll_per_m"] == pytest.approx(14e-3, rel=0.15)
    html = (tmp_path / "o" / "report.html").read_text()
    assert "reliable band" in html and "thesis" in html


def test_captif_profiles_refused_or_believable(tmp_path, shared_data):
    files = sorted((shared_data / "profiles" / "captif").glob("*.dat"))
    assert files
    for k, f in enumerate(files):
        s = _analyse(f, tmp_path / f"o{k}")
        fr = s["friction"]
        if "refused" in fr:
            assert "\n" not in fr["refused"] and "--" in fr["refused"]
            assert any("friction refused" in w for w in s["warnings"])
            assert not (tmp_path / f"o{k}" / "mu.csv").exists()
        else:
            assert 0.3 <= fr["mu_peak"] <= 3.0
        assert s["reliable_band_per_m"][1] < 7.9e4  # no longer up to the noise floor


def test_extension_beyond_the_scan_is_counted_and_warned(tmp_path):
    """--q1 two decades above the scan: most of mu comes from the extension; mu.csv's last
    column and summary.json say so, and the implausible-mu warning names the cut-off."""
    s = _analyse(ROOT / "sample_scans" / "asphalt.x3p", tmp_path / "o", "--q1", "5e6")
    f = s["friction"]
    with open(tmp_path / "o" / "mu.csv") as fh:
        rows = list(csv.reader(fh))
    assert rows[0][-1] == "extrapolated_share" and rows[0][:3] == ["v_m_per_s", "mu", "area_fraction"]
    d = np.array(rows[1:], float)
    i = int(np.argmax(d[:, 1]))
    assert d[i, -1] == pytest.approx(f["extrapolated_share_at_peak"]) and d[i, -1] > 0.3
    assert f["extrapolated_share"][i] == pytest.approx(d[i, -1])
    page = (tmp_path / "o" / "report.html").read_text()
    assert "extrapolated share" in page and "thesis SLS" in page  # per speed, in the report
    if f["mu_peak"] > 3:
        assert any("cut-off" in w and "--q1" in w for w in s["warnings"])
