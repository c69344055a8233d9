"""``--no-figures`` on ``compare`` and ``dry-vs-wet`` (as ``analyse`` and ``combine`` have it):
no PNG written, every number the same as with figures, a report that keeps its tables."""

import json

import numpy as np
import pytest

from pipelines.cli.app import main

DX = "1e-4"
V = ["--velocities", "1e-3:10:4"]


@pytest.fixture(scope="module")
def scans(tmp_path_factory):
    from roadscan.synth import self_affine_surface

    d = tmp_path_factory.mktemp("scans")
    out = []
    for seed, rms in ((3, 3e-4), (4, 5e-4)):
        hm = self_affine_surface(
            128,
            128,
            dx_m=1e-4,
            hurst=0.8,
            rms_height_m=rms,
            q_roll_per_m=2 * np.pi / 6e-3,
            seed=seed,
            name="s",
        )
        p = d / f"s{seed}.npy"
        np.save(p, hm.heights_m)
        out.append(str(p))
    return out


def _numbers(path, drop=()):
    data = json.loads(path.read_text())
    if isinstance(data, dict):
        return {k: v for k, v in data.items() if k not in drop}
    return data


@pytest.mark.parametrize("cmd", ["compare", "dry-vs-wet"])
def test_no_figures_writes_no_png_and_the_same_numbers(cmd, scans, tmp_path):
    argv = [cmd, *(scans if cmd == "compare" else scans[:1]), "--spacing", DX, *V]
    assert main([*argv, "--out", str(tmp_path / "with")]) == 0
    assert main([*argv, "--no-figures", "--out", str(tmp_path / "without")]) == 0
    assert sorted(p.name for p in (tmp_path / "with").glob("*.png"))  # figures drawn by default
    assert list((tmp_path / "without").rglob("*.png")) == []
    drop = ("renderer_3d", "render_note")
    assert _numbers(tmp_path / "without" / "comparison.json", drop) == _numbers(
        tmp_path / "with" / "comparison.json", drop
    )
    page = (tmp_path / "without" / "report.html").read_text(encoding="utf-8")
    assert "<table" in page and "<img" not in page
    if cmd == "dry-vs-wet":
        assert (tmp_path / "without" / "mu.csv").read_bytes() == (tmp_path / "with" / "mu.csv").read_bytes()
        c = json.loads((tmp_path / "without" / "comparison.json").read_text())
        assert c["renderer_3d"] is None and "--no-figures" in c["render_note"]


def test_the_python_door_takes_no_figures(scans, tmp_path):
    import pipelines

    r = pipelines.dry_vs_wet(scans[0], tmp_path / "w", spacing=1e-4, velocities="1e-3:10:4", no_figures=True)
    assert r["renderer_3d"] is None and list((tmp_path / "w").glob("*.png")) == []
    r = pipelines.compare(scans, tmp_path / "c", spacing=1e-4, velocities="1e-3:10:4", no_figures=True)
    assert list((tmp_path / "c").glob("*.png")) == []
