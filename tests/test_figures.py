"""Figures drawn fast without changing any number (issue 13): the height map is shown as block
means, log-axis labels are plain Unicode (no mathtext), ``--no-figures`` leaves every CSV/JSON
output as it is."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pipelines.output._figure_tools import _plain_log_label
from pipelines.output.report import display_image

ROOT = Path(__file__).resolve().parents[1]


def test_display_image_is_block_means_of_the_measured_points():
    rng = np.random.default_rng(4)
    z = rng.normal(size=(1103, 1250))
    z[10:40, 500:530] = np.nan  # a hole bigger than a block
    z[rng.random(z.shape) < 0.05] = np.nan  # scattered dropouts
    shown = display_image(z, points=500)
    k = 1250 // 500
    assert shown.shape == (-(-1103 // k), -(-1250 // k))
    for i, j in [(0, 0), (7, 300), (551, 624), (551, 0), (0, 624), (10, 255)]:
        block = z[i * k : (i + 1) * k, j * k : (j + 1) * k]
        ok = np.isfinite(block)
        if ok.any():
            assert shown[i, j] == pytest.approx(block[ok].mean(), rel=1e-12, abs=1e-15)
        else:
            assert np.isnan(shown[i, j])
    assert np.isnan(shown[20 // k, 515 // k])  # inside the hole: still unmeasured
    assert np.nanmin(shown) >= np.nanmin(z) and np.nanmax(shown) <= np.nanmax(z)
    small = rng.normal(size=(300, 499))
    np.testing.assert_array_equal(display_image(small, points=500), small)  # no reduction needed


@pytest.mark.parametrize(
    "tex, plain",
    [
        (r"$\mathdefault{10^{-5}}$", "10⁻⁵"),
        (r"$\mathdefault{10^{12}}$", "10¹²"),
        (r"$\mathdefault{10^{0}}$", "10⁰"),
        (r"$\mathdefault{2\times10^{-3}}$", "2×10⁻³"),
        (r"$\mathdefault{0.5}$", "0.5"),
        ("", ""),
        ("plain", "plain"),
    ],
)
def test_plain_log_labels(tex, plain):
    assert _plain_log_label(tex) == plain


def test_analyse_figures_need_no_mathtext(tmp_path):
    # mathtext's parser costs 0.3 s or more on first use: none of analyse's figures may need it
    h = np.random.default_rng(1).normal(size=(96, 80)) * 1e-4
    h[5:9, 5:9] = np.nan
    np.save(tmp_path / "s.npy", h)
    code = (
        "from pipelines.cli.app import main\n"
        f"assert main(['analyse', {str(tmp_path / 's.npy')!r}, '--spacing', '1e-4', "
        f"'--out', {str(tmp_path / 'out')!r}]) == 0\n"
        "import matplotlib.mathtext as mt\nprint('PARSER', mt.MathTextParser._parser is not None)\n"
    )
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=ROOT, timeout=120
    )
    assert out.returncode == 0, out.stderr
    assert "PARSER False" in out.stdout
    pngs = sorted(p.name for p in (tmp_path / "out").glob("*.png"))
    assert pngs == ["heightmap.png", "mu.png", "psd.png", "psd2d.png"]


def test_no_figures_changes_no_output(tmp_path):
    from pipelines.cli.app import main

    h = np.random.default_rng(2).normal(size=(64, 72)) * 1e-4
    np.save(tmp_path / "s.npy", h)
    args = ["analyse", str(tmp_path / "s.npy"), "--spacing", "1e-4", "--velocities", "1e-4:1e2:7"]
    assert main(args + ["--out", str(tmp_path / "a")]) == 0
    assert main(args + ["--no-figures", "--out", str(tmp_path / "b")]) == 0
    a, b = tmp_path / "a", tmp_path / "b"
    for name in ("psd.csv", "mu.csv"):
        assert (a / name).read_bytes() == (b / name).read_bytes()
    sa, sb = json.loads((a / "summary.json").read_text()), json.loads((b / "summary.json").read_text())
    assert sa == sb
    assert not list(b.glob("*.png")) and (b / "report.html").exists()
    assert "<img" in (a / "report.html").read_text() and "<img" not in (b / "report.html").read_text()
