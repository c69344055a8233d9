"""`roadscan rubber master`: raw DMA sweeps -> master curve by time-temperature superposition.

pyvisco (NREL, BSD-3) publishes a raw sweep file, a master curve and a shift table
(copies in sample_scans/rubbers/). The published master curve and shift table are not those of
the raw file (shifting the raw sweeps by the published factors puts them up to 40x off the
published curve: :func:`test_published_files_are_not_one_material`), so the comparison is made
on sweeps sampled from the published master curve at the published temperatures and shift
factors, over the raw file's 0.1-100 Hz with scatter; the real raw file is checked for
superposition quality.
"""

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from friction.mastercurve import fit_power_offset, pair_shift, smooth_master
from pipelines.cli.app import main
from pipelines.settings.rubber_file import load_rubber

ROOT = Path(__file__).resolve().parents[1]
RUBBERS = ROOT / "sample_scans" / "rubbers"  # the published master curve and shift table (copies)
RAW = RUBBERS / "freq_user_raw.csv"  # the raw sweeps (copy of pyvisco's)


def _table(path, skip=2):
    with open(path, encoding="utf-8-sig") as fh:
        return np.array(list(csv.reader(fh))[skip:], float)


def _published():
    mc = _table(RUBBERS / "freq_user_master.csv")
    sh = _table(RUBBERS / "freq_user_master__shift_factors.csv")[::-1]  # ascending T
    return mc, sh


def _interp_loglog(f, mc, col):
    return np.exp(np.interp(np.log(f), np.log(mc[:, 0]), np.log(mc[:, col])))


@pytest.fixture(scope="module")
def synthetic_run(tmp_path_factory):
    """Sweeps at pyvisco's temperatures, sampled from its master curve at its shift factors,
    written in the raw file's layout (BOM, units line, spaces, MPa, Set) with 0.3 % / 1 % scatter."""
    mc, sh = _published()
    rng = np.random.default_rng(7)
    fr = np.logspace(-1, 2, 10)
    lines = ["\ufefff,E_stor,E_loss,T,Set", "Hz, MPa, MPa, C, -"]
    for i, (T, la) in enumerate(sh):
        e1 = _interp_loglog(fr * 10**la, mc, 1) * (1 + 0.003 * rng.standard_normal(fr.size))
        e2 = _interp_loglog(fr * 10**la, mc, 2) * (1 + 0.01 * rng.standard_normal(fr.size))
        Ts = T + 0.2 * rng.standard_normal(fr.size)
        lines += [f"{a:g}, {b:.8g}, {c:.8g}, {t:.4f}, {i}" for a, b, c, t in zip(fr, e1, e2, Ts)]
    d = tmp_path_factory.mktemp("tts")
    (d / "raw.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    assert (
        main(
            [
                "rubber",
                "master",
                str(d / "raw.csv"),
                "--reference-temperature",
                "-5",
                "--out",
                str(d / "syn.toml"),
            ]
        )
        == 0
    )
    return d


def test_shift_factors_within_03_decade(synthetic_run):
    _, sh = _published()
    got = _table(synthetic_run / "syn_shift.csv", skip=1)
    np.testing.assert_allclose(got[:, 0], sh[:, 0], atol=0.3)  # sweep temperatures
    err = got[:, 1] - sh[:, 1]
    assert np.max(np.abs(err)) < 0.3, np.round(err, 2)


def _sampled_sweeps(seed):
    """The synthetic_run sweeps as arrays (same recipe, another noise seed)."""
    mc, sh = _published()
    rng = np.random.default_rng(seed)
    fr = np.logspace(-1, 2, 10)
    cols = [[], [], [], [], []]
    for i, (T, la) in enumerate(sh):
        cols[0] += list(fr)
        cols[1] += list(_interp_loglog(fr * 10**la, mc, 1) * 1e6 * (1 + 0.003 * rng.standard_normal(fr.size)))
        cols[2] += list(_interp_loglog(fr * 10**la, mc, 2) * 1e6 * (1 + 0.01 * rng.standard_normal(fr.size)))
        cols[3] += list(T + 0.2 * rng.standard_normal(fr.size))
        cols[4] += [i] * fr.size
    return [np.array(c) for c in cols], sh


def test_shift_accuracy_over_noise_seeds():
    """Not one lucky seed: over 6 noise seeds, the sweeps placed by overlap agree with pyvisco's
    shifts within 0.2 decade (measured <= 0.19); all sweeps, the plateau ones continued by the trend
    of their neighbours included, within 0.4 (measured 0.23-0.36: 0.3 is met by about 6 seeds in 10)."""
    from friction.mastercurve import build_master

    for seed in range(6):
        (f, e1, e2, T, sid), sh = _sampled_sweeps(seed)
        r = build_master(f, e1, e2, T, -5.0, sid)
        err = np.abs(r.log10_aT - sh[:, 1])
        placed = np.array(
            [i["method"] in ("overlap", "reference") and i["sigma_decades"] < 0.3 for i in r.sweep_info]
        )
        assert placed.sum() >= 10
        assert err[placed].max() < 0.2 and err.max() < 0.4, (seed, np.round(err, 2))


def test_master_curve_within_10_percent(synthetic_run):
    mc, _ = _published()
    r = load_rubber(synthetic_run / "syn.toml")  # loadable by --rubber
    k = (mc[:, 0] >= r.f_Hz[0]) & (mc[:, 0] <= r.f_Hz[-1])
    assert np.log10(mc[k, 0][-1] / mc[k, 0][0]) > 20  # overlap: > 20 decades
    E = r.modulus_ref(2 * np.pi * mc[k, 0])
    e1 = E.real / (mc[k, 1] * 1e6) - 1
    assert np.max(np.abs(e1)) < 0.10
    # the published E'' has jumps of its own (23 % within 0.04 decade near 0.025 Hz): compared
    # point by point it agrees to a few % rms; against the published curve smoothed the same way
    # as ours (0.2 decade), within 10 % everywhere
    e2 = E.imag / (mc[k, 2] * 1e6) - 1
    assert np.sqrt(np.mean(e2**2)) < 0.05
    fs, s1, s2 = smooth_master(mc[:, 0], mc[:, 1] * 1e6, mc[:, 2] * 1e6)
    k = (fs >= r.f_Hz[0]) & (fs <= r.f_Hz[-1])
    E = r.modulus_ref(2 * np.pi * fs[k])
    assert np.max(np.abs(E.imag / s2[k] - 1)) < 0.10 and np.max(np.abs(E.real / s1[k] - 1)) < 0.10


def test_outputs_wlf_prony_plot(synthetic_run):
    s = json.loads((synthetic_run / "syn_master.json").read_text())
    w = s["wlf_fit"]
    T = np.array([x["T_C"] for x in s["shift_table"]])
    la = np.array([x["log10_aT"] for x in s["shift_table"]])
    fit = -w["C1"] * (T - w["T_s_C"]) / (w["C2_K"] + T - w["T_s_C"])
    assert w["rms_decades"] == pytest.approx(np.sqrt(np.mean((fit - la) ** 2)), rel=1e-6)
    assert w["T_s_C"] == -5.0 and w["C1"] > 0 and w["C2_K"] > 0
    assert s["prony"]["terms"] >= 10 and s["prony"]["rms_relative_misfit"] < 0.25
    png = synthetic_run / "syn_master.png"
    assert png.read_bytes()[:4] == b"\x89PNG"
    # the Prony series in the TOML is a usable rubber too
    text = (synthetic_run / "syn.toml").read_text().replace('model = "master_curve"', 'model = "prony"')
    (synthetic_run / "prony.toml").write_text(text)
    p = load_rubber(synthetic_run / "prony.toml")
    assert p.E_i_Pa.size == s["prony"]["terms"]
    # and the TOML drives the friction command
    out = synthetic_run / "mu.csv"
    assert (
        main(
            [
                "friction",
                "--psd",
                str(ROOT / "sample_scans" / "asphalt_psd.csv"),
                "--rubber",
                str(synthetic_run / "syn.toml"),
                "--temperature",
                "20",
                "--velocities",
                "1e-4:1:3",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    d = _table(out, skip=1)
    assert np.all((d[:, 1] > 0.05) & (d[:, 1] < 5)) and np.all((d[:, 2] > 0) & (d[:, 2] < 1))


def test_real_raw_sweeps_superpose(tmp_path):
    """The real pyvisco raw file: the shifted storage moduli fall on one curve (1.2 % rms measured),
    aT falls monotonically with T and is 1 at T_ref."""
    assert (
        main(
            ["rubber", "master", str(RAW), "--reference-temperature", "-5", "--out", str(tmp_path / "r.toml")]
        )
        == 0
    )
    sh = _table(tmp_path / "r_shift.csv", skip=1)
    assert sh.shape == (21, 2) and np.all(np.diff(sh[:, 1]) < 0)
    assert np.interp(-5.0, sh[:, 0], sh[:, 1]) == pytest.approx(0.0, abs=1e-9)
    pts = _table(tmp_path / "r_shifted.csv", skip=1)
    r = load_rubber(tmp_path / "r.toml")
    E = r.modulus_ref(2 * np.pi * pts[:, 0])
    assert np.sqrt(np.mean((E.real / pts[:, 1] - 1) ** 2)) < 0.03


def test_published_files_are_not_one_material():
    """Why the pyvisco comparison uses sampled sweeps: the raw sweeps shifted by the published
    factors are far from the published master curve (ratios up to ~40)."""
    raw = _table(RAW)
    mc, sh = _published()
    la = sh[raw[:, 4].astype(int), 1]
    ratio = raw[:, 1] / _interp_loglog(raw[:, 0] * 10**la, mc, 1)
    assert ratio.max() > 10
    # No shift can mend it: E'' as a function of E' (the Cole-Cole curve) does not depend on the
    # shift factors, and the raw sweeps' E'' is 2-4x below the published curve's at the same E'.
    for E in (3000.0, 5000.0, 7000.0):
        pub = np.median(mc[np.abs(np.log(mc[:, 1] / E)) < 0.05, 2])
        got = np.median(raw[np.abs(np.log(raw[:, 1] / E)) < 0.05, 2])
        assert got < 0.65 * pub, (E, got, pub)


def test_published_shifts_do_not_superpose_the_raw_sweeps(tmp_path):
    """Neighbouring raw sweeps shifted by pyvisco's published factors disagree by up to ~17 % in E'
    where they overlap; shifted by ours, by at most a few %."""
    raw = _table(RAW)
    _, sh = _published()
    assert (
        main(
            ["rubber", "master", str(RAW), "--reference-temperature", "-5", "--out", str(tmp_path / "r.toml")]
        )
        == 0
    )
    ours = _table(tmp_path / "r_shift.csv", skip=1)[:, 1]

    def worst_mismatch(la):
        worst = 0.0
        for s in range(20):
            a, b = raw[raw[:, 4] == s], raw[raw[:, 4] == s + 1]
            xa, xb = np.log10(a[:, 0]) + la[s], np.log10(b[:, 0]) + la[s + 1]
            lo, hi = max(xa.min(), xb.min()), min(xa.max(), xb.max())
            if hi - lo < 0.3:
                continue
            x = np.linspace(lo, hi, 20)
            d = np.interp(x, xa, np.log(a[:, 1])) - np.interp(x, xb, np.log(b[:, 1]))
            worst = max(worst, float(np.sqrt(np.mean(d * d))))
        return worst

    assert worst_mismatch(sh[:, 1]) > 0.12 and worst_mismatch(ours) < 0.03


def test_pair_shift_exact_power_law():
    """Two sweeps of E' = 1e6 + 2e7 (f a)^0.4 and E'' = 5e6 (f a)^0.3 with a known relative shift."""
    f = np.logspace(-1, 2, 10)
    E1 = lambda x: 1e6 + 2e7 * x**0.4  # noqa: E731
    E2 = lambda x: 5e6 * x**0.3  # noqa: E731
    for s_true in (0.8, -1.7, 2.5):
        s, d = pair_shift(f, E1(f), E2(f), f, E1(f * 10**s_true), E2(f * 10**s_true))
        assert d["storage"] == pytest.approx(s_true, abs=1e-9) and d["loss"] == pytest.approx(
            s_true, abs=1e-9
        )
        assert s == pytest.approx(s_true, abs=5e-3)  # the overlap refinement fits quadratics
    a, b, e, rms = fit_power_offset(f, E1(f))
    assert (a, b, e) == pytest.approx((2e7, 0.4, 1e6), rel=1e-4) and rms < 1e-3 * 1e6


@pytest.mark.parametrize(
    "text,argv,msg",
    [
        ("f,E_stor,E_loss,T\nHz,MPa,MPa,C\n1,1,1,0\n", ["--reference-temperature", "0"], ">= 2 rows"),
        (
            "f,E_stor,E_loss\nHz,MPa,MPa\n1,1,1\n2,2,2\n",
            ["--reference-temperature", "0"],
            "temperature column",
        ),
        ("f,E_stor,E_loss,T\nHz,MPa,MPa,F\n1,1,1,0\n2,2,2,0\n", ["--reference-temperature", "0"], "C or K"),
    ],
)
def test_bad_raw_files(text, argv, msg, tmp_path, capsys):
    p = tmp_path / "raw.csv"
    p.write_text(text)
    assert main(["rubber", "master", str(p), *argv, "--out", str(tmp_path / "r.toml")]) == 2
    err = capsys.readouterr().err.strip()
    assert msg in err and len(err.splitlines()) == 1 and not (tmp_path / "r.toml").exists()


def test_reference_outside_sweeps_and_kelvin(tmp_path, capsys):
    raw = _table(RAW)
    p = tmp_path / "k.csv"
    p.write_text(
        "f_Hz,E_stor_MPa,E_loss_MPa,T_K\n"
        + "".join(f"{a:g},{b:g},{c:g},{t + 273.15:.4f}\n" for a, b, c, t, _ in raw)
    )
    assert (
        main(
            ["rubber", "master", str(p), "--reference-temperature", "150", "--out", str(tmp_path / "r.toml")]
        )
        == 2
    )
    assert "outside the sweeps" in capsys.readouterr().err
    assert (
        main(["rubber", "master", str(p), "--reference-temperature", "-5", "--out", str(tmp_path / "r.toml")])
        == 0
    )
    sh = _table(tmp_path / "r_shift.csv", skip=1)  # grouped by temperature (no Set column)
    assert sh.shape[0] == 21 and sh[0, 0] == pytest.approx(-49.9, abs=0.1)
