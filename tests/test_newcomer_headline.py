"""Headline figures only when they are ones: the Hurst exponent (null with hurst_note over a
band under half a decade or outside [0, 1]), the friction peak (peak_at_edge when the largest
mu sits at an end of the speed grid), the default rubber named illustrative, --rubber given a
CSV, and the wet model's scope in dry-vs-wet."""

import json
from pathlib import Path

import numpy as np
import pytest
from fault_tools import assert_one_line_error, run_cli

from pipelines.output.headline import (
    RUBBER_ILLUSTRATIVE,
    WET_MODEL,
    WET_MODEL_PERSSON,
    hurst_keys,
    hurst_text,
    peak_keys,
    peak_text,
)

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "sample_scans" / "asphalt.x3p"
SAMPLE_PSD = ROOT / "sample_scans" / "asphalt_psd.csv"


# ------------------------------------------------------------------------------ Hurst
def test_hurst_given_over_a_wide_band_within_0_1():
    k = hurst_keys(0.8, 0.01, (1e3, 1e4))
    assert k["hurst"] == 0.8 and k["hurst_stderr"] == 0.01 and k["hurst_note"] is None
    assert hurst_text(k) == "0.800 ± 0.010"


@pytest.mark.parametrize(
    "H, band, why",
    [
        (2.203, (1e5, 1.26e5), "0.1 decades"),
        (0.7, (1e3, 3e3), "decades"),
        (1.4, (1e3, 1e5), "outside [0, 1]"),
        (-0.2, (1e3, 1e5), "outside [0, 1]"),
        (float("nan"), (1e3, 1e5), "no finite H"),
    ],
)
def test_hurst_null_with_a_note(H, band, why):
    k = hurst_keys(H, 4.485, band)
    assert k["hurst"] is None and k["hurst_stderr"] is None
    assert why in k["hurst_note"]
    if np.isfinite(H):
        assert k["hurst_fit"] == H and k["hurst_fit_stderr"] == 4.485
    assert k["hurst_note"].endswith(hurst_text(k))  # the report says the note, not the number
    assert f"{H:.3f}" not in hurst_text(k, short=True)


def _steep_surface(path, H=1.6, n=256, dx=5e-5, seed=0):
    """A random surface whose spectrum falls as q^-2(1+H) with H > 1 (smoother than any
    self-affine road): its fitted H lies outside [0, 1]."""
    rng = np.random.default_rng(seed)
    qx = 2 * np.pi * np.fft.fftfreq(n, dx)
    q = np.hypot(*np.meshgrid(qx, qx))
    q[0, 0] = np.inf
    h = np.real(np.fft.ifft2(q ** (-(1 + H)) * np.exp(2j * np.pi * rng.random((n, n)))))
    h *= 3e-4 / h.std()
    np.savez(path, heights=h, dx=dx, dy=dx)
    return path


def test_analyse_short_fit_band_gives_no_hurst(tmp_path, capsys):
    out = tmp_path / "out"
    rc, err = run_cli(
        capsys, ["analyse", SAMPLE, "--out", out, "--no-friction", "--no-figures", "--fit-band", "3000,5000"]
    )  # 0.22 decade
    assert rc == 0, err
    s = json.loads((out / "summary.json").read_text())
    assert s["hurst"] is None and "decades" in s["hurst_note"]
    assert np.isfinite(s["hurst_fit"])
    page = (out / "report.html").read_text()
    assert "not given: the fitted band spans" in page


def test_analyse_steep_surface_never_headlines_h_above_1(tmp_path, capsys):
    p = _steep_surface(tmp_path / "steep.npz")
    out = tmp_path / "out"
    rc, err = run_cli(capsys, ["analyse", p, "--out", out, "--no-friction", "--no-figures"])
    assert rc == 0, err
    s = json.loads((out / "summary.json").read_text())
    if s["hurst"] is not None:  # whatever the fit, never a headline outside
        assert 0.0 <= s["hurst"] <= 1.0
    else:
        assert s["hurst_note"]
    assert s["hurst_fit"] > 1.0  # the surface is steeper than self-affine


# ------------------------------------------------------------------------------ peak at edge
def test_peak_keys_inside_and_at_both_ends():
    v = np.geomspace(1e-4, 100, 61)
    bump = np.exp(-(np.log10(v / 0.3) ** 2))
    k = peak_keys(v, bump)
    assert not k["peak_at_edge"] and k["peak_note"] is None
    assert k["v_peak_m_per_s"] == pytest.approx(v[np.argmax(bump)])
    rising = peak_keys(v, np.log1p(v))
    assert rising["peak_at_edge"] and "still rising at 100 m/s" in rising["peak_note"]
    assert "peak" not in peak_text(**rising).replace("no peak", "")
    falling = peak_keys(v, 1 / (1 + v))
    assert falling["peak_at_edge"] and "slowest speed" in falling["peak_note"]


@pytest.mark.parametrize(
    "velocities, edge", [("1e-4:1:20", True), ("1e-4:1000:40", False), ("100:1000:20", True)]
)
def test_friction_peak_at_edge_in_mu_summary(tmp_path, capsys, velocities, edge):
    out = tmp_path / "mu.csv"
    rc, err = run_cli(capsys, ["friction", "--psd", SAMPLE_PSD, "--out", out, "--velocities", velocities])
    assert rc == 0, err
    s = json.loads((tmp_path / "mu_summary.json").read_text())
    mu = np.loadtxt(out, delimiter=",", skiprows=1)[:, 1]  # independent: from mu.csv
    i = int(np.argmax(mu))
    assert s["peak_at_edge"] is (i in (0, mu.size - 1))
    assert s["peak_at_edge"] is edge


def test_friction_console_says_still_rising(tmp_path, capsys):
    from pipelines.cli.app import main

    capsys.readouterr()
    rc = main(
        ["friction", "--psd", str(SAMPLE_PSD), "--out", str(tmp_path / "mu.csv"), "--velocities", "1e-4:1:20"]
    )
    said = capsys.readouterr().out
    assert rc == 0
    assert "still rising at 1.00 m/s" in said and "peak μ" not in said


def test_analyse_summary_and_report_peak_at_edge(tmp_path, capsys):
    out = tmp_path / "out"
    rc, err = run_cli(capsys, ["analyse", SAMPLE, "--out", out, "--no-figures", "--velocities", "1e-4:1:20"])
    assert rc == 0, err
    s = json.loads((out / "summary.json").read_text())
    assert s["friction"]["peak_at_edge"] is True
    assert s["friction"]["v_peak_m_per_s"] == pytest.approx(1.0)
    page = (out / "report.html").read_text()
    assert "still rising at 1.00 m/s" in page and "speed at peak" not in page
    # the default rubber is named illustrative in summary.json and the report
    assert RUBBER_ILLUSTRATIVE in s["friction"]["rubber"]
    assert RUBBER_ILLUSTRATIVE in page


# ------------------------------------------------------------------------------ rubber
def test_rubber_csv_names_master_curve(tmp_path, capsys):
    master = tmp_path / "master.csv"
    master.write_text("f_Hz,E_stor_Pa,E_loss_Pa\n1,1e6,1e5\n10,2e6,3e5\n100,4e6,9e5\n")
    rc, err = run_cli(
        capsys, ["friction", "--psd", SAMPLE_PSD, "--rubber", master, "--out", tmp_path / "mu.csv"]
    )
    assert_one_line_error(rc, err, words=[str(master), "--master-curve", "--shift-table"])
    assert "invalid TOML" not in err


def test_rubber_broken_toml_still_says_toml(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text("[rubber\nkind = 'sls'\n")
    rc, err = run_cli(
        capsys, ["friction", "--psd", SAMPLE_PSD, "--rubber", bad, "--out", tmp_path / "mu.csv"]
    )
    assert_one_line_error(rc, err, words=[str(bad), "TOML"])
    assert "--master-curve" not in err


# ------------------------------------------------------------------------------ wet model
def test_dry_vs_wet_says_what_the_wet_model_covers(tmp_path, capsys):
    # 9 speeds over the default span 1e-4..1e2 m/s instead of 61: what is checked (the model's
    # statements, the edge keys, the report's text) does not depend on the count
    speeds = ["--velocities", "1e-4:1e2:9"]
    out = tmp_path / "dw"
    rc, err = run_cli(capsys, ["dry-vs-wet", SAMPLE, "--out", out, *speeds])
    assert rc == 0, err
    c = json.loads((out / "comparison.json").read_text())
    # the default (persson) model says what it covers and leaves out, as the fill model does
    assert c["wet_model"]["name"] == "persson"
    assert c["wet_model"]["covers"] == WET_MODEL_PERSSON["covers"]
    left = " ".join(c["wet_model"]["leaves_out"])
    for word in ("viscous film", "resolution", "temperature"):
        assert word in left
    assert "peak_at_edge_dry" in c and "peak_at_edge_wet" in c
    page = (out / "report.html").read_text()
    assert "What the wet model covers" in page and "squeeze-out" in page
    assert RUBBER_ILLUSTRATIVE in c["rubber"]
    out = tmp_path / "fill"
    rc, err = run_cli(capsys, ["dry-vs-wet", SAMPLE, "--wet-model", "fill", "--out", out, *speeds])
    assert rc == 0, err
    c = json.loads((out / "comparison.json").read_text())
    assert c["wet_model"]["covers"] == WET_MODEL["covers"]
    left = " ".join(c["wet_model"]["leaves_out"])
    for word in ("adhesion", "squeeze-out", "viscous"):
        assert word in left


def test_compare_names_rubber_and_edge_per_surface(tmp_path, capsys):
    out = tmp_path / "cmp"
    rc, err = run_cli(
        capsys,
        [
            "compare",
            SAMPLE,
            ROOT / "sample_scans" / "coarse_asphalt.x3p",
            "--out",
            out,
            "--velocities",
            "1e-4:1:20",
        ],
    )
    assert rc == 0, err
    c = json.loads((out / "comparison.json").read_text())
    entries = [e for e in c.values() if isinstance(e, dict) and e.get("mu")]
    assert entries
    for e in entries:
        mu = np.array(list(e["mu"].values()), float)
        assert e["peak_at_edge"] is (int(np.argmax(mu)) in (0, mu.size - 1))
        assert RUBBER_ILLUSTRATIVE in e["rubber"]
        assert e["hurst"] is None or 0.0 <= e["hurst"] <= 1.0
    assert RUBBER_ILLUSTRATIVE in (out / "report.html").read_text()
