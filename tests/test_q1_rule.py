"""The large-wavevector cut-off q1 (issue 37, pipelines/chain/cutoff.py): Persson's criterion
where a band ending at the noise floor is steeper than rms slope 1, friction on the real CAPTIF
road profiles, refusal only without a trusted decade, the rule stated in summary.json, the
report and the headline, and the sample scan's band left alone."""

from __future__ import annotations

import json
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from pipelines.chain.cutoff import slope_cutoff

ROOT = Path(__file__).resolve().parents[1]


class PowerLaw:
    """C(q) = K q^-2(1+H) [m^4]: its rms slope from q0 is known in closed form."""

    def __init__(self, K, H):
        self.K, self.H = K, H

    def C(self, q):
        return self.K * np.asarray(q, float) ** (-2 * (1 + self.H))

    def q_at_slope(self, q0, xi):
        # xi^2 = 2 pi K (q^(2-2H) - q0^(2-2H)) / (2 - 2H)
        e = 2 - 2 * self.H
        return (q0**e + xi**2 * e / (2 * np.pi * self.K)) ** (1 / e)

    def K_for(self, q0, q1, xi, H):
        e = 2 - 2 * H
        return xi**2 * e / (2 * np.pi * (q1**e - q0**e))


@pytest.mark.parametrize("H", [0.3, 0.7, 0.9])
def test_slope_cutoff_matches_the_closed_form(H):
    K = PowerLaw(1, H).K_for(1e2, 1e4, 1.0, H)  # rms slope 1 reached at q = 1e4
    psd = PowerLaw(K, H)
    assert psd.q_at_slope(1e2, 1.0) == pytest.approx(1e4, rel=1e-12)
    q = slope_cutoff(psd, 1e2, 1e6)
    assert q == pytest.approx(1e4, rel=2e-3)
    assert slope_cutoff(psd, 1e2, 5e3) is None  # not reached inside the band
    assert slope_cutoff(psd, 1e2, 1e8, target=2.0) == pytest.approx(psd.q_at_slope(1e2, 2.0), rel=2e-3)


def _steep_spectrum(H=0.6, q0=2e3, q1=8e3, xi=2.0):
    """A measured-like spectrum (power law, 2e2..1e5 1/m) whose rms slope over [q0, q1] is xi."""
    from roadscan.fit import fit_self_affine
    from roadscan.spectrum_types import Spectrum

    K = PowerLaw(1, H).K_for(q0, q1, xi, H)
    q = np.geomspace(2e2, 1e5, 400)
    spec = Spectrum(q, PowerLaw(K, H).C(q), kind="2d")
    return spec, fit_self_affine(spec, band=(2e2, 1e5)), PowerLaw(K, H)


def _band(lo, hi):
    return SimpleNamespace(valid=True, lo_per_m=lo, hi_per_m=hi, q_roll_per_m=None, noise_floor_end=True)


def test_steep_noise_floor_band_of_three_decades_is_cut_where_the_slope_reaches_one():
    from pipelines.chain.provenance import rms_slope
    from pipelines.chain.steps import friction_psd, judge_fine_end
    from pipelines.settings.friction import FrictionSettings

    spec, fit, law = _steep_spectrum()
    rb, settings = _band(2e2, 8e4), FrictionSettings()
    psd, band = friction_psd(spec, fit, rb, settings, say=False)
    want = law.q_at_slope(2e2, 1.0)  # closed form on the true spectrum
    assert psd.q1_per_m == pytest.approx(want, rel=0.03)
    assert psd.q1_per_m < rb.hi_per_m
    assert rms_slope(psd) == pytest.approx(1.0, abs=0.02)
    assert "Persson" in band["q1_rule"] and "noise floor" in band["q1_rule"]
    _slope, refused = judge_fine_end(psd, rb, settings)
    assert refused is None


def test_refused_only_without_a_trusted_decade():
    from pipelines.chain.steps import friction_psd, judge_fine_end
    from pipelines.settings.friction import FrictionSettings

    spec, fit, _ = _steep_spectrum()
    rb, settings = _band(2e3, 8e3), FrictionSettings()  # 0.6 decade, rms slope 2
    psd, band = friction_psd(spec, fit, rb, settings, say=False)
    assert psd.q1_per_m == pytest.approx(8e3)
    slope, refused = judge_fine_end(psd, rb, settings)
    assert slope == pytest.approx(2.0, rel=0.03)
    assert refused is not None and "no decade" in refused and "--q1" in refused
    given = FrictionSettings(q1_per_m=6e3)  # the user's end: no refusal
    psd, band = friction_psd(spec, fit, rb, given, say=False)
    assert judge_fine_end(psd, rb, given)[1] is None
    assert band["q1_rule"] == "given by --q1"


def _analyse_cli(path, out, *flags):
    from pipelines.cli.app import main

    assert main(["analyse", str(path), "--out", str(out), "--no-figures", *flags]) == 0
    return json.loads((out / "summary.json").read_text())


def _xi_from_psd_csv(path, q0, q1):
    """rms slope sqrt(2 pi int_{q0}^{q1} q^3 C dq) from psd.csv, trapezoids in q (independent
    of the chain's log-grid quadrature)."""
    rows = np.loadtxt(path, delimiter=",", skiprows=1)
    q, C = rows[:, 0], rows[:, 1]
    g = np.concatenate([[q0], q[(q > q0) & (q < q1)], [q1]])
    Cg = np.exp(np.interp(np.log(g), np.log(q), np.log(C)))
    f = g**3 * Cg
    return math.sqrt(2 * np.pi * float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(g))))


def test_captif_profiles_get_friction_with_the_q1_rule_stated(tmp_path, shared_data, capsys):
    files = sorted((shared_data / "profiles" / "captif").glob("*.dat"))
    assert len(files) == 3
    for k, f in enumerate(files):
        out = tmp_path / f"o{k}"
        s = _analyse_cli(f, out)
        headline = capsys.readouterr().out
        lo, hi = s["reliable_band_per_m"]
        assert math.log10(hi / lo) > 1  # a trusted band over a decade
        fr = s["friction"]
        assert "refused" not in fr and (out / "mu.csv").exists()
        assert fr["q0_per_m"] < fr["q1_per_m"] <= hi * (1 + 1e-9)
        if s["reliable_band_limits_per_m"]["noise_floor"] == hi and fr["q1_per_m"] < hi * 0.999:
            assert "Persson" in fr["q1_rule"]
            xi = _xi_from_psd_csv(out / "psd.csv", fr["q0_per_m"], fr["q1_per_m"])
            assert xi == pytest.approx(1.0, rel=0.05)  # Persson's criterion, re-checked
            assert any("Persson" in w and "--q1" in w for w in s["warnings"])
        assert "q1 = " in headline and fr["q1_rule"] in headline  # the headline says which and why
        html = (out / "report.html").read_text()
        assert "short end q1" in html


def test_sample_scan_keeps_its_band_end_and_says_why():
    import pipelines

    s = pipelines.analyse(ROOT / "sample_scans" / "asphalt.x3p").summary
    fr = s["friction"]
    assert fr["q1_per_m"] == pytest.approx(s["reliable_band_per_m"][1], rel=1e-12)
    assert fr["q1_rule"] == "the reliable band's short end (Nyquist)"
    assert s["reliable_band_reasons"]["hi"].startswith("Nyquist")
