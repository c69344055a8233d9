"""One chain, one answer: ``pipelines.analyse`` equals ``roadscan analyse``; every door that
computes mu(v) from a scan agrees; warnings belong to their run; the band's fine end is judged
by the measurement, whatever the rubber."""

import json
from pathlib import Path

import numpy as np
import pytest

from pipelines.cli.app import main

ROOT = Path(__file__).resolve().parents[1]
RUBBER = ROOT / "sample_scans" / "rubbers" / "pyvisco_master_wlf.toml"
DX = "1e-4"
#: non-default friction flags (a measured rubber, pressure, Poisson ratio, S(q), extrapolation)
FLAGS = [
    "--rubber",
    str(RUBBER),
    "--sigma0",
    "0.25MPa",
    "--nu",
    "0.45",
    "--contact-gamma",
    "0.6",
    "--extrapolate",
    "hold",
    "--temperature",
    "30",
    "--velocities",
    "1e-3:10:9",
]
OPTIONS = dict(
    rubber=str(RUBBER),
    sigma0="0.25MPa",
    nu=0.45,
    contact_gamma=0.6,
    extrapolate="hold",
    temperature=30,
    velocities="1e-3:10:9",
)


@pytest.fixture(scope="module")
def scan(tmp_path_factory):
    from roadscan.synth import self_affine_surface

    hm = self_affine_surface(
        160, 160, dx_m=1e-4, hurst=0.8, rms_height_m=3e-4, q_roll_per_m=2 * np.pi / 6e-3, seed=7, name="s"
    )
    p = tmp_path_factory.mktemp("scan") / "s.npy"
    np.save(p, hm.heights_m)
    return p


def _run(argv):
    assert main([str(a) for a in argv]) == 0, argv


def _mu_csv(path, col=1):
    return np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)[:, col]


def test_api_summary_equals_cli_summary_json(scan, tmp_path):
    import pipelines

    _run(
        [
            "analyse",
            scan,
            "--spacing",
            DX,
            "--window-alpha",
            "0.3",
            "--no-figures",
            "--out",
            tmp_path / "cli",
            *FLAGS,
        ]
    )
    r = pipelines.analyse(scan, spacing=DX, window_alpha=0.3, no_figures=True, **OPTIONS)
    cli = json.loads((tmp_path / "cli" / "summary.json").read_text())
    assert r.summary == cli
    assert "alpha 0.3 " in r.summary["psd_convention"]  # the window actually used
    assert r.summary["friction"]["nu"] == 0.45 and r.summary["friction"]["sigma0_Pa"] == 2.5e5
    np.testing.assert_allclose(r.mu, _mu_csv(tmp_path / "cli" / "mu.csv"), rtol=1e-9)
    np.testing.assert_allclose(r.area_fraction, _mu_csv(tmp_path / "cli" / "mu.csv", 2), rtol=1e-9)
    lo, hi = r.reliable_band_per_m
    assert [lo, hi] == pytest.approx(cli["reliable_band_per_m"])
    assert r.q_per_m.shape == r.C_m4.shape and r.fit.hurst == cli["hurst"]
    r.write(tmp_path / "api")  # the very files of the command
    assert sorted(p.name for p in (tmp_path / "api").iterdir()) == sorted(
        p.name for p in (tmp_path / "cli").iterdir()
    )
    assert json.loads((tmp_path / "api" / "summary.json").read_text()) == cli


def test_unknown_option_is_a_type_error_naming_it(scan):
    import pipelines

    with pytest.raises(TypeError, match="sigma_0"):
        pipelines.analyse(scan, spacing=DX, sigma_0="0.2MPa")
    from roadscan.errors import InputError

    with pytest.raises(InputError, match="--nu"):
        pipelines.analyse(scan, spacing=DX, nu=0.7)


def test_every_door_gives_the_same_mu(scan, tmp_path):
    """analyse, friction --psd on analyse's psd.csv, compare, dry-vs-wet (dry), batch and
    pipelines.analyse, with a measured rubber and non-default flags: equal to 1e-6."""
    import pipelines

    out = tmp_path
    scan_flags = ["--spacing", DX, "--window-alpha", "0.3", "--resolution", "4e-4", *FLAGS]
    _run(["analyse", scan, "--no-figures", "--out", out / "a", *scan_flags])
    ref = _mu_csv(out / "a" / "mu.csv")
    assert json.loads((out / "a" / "summary.json").read_text())["reliable_band_reasons"]["hi"].startswith(
        "lateral resolution"
    )  # the flag shaped the band
    _run(["friction", "--psd", out / "a" / "psd.csv", "--out", out / "f" / "mu.csv", *FLAGS])
    _run(["compare", scan, scan, "--out", out / "c", *scan_flags])
    _run(["dry-vs-wet", scan, "--out", out / "w", *scan_flags])
    # the campaign's mu.csv (its report's exit code is the campaign tests' business)
    main([str(a) for a in ["batch", scan, "--workers", "1", "--out", out / "b", *scan_flags]])
    comp = json.loads((out / "c" / "comparison.json").read_text())
    first = next(iter(comp.values()))["mu"]
    doors = {
        "friction --psd": _mu_csv(out / "f" / "mu.csv"),
        "compare": np.array(list(first.values())),
        "dry-vs-wet": _mu_csv(out / "w" / "mu.csv"),
        "batch": _mu_csv(out / "b" / "s" / "mu.csv"),
        "pipelines.analyse": pipelines.analyse(
            scan, spacing=DX, window_alpha=0.3, resolution=4e-4, **OPTIONS
        ).mu,
    }
    for door, mu in doors.items():
        np.testing.assert_allclose(mu, ref, rtol=1e-6, err_msg=door)


def test_diagnose_scan_takes_the_chains_spectrum(scan):
    """diagnose --scan integrates the spectrum analyse integrates (same band, same nodes)."""
    import pipelines
    from pipelines.diagnosis.inputs import scan_surface
    from pipelines.settings.scan_input import load_scan

    r = pipelines.analyse(scan, spacing=DX)
    psd, *_ = scan_surface(load_scan(scan, spacing=DX))
    np.testing.assert_allclose(psd.q_per_m, r.friction_outcome.psd.q_per_m, rtol=1e-12)
    np.testing.assert_allclose(psd.C_m4, r.friction_outcome.psd.C_m4, rtol=1e-12)


#: flag -> value that must change mu(v) (against the defaults)
CHANGES = [
    ("--nu", "0.3"),
    ("--contact-gamma", "0.5"),
    ("--sigma0", "0.5MPa"),
    ("--temperature", "20"),
    ("--q1", "2e4"),
    ("--q0", "1500"),
    ("--flash", None),
    ("--rubber", str(ROOT / "sample_scans" / "rubbers" / "pyvisco_master_table.toml")),
]


def _mu_of(cmd, scan, out, extra):
    speeds = ["--velocities", "1e-3:10:5", *extra]
    if cmd == "friction":
        _run(["friction", "--psd", out.parent / "base_a" / "psd.csv", "--out", out / "mu.csv", *speeds])
        return _mu_csv(out / "mu.csv")
    scans = [scan, scan] if cmd == "compare" else [scan]  # analyse, compare, dry-vs-wet
    _run([cmd, *scans, "--spacing", DX, "--no-figures", "--out", out, *speeds])
    if cmd == "compare":
        return np.array(
            list(next(iter(json.loads((out / "comparison.json").read_text()).values()))["mu"].values())
        )
    return _mu_csv(out / "mu.csv")


@pytest.mark.parametrize("cmd", ["analyse", "friction", "compare", "dry-vs-wet"])
def test_every_friction_flag_changes_the_result(cmd, scan, tmp_path):
    # what is compared is mu(v): every run without figures (test_no_figures: the same numbers)
    _run(["analyse", scan, "--spacing", DX, "--no-figures", "--out", tmp_path / "base_a"])
    base = _mu_of(cmd, scan, tmp_path / "base", [])
    for k, (flag, value) in enumerate(CHANGES):
        extra = [flag] + ([value] if value is not None else [])
        mu = _mu_of(cmd, scan, tmp_path / f"o{k}", extra)
        assert np.max(np.abs(mu / base - 1)) > 1e-3, (cmd, flag)
    # --extrapolate acts on a master curve beyond its data (slow speeds, hot: 2.6 decades below)
    mc = ["--rubber", str(RUBBER), "--velocities", "1e-9:1e-6:4", "--temperature", "60"]
    a = _mu_of(cmd, scan, tmp_path / "e1", mc + ["--extrapolate", "powerlaw"])
    b = _mu_of(cmd, scan, tmp_path / "e2", mc + ["--extrapolate", "hold"])
    assert np.max(np.abs(a / b - 1)) > 1e-3, (cmd, "--extrapolate")


def test_friction_psd_extends_like_analyse_beyond_the_scan(scan, tmp_path):
    """--q1 above Nyquist: analyse continues C(q) by its self-affine fit; friction --psd on
    analyse's psd.csv (with psd_band.json beside it) does the same, and without the sidecar it
    cannot (the table's own tail), which is why the sidecar exists."""
    q1 = ["--q1", "3e5", "--velocities", "1e-3:10:5"]
    _run(["analyse", scan, "--spacing", DX, "--no-figures", "--out", tmp_path / "a", *q1])
    _run(["friction", "--psd", tmp_path / "a" / "psd.csv", "--out", tmp_path / "f" / "mu.csv", *q1])
    ref = _mu_csv(tmp_path / "a" / "mu.csv")
    np.testing.assert_allclose(_mu_csv(tmp_path / "f" / "mu.csv"), ref, rtol=1e-6)
    bare = tmp_path / "bare"
    bare.mkdir()
    (bare / "psd.csv").write_bytes((tmp_path / "a" / "psd.csv").read_bytes())
    _run(["friction", "--psd", bare / "psd.csv", "--out", tmp_path / "g" / "mu.csv", *q1])
    assert np.max(np.abs(_mu_csv(tmp_path / "g" / "mu.csv") / ref - 1)) > 1e-3


def test_compare_api_equals_the_command(scan, tmp_path):
    from pipelines import compare

    flags = dict(spacing=DX, nu=0.3, contact_gamma=0.5, velocities="1e-3:10:5")
    r = compare([scan, scan], tmp_path / "api", **flags)
    _run(
        [
            "compare",
            scan,
            scan,
            "--spacing",
            DX,
            "--nu",
            "0.3",
            "--contact-gamma",
            "0.5",
            "--velocities",
            "1e-3:10:5",
            "--out",
            tmp_path / "cli",
        ]
    )
    cli = json.loads((tmp_path / "cli" / "comparison.json").read_text())
    assert json.loads((tmp_path / "api" / "comparison.json").read_text()) == cli
    assert r["s"]["mu_peak"] == cli["s"]["mu_peak"]
    with pytest.raises(TypeError, match="poisson"):
        compare([scan, scan], tmp_path / "x", spacing=DX, poisson=0.3)
