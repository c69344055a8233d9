"""End-to-end: ``roadscan dry-vs-wet`` and ``roadscan compare`` (issue 4, items 3 and 4)."""

import json

import numpy as np
import pytest
from conftest import fourier_surface

from pipelines.cli.app import main

V = "1e-4:1e2:7"  # whole decades: keys "0.0001" ... "100"


@pytest.fixture(scope="module")
def scans(tmp_path_factory):
    d = tmp_path_factory.mktemp("scans")
    fine = fourier_surface(192, 5e-5, 0.8, 2e-4, seed=1)
    fine[10:13, 20:25] = np.nan
    coarse = fourier_surface(192, 5e-5, 0.8, 6e-4, seed=2, q_roll=2 * np.pi / 2e-3)
    np.save(d / "fine.npy", fine)
    np.save(d / "coarse.npy", coarse)
    return d / "fine.npy", d / "coarse.npy", fine


def test_dry_vs_wet_contract(scans, tmp_path):
    fine_path, _, fine = scans
    out = tmp_path / "dw"
    assert (
        main(["dry-vs-wet", str(fine_path), "--spacing", "5e-5", "--out", str(out), "--velocities", V]) == 0
    )
    c = json.loads((out / "comparison.json").read_text())
    for key in (
        "rms_height_dry_m",
        "rms_height_wet_m",
        "hurst_dry",
        "hurst_wet",
        "wetted_fraction",
        "water_volume_m3_per_m2",
        "connectivity",
        "mu_dry",
        "mu_wet",
        "max_difference_v_m_per_s",
    ):
        assert key in c, key
    assert c["connectivity"] == 4
    assert set(c["mu_dry"]) == {"0.0001", "0.001", "0.01", "0.1", "1", "10", "100"}
    # water only raises the surface: less rms, less friction, nothing negative
    assert 0 < c["wetted_fraction"] < 1 and c["water_volume_m3_per_m2"] > 0
    assert c["rms_height_wet_m"] < c["rms_height_dry_m"]
    assert all(c["mu_wet"][k] <= c["mu_dry"][k] * 1.001 for k in c["mu_dry"])
    assert c["max_difference_v_m_per_s"] in [float(k) for k in c["mu_dry"]]
    wet = np.load(out / "wet.npy")
    assert wet.shape == fine.shape
    assert np.array_equal(np.isnan(wet), np.isnan(fine))  # unmeasured stays unmeasured
    # same levelled frame as the dry surface: wet >= levelled dry everywhere measured
    from roadscan.heightmap import HeightMap
    from roadscan.level import level

    dry = level(HeightMap(fine, 5e-5, 5e-5), degree=1).heights_m
    ok = ~np.isnan(fine)
    assert np.all(wet[ok] >= dry[ok] - 1e-15)
    assert np.mean(wet[ok] - dry[ok]) == pytest.approx(c["water_volume_m3_per_m2"], rel=0.02)
    for png in ("psd_dry_wet.png", "mu_dry_wet.png", "water_depth.png", "mu_ratio.png"):
        assert (out / png).exists(), png
    assert "base64" in (out / "report.html").read_text()


def test_dry_vs_wet_connectivity_8_holds_less_water(scans, tmp_path):
    fine_path = scans[0]
    a, b = tmp_path / "a", tmp_path / "b"
    assert main(["dry-vs-wet", str(fine_path), "--spacing", "5e-5", "--out", str(a), "--no-friction"]) == 0
    assert (
        main(
            [
                "dry-vs-wet",
                str(fine_path),
                "--spacing",
                "5e-5",
                "--out",
                str(b),
                "--no-friction",
                "--connectivity",
                "8",
            ]
        )
        == 0
    )
    ca = json.loads((a / "comparison.json").read_text())
    cb = json.loads((b / "comparison.json").read_text())
    assert cb["connectivity"] == 8
    assert cb["water_volume_m3_per_m2"] <= ca["water_volume_m3_per_m2"]


def test_compare_contract(scans, tmp_path):
    fine_path, coarse_path, _ = scans
    out = tmp_path / "cmp"
    assert (
        main(
            [
                "compare",
                str(fine_path),
                str(coarse_path),
                "--spacing",
                "5e-5",
                "--out",
                str(out),
                "--velocities",
                V,
            ]
        )
        == 0
    )
    c = json.loads((out / "comparison.json").read_text())
    assert set(c) == {"fine", "coarse"}
    for name in c:
        for key in ("hurst", "rms_height_m", "mu", "h0_m"):
            assert key in c[name]
    assert c["coarse"]["rms_height_m"] > 2 * c["fine"]["rms_height_m"]
    d = c["coarse"]["difference_from_reference"]
    assert d["reference"] == "fine" and d["psd_ratio_median"] > 1
    assert d["max_difference_v_m_per_s"] in [float(k) for k in c["fine"]["mu"]]
    for png in ("psd_all.png", "mu_all.png", "psd_ratio.png", "mu_ratio.png"):
        assert (out / png).exists(), png


def test_compare_needs_two(scans, tmp_path, capsys):
    assert main(["compare", str(scans[0]), "--spacing", "5e-5", "--out", str(tmp_path / "x")]) == 2
    assert "at least two" in capsys.readouterr().err
