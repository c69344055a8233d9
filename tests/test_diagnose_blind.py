"""Blind check of ``roadscan diagnose`` (issue 5) with cases made independently of the diagnosis.

The cases come from ``benchmarks/bench_diagnose_blind.py`` (its own effect implementations on the
friction engine's public API; ``pipelines/diagnose`` is not imported). The diagnosis is run as a
subprocess and only ``diagnosis.json`` is read. All diagnoses of this file run once, two at a
time, in a module fixture.

The cases kept here are a few representatives: one per effect kind the assertions need, one null
and the input-handling cases. Accuracy over whole seeded sets (the issue's >= 90 % named right,
null false positives, every effect kind) is the job of ``benchmarks/bench_diagnose_blind.py``
(friction level, ``--level friction``; surface level, ``--level surface``), not of this test.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from numbers import Real
from pathlib import Path

import numpy as np
import pytest

import friction as F

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location(
    "bench_diagnose_blind", ROOT / "benchmarks" / "bench_diagnose_blind.py"
)
B = importlib.util.module_from_spec(_spec)
sys.modules.setdefault("bench_diagnose_blind", B)
_spec.loader.exec_module(B)

# a temperature offset (dT = -21.4 C, speeds 3.8e-3..26 m/s, psd.csv) on which the diagnosis
# crashed with a traceback (exit 1: its flash fit's mu_flash did not converge) when written; it
# passes the benchmark's identifiability filter, so it is also this file's temperature-offset case
CRASH_CASE = (1011, "temperature_offset")
# seeded effect cases (psd.csv surfaces, default speed draw); chosen as the first seeds whose case
# passes the benchmark's own identifiability filter, never by the diagnosis' answer. Three kinds:
# the temperature offset (the contract test's case), adhesion (the --noise test's case) and the
# contact correction; fine roughness, relaxation spectrum and flash temperature are named in
# tests/test_diagnose.py::test_proof_small_blind_cases_meet_the_goals; load, water and every
# kind over whole seed sets in benchmarks/bench_diagnose_blind.py.
ACCURACY_CASES = [
    CRASH_CASE,
    (12, "adhesion"),
    (14, "contact_correction"),
]
# one null case, a psd.csv one (seed 23: of the former three nulls 21, 22 and 23 the shortest
# run; the scan null 22 took three times as long, and friction-level diagnoses from a scan are
# run by test_diagnose_scan_read.py and test_diagnose_band_end.py); null false-positive rates
# are the benchmark's
NULL_SEEDS = [23]


def _cli(args):
    return subprocess.run(
        [sys.executable, "-m", "pipelines.cli", "diagnose", *args], capture_output=True, text=True, cwd=ROOT
    )


def _diag(args, out):
    pr = _cli([*args, "--out", str(out)])
    assert pr.returncode == 0, pr.stderr[-2000:]
    return json.loads((Path(out) / "diagnosis.json").read_text())


def _first_identifiable(seed, effect, tmp):
    """First seed from ``seed`` upwards whose case is strong and unambiguous (own filter)."""
    for s in range(seed, seed + 40 * 1000, 1000):
        c = B.make_case(s, effect, tmp / f"{effect}_{s}", kind="psd")
        if c.strong and c.unambiguous:
            return c
    raise AssertionError(f"no identifiable {effect} case found")


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("blind")
    jobs = {}
    cases = {}
    # accuracy cases (with a validation measurement at another temperature or load)
    for seed, eff in ACCURACY_CASES:
        c = _first_identifiable(seed, eff, tmp)
        cases[eff] = c
        jobs[eff] = lambda c=c: B.run_diagnose(c)[0]
    # the crash case is the temperature-offset case (run with its validation measurement)
    cases["crash"] = cases[CRASH_CASE[1]]
    for s in NULL_SEEDS:
        c = B.make_case(s, None, tmp / f"null_{s}", kind="psd" if s % 2 else "scan", small=True)
        cases[f"null{s}"] = c
        jobs[f"null{s}"] = lambda c=c: B.run_diagnose(c)[0]
    # --noise given: a large value must silence the strongest effect case
    c = cases["adhesion"]
    jobs["noise_big"] = lambda c=c: B.run_diagnose(
        c, extra=["--noise", "5.0"], validate=False, out_name="out_noise"
    )[0]
    # column precedence: truth at T0 = 75 C and sigma0 = 2 MPa, noise 2 %
    rng = np.random.default_rng(7)
    d = tmp / "precedence"
    d.mkdir()
    surf = B._psd_surface(rng, d)
    v = np.logspace(-4, 1, 30)
    rub = F.thesis_rubber()
    noise = np.exp(0.02 * rng.standard_normal(v.size))
    mu_T = F.mu_isothermal(surf.psd, rub, v, T0_C=75.0).mu * noise
    mu_S = F.mu_isothermal(surf.psd, rub, v, sigma0_Pa=2e6).mu * noise
    B.write_mu_csv(d / "T_col.csv", v, mu_T, T0_C=75.0)
    B.write_mu_csv(d / "T_nocol.csv", v, mu_T)
    B.write_mu_csv(d / "S_col.csv", v, mu_S, sigma0_Pa=2e6)
    B.write_mu_csv(d / "S_nocol.csv", v, mu_S)
    psd = ["--psd", str(d / "psd.csv")]
    for name, extra in {
        "T_col": ["--temperature", "60"],
        "T_nocol": ["--temperature", "60"],
        "T_flag": ["--temperature", "75"],
        "S_col": ["--sigma0", "2e5"],
        "S_nocol": ["--sigma0", "2e5"],
    }.items():
        csv = d / (name.replace("_flag", "_nocol") + ".csv")
        jobs[name] = lambda csv=csv, extra=extra, name=name: _diag(
            ["--measured", str(csv), *psd, *extra], d / f"out_{name}"
        )
    with ThreadPoolExecutor(max_workers=2) as ex:
        futs = {k: ex.submit(f) for k, f in jobs.items()}
        res = {k: f.result() for k, f in futs.items()}
    res["crash"] = res[CRASH_CASE[1]]
    res["_cases"] = cases
    res["_tmp"] = tmp
    return res


def _is_num(x):
    return isinstance(x, Real) and not isinstance(x, bool) and np.isfinite(x)


def test_contract_keys_and_types(runs):
    c = runs["_cases"]["temperature_offset"]
    diag = runs["temperature_offset"]
    assert "error" not in diag, diag
    for k in ("level", "baseline_gap", "noise", "where", "effects", "verdict"):
        assert k in diag, k
    assert diag["level"] == "friction"
    assert _is_num(diag["baseline_gap"]) and _is_num(diag["noise"]) and diag["noise"] > 0
    # the baseline gap is the rms of log10(real / sim): the case's own value, within the noise
    own = B._rms(np.log10(c.mu_meas / c.mu_model))
    assert abs(diag["baseline_gap"] - own) < 0.02 * own + 1e-3
    assert isinstance(diag["where"], list) and diag["where"]
    for w in diag["where"]:
        assert _is_num(w["v_min_m_per_s"]) and _is_num(w["v_max_m_per_s"]) and _is_num(w["gap"])
        assert w["v_min_m_per_s"] <= w["v_max_m_per_s"]
        # bands may be fixed bins: each must overlap the measured speeds
        assert w["v_max_m_per_s"] >= c.v[0] * 0.999 and w["v_min_m_per_s"] <= c.v[-1] * 1.001
    covered = [(w["v_min_m_per_s"], w["v_max_m_per_s"]) for w in diag["where"]]
    assert min(a for a, _ in covered) <= c.v[0] * 1.001 and max(b for _, b in covered) >= c.v[-1] * 0.999
    assert isinstance(diag["effects"], list) and diag["effects"]
    for e in diag["effects"]:
        assert isinstance(e["name"], str) and isinstance(e["params"], dict)
        for k in ("gap_train", "gap_heldout", "shrink"):
            assert _is_num(e[k]), (e["name"], k)
        assert 0 < len(e["name"].split("+")) <= 2
        # an effect fitted with the calibrated inputs keeps the effect's name (issue 19)
        assert set(e["name"].split("+")) <= set(B.EFFECTS), e["name"]
    heldout = [e["gap_heldout"] for e in diag["effects"]]
    ver = diag["verdict"]
    for k in ("effect", "shrink", "gap_validate"):
        assert k in ver
    eff = ver["effect"]
    assert isinstance(eff, str) or (
        isinstance(eff, list) and len(eff) == 2 and all(isinstance(n, str) for n in eff)
    )
    name = eff if isinstance(eff, str) else "+".join(eff)
    names = [e["name"] for e in diag["effects"]]
    assert name in names or "+".join(reversed(eff)) in names
    assert _is_num(ver["shrink"]) and _is_num(ver["gap_validate"])
    # shrink = 1 - gap_after / gap_before on held-out points: consistent with its entry
    entry = diag["effects"][names.index(name) if name in names else names.index("+".join(reversed(eff)))]
    assert abs(entry["shrink"] - ver["shrink"]) < 1e-6
    assert entry["gap_heldout"] <= min(heldout) * 1.5 + 1e-9
    assert (c.dir / "out" / "report.html").is_file()


def test_accuracy_on_seeded_blind_cases(runs):
    """Each kept case is named right (strictly: the hidden effect alone). A fraction over three
    cases says nothing of the issue's 90 % goal, which benchmarks/bench_diagnose_blind.py
    measures over whole seed sets; so every case kept here must be right."""
    hits_strict, hits_lenient, lines = 0, 0, []
    for _, eff in ACCURACY_CASES:
        diag = runs[eff]
        strict, lenient, called = B.score(runs["_cases"][eff], diag)
        hits_strict += strict
        hits_lenient += lenient
        lines.append(f"{eff} -> {called}")
    # when written, contact_correction with gamma = 0.26 (below the fit's range then) and a
    # bell-shaped adhesion were missed; since the fixes both are hit
    n = len(ACCURACY_CASES)
    assert hits_lenient == n, lines
    assert hits_strict == n, lines


def test_shrink_and_validate_when_right(runs):
    shrinks = []
    for _, eff in ACCURACY_CASES:
        diag, c = runs[eff], runs["_cases"][eff]
        if eff not in B.verdict_names(diag):
            continue
        shrinks.append(diag["verdict"]["shrink"])
        gv = diag["verdict"]["gap_validate"]
        assert gv is not None
        # the other temperature/load is predicted much better than by the plain model
        assert gv < 0.5 * c.validate["model_gap"] + 2 * c.noise_log10, (eff, gv, c.validate)
    assert len(shrinks) >= 3
    assert np.median(shrinks) >= 0.7, shrinks


def test_null_cases_name_no_effect(runs):
    """The kept null case names no effect (the false-positive rate over many nulls is
    benchmarks/bench_diagnose_blind.py's)."""
    # "calibration" and inconclusive are not named effects (issue 19)
    fps = [k for k in runs if k.startswith("null") and B.named(B._label(runs[k], B.verdict_names(runs[k])))]
    assert not fps, [(k, runs[k]["verdict"]) for k in fps]
    for s in NULL_SEEDS:
        d = runs[f"null{s}"]
        assert d["verdict"]["effect"] in (None, "calibration")
        if d["verdict"]["effect"] is None:
            assert d["verdict"]["gap_validate"] is None


def test_noise_flag_is_used(runs):
    d = runs["noise_big"]
    assert abs(d["noise"] - 5.0) < 1e-9
    assert d["verdict"]["effect"] is None  # every gap is far inside a noise of 5 decades
    assert runs["adhesion"]["verdict"]["effect"] is not None


def test_csv_columns_take_precedence(runs):
    # truth at 75 C: the T0_C column makes the model right although the flag says 60 C
    assert runs["T_col"]["verdict"]["effect"] is None
    assert runs["T_flag"]["verdict"]["effect"] is None
    assert runs["T_col"]["baseline_gap"] < 0.3 * runs["T_nocol"]["baseline_gap"]
    assert runs["T_nocol"]["verdict"]["effect"] is not None
    # truth at 2 MPa: the sigma0_Pa column beats --sigma0 2e5
    assert runs["S_col"]["baseline_gap"] < 0.6 * runs["S_nocol"]["baseline_gap"]
    assert runs["S_col"]["verdict"]["effect"] is None


@pytest.mark.parametrize(
    "content,extra",
    [
        ("speed,mu\n1e-3,0.1\n1e-2,0.2\n", []),  # wrong header
        ("v_m_per_s,mu\n1e-3,0.1\n-1e-2,0.2\n1e-1,0.3\n", []),  # negative speed
        ("v_m_per_s,mu\n1e-3,abc\n1e-2,0.2\n", []),  # not a number
        ("v_m_per_s,mu\n1e-3,0.1\n1e-2,0.2\n1e-1,0.3\n", ["--missing-psd"]),  # psd file missing
    ],
)
def test_bad_input_exit_2_one_line(tmp_path, content, extra):
    q = np.logspace(3, 5, 30)
    np.savetxt(
        tmp_path / "psd.csv",
        np.column_stack([q, 1e-20 * (q / 1e3) ** -3.6]),
        delimiter=",",
        header="q_per_m,C_m4",
        comments="",
    )
    (tmp_path / "mu.csv").write_text(content)
    psd = tmp_path / ("nope.csv" if extra == ["--missing-psd"] else "psd.csv")
    pr = _cli(["--measured", str(tmp_path / "mu.csv"), "--psd", str(psd), "--out", str(tmp_path / "out")])
    assert pr.returncode == 2, (pr.returncode, pr.stderr)
    lines = [ln for ln in pr.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, pr.stderr
    assert "Traceback" not in pr.stderr


def test_no_crash_on_fast_cold_temperature_offset(runs):
    c, diag = runs["_cases"]["crash"], runs["crash"]
    assert c.strong and c.unambiguous
    assert "error" not in diag, diag["error"][-300:]
    assert "temperature_offset" in B.verdict_names(diag)


# ----------------------------------------------------------------------------- surface level (issue 11)
# the benchmark's own surface generator (roadscan.synth + scipy only), run through the CLI; the
# first seed of each kind in the benchmark's seed order from --seed 500 (rolloff left out: its
# weakest cases are the benchmark's business, not a test's). height_skew 517 is the log-normal
# variant and is named by the whole-scan height law, seams 534 a 4 x 4 stitching.
SURFACE_CASES = [("anisotropy", 500), ("height_skew", 517), ("seams", 534), ("noise_floor", 568), (None, 585)]


@pytest.fixture(scope="module")
def surface_runs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("blind_surface")
    with ThreadPoolExecutor(max_workers=2) as ex:
        rows = list(ex.map(lambda ks: B.run_surface_case(ks[0], ks[1], tmp), SURFACE_CASES))
    return rows, tmp


def test_surface_blind_cases_and_contract(surface_runs):
    rows, tmp = surface_runs
    for r in rows:
        assert "error" not in r, r
        assert r["right"], r
    d = json.loads((tmp / "surface_500_anisotropy" / "out" / "diagnosis.json").read_text())
    assert d["level"] == "surface" and d["verdict"]["effect"] == "anisotropy"
    for k in ("families", "at_bound", "inconclusive"):
        assert k in d
    fam = d["families"]
    assert {"spectrum", "height", "anisotropy", "seams", "rain"} <= set(fam)
    for f in fam.values():
        assert _is_num(f["gap_baseline"]) and f["gap_baseline"] >= 0
    # the anisotropy family carries the gap and the verdict closes it
    assert fam["anisotropy"]["gap_baseline"] == max(x["gap_baseline"] for x in fam.values())
    assert fam["anisotropy"]["gap_after"] < 0.3 * fam["anisotropy"]["gap_baseline"]
    lo, hi = d["verdict"]["shrink_interval"]
    assert 0.5 <= lo <= d["verdict"]["shrink"] <= hi <= 1.0
    null = json.loads((tmp / "surface_585_null" / "out" / "diagnosis.json").read_text())
    assert null["verdict"]["effect"] is None and null["verdict"]["inconclusive"] == []
    # every verdict says where its evidence comes from; the whole-scan checks are in the JSON
    for name in ("surface_517_height_skew", "surface_534_seams"):
        d = json.loads((tmp / name / "out" / "diagnosis.json").read_text())
        assert d["verdict"]["evidence"] and d["verdict"]["shrink"] >= 0.4
        for k in ("whole_spectrum", "whole_height", "whole_seams"):
            assert isinstance(d[k], dict) and "significant" in d[k]
