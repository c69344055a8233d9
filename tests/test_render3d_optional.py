"""pyvista is an optional extra (issue 23): without it ``dry-vs-wet`` draws its 3D view with
matplotlib and says so; when that fails too, one warning line says how to get pyvista, in
stderr, ``comparison.json`` and the report, and every other output is still written."""

import json
import sys

import numpy as np
import pytest
from conftest import fourier_surface

from pipelines.cli.app import main
from pipelines.jobs.render3d import NEEDS_PYVISTA

OUTPUTS = ("comparison.json", "report.html", "wet.npy", "psd_dry_wet.png", "water_depth.png")


@pytest.fixture(scope="module")
def scan(tmp_path_factory):
    path = tmp_path_factory.mktemp("scan3d") / "s.npy"
    np.save(path, fourier_surface(96, 5e-5, 0.8, 2e-4, seed=3))
    return path


def _run(scan, out):
    return main(["dry-vs-wet", str(scan), "--spacing", "5e-5", "--no-friction", "--out", str(out)])


def _bluish(png):
    """Pixels where blue clearly dominates red (water over copper ground, which is red-brown)."""
    import matplotlib.image as mpimg

    img = mpimg.imread(png)[..., :3]
    return int(np.sum(img[..., 2] - img[..., 0] > 0.25))


def test_without_pyvista_matplotlib_draws_the_view(scan, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyvista", None)  # `import pyvista` raises ImportError
    out = tmp_path / "mpl"
    assert _run(scan, out) == 0
    for name in OUTPUTS + ("surface_3d.png",):
        assert (out / name).exists(), name
    c = json.loads((out / "comparison.json").read_text())
    assert c["renderer_3d"] == "matplotlib"
    assert "matplotlib" in c["render_note"] and NEEDS_PYVISTA not in c["warnings"]
    page = (out / "report.html").read_text()
    assert "3D view drawn with" in page and "matplotlib" in page
    # the water is drawn: blue on the wetted surface, none on the same surface drawn dry
    assert c["wetted_fraction"] > 0
    from pipelines.jobs.render3d import render_surface_with_water_mpl
    from roadscan.heightmap import HeightMap
    from roadscan.level import level

    dry = level(HeightMap(np.load(scan), 5e-5, 5e-5), degree=1)
    render_surface_with_water_mpl(dry, np.zeros(dry.heights_m.shape), tmp_path / "dry.png")
    assert _bluish(out / "surface_3d.png") > 50 * max(1, _bluish(tmp_path / "dry.png"))


def test_without_any_renderer_one_warning_everywhere(scan, tmp_path, monkeypatch, capsys):
    import pipelines.jobs.render3d as r3d

    def broken(*a, **k):
        raise RuntimeError("no 3D toolkit")

    monkeypatch.setitem(sys.modules, "pyvista", None)
    monkeypatch.setattr(r3d, "render_surface_with_water_mpl", broken)
    out = tmp_path / "none"
    assert _run(scan, out) == 0
    for name in OUTPUTS:
        assert (out / name).exists(), name
    assert not (out / "surface_3d.png").exists()
    c = json.loads((out / "comparison.json").read_text())
    assert c["renderer_3d"] is None
    assert c["warnings"].count(NEEDS_PYVISTA) == 1
    err = capsys.readouterr().err
    assert sum(NEEDS_PYVISTA in line for line in err.splitlines()) == 1
    import html

    page = html.unescape((out / "report.html").read_text())  # the text a reader sees
    assert "3D view needs pyvista: pip install 'roadscan[3d]'" in page
    assert "not drawn" in page
