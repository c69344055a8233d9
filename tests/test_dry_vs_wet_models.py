"""``roadscan dry-vs-wet --wet-model persson|fill`` (issue 35): the fill model is the thesis's
as it was, the persson model writes the contract keys, the flags reach the model, and every
warning is in comparison.json and the report."""

from __future__ import annotations

import html
import importlib.util
import json
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from conftest import fourier_surface

from friction.wet.water import DEFAULT_SOURCES
from pipelines.cli.app import main
from roadscan import RoadscanWarning
from roadscan.heightmap import HeightMap

ROOT = Path(__file__).resolve().parents[1]
V = "1e-3,1e-1,5.556,11.11,27.78"  # 20, 40 and 100 km/h among them
#: the last commit before the persson model was wired in (the move of pipelines/ alone)
BEFORE_WIRING = "4c5eaac"
CONTRACT = (
    "wet_model",
    "film_m",
    "mechanisms",
    "speed_constant_model_kmh",
    "mpd_m",
    "ifi_speed_constant_kmh",
    "contact_lost_v_m_per_s",
)


@pytest.fixture(scope="module")
def long_scan(tmp_path_factory):
    """Rows of 102.4 mm (an ISO 13473-1 MPD exists), 48 of them: asphalt-like, 0.3 mm rms."""
    h = fourier_surface(1024, 1e-4, 0.8, 3e-4, seed=5, q_roll=2 * np.pi / 8e-3)[:48]
    path = tmp_path_factory.mktemp("wet") / "road.npy"
    np.save(path, h)
    return path


def _run(scan, out, *flags):
    assert (
        main(["dry-vs-wet", str(scan), "--spacing", "1e-4", "--out", str(out), "--velocities", V, *flags])
        == 0
    )
    return json.loads((out / "comparison.json").read_text())


@pytest.fixture(scope="module")
def persson(long_scan, tmp_path_factory):
    out = tmp_path_factory.mktemp("p") / "out"
    return _run(long_scan, out), out


@pytest.fixture(scope="module")
def fill(long_scan, tmp_path_factory):
    out = tmp_path_factory.mktemp("f") / "out"
    return _run(long_scan, out, "--wet-model", "fill"), out


def _old_module():
    """The dry-vs-wet job of commit BEFORE_WIRING, from git (skip without the history)."""
    try:
        src = subprocess.run(
            ["git", "show", f"{BEFORE_WIRING}:pipelines/jobs/dry_vs_wet.py"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
            timeout=30,
        ).stdout
    except (OSError, subprocess.SubprocessError):
        pytest.skip("no git history to read the code before the persson model")
    spec = importlib.util.spec_from_loader("old_dry_vs_wet", loader=None)
    mod = importlib.util.module_from_spec(spec)
    exec(compile(src, "old_dry_vs_wet.py", "exec"), mod.__dict__)
    sys.modules.pop("old_dry_vs_wet", None)
    return mod


def test_fill_reproduces_the_thesis_model_as_it_was(tmp_path):
    # the same scan through the code before the wiring and through --wet-model fill: every key
    # the old comparison.json had keeps its value (wet_model keeps its keys, gains name and
    # parameters), and the files are the same
    from pipelines.checks.validate import collecting
    from pipelines.jobs.dry_vs_wet import run_dry_vs_wet
    from pipelines.settings.friction import FrictionSettings

    old = _old_module()
    scan = HeightMap(fourier_surface(128, 5e-5, 0.8, 2e-4, seed=11), 5e-5, 5e-5, name="s")
    settings = FrictionSettings(v_m_per_s=np.array([1e-3, 1e-1, 10.0]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with collecting():
            a = old.run_dry_vs_wet(scan, tmp_path / "old", settings)
        with collecting():
            b = run_dry_vs_wet(scan, tmp_path / "new", settings, wet_model="fill")
    a, b = (json.loads((tmp_path / d / "comparison.json").read_text()) for d in ("old", "new"))
    assert a["mu_wet"] and a["mu_wet"] != a["mu_dry"]  # a run with friction to compare
    for key, value in a.items():
        if key == "wet_model":
            assert {k: b[key][k] for k in value} == value
            assert b[key]["name"] == "fill"
        else:
            assert b[key] == value, key
    for f in ("mu.csv", "wet.npy"):
        assert (tmp_path / "old" / f).read_bytes() == (tmp_path / "new" / f).read_bytes(), f


def test_fill_is_friction_on_the_rain_filled_map(fill, long_scan):
    # independent of history: the thesis's definition composed from the chain's steps
    from pipelines.chain.steps import measure, scan_friction
    from pipelines.chain.surface import analyse_surface
    from pipelines.settings.friction import FrictionSettings
    from roadscan.level import level
    from roadscan.rain import rain_fill

    c, _ = fill
    dry = level(HeightMap(np.load(long_scan), 1e-4, 1e-4, name="road"), degree=1)
    v = np.array([float(s) for s in c["mu_dry"]])
    st = FrictionSettings(v_m_per_s=v)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        an, rb = measure(dry)
        od = scan_friction(an, rb, st)
        ow = scan_friction(analyse_surface(rain_fill(dry).wet), rb, st, fit=an.fit, v_m_per_s=v)
    assert np.allclose(list(c["mu_dry"].values()), od.result.mu, rtol=1e-12)
    assert np.allclose(list(c["mu_wet"].values()), ow.result.mu, rtol=1e-12)


@pytest.mark.parametrize("model", ["persson", "fill"])
def test_contract_keys(model, persson, fill):
    c, _ = persson if model == "persson" else fill
    for key in CONTRACT:
        assert key in c, key
    wm = c["wet_model"]
    assert wm["name"] == model and isinstance(wm["parameters"], dict)
    speeds = set(c["mu_wet"])
    # MPD: ISO 13473-1 on 102.4 mm rows; ASTM E1960's Sp from it
    assert 1e-5 < c["mpd_m"] < 3e-3
    assert c["ifi_speed_constant_kmh"] == pytest.approx(14.2 + 89.7 * c["mpd_m"] * 1e3, rel=1e-12)
    sp = c["speed_constant_model_kmh"]
    assert sp is None or sp > 0
    if model == "fill":
        assert c["film_m"] is None and c["mechanisms"] is None and c["contact_lost_v_m_per_s"] is None
        assert wm["parameters"]["connectivity"] == 4
        return
    assert set(c["film_m"]) == speeds
    assert all(x is not None and x >= 0 for x in c["film_m"].values())
    assert set(c["mechanisms"]) == {"sealing", "squeeze_out", "adhesion"}
    for s in speeds:
        shares = [c["mechanisms"][k][s] for k in ("sealing", "squeeze_out", "adhesion")]
        loss = c["mu_dry"][s] - c["mu_wet"][s]
        if loss > 1e-12 * c["mu_dry"][s]:  # shares of a positive loss add up to it
            assert sum(shares) == pytest.approx(1.0, abs=1e-6), s
        else:
            assert shares == [None, None, None], s
    assert set(c["dynamic_lift_share"]) == speeds  # Horne & Dreher's inertia
    assert all(0 <= x <= 1 for x in c["dynamic_lift_share"].values())
    v_lost = c["contact_lost_v_m_per_s"]
    assert v_lost is None or f"{v_lost:g}" in speeds
    for k, (value, _) in DEFAULT_SOURCES.items():
        assert wm["parameters"][k] == value and wm["sources"][k]  # defaults with sources
    assert wm["given"] == [] and "left out" in wm["adhesion"]


def test_flags_reach_the_model(long_scan, tmp_path, persson):
    c = _run(
        long_scan,
        tmp_path / "o",
        "--water-depth",
        "2e-3",
        "--water-temperature",
        "5",
        "--footprint",
        "0.1",
        "--block-size",
        "0.02",
        "--shear-stress",
        "2e6",
    )
    p = c["wet_model"]["parameters"]
    assert (
        p["water_depth_m"],
        p["water_temperature_C"],
        p["footprint_m"],
        p["block_size_m"],
        p["shear_stress_Pa"],
    ) == (2e-3, 5.0, 0.1, 0.02, 2e6)
    assert p["water_viscosity_Pa_s"] > 1.4e-3  # colder water is more viscous
    assert set(c["wet_model"]["given"]) == {
        "water_depth_m",
        "water_temperature_C",
        "footprint_m",
        "block_size_m",
        "shear_stress_Pa",
    }
    # tau_f adds the adhesive term to dry friction, and water removes some of it
    base = persson[0]
    assert all(c["mu_dry"][s] > base["mu_dry"][s] for s in base["mu_dry"])
    assert any((c["mechanisms"]["adhesion"][s] or 0) > 0 for s in c["mu_dry"])


def test_fill_says_it_ignores_the_persson_flags(tmp_path):
    import pipelines

    scan = HeightMap(fourier_surface(64, 1e-4, 0.8, 2e-4, seed=3), 1e-4, 1e-4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = pipelines.dry_vs_wet(scan, tmp_path / "o", wet_model="fill", water_depth=1e-3, no_friction=True)
    assert any("--water-depth" in w and "ignores" in w for w in r["warnings"])


def test_a_wrong_wet_flag_is_refused_in_one_line(long_scan, tmp_path, capsys):
    rc = main(
        [
            "dry-vs-wet",
            str(long_scan),
            "--spacing",
            "1e-4",
            "--out",
            str(tmp_path / "o"),
            "--water-temperature",
            "120",
        ]
    )
    err = capsys.readouterr().err
    assert rc == 2 and "--water-temperature" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("model", ["persson", "fill"])
def test_report_says_what_the_issue_asks(model, persson, fill):
    c, out = persson if model == "persson" else fill
    text = html.unescape((out / "report.html").read_text())
    for w in c["warnings"]:  # every warning on the page too
        assert " ".join(w.split()) in " ".join(text.split()), w
    assert "IFI" in text and "14.2 + 89.7 MPD" in text
    assert "Parameters, defaults and sources" in text
    assert text.count("data:image/png;base64") >= 4
    if model == "persson":
        for phrase in (
            "contact lost",
            "isothermal",
            "ASTM E274",
            "Gent & Walter",
            "Dapp et al.",
            "Which friction model",
            "squeeze-out",
            "adhesion left out",
        ):
            assert phrase in text, phrase
        assert (out / "film_left.png").exists() and (out / "mu_mechanisms.png").exists()
    else:
        assert "rain-filled" in text and not (out / "film_left.png").exists()


def test_every_warning_lands_in_comparison_json(tmp_path):
    # a 64^2 scan at 0.1 mm: its reliable band is narrow, so the chain warns
    import pipelines

    scan = HeightMap(fourier_surface(64, 1e-4, 0.8, 2e-4, seed=3), 1e-4, 1e-4)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = pipelines.dry_vs_wet(scan, tmp_path / "o", velocities="1e-3,1,10")
    said = {" ".join(str(w.message).split()) for w in caught if issubclass(w.category, RoadscanWarning)}
    assert said and said <= set(r["warnings"])
    assert json.loads((tmp_path / "o" / "comparison.json").read_text())["warnings"] == r["warnings"]
