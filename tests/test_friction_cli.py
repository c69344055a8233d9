"""`roadscan friction` and the rubber TOML reader."""

import csv
from pathlib import Path

import numpy as np
import pytest

from friction import SelfAffinePSD, mu_isothermal, thesis_rubber
from pipelines.cli.app import main
from pipelines.settings.rubber_file import load_rubber
from roadscan.errors import InputError

RUBBERS = Path(__file__).resolve().parents[1] / "sample_scans" / "rubbers"


def _read(path):
    with open(path) as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array(rows[1:], float)


def test_cli_self_affine_defaults(tmp_path):
    out = tmp_path / "mu.csv"
    assert main(["friction", "--self-affine", "H=0.85,h0=5e-4,q0=2000,q1=2e5", "--out", str(out)]) == 0
    head, d = _read(out)
    assert head[:3] == ["v_m_per_s", "mu", "area_fraction"] and d.shape[0] == 61
    assert d[0, 0] == pytest.approx(1e-4) and d[-1, 0] == pytest.approx(1e2)
    res = mu_isothermal(SelfAffinePSD(0.85, 5e-4, 2000.0, 2e5), thesis_rubber(), d[:, 0])
    np.testing.assert_allclose(d[:, 1], res.mu, rtol=1e-8)
    np.testing.assert_allclose(d[:, 2], res.P[:, -1], rtol=1e-8)
    assert np.all((d[:, 2] > 0) & (d[:, 2] < 1))
    png = out.with_suffix(".png")
    assert png.exists() and png.read_bytes()[:4] == b"\x89PNG"


def test_cli_psd_file_flash_and_rubber(tmp_path):
    q = np.logspace(np.log10(1500), np.log10(6e5), 60)
    C = SelfAffinePSD(0.8, 6.67e-4, 1500.0, 6e5).C(q)
    psd = tmp_path / "psd.csv"
    psd.write_text("q_per_m,C_m4\n" + "".join(f"{a:.12g},{b:.12g}\n" for a, b in zip(q, C)))
    out = tmp_path / "flash.csv"
    rc = main(
        [
            "friction",
            "--psd",
            str(psd),
            "--rubber",
            str(RUBBERS / "thesis_prony.toml"),
            "--sigma0",
            "4e5",
            "--flash",
            "--velocities",
            "1e-4:1e2:7",
            "--magnifications",
            "3,10",
            "--out",
            str(out),
        ]
    )
    assert rc == 0
    head, d = _read(out)
    assert head == [
        "v_m_per_s",
        "mu",
        "area_fraction",
        "T_flash_max_C",
        "T_C_zeta_1",
        "T_C_zeta_max",
        "T_C_zeta_3",
        "T_C_zeta_10",
        "extrapolated_share",
    ]
    assert d.shape == (7, 9) and np.all(d[:, 3:8] >= 60.0 - 1e-9) and np.all(d[:, 8] == 0)
    d = np.delete(d, 2, axis=1)  # the columns of the former layout follow T_flash_max_C
    assert np.all(d[:, 2] >= d[:, 3:].max(axis=1) - 1e-9)  # the hottest over all length scales
    d = np.delete(d, 2, axis=1)
    assert d[-1, 3] > d[-1, 5] > d[-1, 2] > 60.0  # smaller length scales run hotter at 100 m/s


@pytest.mark.parametrize(
    "argv",
    [
        ["--self-affine", "H=0.8,h0=1e-3,q0=1e3"],
        ["--self-affine", "H=0.8,h0=1e-3,q0=1e3,q1=1e5", "--velocities", "1:0.1:5"],
        ["--self-affine", "H=0.8,h0=1e-3,q0=1e3,q1=1e5", "--sigma0", "-1"],
        ["--psd", "/nonexistent/psd.csv"],
    ],
)
def test_cli_bad_input_exits_2(argv, tmp_path, capsys):
    assert main(["friction", *argv, "--out", str(tmp_path / "m.csv")]) == 2
    assert "error" in capsys.readouterr().err
    assert not (tmp_path / "m.csv").exists()


def test_example_rubbers_load():
    sls = load_rubber(RUBBERS / "thesis_sls.toml")
    np.testing.assert_allclose(sls.modulus([1.0, 1e6], 80.0), thesis_rubber().modulus([1.0, 1e6], 80.0))
    pr = load_rubber(RUBBERS / "thesis_prony.toml")
    np.testing.assert_allclose(pr.modulus([1.0, 1e6]), sls.modulus([1.0, 1e6]), rtol=1e-12)
    mt = load_rubber(RUBBERS / "pyvisco_master_table.toml")
    assert mt.T_ref_C == -5.0 and mt.E_storage_Pa[0] == pytest.approx(88.79651575665739e6)
    assert mt.shift.log10_aT(25.0) == pytest.approx(-4.08)
    mw = load_rubber(RUBBERS / "pyvisco_master_wlf.toml")
    assert mw.shift.log10_aT(-5.0) == pytest.approx(0.0)
    np.testing.assert_allclose(mw.E_loss_Pa, mt.E_loss_Pa)


def test_bad_rubber_files(tmp_path):
    p = tmp_path / "r.toml"
    for text, msg in [
        ("model = 'sls'\n[sls]\nE1_Pa = 'x'\n", "E1_Pa"),
        ("model = [\n", "TOML"),
        ("model='master_curve'\n[master_curve]\nfile='missing.csv'\n", "no such file"),
    ]:
        p.write_text(text)
        with pytest.raises(InputError, match=msg):
            load_rubber(p)
    (tmp_path / "mc.csv").write_text(
        "\ufefff, E_stor, E_loss\nHz, furlongs, MPa\n1, 2, 3\n2, 3, 4\n", encoding="utf-8"
    )
    p.write_text("model='master_curve'\n[master_curve]\nfile='mc.csv'\n")
    with pytest.raises(InputError, match="unit"):
        load_rubber(p)
