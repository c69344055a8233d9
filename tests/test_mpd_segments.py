"""MPD honesty (ISO 13473-1): mpd_valid beside mpd_m, ETD and IFI null with the reason when the
MPD is not valid, mpd_segments.csv and the segment plot."""

import contextlib
import csv
import io
import json
from pathlib import Path

import numpy as np
import pytest
from conftest import _shared_dir

from pipelines.cli.app import main
from roadscan.heightmap import HeightMap, Profile
from roadscan.roughness import mean_profile_depth, segment_depths
from roadscan.texture_depth import mpd_segments

CAPTIF = (_shared_dir() or Path("/nonexistent")) / "data" / "profiles" / "captif"
needs_captif = pytest.mark.skipif(not CAPTIF.is_dir(), reason="CAPTIF profiles not available")
HEADER = ["start_m", "end_m", "msd_m", "valid", "reason"]


def _run(argv):
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
        rc = main(argv)
    return rc, buf.getvalue()


def _rows(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], rows[1:]


def test_segments_agree_with_the_mpd_chain():
    """The table's MSDs are segment_depths'; its MPD is mean_profile_depth's."""
    rng = np.random.default_rng(2)
    dx = 0.5e-3
    z = np.convolve(rng.normal(size=1224), np.ones(24) / 24, mode="valid")[:1200] * 8e-3
    z[130:160] = np.nan  # 30 dropouts of 200 in segment 0: invalid
    p = Profile(z, dx)
    seg = mpd_segments(p)
    res = segment_depths(p.heights_m, dx, p.unmeasured)
    assert seg.n_total == 6 and np.allclose(seg.msd_m, res["msd_m"].ravel())
    assert not seg.valid[0] and "dropouts 15 % > 10 %" in seg.reason[0]
    assert seg.reason[1:] == [""] * 5
    mpd, _ = mean_profile_depth(p)
    assert seg.mpd_m == pytest.approx(mpd) and seg.mpd_valid
    assert np.allclose(seg.start_m, np.arange(6) * 0.1) and np.allclose(seg.end_m - seg.start_m, 0.1)


def test_fewer_than_half_valid_is_not_valid():
    dx = 0.5e-3
    z = np.sin(np.arange(800) * dx * 2 * np.pi / 5e-3) * 1e-3
    z[:500] = np.nan  # 2.5 of 4 segments without data
    seg = mpd_segments(Profile(z, dx))
    assert seg.n_valid == 1 and seg.n_total == 4 and not seg.mpd_valid
    assert seg.validity_text() == "not valid per ISO 13473-1 (1 of 4 segments)"


@needs_captif
def test_captif_station_1_is_not_valid(tmp_path):
    out = tmp_path / "s1"
    rc, text = _run(
        [
            "analyse",
            str(CAPTIF / "20211011_aylesbury_dec_station_1.dat"),
            "--out",
            str(out),
            "--no-friction",
            "--friction-measurement",
            "0.5@60",
            "--ifi-constants",
            "0.045,0.925",
        ]
    )
    assert rc == 0, text
    s = json.loads((out / "summary.json").read_text())
    assert s["mpd_m"] is not None and s["mpd_valid"] is False
    assert (s["mpd_valid_segments"], s["mpd_total_segments"]) == (3, 18)
    assert s["etd_m"] is None and s["ifi_speed_constant_kmh"] is None and s["ifi_F60"] is None
    assert "not valid per ISO 13473-1 (3 of 18 segments)" in s["etd_note"]
    keys = list(s)
    assert keys.index("mpd_valid") == keys.index("mpd_m") + 1
    html = (out / "report.html").read_text()
    assert "not valid per ISO 13473-1 (3 of 18 segments)" in html
    assert "mpd_segments.png" in html or (out / "mpd_segments.png").exists()
    head, rows = _rows(out / "mpd_segments.csv")
    assert head == HEADER and len(rows) == 18
    assert sum(r[3] == "true" for r in rows) == 3
    assert all(r[4] for r in rows if r[3] == "false")


@needs_captif
def test_captif_station_0_writes_segments(tmp_path):
    out = tmp_path / "s0"
    rc, text = _run(
        ["analyse", str(CAPTIF / "20211011_aylesbury_dec_station_0.dat"), "--out", str(out), "--no-friction"]
    )
    assert rc == 0, text
    s = json.loads((out / "summary.json").read_text())
    head, rows = _rows(out / "mpd_segments.csv")
    assert head == HEADER and len(rows) == s["mpd_total_segments"] == 18
    valid = [float(r[2]) for r in rows if r[3] == "true"]
    assert len(valid) == s["mpd_valid_segments"]
    assert s["mpd_m"] == pytest.approx(np.mean(valid), rel=1e-8)
    assert s["mpd_valid"] is True and s["etd_m"] == pytest.approx(0.2e-3 + 0.8 * s["mpd_m"])
    assert (out / "mpd_segments.png").stat().st_size > 5000


def test_area_line_set(tmp_path):
    """An area's rows are its lines: rows x segments rows in the CSV, line after line."""
    rng = np.random.default_rng(3)
    dx = 0.5e-3
    z = np.convolve(rng.normal(size=(20 * 430)), np.ones(30) / 30, mode="same").reshape(20, 430) * 5e-3
    np.save(tmp_path / "area.npy", z)
    rc, text = _run(
        [
            "analyse",
            str(tmp_path / "area.npy"),
            "--spacing",
            str(dx),
            "--no-friction",
            "--out",
            str(tmp_path / "o"),
        ]
    )
    assert rc == 0, text
    head, rows = _rows(tmp_path / "o" / "mpd_segments.csv")
    assert head == HEADER and len(rows) == 20 * 2  # 215 mm lines: two segments each
    assert [float(r[0]) for r in rows[:4]] == [0.0, 0.1, 0.0, 0.1]
    seg = mpd_segments(HeightMap(z, dx, dx))
    assert np.allclose([float(r[2]) for r in rows], seg.msd_m, rtol=1e-9)
