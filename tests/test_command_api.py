"""Each computing command is one function of ``pipelines``: the function and the command
(which parses, calls it and prints) write the same main JSON and the same files; an unknown
keyword is a TypeError; a keyword changes the result as its flag does."""

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import fourier_surface

import pipelines as api
from pipelines.cli.app import main

ROOT = Path(__file__).resolve().parents[1]
DX = "5e-5"
V = "1e-3:10:5"
#: keys that name the run's own paths, or its timings
PATHS = {"scan", "source", "out", "seconds"}


@pytest.fixture(scope="module")
def scan(tmp_path_factory):
    h = fourier_surface(96, 5e-5, 0.8, 2e-4, seed=3)
    h[10:12, 20:23] = np.nan
    p = tmp_path_factory.mktemp("scan") / "s.npy"
    np.save(p, h)
    return p


def _cli(argv):
    assert main([str(a) for a in argv]) == 0, argv


def _aside(d):
    """``d`` without its paths and timings, at every level."""
    if isinstance(d, dict):
        return {k: _aside(v) for k, v in d.items() if k not in PATHS}
    if isinstance(d, list):
        return [_aside(v) for v in d]
    return d


def _json(path):
    return _aside(json.loads(Path(path).read_text()))


def _names(folder):
    return sorted(p.name for p in Path(folder).iterdir())


def _plain(d):
    """The dict as its JSON file holds it."""
    return json.loads(json.dumps(d, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o)))


def _json_of(d):
    """The returned dict without its paths and timings, as its JSON file holds it."""
    return _aside(_plain(d))


def test_dry_vs_wet_api_equals_cli(scan, tmp_path):
    _cli(
        [
            "dry-vs-wet",
            scan,
            "--spacing",
            DX,
            "--connectivity",
            "8",
            "--nu",
            "0.45",
            "--velocities",
            V,
            "--out",
            tmp_path / "cli",
        ]
    )
    r = api.dry_vs_wet(scan, tmp_path / "api", spacing=DX, connectivity=8, nu=0.45, velocities=V)
    cli = _json(tmp_path / "cli" / "comparison.json")
    assert _json(tmp_path / "api" / "comparison.json") == cli
    assert _json_of(r) == cli
    assert _names(tmp_path / "api") == _names(tmp_path / "cli")
    assert cli["connectivity"] == 8
    r3 = api.dry_vs_wet(scan, tmp_path / "nu3", spacing=DX, connectivity=8, nu=0.3, velocities=V)
    assert r3["mu_dry"] != r["mu_dry"]  # the flag reaches the friction
    with pytest.raises(TypeError, match="colour"):
        api.dry_vs_wet(scan, tmp_path / "x", spacing=DX, colour="red")
    from roadscan.errors import InputError

    with pytest.raises(InputError, match=r"max-depth|max_depth"):
        api.dry_vs_wet(scan, tmp_path / "x", spacing=DX, max_depth=-1)
    assert not (tmp_path / "x").exists()


def test_rain_fill_api_equals_cli(scan, tmp_path):
    _cli(
        ["rain-fill", scan, "--spacing", DX, "--water-film", "2e-5", "--no-level", "--out", tmp_path / "cli"]
    )
    r = api.rain_fill(scan, tmp_path / "api", spacing=DX, water_film=2e-5, no_level=True)
    cli = _json(tmp_path / "cli" / "rainfill.json")
    assert _json(tmp_path / "api" / "rainfill.json") == cli == _json_of(r)
    assert _names(tmp_path / "api") == _names(tmp_path / "cli")
    assert cli["levelled"] is False and cli["water_film_m"] == 2e-5
    r8 = api.rain_fill(scan, tmp_path / "c8", spacing=DX, connectivity=8)
    r4 = api.rain_fill(scan, tmp_path / "c4", spacing=DX)
    assert r8["connectivity"] == 8 and r8["water_volume_m3_per_m2"] < r4["water_volume_m3_per_m2"]
    with pytest.raises(TypeError, match="depth"):
        api.rain_fill(scan, tmp_path / "x", spacing=DX, depth=1e-4)


SELF_AFFINE = "H=0.8,h0=2e-4,q0=2e3,q1=1e6"


def test_friction_api_equals_cli(tmp_path):
    psd = ROOT / "sample_scans" / "asphalt_psd.csv"
    (tmp_path / "cli").mkdir()
    _cli(
        [
            "friction",
            "--psd",
            psd,
            "--nu",
            "0.45",
            "--sigma0",
            "0.3MPa",
            "--velocities",
            V,
            "--out",
            tmp_path / "cli" / "mu.csv",
        ]
    )
    r = api.friction(tmp_path / "api" / "mu.csv", psd=psd, nu=0.45, sigma0="0.3MPa", velocities=V)
    cli = _json(tmp_path / "cli" / "mu_summary.json")
    api_json = _json(tmp_path / "api" / "mu_summary.json")
    # a warning names the file it is about: the two runs wrote to two folders
    api_json["warnings"] = [
        w.replace(str(tmp_path / "api"), str(tmp_path / "cli")) for w in api_json["warnings"]
    ]
    assert api_json == cli
    assert _json(tmp_path / "api" / "mu_summary.json") == _json_of(r)
    assert _names(tmp_path / "api") == _names(tmp_path / "cli") == ["mu.csv", "mu.png", "mu_summary.json"]
    assert cli["nu"] == 0.45 and cli["sigma0_Pa"] == 3e5
    a = api.friction(tmp_path / "a.csv", self_affine=SELF_AFFINE, nu=0.45, velocities=V)
    b = api.friction(tmp_path / "b.csv", self_affine=SELF_AFFINE, nu=0.3, velocities=V)
    assert a["mu_peak"] != b["mu_peak"]
    with pytest.raises(TypeError, match="poisson"):
        api.friction(tmp_path / "c.csv", self_affine=SELF_AFFINE, poisson=0.4)
    from roadscan.errors import InputError

    with pytest.raises(InputError):
        api.friction(tmp_path / "c.csv", self_affine=SELF_AFFINE, psd=psd)  # one of the two
    with pytest.raises(InputError, match="nu"):
        api.friction(tmp_path / "c.csv", self_affine=SELF_AFFINE, nu=0.7)


def test_combine_api_equals_cli(tmp_path):
    from roadscan.synth_measure import measure_synthetic

    lines = ["file,spacing_m,label"]
    for i, (a, noise) in enumerate(((50e-6, 1e-5), (3e-6, 2e-8))):
        hm = measure_synthetic(128, a, 0.8, 1e-3, resolution_m=2 * a, noise_rms_m=noise, seed=10 + i, pad=3)
        np.save(tmp_path / f"i{i}.npy", hm.heights_m)
        lines.append(f"i{i}.npy,{a!r},instrument {i}")
    ins = [tmp_path / "m.csv"]
    ins[0].write_text("\n".join(lines) + "\n")
    _cli(["combine", *ins, "--resolution", "1e-5", "--no-figures", "--out", tmp_path / "cli"])
    r = api.combine(ins, tmp_path / "api", resolution=1e-5, no_figures=True)
    cli = _json(tmp_path / "cli" / "combine.json")
    assert _json(tmp_path / "api" / "combine.json") == cli == _json_of(r)
    assert _names(tmp_path / "api") == _names(tmp_path / "cli") == ["combine.json", "psd.csv", "report.html"]
    fine = api.combine(ins, tmp_path / "r", resolution=5e-6, no_figures=True)
    assert fine["merged_band_per_m"] != r["merged_band_per_m"]  # the flag reaches the band
    with pytest.raises(TypeError, match="figures"):
        api.combine(ins, tmp_path / "x", figures=False)


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    from pipelines.diagnosis.cases import make_case
    from pipelines.diagnosis.inputs import write_psd_csv
    from pipelines.output.report import write_csv

    d = tmp_path_factory.mktemp("measured")
    c = make_case(11, "temperature_offset", scan=False)
    q = np.geomspace(c.psd.q_min_per_m, c.psd.q1_per_m, 60)
    psd = write_psd_csv(d / "psd.csv", q, c.psd.C(q))
    # 8 of the case's speeds, spread over its span: the checks (API = CLI, a flag reaches the
    # model, bad arguments refused) do not depend on the count, the run time does
    keep = np.unique(np.linspace(0, c.curve.v_m_per_s.size - 1, 8).round().astype(int))
    mu = write_csv(d / "mu.csv", ["v_m_per_s", "mu"], [c.curve.v_m_per_s[keep], c.curve.mu[keep]])
    return mu, psd


def test_diagnose_api_equals_cli(measured, tmp_path):
    mu, psd = measured
    _cli(
        [
            "diagnose",
            "--measured",
            mu,
            "--psd",
            psd,
            "--nu",
            "0.45",
            "--noise",
            "0.02",
            "--uncertain",
            "q1=known",
            "--out",
            tmp_path / "cli",
        ]
    )  # q1 known: fewer candidates
    r = api.diagnose(tmp_path / "api", measured=mu, psd=psd, nu=0.45, noise=0.02, uncertain="q1=known")
    cli = _json(tmp_path / "cli" / "diagnosis.json")
    assert _json(tmp_path / "api" / "diagnosis.json") == cli == _json_of(r)
    assert _names(tmp_path / "api") == _names(tmp_path / "cli") == ["diagnosis.json", "report.html"]
    assert cli["engine_settings"]["nu"] == 0.45 and cli["noise"] == 0.02
    r3 = api.diagnose(tmp_path / "nu3", measured=mu, psd=psd, nu=0.3, noise=0.02, uncertain="q1=known")
    assert r3["baseline_gap"] != r["baseline_gap"]  # the flag reaches the model
    with pytest.raises(TypeError, match="measure"):
        api.diagnose(tmp_path / "x", measure=mu, psd=psd)
    from roadscan.errors import InputError

    with pytest.raises(InputError, match="noise"):
        api.diagnose(tmp_path / "x", measured=mu, psd=psd, noise=-1)
