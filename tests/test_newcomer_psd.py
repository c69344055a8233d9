"""A spectrum file is checked against what a profiler can measure: q in 1/mm with C in mm^4
under the SI header is refused naming the slip; a C in the (2 pi)^2 larger normalisation gives
an implausible-mu warning that names the normalisation; analyse's own psd.csv is accepted."""

import json
from pathlib import Path

import numpy as np
import pytest
from fault_tools import assert_one_line_error, run_cli

from pipelines.checks.psd_plausibility import check_psd_table, spectrum_figures
from pipelines.output.csv_files import read_psd_csv
from roadscan.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
SAMPLE_PSD = ROOT / "sample_scans" / "asphalt_psd.csv"


def _self_affine(H=0.8, q0=100.0, q1=1e5, h_rms=4e-4, n=200):
    """A self-affine table C = C0 (q/q0)^-2(1+H) [m^4] scaled to rms height h_rms [m]."""
    q = np.geomspace(q0, q1, n)
    C = (q / q0) ** (-2 * (1 + H))
    C *= h_rms**2 / (2 * np.pi * np.trapezoid(q * C, q))
    return q, C


def _write(path, q, C):
    np.savetxt(path, np.column_stack([q, C]), delimiter=",", header="q_per_m,C_m4", comments="", fmt="%.10g")
    return path


def test_figures_against_the_analytic_self_affine_integrals():
    H, q0, q1 = 0.8, 100.0, 1e5
    q, C = _self_affine(H, q0, q1, n=4000)
    lmin, lmax, h, s = spectrum_figures(q, C)
    assert (lmin, lmax) == pytest.approx((2 * np.pi / q1, 2 * np.pi / q0))
    assert h == pytest.approx(4e-4, rel=1e-6)
    # analytic: s^2 / h^2 = int q^3 q^-2(1+H) / int q q^-2(1+H) = [(1-H)^-1 q^(2-2H)] / [(2H)^-1 q^-2H]
    num = (q1 ** (2 - 2 * H) - q0 ** (2 - 2 * H)) / (2 - 2 * H)
    den = (q0 ** (-2 * H) - q1 ** (-2 * H)) / (2 * H)
    assert s == pytest.approx(4e-4 * np.sqrt(num / den), rel=1e-3)


def test_mm_spectrum_refused_naming_the_slip(tmp_path):
    q, C = _self_affine()
    p = _write(tmp_path / "psd_mm.csv", q * 1e-3, C * 1e12)  # 1/mm and mm^4, SI header
    with pytest.raises(InputError) as e:
        read_psd_csv(p)
    msg = str(e.value)
    assert "\n" not in msg and str(p) in msg
    assert "q in 1/mm and C in mm^4" in msg and "units?" in msg


def test_mm_spectrum_refused_by_friction_in_one_line(tmp_path, capsys):
    d = np.genfromtxt(SAMPLE_PSD, delimiter=",", names=True)
    p = _write(tmp_path / "psd_mm.csv", d["q_per_m"] * 1e-3, d["C_m4"] * 1e12)
    rc, err = run_cli(capsys, ["friction", "--psd", p, "--out", tmp_path / "mu.csv"])
    assert_one_line_error(rc, err, words=[str(p), "1/mm", "mm^4"])
    assert not (tmp_path / "mu.csv").exists()


@pytest.mark.parametrize(
    "fq, fc, what", [(1e-3, 1.0, "q in 1/mm (C in m^4)"), (1.0, 1e12, "C in mm^4 (q in 1/m)")]
)
def test_single_column_slips_named(tmp_path, fq, fc, what):
    q, C = _self_affine()
    with pytest.raises(InputError) as e:
        check_psd_table(tmp_path / "x.csv", q * fq, C * fc)
    assert what in str(e.value)


def test_plausible_spectra_accepted():
    for args in [
        dict(),
        dict(q0=1e4, q1=1e8, h_rms=2e-8),  # a microscope's
        dict(q0=3.0, q1=8e4, h_rms=3e-3),
    ]:  # a 2 m road profile's
        q, C = _self_affine(**args)
        out = check_psd_table("x.csv", q, C)
        assert out["rms_height_m"] == pytest.approx(args.get("h_rms", 4e-4), rel=1e-6)


def test_analyse_psd_accepted_by_friction(tmp_path, capsys):
    out = tmp_path / "an"
    rc, err = run_cli(
        capsys,
        ["analyse", ROOT / "sample_scans" / "asphalt.x3p", "--out", out, "--no-friction", "--no-figures"],
    )
    assert rc == 0, err
    psd = read_psd_csv(out / "psd.csv")
    assert psd.q_min_per_m > 0
    rc, err = run_cli(capsys, ["friction", "--psd", out / "psd.csv", "--out", tmp_path / "mu.csv"])
    assert rc == 0, err


def test_other_normalisation_named_among_the_causes(tmp_path, capsys):
    d = np.genfromtxt(SAMPLE_PSD, delimiter=",", names=True)
    p = _write(tmp_path / "psd_st.csv", d["q_per_m"], d["C_m4"] * (2 * np.pi) ** 2)
    rc, err = run_cli(capsys, ["friction", "--psd", p, "--out", tmp_path / "mu.csv"])
    assert rc == 0, err
    s = json.loads((tmp_path / "mu_summary.json").read_text())
    assert s["mu_peak"] > 3  # implausible: the warning must say why
    warned = [w for w in s["warnings"] if "likely cause" in w]
    assert warned and "normalisation" in warned[0] and "39.5" in warned[0], s["warnings"]
    assert "normalisation" in err
