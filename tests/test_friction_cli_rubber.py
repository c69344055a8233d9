"""`roadscan friction` with a real master curve, a linear aT table, q0/q1, nu, sigma0 and gamma
(issue 10): the command line against an independent direct evaluation of Persson's formulas,
and the unit handling and warnings of the flags."""

import csv
import json
import logging
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.special import erf

from pipelines.cli.app import main
from pipelines.settings.friction import parse_pressure
from roadscan.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
RUBBERS = ROOT / "sample_scans" / "rubbers"
PSD = ROOT / "sample_scans" / "asphalt_psd.csv"


def _read(path):
    with open(path) as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array(rows[1:], float)


def _table(path, skip_units=False):
    with open(path, encoding="utf-8-sig") as fh:
        rows = [r for r in csv.reader(fh)]
    return np.array(rows[2 if skip_units else 1 :], float)


@pytest.fixture(scope="module")
def rubber_files(tmp_path_factory):
    """The pyvisco master curve (MPa, T_ref = -5 C) and its shift table written as linear aT."""
    d = tmp_path_factory.mktemp("rubber")
    sh = _table(RUBBERS / "freq_user_master__shift_factors.csv", skip_units=True)
    (d / "aT.csv").write_text("T_C,aT\n" + "".join(f"{t:g},{10**a:.10e}\n" for t, a in sh))
    (d / "rubber.toml").write_text(
        'model = "master_curve"\nT_ref_C = -5.0\n[master_curve]\nfile '
        f'= "{RUBBERS / "freq_user_master.csv"}"\n'
        '[shift]\nkind = "table"\nfile = "aT.csv"\n'
    )
    return d


def persson_direct(
    q_tab, C_tab, f_Hz, E1, E2, T_tab, log_aT, T_ref, T0, v, sigma0, nu, gamma, q0, q1, nq=3000, nphi=500
):
    """Persson's formulas evaluated directly, written independently of the engine:

    mu = 1/2 int_{q0}^{q1} q^3 C S P M dq, M = int_0^{2pi} cos(phi) Im E(q v cos phi) dphi / s,
    G = 1/8 int_{q0}^{q} q^3 C W dq, W = int_0^{2pi} |E|^2 dphi / s^2, s = (1 - nu^2) sigma0,
    P = erf(1 / (2 sqrt G)), S = gamma + (1 - gamma) P^2; E(omega, T0) = E_ref(omega aT(T0)/aT(T_ref)).
    C: log-log interpolation, above the table the power law least-squares fitted to its top decade.
    Plain trapezoids on a grid graded towards q0 (where P drops steeply) and towards phi = pi/2.
    """
    lq_t, lC_t = np.log(q_tab), np.log(C_tab)
    top = lq_t >= lq_t[-1] - np.log(10.0)
    if top.sum() < 4:
        top[-4:] = True
    slope = np.polyfit(lq_t[top], lC_t[top], 1)[0]
    s_q = np.log(q0) + (np.log(q1) - np.log(q0)) * np.linspace(0, 1, nq) ** 2
    q = np.exp(s_q)
    C = np.where(q <= q_tab[-1], np.exp(np.interp(s_q, lq_t, lC_t)), C_tab[-1] * (q / q_tab[-1]) ** slope)
    u = np.concatenate([[0.0], np.geomspace(1e-10, np.pi / 2, nphi)])  # u = pi/2 - phi
    cphi = np.sin(u)
    la = np.interp(T0, T_tab, log_aT) - np.interp(T_ref, T_tab, log_aT)
    lf = np.log(f_Hz)
    s = (1 - nu * nu) * sigma0
    mu, area = [], []
    for vi in v:
        f = q[:, None] * vi * cphi[None, :] * 10**la / (2 * np.pi)
        x = np.log(np.maximum(f, 1e-300))
        Er = np.exp(np.interp(x, lf, np.log(E1)))
        Ei = np.exp(np.interp(x, lf, np.log(E2))) * (f > 0)
        M = 4 * np.trapezoid(cphi * Ei, u, axis=1) / s
        W = 4 * np.trapezoid(Er**2 + Ei**2, u, axis=1) / s**2
        g = q**4 * C * W / 8
        G = np.concatenate([[0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * np.diff(s_q))])
        with np.errstate(divide="ignore"):
            P = np.where(G > 0, erf(0.5 / np.sqrt(G)), 1.0)
        S = gamma + (1 - gamma) * P**2
        mu.append(0.5 * np.trapezoid(q**4 * C * S * P * M, s_q))
        area.append(P[-1])
    return np.array(mu), np.array(area)


@pytest.mark.parametrize("route", ["toml", "flags"])
def test_cli_reproduces_direct_persson(route, rubber_files, tmp_path):
    """Master curve + linear aT table + q0, q1 (beyond the scan), nu, sigma0 with a unit, gamma."""
    out = tmp_path / "mu.csv"
    q0, q1, nu, gamma, T0 = 300.0, 1.019e6, 0.45, 0.746, 20.0
    rubber = (
        ["--rubber", str(rubber_files / "rubber.toml")]
        if route == "toml"
        else [
            "--master-curve",
            str(RUBBERS / "freq_user_master.csv"),
            "--shift-table",
            str(rubber_files / "aT.csv"),
            "--reference-temperature",
            "-5",
        ]
    )
    # the flags route takes a tabulated speed list (another program's grid), the TOML route a range
    speeds = "1e-8:1e4:7" if route == "toml" else "3.7e-7,1e-8,2.2e-3,0.05,1.3,47,1e4"
    rc = main(
        [
            "friction",
            "--psd",
            str(PSD),
            *rubber,
            "--temperature",
            str(T0),
            "--q0",
            str(q0),
            "--q1",
            str(q1),
            "--nu",
            str(nu),
            "--sigma0",
            "0.3MPa",
            "--contact-gamma",
            str(gamma),
            "--velocities",
            speeds,
            "--out",
            str(out),
        ]
    )
    assert rc == 0
    head, d = _read(out)
    assert head[:3] == ["v_m_per_s", "mu", "area_fraction"] and d.shape[0] == 7
    if route == "flags":
        np.testing.assert_allclose(d[:, 0], [1e-8, 3.7e-7, 2.2e-3, 0.05, 1.3, 47, 1e4], rtol=1e-9)
    psd = _table(PSD)
    mc = _table(RUBBERS / "freq_user_master.csv", skip_units=True)
    sh = _table(RUBBERS / "freq_user_master__shift_factors.csv", skip_units=True)[::-1]
    mu, area = persson_direct(
        psd[:, 0],
        psd[:, 1],
        mc[:, 0],
        mc[:, 1] * 1e6,
        mc[:, 2] * 1e6,
        sh[:, 0],
        sh[:, 1],
        -5.0,
        T0,
        d[:, 0],
        0.3e6,
        nu,
        gamma,
        q0,
        q1,
    )
    np.testing.assert_allclose(d[:, 1], mu, rtol=0.003)  # measured: 0.05 %
    np.testing.assert_allclose(d[:, 2], area, rtol=0.001)  # measured: 1e-4
    s = json.loads((tmp_path / "mu_summary.json").read_text())
    assert s["band"]["q0_per_m"] == pytest.approx(q0) and s["band"]["q1_per_m"] == pytest.approx(q1)
    assert s["band"]["extended_decades"] == pytest.approx(np.log10(q1 / psd[-1, 0]))
    assert s["pressure_in_P_Pa"] == pytest.approx((1 - nu**2) * 0.3e6)
    assert s["contact_gamma"] == gamma


def test_band_changes_the_answer(tmp_path):
    """q1 above the scan's last point integrates the power-law tail: mu grows, A/A0 shrinks, and a
    one-line note says so; q0 inside the spectrum drops the long wavelengths."""
    base = ["friction", "--psd", str(PSD), "--velocities", "1e-2:1e2:3"]
    assert main(base + ["--out", str(tmp_path / "a.csv")]) == 0
    assert main(base + ["--q1", "1e6", "--out", str(tmp_path / "b.csv")]) == 0
    assert main(base + ["--q0", "1e3", "--out", str(tmp_path / "c.csv")]) == 0
    a, b, c = (_read(tmp_path / f"{k}.csv")[1] for k in "abc")
    assert np.all(b[:, 1] > a[:, 1] * 1.05) and np.all(b[:, 2] < a[:, 2])
    assert np.all(c[:, 2] > a[:, 2])  # fewer scales of roughness: more contact


def test_q1_note_printed_once(tmp_path, capsys):
    assert (
        main(
            [
                "friction",
                "--psd",
                str(PSD),
                "--velocities",
                "1:10:2",
                "--q1",
                "2e5",
                "--out",
                str(tmp_path / "m.csv"),
            ]
        )
        == 0
    )
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.startswith("note:")]
    assert len(err) == 1 and "extended" in err[0] and "power law" in err[0]


@pytest.mark.parametrize(
    "text,pa",
    [
        ("0.3MPa", 3e5),
        ("300kPa", 3e5),
        ("300 kPa", 3e5),
        ("3e5", 3e5),
        ("3e5Pa", 3e5),
        ("2bar", 2e5),
        ("1.5e3", 1.5e3),
    ],
)
def test_parse_pressure_units(text, pa):
    assert parse_pressure(text) == pytest.approx(pa)


@pytest.mark.parametrize(
    "text,msg",
    [
        ("0.3", "did you mean 0.3MPa"),
        ("300", "did you mean 300kPa"),
        ("-2MPa", "positive"),
        ("3 furlongs", "unknown unit"),
        ("abc", "expected a pressure"),
    ],
)
def test_parse_pressure_refuses(text, msg):
    with pytest.raises(InputError, match=msg):
        parse_pressure(text)


def test_sigma0_units_same_result(tmp_path):
    base = ["friction", "--self-affine", "H=0.8,h0=5e-4,q0=2000,q1=2e5", "--velocities", "1e-3:1:4"]
    outs = []
    for k, p in enumerate(["0.3MPa", "300kPa", "3e5"]):
        assert main(base + ["--sigma0", p, "--out", str(tmp_path / f"{k}.csv")]) == 0
        outs.append(_read(tmp_path / f"{k}.csv")[1])
    np.testing.assert_array_equal(outs[0], outs[1])
    np.testing.assert_array_equal(outs[0], outs[2])


@pytest.mark.parametrize(
    "argv,msg",
    [
        (["--sigma0", "0.3"], "did you mean 0.3MPa"),
        (["--nu", "0.6"], "--nu"),
        (["--nu", "-0.1"], "--nu"),
        (["--contact-gamma", "1.5"], "--contact-gamma"),
        (["--q0", "10"], "below the spectrum's lowest wave vector"),
        (["--q0", "1e4", "--q1", "1e3"], "--q0"),
        (["--q1", "-5"], "--q1"),
        (["--shift-table", "x.csv"], "--master-curve"),
    ],
)
def test_bad_flags_one_line_exit_2(argv, msg, tmp_path, capsys):
    out = tmp_path / "m.csv"
    assert main(["friction", "--psd", str(PSD), *argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert msg in err and len(err.splitlines()) == 1
    assert not out.exists()


def test_shift_tables_linear_log_and_inverse(tmp_path, capsys, caplog):
    from pipelines.settings.rubber_file import load_rubber

    sh = _table(RUBBERS / "freq_user_master__shift_factors.csv", skip_units=True)
    mc = RUBBERS / "freq_user_master.csv"
    variants = {
        "lin.csv": "T_C,aT\n" + "".join(f"{t:g},{10**a:.12e}\n" for t, a in sh),
        "log.csv": "T_C,log10_aT\n" + "".join(f"{t:g},{a:g}\n" for t, a in sh),
        "kelvin.csv": "T [K],log_aT\n" + "".join(f"{t + 273.15:.2f},{a:g}\n" for t, a in sh),
        "inverse.csv": "T_C,aT\n" + "".join(f"{t:g},{10**-a:.12e}\n" for t, a in sh),
    }
    T = np.array([-50.0, -5.0, 10.0, 37.0, 100.0])
    ref = np.interp(T, sh[::-1, 0], sh[::-1, 1])
    for name, text in variants.items():
        (tmp_path / name).write_text(text)
        (tmp_path / "r.toml").write_text(
            f'model = "master_curve"\nT_ref_C = -5.0\n[master_curve]\n'
            f'file = "{mc}"\n[shift]\nkind = "table"\nfile = "{name}"\n'
        )
        with caplog.at_level(logging.INFO, logger="roadscan"):  # a note, through logging
            r = load_rubber(tmp_path / "r.toml")
        np.testing.assert_allclose(r.shift.log10_aT(T), ref, atol=1e-9, err_msg=name)
    assert "inverse convention" in caplog.text
    assert capsys.readouterr().err == ""  # the library prints nothing
    (tmp_path / "bad.csv").write_text("T_C,aT\n0,1\n10,-1\n")
    (tmp_path / "r.toml").write_text(
        f'model = "master_curve"\nT_ref_C = -5.0\n[master_curve]\n'
        f'file = "{mc}"\n[shift]\nkind = "table"\nfile = "bad.csv"\n'
    )
    with pytest.raises(InputError, match="positive"):
        load_rubber(tmp_path / "r.toml")


def test_inline_linear_aT_and_moduli_unit_guard(tmp_path):
    import friction

    r = friction.rubber_from_dict(
        {
            "model": "master_curve",
            "T_ref_C": 0.0,
            "master_curve": {"f_Hz": [1, 10], "E_storage_Pa": [1e6, 2e6], "E_loss_Pa": [1e5, 2e5]},
            "shift": {"kind": "table", "T_C": [0, 10], "aT": [1.0, 0.01]},
        }
    )
    assert r.shift.log10_aT(10.0) == pytest.approx(-2.0)
    from pipelines.settings.rubber_file import read_master_curve_csv

    p = tmp_path / "mc.csv"
    p.write_text("f,E_stor,E_loss\n1,5.0,0.5\n10,8.0,1.0\n")  # MPa values without a unit
    with pytest.raises(InputError, match="MPa"):
        read_master_curve_csv(p)
    p.write_text("f_Hz,E_stor_MPa,E_loss_MPa\n1,5.0,0.5\n10,8.0,1.0\n")
    f, E1, E2 = read_master_curve_csv(p)
    assert E1[0] == 5e6 and E2[1] == 1e6
    p.write_text("omega_rad_s,E' [kPa],E'' [kPa]\n6.283185307179586,5000,500\n62.83185307179586,8000,1000\n")
    f, E1, E2 = read_master_curve_csv(p)
    np.testing.assert_allclose(f, [1.0, 10.0]) and np.testing.assert_allclose(E1, [5e6, 8e6])


def _narrow_curve(tmp_path, lo=1e-2, hi=1e6):
    mc = _table(RUBBERS / "freq_user_master.csv", skip_units=True)
    k = (mc[:, 0] >= lo) & (mc[:, 0] <= hi)
    p = tmp_path / "narrow.csv"
    p.write_text(
        "f,E_stor,E_loss\nHz,MPa,MPa\n" + "".join(f"{a:.17g},{b:.17g},{c:.17g}\n" for a, b, c in mc[k])
    )
    return p


def test_extrapolation_warned_once_with_figures(tmp_path, capsys):
    """A master curve cut to 1e-2..1e6 Hz read far outside: one warning line per run, the figures in
    the summary, --extrapolate changes the answer; no numpy RuntimeWarning leaks."""
    curve = _narrow_curve(tmp_path)
    base = [
        "friction",
        "--psd",
        str(PSD),
        "--master-curve",
        str(curve),
        "--reference-temperature",
        "-5",
        "--shift-table",
        str(RUBBERS / "freq_user_master__shift_factors.csv"),
        "--velocities",
        "1e-4:1e2:4",
        "--q1",
        "1e6",
    ]
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        assert main(base + ["--temperature", "-20", "--out", str(tmp_path / "c.csv")]) == 0
        assert main(base + ["--temperature", "62", "--out", str(tmp_path / "p.csv")]) == 0
        assert (
            main(base + ["--temperature", "62", "--extrapolate", "hold", "--out", str(tmp_path / "h.csv")])
            == 0
        )
    err = [
        ln for ln in capsys.readouterr().err.splitlines() if "warning: " in ln and "on the master curve" in ln
    ]  # recorded warnings (issue 20)
    assert len(err) == 3 and "decades above" in err[0] and "decades below" in err[1]
    assert "--extrapolate powerlaw" in err[1] and "--extrapolate hold" in err[2]
    s = json.loads((tmp_path / "c_summary.json").read_text())["rubber_checks"]["frequency_coverage"]
    # v_max q1 / 2 pi shifted to -20 C (log aT(-20) - log aT(-5) = 2.58) against the curve's top
    hi = np.log10(1e2 * 1e6 / (2 * np.pi)) + 2.58
    assert np.log10(s["f_needed_Hz"][1]) == pytest.approx(hi, abs=1e-6)
    assert s["extrapolated_decades_above"] == pytest.approx(hi - np.log10(s["f_curve_Hz"][1]), abs=1e-6)
    s = json.loads((tmp_path / "p_summary.json").read_text())["rubber_checks"]["frequency_coverage"]
    # v_min q0 / 2 pi at 62 C (log aT = -7.74) against the curve's bottom
    lo = np.log10(1e-4 * _table(PSD)[0, 0] / (2 * np.pi)) - 7.74
    assert np.log10(s["f_needed_Hz"][0]) == pytest.approx(lo, abs=1e-6)
    assert s["extrapolated_decades_below"] == pytest.approx(np.log10(s["f_curve_Hz"][0]) - lo, abs=1e-6)
    assert s["warning"].startswith("warning")
    p, h = _read(tmp_path / "p.csv")[1], _read(tmp_path / "h.csv")[1]
    assert not np.allclose(p[:, 1], h[:, 1], rtol=1e-2)


def test_no_warning_inside_curve_and_wlf_report(rubber_files, tmp_path, capsys):
    assert (
        main(
            [
                "friction",
                "--psd",
                str(PSD),
                "--rubber",
                str(rubber_files / "rubber.toml"),
                "--temperature",
                "20",
                "--velocities",
                "1e-6:1:3",
                "--out",
                str(tmp_path / "m.csv"),
            ]
        )
        == 0
    )
    # the speeds stop before the peak (that warning is expected); nothing about the rubber
    said = [ln for ln in capsys.readouterr().err.splitlines() if "warning" in ln]
    assert all("still rising" in ln for ln in said), said
    s = json.loads((tmp_path / "m_summary.json").read_text())["rubber_checks"]
    assert s["frequency_coverage"]["extrapolated_decades"] == 0.0
    w = s["wlf_fit_to_shift_table"]
    sh = _table(RUBBERS / "freq_user_master__shift_factors.csv", skip_units=True)
    fit = -w["C1"] * (sh[:, 0] - w["T_s_C"]) / (w["C2_K"] + sh[:, 0] - w["T_s_C"])
    assert w["rms_decades"] == pytest.approx(np.sqrt(np.mean((fit - sh[:, 1]) ** 2)), rel=1e-6)
    assert 0 < w["rms_decades"] < 1.0


def test_wlf_report_recovers_exact_constants():
    from friction import ShiftTable
    from friction.rubber_checks import wlf_fit_report

    T = np.linspace(-30, 90, 13)
    y = -17.4 * (T - 10) / (51.6 + T - 10)
    r = wlf_fit_report(ShiftTable(T, y))
    assert r["C1"] == pytest.approx(17.4, rel=1e-4) and r["C2_K"] == pytest.approx(51.6, rel=1e-4)
    assert r["T_s_C"] == pytest.approx(10.0) and r["rms_decades"] < 1e-6


def test_whitespace_and_semicolon_tables(tmp_path):
    from pipelines.settings.rubber_file import read_master_curve_csv, read_shift_csv

    (tmp_path / "m.dat").write_text("f_Hz  E_stor_MPa\tE_loss_MPa\n1 5 0.5\n10 8 1\n")
    (tmp_path / "a.csv").write_text("T_C;aT\n0;1\n10;0.01\n")
    _f, E1, E2 = read_master_curve_csv(tmp_path / "m.dat")
    np.testing.assert_allclose(E1, [5e6, 8e6]) and np.testing.assert_allclose(E2, [5e5, 1e6])
    _T, la = read_shift_csv(tmp_path / "a.csv")
    np.testing.assert_allclose(la, [0.0, -2.0])


def test_contact_gamma_in_the_flash_model():
    """S(q) = gamma + (1 - gamma) P^2 <= 1 lowers mu; without heating the flash model with gamma
    equals the isothermal model with gamma (both engines apply S to the same integrand)."""
    from friction import SelfAffinePSD, mu_flash, mu_isothermal, thesis_rubber

    psd = SelfAffinePSD(0.8, 5e-4, 2000.0, 2e5)
    v = np.logspace(-3, 1, 5)
    r = thesis_rubber()
    iso_g = mu_isothermal(psd, r, v, contact_gamma=0.5, tol=1e-4).mu
    fl_g0 = mu_flash(psd, r, v, contact_gamma=0.5, heat_scale=0.0, tol=1e-4).mu
    np.testing.assert_allclose(fl_g0, iso_g, rtol=2e-3)
    fl = mu_flash(psd, r, v).mu
    fl_g = mu_flash(psd, r, v, contact_gamma=0.5).mu
    assert np.all(fl_g < fl)
    with pytest.raises(ValueError, match="contact_gamma"):
        mu_isothermal(psd, r, v, contact_gamma=1.5)


def test_analyse_and_diagnose_flags(tmp_path, capsys):
    from conftest import fourier_surface

    p = tmp_path / "s.npy"
    np.save(p, fourier_surface(128, 5e-5, 0.8, 3e-4, seed=1))
    assert (
        main(["analyse", str(p), "--spacing", "5e-5", "--sigma0", "0.3", "--out", str(tmp_path / "x")]) == 2
    )
    assert "did you mean 0.3MPa" in capsys.readouterr().err
    out = tmp_path / "a"
    assert (
        main(
            [
                "analyse",
                str(p),
                "--spacing",
                "5e-5",
                "--sigma0",
                "300kPa",
                "--q0",
                "2e3",
                "--q1",
                "2e5",
                "--contact-gamma",
                "0.6",
                "--nu",
                "0.45",
                "--velocities",
                "1e-3:1:4",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    s = json.loads((out / "summary.json").read_text())["friction"]
    assert s["sigma0_Pa"] == 3e5 and s["contact_gamma"] == 0.6 and s["nu"] == 0.45
    assert s["q0_per_m"] == pytest.approx(2e3) and s["q1_per_m"] == pytest.approx(2e5)
    assert "self-affine fit" in s["band"]["note"]
    head, d = _read(out / "mu.csv")
    assert head[:3] == ["v_m_per_s", "mu", "area_fraction"] and d.shape == (4, 4)
    assert (
        main(
            [
                "diagnose",
                "--measured",
                str(tmp_path / "none.csv"),
                "--psd",
                str(PSD),
                "--sigma0",
                "0.2",
                "--out",
                str(tmp_path / "d"),
            ]
        )
        == 2
    )
    assert "did you mean 0.2MPa" in capsys.readouterr().err


def test_master_curve_reference_temperature_defaults_to_unit_shift(tmp_path):
    import friction

    base = {
        "model": "master_curve",
        "master_curve": {"f_Hz": [1, 10], "E_storage_Pa": [1e6, 2e6], "E_loss_Pa": [1e5, 2e5]},
    }
    r = friction.rubber_from_dict(
        {**base, "shift": {"kind": "table", "T_C": [0, 10, 30], "aT": [30, 3, 0.1]}}
    )
    assert r.T_ref_C == pytest.approx(10 + (0 - np.log10(3)) / (np.log10(0.1) - np.log10(3)) * 20)
    assert (
        friction.rubber_from_dict({**base, "shift": {"kind": "wlf", "C1": 9, "C2_K": 50, "T_s_C": 7}}).T_ref_C
        == 7
    )
    with pytest.raises(ValueError, match="T_ref_C"):
        friction.rubber_from_dict(base)
    assert friction.rubber_from_dict({**base, "T_ref_C": 20}).T_ref_C == 20  # sls/prony keep 60 C
    out = tmp_path / "m.csv"
    assert (
        main(
            [
                "friction",
                "--psd",
                str(PSD),
                "--master-curve",
                str(RUBBERS / "freq_user_master.csv"),
                "--shift-table",
                str(RUBBERS / "freq_user_master__shift_factors.csv"),
                "--temperature",
                "20",
                "--velocities",
                "1:10:2",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    assert json.loads((tmp_path / "m_summary.json").read_text())["rubber"]["T_ref_C"] == -5.0


def test_shift_table_file_with_wlf_constants(tmp_path):
    from pipelines.settings.rubber_file import rubber_from_csv_files

    (tmp_path / "wlf.csv").write_text("C1,C2_K,T_s_C\n24.9024,138.470,-5\n")
    r = rubber_from_csv_files(RUBBERS / "freq_user_master.csv", tmp_path / "wlf.csv")
    assert r.T_ref_C == -5.0
    assert r.shift.log10_aT(20.0) == pytest.approx(-24.9024 * 25 / (138.470 + 25))
    (tmp_path / "bad.csv").write_text("C1,C2_K\n24.9,138\n")
    with pytest.raises(InputError, match="T_s_C"):
        rubber_from_csv_files(RUBBERS / "freq_user_master.csv", tmp_path / "bad.csv")


def test_diagnose_engine_receives_nu_and_gamma():
    """diagnose's model passes nu and gamma to both engines (the flash branch too) and the band map."""
    from friction import SelfAffinePSD, mu_flash, mu_isothermal, thesis_rubber
    from pipelines.diagnosis.model import FrictionContext, SimSpec, simulate
    from pipelines.diagnosis.report.bandmap import band_map

    psd, r = SelfAffinePSD(0.8, 5e-4, 2000.0, 2e5), thesis_rubber()
    v = np.logspace(-3, 1, 4)
    ctx = FrictionContext(v, np.full(4, np.nan), np.full(4, 3e5), np.zeros(4, bool), None)
    spec = SimSpec(psd=psd, rubber=r, nu=0.3, contact_gamma=0.6)
    np.testing.assert_allclose(
        simulate(spec, ctx), mu_isothermal(psd, r, v, sigma0_Pa=3e5, nu=0.3, contact_gamma=0.6).mu, rtol=1e-12
    )
    fl = spec.with_(flash={"zeta_m": 3.0})
    np.testing.assert_allclose(
        simulate(fl, ctx), mu_flash(psd, r, v, sigma0_Pa=3e5, nu=0.3, contact_gamma=0.6).mu, rtol=1e-12
    )
    bm, _ = band_map(spec, [(1e-3, 1e-2), (1.0, 10.0)], sigma0_Pa=3e5)
    vc = np.sqrt([1e-5, 10.0])
    ref = mu_isothermal(psd, r, vc, sigma0_Pa=3e5, nu=0.3, contact_gamma=0.6).mu
    np.testing.assert_allclose([b["mu_at_centre"] for b in bm], ref, rtol=1e-12)


def test_diagnose_master_curve_flags_band_and_coverage(tmp_path, capsys):
    """diagnose takes --master-curve/--shift-table (linear aT), --nu, --q0/--q1, --contact-gamma and
    --extrapolate like friction: one warning line beyond a decade, the figures in diagnosis.json."""
    curve = _narrow_curve(tmp_path)
    sh = _table(RUBBERS / "freq_user_master__shift_factors.csv", skip_units=True)
    (tmp_path / "aT.csv").write_text("T_C,aT\n" + "".join(f"{t:g},{10**a:.10e}\n" for t, a in sh))
    v = np.logspace(-4, 0, 6)
    (tmp_path / "mu.csv").write_text(
        "v_m_per_s,mu,T0_C\n"
        + "".join(f"{x:g},{0.3 + 0.02 * i},{62 if i < 3 else 70}\n" for i, x in enumerate(v))
    )
    out = tmp_path / "d"
    assert (
        main(
            [
                "diagnose",
                "--measured",
                str(tmp_path / "mu.csv"),
                "--psd",
                str(PSD),
                "--master-curve",
                str(curve),
                "--shift-table",
                str(tmp_path / "aT.csv"),
                "--reference-temperature",
                "-5",
                "--nu",
                "0.4",
                "--sigma0",
                "0.3MPa",
                "--q0",
                "300",
                "--q1",
                "1e6",
                "--contact-gamma",
                "0.7",
                "--extrapolate",
                "hold",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    err = [
        ln for ln in capsys.readouterr().err.splitlines() if "warning: " in ln and "on the master curve" in ln
    ]  # recorded warnings (issue 20)
    assert len(err) == 1 and "decades below" in err[0] and "--extrapolate hold" in err[0]
    s = json.loads((out / "diagnosis.json").read_text())["engine_settings"]
    assert s["nu"] == 0.4 and s["contact_gamma"] == 0.7 and s["rubber"]["T_ref_C"] == -5.0
    assert s["band"]["q0_per_m"] == pytest.approx(300) and s["band"]["q1_per_m"] == pytest.approx(1e6)
    cov = s["rubber_checks"]["frequency_coverage"]
    # lowest: v_min q0 / 2 pi at the hottest row (70 C, log aT = -8.46) against the curve's bottom
    lo = np.log10(1e-4 * 300 / (2 * np.pi)) - 8.46
    assert np.log10(cov["f_needed_Hz"][0]) == pytest.approx(lo, abs=1e-6)
    assert cov["f_curve_Hz"][0] >= 1e-2
    assert cov["extrapolated_decades_below"] == pytest.approx(np.log10(cov["f_curve_Hz"][0]) - lo, abs=1e-6)
    assert s["rubber_checks"]["wlf_fit_to_shift_table"]["rms_decades"] > 0
    assert (
        main(
            [
                "diagnose",
                "--measured",
                str(tmp_path / "mu.csv"),
                "--psd",
                str(PSD),
                "--nu",
                "0.7",
                "--out",
                str(tmp_path / "e"),
            ]
        )
        == 2
    )
    assert "--nu" in capsys.readouterr().err


def test_master_curve_log_columns_and_aliases(tmp_path):
    """Master curves tabulated as decimal logs (log10 omega, log10 E) or with ReE/ImE headers."""
    from pipelines.settings.rubber_file import read_master_curve_csv

    (tmp_path / "a.csv").write_text(
        "log10_omega_rad_s,log10_E_stor_Pa,log10(E_loss) [Pa]\n0,6,5\n1,6.5,5.5\n2,7,6\n"
    )
    f, E1, E2 = read_master_curve_csv(tmp_path / "a.csv")
    np.testing.assert_allclose(f, np.array([1, 10, 100]) / (2 * np.pi))
    np.testing.assert_allclose(E1, [1e6, 10**6.5, 1e7]) and np.testing.assert_allclose(
        E2, [1e5, 10**5.5, 1e6]
    )
    (tmp_path / "b.csv").write_text("log f,ReE,ImE\nHz,MPa,MPa\n0,1,0.1\n1,2,0.2\n")
    f, E1, E2 = read_master_curve_csv(tmp_path / "b.csv")
    np.testing.assert_allclose(f, [1, 10]) and np.testing.assert_allclose(E2, [1e5, 2e5])
