"""Steps and seams far above the texture are warned (issue 22): a 2 mm step across a 0.2 mm-rms
scan, a seam between two tiles over part of the scan, a plate edge in a profile; the shipped and
shared real scans, and clean random textures, give no warning."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import ROOT, fourier_surface

from pipelines.cli.app import main
from roadscan.heightmap import HeightMap, Profile
from roadscan.io import read
from roadscan.seams import find_steps

DX = 5e-5


@pytest.mark.parametrize("seed", range(4))
def test_full_step_found_where_it_is(seed):
    h = fourier_surface(256, DX, 0.8, 2e-4, seed=seed)
    assert find_steps(HeightMap(h, DX, DX)) == []
    h[:, 100:] += 2e-3
    (line,) = find_steps(HeightMap(h, DX, DX))
    assert "step of 2" in line and "along x at x = 5.00 mm" in line and "stitching fault" in line
    hy = fourier_surface(256, DX, 0.8, 2e-4, seed=seed)
    hy[180:, :] -= 2e-3
    (line,) = find_steps(HeightMap(hy, DX, DX))
    assert "along y at y = 9.00 mm" in line


def test_seam_over_part_of_the_scan_found():
    h = fourier_surface(256, DX, 0.8, 2e-4, seed=7)
    h[128:, 64:] += 1e-3  # one tile of a 2x2 grid lifted 1 mm
    lines = find_steps(HeightMap(h, DX, DX))
    assert any("along x at x = 3.20 mm" in s for s in lines)
    assert any("along y at y = 6.40 mm" in s for s in lines)


def test_profile_plate_edge_found():
    rng = np.random.default_rng(1)
    z = 2e-4 * rng.normal(size=20000)
    z[12000:] += 3e-3
    (line,) = find_steps(Profile(z, 5e-5))
    assert "step of 3" in line


def test_real_scans_have_no_step(shared_data):
    files = [ROOT / "sample_scans" / "asphalt.x3p", ROOT / "sample_scans" / "coarse_asphalt.x3p"]
    files += sorted((shared_data / "profiles" / "captif").glob("*.dat"))
    files += sorted((ROOT / "sample_scans" / "tiles").glob("*.npz"))
    for f in files:
        assert find_steps(read(f)) == [], f
    truth = np.load(ROOT / "sample_scans" / "tiles_truth.npy")
    assert find_steps(HeightMap(truth, DX, DX)) == []


def test_step_warning_reaches_summary_and_stderr(tmp_path, capsys):
    h = fourier_surface(128, DX, 0.8, 2e-4, seed=3)
    h[:, 64:] += 2e-3
    np.save(tmp_path / "s.npy", h)
    out = tmp_path / "o"
    capsys.readouterr()
    assert (
        main(
            [
                "analyse",
                str(tmp_path / "s.npy"),
                "--spacing",
                str(DX),
                "--out",
                str(out),
                "--no-friction",
                "--no-figures",
            ]
        )
        == 0
    )
    err = capsys.readouterr().err
    s = json.loads(next(out.rglob("summary.json")).read_text())
    assert any("stitching fault" in w and "s.npy" in w for w in s["warnings"])
    assert "stitching fault" in err


def test_step_warning_reaches_comparison_json(tmp_path):
    h = fourier_surface(128, DX, 0.8, 2e-4, seed=3)
    np.save(tmp_path / "a.npy", h)
    h[:, 64:] += 2e-3
    np.save(tmp_path / "b.npy", h)
    out = tmp_path / "o"
    assert (
        main(
            [
                "compare",
                str(tmp_path / "a.npy"),
                str(tmp_path / "b.npy"),
                "--spacing",
                str(DX),
                "--out",
                str(out),
                "--no-friction",
            ]
        )
        == 0
    )
    c = json.loads((out / "comparison.json").read_text())
    assert set(c) == {"a", "b"} and "warnings" not in c["a"]
    assert any("stitching fault" in w and "b.npy" in w for w in c["b"]["warnings"])


def test_a_map_with_almost_nothing_measured_has_no_step_to_judge():
    # 18 measured points of 480: the local texture's rms is 0, no step can be sized against it
    # (a division by zero before: the fuzz suite's nan_most case)
    from fuzz_files import _rough

    from roadscan.heightmap import HeightMap
    from roadscan.seams import find_steps

    rng = np.random.default_rng(2)
    z = _rough(rng, (16, 30)) * 1e-4
    z[rng.random(z.shape) < 0.97] = np.nan
    assert find_steps(HeightMap(z, 5e-5, 5e-5)) == []
