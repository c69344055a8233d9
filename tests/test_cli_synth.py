"""``roadscan synth``: reproducible Gaussian self-affine surfaces written to a file."""

import numpy as np
import pytest

from pipelines.cli.app import main
from roadscan.io import read


def test_synth_writes_reproducible_surface_with_exact_rms(tmp_path):
    a, b, c = tmp_path / "a.x3p", tmp_path / "b.x3p", tmp_path / "c.npz"
    args = ["--nx", "256", "--ny", "192", "--spacing", "5e-5", "--hurst", "0.7", "--rms", "1e-4"]
    assert main(["synth", "--out", str(a), "--seed", "3"] + args) == 0
    assert main(["synth", "--out", str(b), "--seed", "3"] + args) == 0
    assert main(["synth", "--out", str(c), "--seed", "4"] + args) == 0
    ha, hb, hc = read(a), read(b), read(c)
    assert ha.shape == (192, 256) and ha.dx_m == pytest.approx(5e-5)
    np.testing.assert_array_equal(ha.heights_m, hb.heights_m)
    assert not np.allclose(ha.heights_m, hc.heights_m)
    assert ha.heights_m.std() == pytest.approx(1e-4, rel=1e-9)


def test_synth_surface_analyses_to_its_hurst_exponent(tmp_path):
    p = tmp_path / "s.x3p"
    assert (
        main(["synth", "--out", str(p), "--nx", "512", "--hurst", "0.6", "--rms", "2e-4", "--seed", "1"]) == 0
    )
    from roadscan.fit import fit_self_affine
    from roadscan.spectrum import psd_area

    spec, _ = psd_area(read(p))
    assert fit_self_affine(spec).hurst == pytest.approx(0.6, abs=0.05)


def test_synth_rejects_bad_hurst(tmp_path, capsys):
    assert main(["synth", "--out", str(tmp_path / "x.x3p"), "--hurst", "1.5"]) == 2
    assert "--hurst" in capsys.readouterr().err
    assert not (tmp_path / "x.x3p").exists()
