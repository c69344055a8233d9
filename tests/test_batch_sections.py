"""``roadscan batch --section-length``: a long line profile cut along chainage, read in chunks."""

import csv
import json
import tracemalloc

import numpy as np
import pytest

from pipelines.campaign import sections as secmod
from pipelines.campaign.sections import iter_sections
from pipelines.cli.app import main
from roadscan.heightmap import Profile
from roadscan.roughness import mean_profile_depth

DX = 5e-4  # 0.5 mm, a road texture laser's interval


def _profile(n, seed=0):
    """Random texture, mm-scale: white noise low-passed by a running mean, plus a slow wave."""
    rng = np.random.default_rng(seed)
    z = np.convolve(rng.normal(size=n + 8), np.ones(8) / 8, mode="valid")[:n] * 2e-3
    x = np.arange(n) * DX
    return x, z + 1e-3 * np.sin(2 * np.pi * x / 3.0)


def _write_xz_mm(path, x, z, dropouts=()):
    with open(path, "w") as fh:
        fh.write("distance (mm), height (mm)\n")
        keep = np.ones(x.size, bool)
        keep[list(dropouts)] = False
        np.savetxt(fh, np.column_stack([x[keep] * 1e3, z[keep] * 1e3]), fmt="%.6f", delimiter=", ")


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_sections_match_mpd_of_each_slice(tmp_path):
    n = 8000  # 4 m at 0.5 mm
    x, z = _profile(n)
    np.save(tmp_path / "line.npy", z)
    _write_xz_mm(tmp_path / "line.txt", x, z, dropouts=range(3000, 3010))
    L = 1.0
    per = int(round(L / DX))
    got_npy = list(iter_sections(tmp_path / "line.npy", L, spacing=str(DX)))
    got_txt = list(iter_sections(tmp_path / "line.txt", L))
    assert [s for s, _ in got_npy] == [0.0, 1.0, 2.0, 3.0] == [s for s, _ in got_txt]
    for k, ((_, a), (_, b)) in enumerate(zip(got_npy, got_txt)):
        ref = z[k * per : (k + 1) * per]
        np.testing.assert_array_equal(a.heights_m, ref)
        assert a.dx_m == DX and b.dx_m == pytest.approx(DX, rel=1e-6)
        assert b.n == per
        # text: printed to 1 nm, dropouts of section 1 unmeasured
        ok = ~b.unmeasured
        np.testing.assert_allclose(b.heights_m[ok], ref[ok], atol=1e-9)
        assert b.unmeasured.sum() == (10 if k == 1 else 0)
        # MPD of the section = ISO 13473-1 MPD of that slice of the whole profile
        m_ref, _ = mean_profile_depth(Profile(ref, DX))
        m_a, _ = mean_profile_depth(a)
        assert m_a == m_ref


def test_batch_section_rows(tmp_path):
    n = 12000  # 6 m
    x, z = _profile(n, seed=3)
    _write_xz_mm(tmp_path / "lane.txt", x, z)
    (tmp_path / "m.csv").write_text("file,chainage_m,label\nlane.txt,1000,lane 1\n")
    out = tmp_path / "out"
    rc = main(
        [
            "batch",
            str(tmp_path / "m.csv"),
            "--section-length",
            "2",
            "--no-friction",
            "--out",
            str(out),
            "--workers",
            "1",
        ]
    )
    assert rc == 0
    rows = _rows(out / "campaign.csv")
    assert [float(r["chainage_m"]) for r in rows] == [1000.0, 1002.0, 1004.0]
    assert [int(r["section"]) for r in rows] == [0, 1, 2]
    assert all(r["status"] == "ok" and r["label"] == "lane 1" for r in rows)
    per = int(round(2 / DX))
    for k, r in enumerate(rows):
        ref = Profile(z[k * per : (k + 1) * per], DX)
        m_ref, _ = mean_profile_depth(ref)
        assert float(r["mpd_m"]) == pytest.approx(m_ref, rel=1e-4)  # text printed to 1 nm
        # rms of the section: Rq of its levelled heights (first-degree line removed)
        xs = np.arange(per)
        resid = ref.heights_m - np.polyval(np.polyfit(xs, ref.heights_m, 1), xs)
        assert float(r["rms_height_m"]) == pytest.approx(resid.std(), rel=1e-4)
        # this toy texture (low-passed white noise) is not self-affine: within its reliable band
        # (issue 20) the fit may find H < 0, which the row's warnings then say
        # (or a band under half a decade): then hurst is empty, its note in summary.json
        s = json.loads((out / "lane" / f"section_{k:05d}" / "summary.json").read_text())
        assert (
            (r["hurst"] == "" and s["hurst"] is None and s["hurst_note"])
            or 0 < float(r["hurst"]) < 1.5
            or "not self-affine" in r["warnings"]
        )
        assert (out / "lane" / f"section_{k:05d}" / "psd.csv").exists()
    side = _rows(out / "lane" / "sections.csv")
    assert [s["mpd_m"] for s in side] == [r["mpd_m"] for r in rows]


def test_captif_and_area_inputs(tmp_path, shared_data):
    cap = sorted((shared_data / "profiles").rglob("*.dat"))
    if not cap:
        pytest.skip("no CAPTIF profile in shared data")
    from roadscan.io import read

    whole = read(cap[0])
    secs = list(iter_sections(cap[0], 0.2))
    assert len(secs) >= 1
    total = sum(p.n for _, p in secs)
    assert abs(total - whole.n) <= len(secs) + 2  # the boundary gaps at most
    assert secs[0][1].dx_m == pytest.approx(whole.dx_m, rel=1e-3)
    np.save(tmp_path / "area.npy", np.zeros((16, 16)))
    with pytest.raises(Exception, match="line profile"):
        list(iter_sections(tmp_path / "area.npy", 1.0, spacing="1e-4"))


def test_streaming_memory_is_bounded(tmp_path, monkeypatch):
    """A 400 000-point text profile, read in chunks of 4096 rows: the peak of Python/numpy
    allocations stays far below what the whole profile takes (x and z float64: 6.4 MB)."""
    n = 400_000
    x, z = _profile(n, seed=5)
    _write_xz_mm(tmp_path / "long.txt", x, z)
    monkeypatch.setattr(secmod, "CHUNK_ROWS", 4096)
    tracemalloc.start()
    count, pts = 0, 0
    for _, p in iter_sections(tmp_path / "long.txt", 0.5):
        count += 1
        pts += p.n
        del p
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert count == 400 and pts == n
    assert peak < 0.25 * (2 * 8 * n), peak
