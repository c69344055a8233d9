"""Height plausibility against the scan itself (issue 22): a factor-1000 units slip is refused
with "units?" and the flag that fixes it, in every command that reads heights, before any
output; the real and shipped scans all pass.

The slipped files are the shipped asphalt sample's own heights multiplied by 1e3 / 1e6 (what a
file written in mm / um holds) or read with a wrong --units; the expected flag follows from the
factor applied, not from the code."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT

from pipelines.cli.app import main
from roadscan.errors import InputError
from roadscan.heightmap import HeightMap, Profile
from roadscan.io import read, write
from roadscan.plausibility import check_plausible, detrended_rms

SAMPLE = ROOT / "sample_scans" / "asphalt.x3p"


@pytest.fixture(scope="module")
def asphalt():
    m = read(SAMPLE)
    h = m.heights_m[:256, :256]  # 14 mm square: fast
    return h, m.dx_m


def _refused(capsys, argv, flag, out):
    capsys.readouterr()
    assert main([str(a) for a in argv]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "units?" in err and flag in err, err
    assert not out.exists()
    return err


@pytest.mark.parametrize("factor, flag", [(1e3, "--units mm"), (1e6, "--units um")])
def test_slipped_npy_refused_by_analyse(asphalt, tmp_path, capsys, factor, flag):
    h, dx = asphalt
    np.save(tmp_path / "s.npy", h * factor)  # heights written in mm (um), read as m
    out = tmp_path / "o"
    err = _refused(capsys, ["analyse", tmp_path / "s.npy", "--spacing", dx, "--out", out], flag, out)
    assert "s.npy" in err
    assert (
        main(
            [
                "analyse",
                str(tmp_path / "s.npy"),
                "--spacing",
                str(dx),
                "--out",
                str(out),
                "--no-friction",
                "--no-figures",
                *flag.split(),
            ]
        )
        == 0
    )


def test_units_um_on_metres_refused(asphalt, tmp_path, capsys):
    h, dx = asphalt
    np.save(tmp_path / "m.npy", h)
    out = tmp_path / "o"
    _refused(
        capsys,
        ["analyse", tmp_path / "m.npy", "--spacing", dx, "--units", "um", "--no-friction", "--out", out],
        "--units m",
        out,
    )


@pytest.mark.parametrize("command", ["rain-fill", "compare", "dry-vs-wet"])
def test_every_height_command_refuses(asphalt, tmp_path, capsys, command):
    h, dx = asphalt
    np.save(tmp_path / "s.npy", h * 1e3)
    np.save(tmp_path / "r.npy", h[::-1] * 1e3)
    out = tmp_path / "o"
    files = [tmp_path / "s.npy"] + ([tmp_path / "r.npy"] if command == "compare" else [])
    extra = ["--no-friction"] if command == "compare" else []
    _refused(capsys, [command, *files, "--spacing", dx, "--out", out, *extra], "--units mm", out)


def test_convert_and_stitch_refuse(asphalt, tmp_path, capsys):
    h, dx = asphalt
    np.save(tmp_path / "s.npy", h * 1e3)
    out = tmp_path / "o.x3p"
    _refused(capsys, ["convert", tmp_path / "s.npy", out, "--spacing", dx], "--units mm", out)
    np.save(tmp_path / "t00.npy", h[:, :160] * 1e3)
    np.save(tmp_path / "t01.npy", h[:, 96:] * 1e3)
    _refused(
        capsys,
        [
            "stitch",
            tmp_path / "t00.npy",
            tmp_path / "t01.npy",
            "--grid",
            "1x2",
            "--overlap",
            "0.25",
            "--spacing",
            dx,
            "--out",
            out,
        ],
        "--units mm",
        out,
    )


def test_x3p_holding_mm_needs_override(asphalt, tmp_path, capsys):
    h, dx = asphalt
    write(tmp_path / "mm.x3p", HeightMap(h * 1e3, dx, dx))  # a writer that put mm in an X3P
    out = tmp_path / "o"
    err = _refused(
        capsys,
        ["analyse", tmp_path / "mm.x3p", "--out", out, "--no-friction"],
        "--units mm --override-calibration",
        out,
    )
    assert "as the file states" in err
    assert (
        main(
            [
                "analyse",
                str(tmp_path / "mm.x3p"),
                "--out",
                str(out),
                "--no-friction",
                "--no-figures",
                "--units",
                "mm",
                "--override-calibration",
            ]
        )
        == 0
    )


def test_rms_is_detrended_and_spike_robust():
    rng = np.random.default_rng(0)
    h = rng.normal(size=(200, 300)) * 1e-6
    yy, xx = np.indices(h.shape)
    tilted = h + 0.05 + 1e-3 * xx - 2e-3 * yy  # offset and a steep plane
    tilted[5, 5] = 1e3  # one spike
    m = HeightMap(tilted, 1e-6, 1e-6)
    assert detrended_rms(m) == pytest.approx(np.std(h), rel=0.15)  # 1 % trims: ~10 % low
    p = Profile(np.sin(np.arange(1000)) * 1e-3 + 0.5 * np.arange(1000), 1e-3)
    assert detrended_rms(p) == pytest.approx(1e-3 / np.sqrt(2), rel=0.15)


def _real_scans(shared_data):
    files = [ROOT / "sample_scans" / "asphalt.x3p", ROOT / "sample_scans" / "coarse_asphalt.x3p"]
    files += sorted((shared_data / "profiles" / "captif").glob("*.dat"))
    try:
        import SurfaceTopography  # noqa: F401

        files += sorted((shared_data / "formats").glob("*-*.*"))
    except ImportError:
        pass
    return [f for f in files if f.suffix != ".json"]


def test_real_scans_pass(shared_data):
    scans = _real_scans(shared_data)
    assert len(scans) >= 5
    for f in scans:
        check_plausible(read(f), f)
    truth = np.load(ROOT / "sample_scans" / "tiles_truth.npy")
    check_plausible(HeightMap(truth, 5e-5, 5e-5), "tiles_truth")


def test_legitimate_extremes_pass():
    rng = np.random.default_rng(2)
    # a road profile 1.8 m long with mm texture and cm unevenness
    x = np.arange(48000) * 37.5e-6
    road = 1e-3 * rng.normal(size=x.size) + 0.01 * np.sin(2 * np.pi * x / 1.8)
    check_plausible(Profile(road, 37.5e-6), "road")
    # a microscope scan 100 um wide with nm roughness; a polished one with 0.1 nm
    check_plausible(HeightMap(1e-9 * rng.normal(size=(512, 512)), 100e-6 / 512, 100e-6 / 512), "m")
    check_plausible(HeightMap(1e-10 * rng.normal(size=(256, 256)), 1e-6, 1e-6), "wafer")
    # steep microstructure: 25 um rms over a 100 um field
    check_plausible(HeightMap(25e-6 * rng.normal(size=(128, 128)), 100e-6 / 128, 100e-6 / 128), "g")


def test_boundaries_are_where_documented():
    rng = np.random.default_rng(3)
    n = rng.normal(size=(64, 64))
    n /= n.std()
    L = 64 * 1e-4
    check_plausible(HeightMap(n * 0.45 * L, 1e-4, 1e-4), "a")
    with pytest.raises(InputError, match=r"units?"):
        check_plausible(HeightMap(n * 0.6 * L, 1e-4, 1e-4), "a")
    # the 20 um pixel floor of 10 nm
    check_plausible(HeightMap(n * 12e-9, 20e-6, 20e-6), "b")
    with pytest.raises(InputError, match=r"units?"):
        check_plausible(HeightMap(n * 8e-9, 20e-6, 20e-6), "b")


def test_batch_sections_refuse_a_slipped_profile(tmp_path):
    import csv

    rng = np.random.default_rng(4)
    z = np.convolve(rng.normal(size=40008), np.ones(8) / 8, mode="valid")[:40000] * 2e-3
    np.save(tmp_path / "lane.npy", z * 1e3)  # mm numbers read as metres
    out = tmp_path / "o"
    main(
        [
            "batch",
            str(tmp_path / "lane.npy"),
            "--section-length",
            "0.5",
            "--spacing",
            "5e-5",
            "--no-friction",
            "--out",
            str(out),
            "--workers",
            "1",
        ]
    )
    rows = list(csv.DictReader(open(out / "campaign.csv")))
    assert rows and all(r["status"] != "ok" for r in rows)
    assert any("units?" in r["error"] and "--units mm" in r["error"] for r in rows)
