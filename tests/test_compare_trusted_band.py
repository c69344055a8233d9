"""compare judges its PSD ratios where both surfaces are trusted (issue 37): the largest ratio,
comparison.json's ``largest_psd_ratio`` = {ratio, q_per_m, band_per_m}, lies inside both
surfaces' fit and reliable bands and is the ratio of the two spectra there; every missing figure
says why."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "sample_scans"


def _compare(tmp_path, a, b, capsys):
    from pipelines.cli.app import main

    out = tmp_path / "cmp"
    assert main(["compare", str(a), str(b), "--out", str(out), "--no-friction"]) == 0
    capsys.readouterr()
    return json.loads((out / "comparison.json").read_text()), out


def _psd(path):
    """The spectrum roadscan analyse gives the scan alone (psd.csv's rows, in memory)."""
    import pipelines

    r = pipelines.analyse(path, no_friction=True)
    return r.spectrum.q_per_m, r.spectrum.C_m4, r.summary


@pytest.mark.parametrize("other", ["coarse_asphalt.x3p", "captif_station_1_excerpt.dat"])
def test_largest_ratio_inside_both_bands_and_is_the_spectra_ratio(tmp_path, capsys, other):
    ref, oth = SAMPLES / "asphalt.x3p", SAMPLES / other
    c, out = _compare(tmp_path, ref, oth, capsys)
    names = list(c)
    d = c[names[1]]["difference_from_reference"]
    big = d["largest_psd_ratio"]
    assert set(big) == {"ratio", "q_per_m", "band_per_m"}
    q_ref, C_ref, s_ref = _psd(ref)
    q_oth, C_oth, s_oth = _psd(oth)
    lo, hi = big["band_per_m"]
    for s in (s_ref, s_oth):  # inside each fit and reliable band
        for band in (s["fit_band_per_m"], s["reliable_band_per_m"]):
            assert band[0] * (1 - 1e-9) <= lo and hi <= band[1] * (1 + 1e-9)
    for e in (c[names[0]], c[names[1]]):
        assert e["fit_band_per_m"][0] * (1 - 1e-9) <= big["q_per_m"] <= e["fit_band_per_m"][1] * (1 + 1e-9)
    # the ratio is the spectra's own at that q, and no point inside the band is farther from 1
    at = np.interp(np.log(big["q_per_m"]), np.log(q_oth), np.log(C_oth)) - np.interp(
        np.log(big["q_per_m"]), np.log(q_ref), np.log(C_ref)
    )
    assert big["ratio"] == pytest.approx(float(np.exp(at)), rel=1e-6)
    inside = (q_ref >= lo) & (q_ref <= hi)
    r = np.exp(np.interp(np.log(q_ref[inside]), np.log(q_oth), np.log(C_oth))) / C_ref[inside]
    assert abs(np.log(big["ratio"])) >= np.max(np.abs(np.log(r))) * (1 - 1e-9)
    assert d["psd_ratio_at_max"] == big["ratio"] and d["q_at_max_ratio_per_m"] == big["q_per_m"]
    page = (out / "report.html").read_text()
    assert "band both are trusted on" in page


def test_every_missing_figure_says_why(tmp_path, capsys):
    c, out = _compare(tmp_path, SAMPLES / "asphalt.x3p", SAMPLES / "coarse_asphalt.x3p", capsys)
    page = (out / "report.html").read_text()
    for e in c.values():
        why = e["why_missing"]
        assert e["mpd_m"] is None and "100 mm" in why["mpd_m"]  # 54 mm rows: no MPD
        assert e.get("mu_peak") is None and "--no-friction" in why["mu_peak"]
        assert why["mpd_m"] in page.replace("&#39;", "'")
        for key, value in e.items():
            if value is None and key in ("hurst", "h0_m", "mpd_m", "mu_peak"):
                assert key in why


def test_no_shared_trusted_band_gives_no_ratio_and_says_why():
    from pipelines.jobs.compare import spectrum_difference
    from roadscan.spectrum_types import Spectrum

    q = np.geomspace(1e2, 1e5, 200)
    a, b = Spectrum(q, q**-3.6), Spectrum(q, 4 * q**-3.6)
    d = spectrum_difference(a, b, None, "the bands do not overlap")
    assert d["largest_psd_ratio"] is None and d["largest_psd_ratio_note"] == "the bands do not overlap"
    d = spectrum_difference(a, b, (1e3, 1e4))
    assert d["largest_psd_ratio"]["ratio"] == pytest.approx(4.0, rel=1e-9)
    assert 1e3 <= d["largest_psd_ratio"]["q_per_m"] <= 1e4
