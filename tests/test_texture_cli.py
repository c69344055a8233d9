"""Texture figures through the commands (issue 21): analyse's texture_spectrum.csv/png and
summary keys, IFI flags, the MPD spike note, short scans, batch's campaign.csv columns."""

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from conftest import _shared_dir

from pipelines.cli.app import main
from roadscan.texture_spectrum import NOMINAL_MM

CAPTIF = (_shared_dir() or Path("/nonexistent")) / "data" / "profiles" / "captif"
needs_captif = pytest.mark.skipif(not CAPTIF.is_dir(), reason="CAPTIF profiles not available")
LABELS = {
    "0.5",
    "0.63",
    "0.8",
    "1",
    "1.25",
    "1.6",
    "2",
    "2.5",
    "3.15",
    "4",
    "5",
    "6.3",
    "8",
    "10",
    "12.5",
    "16",
    "20",
    "25",
    "31.5",
    "40",
    "50",
    "63",
    "80",
    "100",
    "125",
    "160",
    "200",
    "250",
    "315",
    "400",
    "500",
}


def test_labels_are_the_nominal_series():
    assert {f"{v:g}" for v in NOMINAL_MM} == LABELS


@needs_captif
def test_analyse_profile_texture_outputs_and_ifi(tmp_path):
    out = tmp_path / "s0"
    rc = main(
        [
            "analyse",
            str(CAPTIF / "20211011_aylesbury_dec_station_0.dat"),
            "--out",
            str(out),
            "--no-friction",
            "--friction-measurement",
            "0.52@65",
            "--ifi-constants",
            "0.045,0.925,0.01",
        ]
    )
    assert rc == 0
    s = json.loads((out / "summary.json").read_text())
    mpd = s["mpd_m"]
    assert mpd is not None
    assert s["etd_m"] == 0.2e-3 + 0.8 * mpd
    assert s["ifi_speed_constant_kmh"] == 14.2 + 89.7 * mpd * 1e3
    sp = s["ifi_speed_constant_kmh"]
    assert s["ifi_F60"] == pytest.approx(
        0.045 + 0.925 * 0.52 * np.exp((65 - 60) / sp) + 0.01 * mpd * 1e3, rel=1e-12
    )
    lines = (out / "texture_spectrum.csv").read_text().splitlines()
    assert lines[0] == "centre_wavelength_m,band_lo_m,band_hi_m,level_dB"
    rows = np.loadtxt(out / "texture_spectrum.csv", delimiter=",", skiprows=1)
    levels = s["texture_level_dB"]
    assert set(levels) <= LABELS and {"2.5", "80", "0.63", "31.5"} <= set(levels)
    assert len(levels) == rows.shape[0]
    by_centre = {f"{n:g}": r for n, r in zip(NOMINAL_MM, 10 ** (np.arange(-3, 28) / 10) * 1e-3)}
    for lab, lvl in levels.items():
        i = int(np.argmin(np.abs(rows[:, 0] - by_centre[lab])))
        assert abs(rows[i, 0] / by_centre[lab] - 1) < 1e-8 and rows[i, 3] == pytest.approx(lvl, abs=1e-6)
        assert rows[i, 1] == pytest.approx(rows[i, 0] * 10**-0.05) and rows[i, 2] == pytest.approx(
            rows[i, 0] * 10**0.05
        )
    assert (out / "texture_spectrum.png").stat().st_size > 5000
    html = (out / "report.html").read_text()
    assert "ISO 13473-4" in html and "dB re 1 µm" in html and "ETD" in html
    assert "0.00339" not in html  # MPD as "3.39 mm", not in metres
    assert f"{mpd * 1e3:.3g} mm" in html


@needs_captif
def test_spike_note_names_the_alpha_that_passes(tmp_path):
    f = str(CAPTIF / "20211011_aylesbury_dec_station_10.dat")
    rc = main(["analyse", f, "--out", str(tmp_path / "a"), "--no-friction", "--no-figures"])
    assert rc == 0
    s = json.loads((tmp_path / "a" / "summary.json").read_text())
    assert s["mpd_m"] is None and s["etd_m"] is None and s["ifi_speed_constant_kmh"] is None
    assert "--mpd-spike-alpha" in s["mpd_note"]
    alpha = s["mpd_spike_alpha_to_pass"]
    assert f"--mpd-spike-alpha {alpha:g}" in s["mpd_note"]
    rc = main(
        [
            "analyse",
            f,
            "--out",
            str(tmp_path / "b"),
            "--no-friction",
            "--no-figures",
            "--mpd-spike-alpha",
            f"{alpha:g}",
        ]
    )
    s2 = json.loads((tmp_path / "b" / "summary.json").read_text())
    assert s2["mpd_m"] is not None and "not valid" not in s2["mpd_note"]


def _area(tmp_path, n=(400, 1100), dx=0.05e-3):
    rng = np.random.default_rng(5)
    x = np.arange(n[1]) * dx
    h = 0.4e-3 * np.sin(2 * np.pi * x / 2.5e-3)[None, :] + 1e-5 * rng.normal(size=n)
    p = tmp_path / "short_area.npy"
    np.save(p, h)
    return p, dx


def test_short_area_scan_gets_msd_short_and_direction(tmp_path):
    p, dx = _area(tmp_path)
    out = tmp_path / "o"
    assert (
        main(["analyse", str(p), "--spacing", str(dx), "--out", str(out), "--no-friction", "--no-figures"])
        == 0
    )
    s = json.loads((out / "summary.json").read_text())
    assert s["mpd_m"] is None and s["etd_m"] is None
    assert s["msd_short_baseline_m"] == pytest.approx(0.055)
    assert 0.1e-3 < s["msd_short_m"] < 0.4e-3  # a 2.5 mm sine, halved by the 2.4 mm low-pass
    assert "not ISO" in s["msd_short_note"]
    assert s["texture_direction"] == "x"
    a = 20 * np.log10(0.4e-3 / np.sqrt(2) / 1e-6)
    assert abs(s["texture_level_dB"]["2.5"] - a) < 0.5
    out_y = tmp_path / "y"
    assert (
        main(
            [
                "analyse",
                str(p),
                "--spacing",
                str(dx),
                "--out",
                str(out_y),
                "--no-friction",
                "--no-figures",
                "--direction",
                "y",
            ]
        )
        == 0
    )
    sy = json.loads((out_y / "summary.json").read_text())
    assert sy["texture_direction"] == "y" and "2.5" not in sy["texture_level_dB"]  # 20 mm along y


@pytest.mark.parametrize(
    "flags",
    [
        ["--friction-measurement", "0.5@30"],
        ["--ifi-constants", "1,2"],
        ["--friction-measurement", "x@30", "--ifi-constants", "1,2"],
        ["--direction", "z"],
    ],
)
def test_bad_flags_exit_2(tmp_path, capsys, flags):
    p, dx = _area(tmp_path, n=(20, 200))
    try:
        rc = main(
            [
                "analyse",
                str(p),
                "--spacing",
                str(dx),
                "--out",
                str(tmp_path / "o"),
                "--no-friction",
                "--no-figures",
                *flags,
            ]
        )
    except SystemExit as exc:  # argparse's own refusal
        rc = exc.code
    assert rc == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.strip()
    assert not (tmp_path / "o").exists()


def test_batch_campaign_columns(tmp_path):
    p, dx = _area(tmp_path)
    out = tmp_path / "camp"
    rc = main(["batch", str(p), "--spacing", str(dx), "--out", str(out), "--workers", "1", "--no-friction"])
    assert rc == 0
    with open(out / "campaign.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    head = list(rows[0])
    assert "etd_m" in head and "ifi_speed_constant_kmh" in head
    assert "texture_level_dB.2.5" in head
    assert not any(h.startswith("anisotropy.sector_") for h in head)
    a = 20 * np.log10(0.4e-3 / np.sqrt(2) / 1e-6)
    assert abs(float(rows[0]["texture_level_dB.2.5"]) - a) < 0.5
    with open(out / "campaign_anisotropy.csv", newline="") as fh:
        side = list(csv.DictReader(fh))
    assert any(h.startswith("anisotropy.sector_power_fraction.") for h in side[0])


def test_batch_sections_carry_texture_along_chainage(tmp_path):
    dx = 0.5e-3
    x = np.arange(6000) * dx  # 3 m, two 1.5 m sections
    amp = np.where(x < 1.5, 1.0e-3, 0.5e-3)  # the 80 mm texture halves at 1.5 m
    h = amp * np.sin(2 * np.pi * x / 80e-3) + 0.1e-3 * np.sin(2 * np.pi * x / 5e-3)
    p = tmp_path / "lane.npy"
    np.save(p, h)
    out = tmp_path / "camp"
    rc = main(
        [
            "batch",
            str(p),
            "--spacing",
            str(dx),
            "--out",
            str(out),
            "--workers",
            "1",
            "--no-friction",
            "--section-length",
            "1.5",
        ]
    )
    assert rc == 0
    with open(out / "lane" / "sections.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 2
    l80 = [float(r["texture_level_dB.80"]) for r in rows]
    assert l80[0] - l80[1] == pytest.approx(20 * np.log10(2), abs=0.5)
    assert float(rows[0]["texture_level_dB.5"]) == pytest.approx(
        20 * np.log10(0.1e-3 / np.sqrt(2) / 1e-6), abs=0.5
    )
    assert all(float(r["etd_m"]) == pytest.approx(0.2e-3 + 0.8 * float(r["mpd_m"]), rel=1e-9) for r in rows)
    with open(out / "campaign.csv", newline="") as fh:
        camp = list(csv.DictReader(fh))
    assert len(camp) == 2 and camp[1]["texture_level_dB.80"] == rows[1]["texture_level_dB.80"]


def test_direction_y_takes_mpd_along_y(tmp_path):
    dx = 0.1e-3
    y = np.arange(1100) * dx  # 110 mm along y, 6 mm along x
    h = np.repeat((0.5e-3 * np.sin(2 * np.pi * y / 5e-3))[:, None], 60, axis=1)
    p = tmp_path / "along_y.npy"
    np.save(p, h)
    base = ["analyse", str(p), "--spacing", str(dx), "--no-friction", "--no-figures"]
    assert main(base + ["--out", str(tmp_path / "x")]) == 0
    sx = json.loads((tmp_path / "x" / "summary.json").read_text())
    assert sx["mpd_m"] is None and sx["msd_short_m"] is None  # 6 mm rows: nothing to give
    assert main(base + ["--out", str(tmp_path / "y"), "--direction", "y"]) == 0
    sy = json.loads((tmp_path / "y" / "summary.json").read_text())
    assert 0.3e-3 < sy["mpd_m"] < 0.55e-3 and "along y" in sy["mpd_note"]
    assert sy["etd_m"] == 0.2e-3 + 0.8 * sy["mpd_m"]
    assert abs(sy["texture_level_dB"]["5"] - 20 * np.log10(0.5e-3 / np.sqrt(2) / 1e-6)) < 0.5
