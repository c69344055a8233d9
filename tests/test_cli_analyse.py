"""End-to-end: ``roadscan analyse`` as a user runs it (contract of issue 2, item 8)."""

import csv
import json
import subprocess
import sys

import numpy as np
import pytest
from conftest import fourier_surface

from pipelines.cli.app import main


@pytest.fixture(scope="module")
def scan_npy(tmp_path_factory):
    d = tmp_path_factory.mktemp("scan")
    h = fourier_surface(256, 5e-5, 0.8, 3e-4, seed=3)
    x = np.arange(256) * 5e-5
    h = h + 2e-3 * x[None, :] - 1e-3 * x[:, None]  # tilt
    h[100:104, 50:60] = np.nan  # dropouts
    p = d / "tile.npy"
    np.save(p, h)
    return p, h


def test_analyse_single_file_contract(scan_npy, tmp_path):
    path, h = scan_npy
    out = tmp_path / "out"
    assert main(["analyse", str(path), "--spacing", "5e-5", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    for key in (
        "hurst",
        "hurst_stderr",
        "rms_height_m",
        "band_rms_m",
        "h0_m",
        "q_min_per_m",
        "q_max_per_m",
        "fit_band_per_m",
        "roughness",
        "mpd_m",
        "mpd_note",
        "filled_fraction",
    ):
        assert key in s, key
    assert len(s["fit_band_per_m"]) == 2
    assert s["mpd_m"] is None and s["mpd_note"]  # 12.8 mm: too short for a 100 mm baseline
    assert abs(s["hurst"] - 0.8) < 0.1
    # rms height is Sq of the levelled measured heights: the tilt must be gone
    assert s["rms_height_m"] == pytest.approx(s["roughness"]["Sq_m"])
    # independent check: the added tilt is planar, so the levelled heights are the original
    # (untilted) surface minus its own least-squares plane over the measured points
    h0 = fourier_surface(256, 5e-5, 0.8, 3e-4, seed=3)
    ok = ~np.isnan(h)
    yy, xx = np.nonzero(ok)
    A = np.column_stack([np.ones(xx.size), xx, yy])
    coef, *_ = np.linalg.lstsq(A, h0[ok], rcond=None)
    assert s["rms_height_m"] == pytest.approx(np.sqrt(np.mean((h0[ok] - A @ coef) ** 2)), rel=1e-6)
    assert s["filled_fraction"] == pytest.approx(40 / 256**2, rel=1e-6)
    assert s["q_min_per_m"] == pytest.approx(2 * np.pi / (256 * 5e-5))
    assert s["q_max_per_m"] == pytest.approx(np.pi / 5e-5)
    for k in ("Sa_m", "Sq_m", "Ssk", "Sku", "Sp_m", "Sv_m", "Sz_m", "Sdq", "Sdr"):
        assert k in s["roughness"]
    with open(out / "psd.csv") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["q_per_m", "C_m4"]
    q, C = np.array(rows[1:], float).T
    assert np.all(np.diff(q) > 0) and np.all(C > 0)
    # the radial PSD integrates to roughly the variance (DESIGN.md: ~10 % on a radial curve)
    var = 2 * np.pi * np.trapezoid(q * C, q)
    assert var == pytest.approx(s["rms_height_m"] ** 2, rel=0.35)
    with open(out / "mu.csv") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["v_m_per_s", "mu", "area_fraction", "extrapolated_share"]
    v, mu, area, share = np.array(rows[1:], float).T
    assert np.all((share >= 0) & (share <= 1))
    assert np.all((area > 0) & (area <= 1)) and np.all(np.diff(area) <= 1e-12)  # A/A0 falls with v
    assert len(v) == 61 and v[0] == pytest.approx(1e-4) and v[-1] == pytest.approx(1e2)
    assert np.all(np.isfinite(mu)) and np.all(mu >= 0) and mu.max() > 0.1
    for png in ("heightmap.png", "psd.png", "mu.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    html = (out / "report.html").read_text()
    assert "data:image/png;base64," in html and 'src="http' not in html


def test_analyse_units_give_same_spectrum(scan_npy, tmp_path):
    path, h = scan_npy
    mm = tmp_path / "mm.npy"
    np.save(mm, h * 1e3)
    a, b = tmp_path / "a", tmp_path / "b"
    assert main(["analyse", str(path), "--spacing", "5e-5", "--out", str(a), "--no-friction"]) == 0
    assert (
        main(["analyse", str(mm), "--spacing", "5e-5", "--units", "mm", "--out", str(b), "--no-friction"])
        == 0
    )
    ca = np.loadtxt(a / "psd.csv", delimiter=",", skiprows=1)
    cb = np.loadtxt(b / "psd.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(ca, cb, rtol=1e-6)
    assert not (a / "mu.csv").exists()


def test_analyse_several_files(scan_npy, tmp_path):
    path, _ = scan_npy
    other = tmp_path / "other.npy"
    np.save(other, fourier_surface(128, 5e-5, 0.5, 1e-4, seed=9))
    out = tmp_path / "many"
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "pipelines.cli",
            "analyse",
            str(path),
            str(other),
            "--spacing",
            "5e-5",
            "--out",
            str(out),
            "--velocities",
            "1e-4:1e2:13",
        ],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    assert "[1/2]" in r.stderr and "[2/2]" in r.stderr
    assert (out / "tile" / "summary.json").exists() and (out / "other" / "summary.json").exists()
    lines = (out / "summary.csv").read_text().splitlines()
    assert lines[0].startswith("scan,hurst") and len(lines) == 3
    assert json.loads((out / "other" / "summary.json").read_text())["hurst"] < 0.7


@pytest.mark.parametrize(
    "content,expect",
    [
        (None, "no such file"),
        (b"", ""),
        (b"1 2 3\n4 5\n", ""),
    ],
)
def test_bad_input_is_one_line_exit_2(tmp_path, content, expect):
    p = tmp_path / "bad.txt"
    if content is not None:
        p.write_bytes(content)
    out = tmp_path / "o"
    r = subprocess.run(
        [sys.executable, "-m", "pipelines.cli", "analyse", str(p), "--out", str(out)],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 2
    err = r.stderr.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert "bad.txt" in err and expect in err
    assert not out.exists() or not any(out.iterdir())


def test_npy_without_spacing_is_refused(scan_npy, tmp_path):
    path, _ = scan_npy
    r = subprocess.run(
        [sys.executable, "-m", "pipelines.cli", "analyse", str(path), "--out", str(tmp_path / "o")],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 2 and "tile.npy" in r.stderr and "spacing" in r.stderr


def test_extension_beyond_nyquist_raises_friction(scan_npy, tmp_path):
    """Roughness below the scan's resolution adds friction (thesis: +58 % at q1 = 6e5 1/m)."""
    path, _ = scan_npy
    a, b = tmp_path / "a", tmp_path / "b"
    common = ["--spacing", "5e-5", "--velocities", "1e-4:1e2:25"]
    assert main(["analyse", str(path), "--out", str(a)] + common) == 0
    assert main(["analyse", str(path), "--out", str(b), "--q1", "6e5"] + common) == 0
    sa = json.loads((a / "summary.json").read_text())["friction"]
    sb = json.loads((b / "summary.json").read_text())["friction"]
    assert sb["q1_per_m"] == pytest.approx(6e5)
    assert sa["q1_per_m"] <= np.pi / 5e-5
    assert sb["mu_peak"] > 1.2 * sa["mu_peak"]
    # the measured spectrum itself (psd.csv) is not changed by the extension
    np.testing.assert_allclose(
        np.loadtxt(a / "psd.csv", delimiter=",", skiprows=1),
        np.loadtxt(b / "psd.csv", delimiter=",", skiprows=1),
    )


def test_analyse_captif_line_profile(shared_data, tmp_path):
    """A real CAPTIF .dat read as it is: 1D PSD, its 2D estimate, Ra/Rq and MPD."""
    src = shared_data / "profiles/captif/20211011_aylesbury_dec_station_0.dat"
    out = tmp_path / "cap"
    assert main(["analyse", str(src), "--out", str(out), "--velocities", "1e-3:1e1:5"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["kind"] == "profile" and "Abel" in s["psd_conversion"]
    assert "reference plates removed" in s["trim_note"]
    assert {"Ra_m", "Rq_m"} <= set(s["roughness"])
    assert s["rms_height_m"] == pytest.approx(s["roughness"]["Rq_m"])
    assert 1e-3 < s["mpd_m"] < 5e-3  # a chip seal: a few mm
    assert 0.3 < s["hurst"] < 1.0 and s["filled_fraction"] > 0
    c1 = np.loadtxt(out / "psd1d.csv", delimiter=",", skiprows=1)
    assert (out / "psd1d.csv").read_text().splitlines()[0] == "q_per_m,C1_m3"
    # the 1D PSD integrates to the variance of the (filled, levelled) profile: <h^2> = 2 int C1 dq
    dq = c1[1, 0] - c1[0, 0]
    assert 2 * np.sum(c1[:, 1]) * dq == pytest.approx(s["rms_height_m"] ** 2, rel=0.25)
    assert (out / "profile.png").exists() and (out / "psd1d.png").exists()


def test_mpd_spike_criterion_option(shared_data, tmp_path):
    """The chip seal's steep stone edges trip the standard's default spike criterion (alpha 3);
    CAPTIF's own setting (alpha 6) keeps most 100 mm segments valid."""
    src = shared_data / "profiles/captif/20211011_aylesbury_dec_station_10.dat"
    notes = {}
    for alpha in ("3", "6"):
        out = tmp_path / alpha
        assert (
            main(["analyse", str(src), "--out", str(out), "--no-friction", "--mpd-spike-alpha", alpha]) == 0
        )
        notes[alpha] = json.loads((out / "summary.json").read_text())
    assert notes["3"]["mpd_m"] is None and "no valid segment" in notes["3"]["mpd_note"]
    assert 2e-3 < notes["6"]["mpd_m"] < 5e-3 and "14 of 18" in notes["6"]["mpd_note"]
    assert main(["analyse", str(src), "--out", str(tmp_path / "x"), "--mpd-spike-alpha", "-1"]) == 2
