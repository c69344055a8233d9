"""Issue 19: honest cross-validation, physical plausibility, uncertain inputs, provenance and
several measurements at once (pipelines/diagnose)."""

from __future__ import annotations

import hashlib
import json

import numpy as np
import pytest

import friction
from pipelines.cli.app import main as cli
from pipelines.diagnosis.effects import Effect, Param, get
from pipelines.diagnosis.fit import cv as cvmod
from pipelines.diagnosis.fit.calibration import calibration_effect, parse_uncertain
from pipelines.diagnosis.fit.fitting import Candidate, too_many_parameters
from pipelines.diagnosis.inputs import build_context, write_psd_csv
from pipelines.diagnosis.measured import MeasuredCurve
from pipelines.diagnosis.model import simulate
from pipelines.diagnosis.verdict.many import decide
from pipelines.diagnosis.verdict.search import diagnose_friction
from pipelines.output.report import write_csv
from roadscan.errors import InputError

PSD = friction.SelfAffinePSD(0.8, 5e-4, 2000.0, 2e5)


def _curve(v, mu=None, T=np.nan):
    n = v.size
    return MeasuredCurve(
        v, np.ones(n) if mu is None else mu, np.full(n, T), np.full(n, 2e5), np.zeros(n, bool), False, "t"
    )


# ----------------------------------------------------------------------------- cross-validation
def test_few_points_fit_every_model_and_charge_its_parameters_in_the_evidence():
    """Below 20 points no model is skipped for its number of parameters (the Bayesian evidence's
    Occam factor is the penalty); the held-out rule still refuses k > n_train / 2."""
    assert too_many_parameters(5, 4) and too_many_parameters(3, 5) and not too_many_parameters(2, 4)
    five = Effect(
        name="zz_five",
        level="friction",
        params=tuple(Param(f"p{i}", 0.5, 2.0, 1.0, "log") for i in range(5)),
        modify=lambda s, p, c: s.with_(sigma0_scale=s.sigma0_scale * p["p0"] * p["p1"] * p["p2"]),
        null=lambda c: {f"p{i}": 1.0 for i in range(5)},
    )
    v = np.logspace(-4, 0, 5)
    ctx = build_context(_curve(v), PSD)
    mu = simulate(ctx.base, ctx) * 1.5
    d = diagnose_friction(ctx, mu, noise=0.01, effects=[five, get("load")], default_q1=False)
    names = {c.name for c in d.candidates}
    assert {"zz_five", "load"} <= names
    assert not any("free parameters" in s["reason"] for s in d.skipped)
    ev = {m["name"]: m for m in d.verdict["evidence"]["models"]}
    assert ev["zz_five"]["log_occam"] < 0 and ev["load"]["log_occam"] < 0
    assert ev["zz_five"]["log_evidence"] == pytest.approx(
        ev["zz_five"]["log_likelihood"] + ev["zz_five"]["log_occam"]
    )


def test_few_points_are_never_scored_on_held_out_folds():
    """Below 20 points every point trains (no fold of four points carries a verdict)."""
    ho = cvmod.holdout(9)
    assert ho.cv and ho.train.all() and "evidence" in ho.description
    ho = cvmod.holdout(24)
    assert not ho.cv and ho.held.sum() == 8 and not (ho.train & ho.held).any()  # indices 1, 4, ..., 22
    with pytest.raises(ValueError):
        cvmod.evaluate(None, None, np.ones(9), cvmod.holdout(9), np.zeros(9))


def test_interval_below_minimum_shrink_gives_low_confidence():
    e = get("temperature_offset")
    rng = np.random.default_rng(3)
    r = rng.normal(0, 0.01, 30)

    def cand(shrink, lo):
        return Candidate(
            (e,),
            [{"dT_C": 5.0}],
            np.ones(30),
            0.01,
            0.01,
            0.01,
            shrink=shrink,
            score=0.01,
            r_held=r,
            shrink_interval=(lo, 0.9),
        )

    st = dict(g_all=0.1, g_ho=0.1, noise=0.01, n=30, significant=True, p=1e-9, boot=None)
    v, _best = decide([cand(0.6, 0.1)], [], None, [], st)
    assert v["effect"] == "temperature_offset" and v["confidence"] == "low"
    v, _ = decide([cand(0.6, 0.4)], [], None, [], st)
    assert v["confidence"] == "high"


def test_null_reason_names_the_best_heldout_shrink():
    e, a = get("load"), get("adhesion")
    r = np.full(10, 0.05)
    load = Candidate(
        (e,), [{"sigma0_scale": 1.0}], np.ones(10), 0.1, 0.1, 0.1, shrink=0.0, score=0.1, r_held=r
    )
    adh = Candidate(
        (a,),
        [{"amplitude": 0.1, "v_c_m_per_s": 1e-3, "exponent": 1.0, "rise_decades": 2.0}],
        np.ones(10),
        0.05,
        0.064,
        0.06,
        shrink=0.36,
        score=0.13,
        r_held=r,
    )
    st = dict(g_all=0.1, g_ho=0.1, noise=0.01, n=10, significant=True, p=1e-9, boot=None)
    v, best = decide([load, adh], [], None, [], st)
    assert best is None and v["effect"] is None
    assert "adhesion 36%" in v["reason"] and "tried 2 candidates" in v["reason"]


# ----------------------------------------------------------------------------- plausibility
def test_effects_flag_implausible_parameters():
    v = np.logspace(-4, 0, 6)
    ctx = build_context(_curve(v), PSD)
    mu = np.full(6, 0.8)
    flash = get("flash_temperature")
    assert [n for n, _ in flash.implausible(ctx, {"zeta_m": 3.0, "heat_scale": 0.05}, mu)] == ["heat_scale"]
    assert flash.implausible(ctx, {"zeta_m": 3.0, "heat_scale": 1.5}, mu) == []
    assert flash.implausible(ctx, {"zeta_m": 3.0, "heat_scale": 1e-3}, mu) == []  # the no-effect limit
    adh = get("adhesion")
    p = {"amplitude": 2.5, "v_c_m_per_s": 1e-3, "exponent": 1.0, "rise_decades": 2.0}
    assert [n for n, _ in adh.implausible(ctx, p, mu)] == ["amplitude"]
    assert adh.implausible(ctx, dict(p, amplitude=0.3), mu) == []
    # a temperature outside a shift table's range is flagged (extrapolated)
    rub = friction.StandardLinearSolid(
        shift=friction.ShiftTable(np.array([0.0, 40.0, 80.0]), np.array([2.0, 0.0, -2.0])), T_ref_C=40.0
    )
    ctx2 = build_context(_curve(v, T=60.0), PSD, rubber=rub)
    t = get("temperature_offset")
    assert [n for n, _ in t.implausible(ctx2, {"dT_C": 25.0}, mu)] == ["dT_C"]
    assert t.implausible(ctx2, {"dT_C": 10.0}, mu) == []


def test_an_implausible_fit_is_never_named():
    a = get("adhesion")
    r = np.random.default_rng(0).normal(0, 0.01, 20)
    c = Candidate(
        (a,),
        [{"amplitude": 2.5, "v_c_m_per_s": 1e-3, "exponent": 1.0, "rise_decades": 2.0}],
        np.ones(20),
        0.01,
        0.01,
        0.01,
        shrink=0.9,
        score=0.01,
        r_held=r,
        shrink_interval=(0.8, 0.95),
        implausible=["amplitude"],
        implausible_why=["amplitude 2.5 exceeds the largest measured mu"],
    )
    st = dict(g_all=0.1, g_ho=0.1, noise=0.01, n=20, significant=True, p=1e-9, boot=None)
    v, best = decide([c], [], None, [], st)
    assert best is None and v["effect"] is None and v["implausible"] == ["amplitude"]
    assert "not physical" in v["reason"]


# ----------------------------------------------------------------------------- uncertain inputs
def test_uncertain_parsing():
    u = parse_uncertain("q1=1e4:1e6, sigma0=0.15MPa:300kPa,psd_scale=0.5:2,temperature=10:30")
    assert (u["q1"].lo, u["q1"].hi) == (1e4, 1e6)
    assert (u["sigma0"].lo, u["sigma0"].hi) == (0.15e6, 0.3e6)
    assert (u["temperature"].lo, u["temperature"].hi) == (10.0, 30.0)
    assert parse_uncertain("q1=known")["q1"].source == "known"
    for bad in (
        "q1=3",
        "zz=1:2",
        "q1=5:1",
        "psd_scale=0:2",
        "q1=1:2,q1=1:3",
        "sigma0=0.3:1MPa",
        "temperature=a:3",
    ):
        with pytest.raises(InputError):
            parse_uncertain(bad)


@pytest.mark.parametrize("spec", ["q1=3", "zz=1:2", "sigma0=0.3MPa:0.1MPa", "psd_scale=-1:2"])
def test_uncertain_errors_exit_2_in_one_line(tmp_path, capsys, spec):
    v = np.logspace(-4, 0, 8)
    m = write_csv(tmp_path / "mu.csv", ["v_m_per_s", "mu"], [v, np.full(8, 0.5)])
    p = write_psd_csv(tmp_path / "psd.csv", np.logspace(3, 5, 30), PSD.C(np.logspace(3, 5, 30)))
    rc = cli(
        ["diagnose", "--measured", str(m), "--psd", str(p), "--uncertain", spec, "--out", str(tmp_path / "o")]
    )
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1 and "--uncertain" in err
    assert not (tmp_path / "o").exists()


def test_calibration_verdict_on_a_world_with_only_a_q1_offset():
    """A world whose only difference is q1 (2.5 x the stated one, inside the uncertain range):
    over five noise draws (2 % in ln mu) the verdict is "calibration" with q1 found, at least
    four times, and never a named effect. The evidence rule (:mod:`.verdict.calibration_rule`)
    may abstain on a draw where an extra parameter fits the noise: draw 7 gives load fitted with
    the calibration a Bayes factor of about 4 in-sample while the held-out points find nothing,
    and the verdict is inconclusive with the calibration among the explanations."""
    v = np.logspace(-4, 0.5, 24)
    ctx = build_context(_curve(v), PSD)
    truth = simulate(ctx.base.with_(psd=PSD.with_q1(2.5 * PSD.q1_per_m)), ctx)
    effects = [get(n) for n in ("temperature_offset", "contact_correction", "load")]
    named = 0
    for seed in (3, 4, 5, 6, 7):
        mu = truth * np.exp(0.02 * np.random.default_rng(seed).standard_normal(v.size))
        d = diagnose_friction(ctx, mu, effects=effects, uncertain=parse_uncertain("q1=5e4:2e6"))
        if d.verdict["effect"] is None:
            assert "calibration" in d.verdict["inconclusive"], (seed, d.verdict["reason"])
            continue
        assert d.verdict["effect"] == "calibration", (seed, d.verdict["reason"])
        named += 1
        q1 = d.verdict["calibrated"]["q1_per_m"]
        assert q1["value"] == pytest.approx(5e5, rel=0.25), seed
        assert q1["interval"][0] <= q1["value"] <= q1["interval"][1]
    assert named >= 4


def test_calibration_effect_moves_each_input():
    v = np.logspace(-4, 0, 6)
    ctx = build_context(_curve(v), PSD)
    e = calibration_effect(ctx, parse_uncertain("psd_scale=0.5:2,sigma0=0.1MPa:0.4MPa,temperature=40:80"))
    spec = e.modify(ctx.base, {"psd_scale": 2.0, "sigma0_Pa": 0.4e6, "temperature_C": 70.0}, ctx)
    assert spec.psd.C(1e4) == pytest.approx(2.0 * PSD.C(1e4), rel=1e-12)
    assert spec.sigma0_scale == pytest.approx(2.0) and spec.T0_shift_C == pytest.approx(10.0)  # T_ref 60 C


# ----------------------------------------------------------------------------- provenance, several rows
def _two_rows(tmp_path):
    d = tmp_path / "m"
    d.mkdir()
    v = np.logspace(-4, 0, 20)
    q = np.logspace(np.log10(2000), np.log10(2e5), 40)
    p = write_psd_csv(tmp_path / "psd.csv", q, PSD.C(q))
    rubs = {"sls": "thesis_sls.toml", "prony": "thesis_prony.toml"}
    import shutil
    from pathlib import Path

    src = Path(__file__).resolve().parents[1] / "sample_scans" / "rubbers"
    lines = ["measured,rubber,label,temperature_C"]
    for i, (label, toml) in enumerate(rubs.items()):
        shutil.copy(src / toml, d / toml)
        ctx = build_context(_curve(v, T=50.0), PSD)
        mu = simulate(ctx.base.with_(psd=PSD.with_q1(1.5 * PSD.q1_per_m)), ctx)
        mu = mu * np.exp(0.02 * np.random.default_rng(i).standard_normal(v.size))
        write_csv(d / f"{label}.csv", ["v_m_per_s", "mu"], [v, mu])
        lines.append(f"{label}.csv,{toml},{label},50")
    (d / "M.csv").write_text("\n".join(lines) + "\n")
    return d / "M.csv", p


def test_several_measurements_json_keys(tmp_path, monkeypatch):
    import pipelines.diagnosis.verdict.search as search

    few = [get("temperature_offset"), get("load")]
    monkeypatch.setattr(search, "all_effects", lambda level=None: few)
    m, p = _two_rows(tmp_path)
    out = tmp_path / "out"
    rc = cli(
        [
            "diagnose",
            "--measurements",
            str(m),
            "--psd",
            str(p),
            "--uncertain",
            "q1=5e4:1e6",
            "--out",
            str(out),
        ]
    )
    assert rc == 0
    data = json.loads((out / "diagnosis.json").read_text())
    assert set(data["measurements"]) == {"sls", "prony"}
    assert {"calibrated", "effects", "shared_inputs"} <= set(data["joint"])
    q1 = data["joint"]["calibrated"]["q1_per_m"]
    assert q1["interval"][0] <= q1["value"] <= q1["interval"][1] and q1["value"] == pytest.approx(
        3e5, rel=0.3
    )
    for label, one in data["measurements"].items():
        for key in (
            "verdict",
            "effects",
            "baseline_gap",
            "noise",
            "heldout",
            "where",
            "band_map",
            "inputs",
            "engine_settings",
        ):
            assert key in one, (label, key)
        for key in (
            "effect",
            "inconclusive",
            "at_bound",
            "confidence",
            "shrink_interval",
            "implausible",
            "calibrated",
        ):
            assert key in one["verdict"]
        assert one["inputs"]["temperature_C"] == 50.0 and "temperature_C" not in one["inputs"]["assumed"]
        files = {f["role"]: f for f in one["inputs"]["files"]}
        assert files["psd"]["sha256"] == hashlib.sha256(p.read_bytes()).hexdigest()
        assert files["rubber"]["path"].endswith(".toml")
    assert (out / "report.html").read_text().count("Compound ") >= 2


def test_single_diagnosis_records_inputs_and_assumed(tmp_path, monkeypatch):
    import pipelines.diagnosis.verdict.search as search

    monkeypatch.setattr(search, "all_effects", lambda level=None: [get("temperature_offset")])
    v = np.logspace(-4, 0, 20)
    ctx = build_context(_curve(v), PSD)
    mu = simulate(ctx.base, ctx) * np.exp(0.02 * np.random.default_rng(4).standard_normal(20))
    m = write_csv(tmp_path / "mu.csv", ["v_m_per_s", "mu"], [v, mu])
    q = np.logspace(np.log10(2000), np.log10(2e5), 40)
    p = write_psd_csv(tmp_path / "psd.csv", q, PSD.C(q))
    out = tmp_path / "o"
    assert (
        cli(["diagnose", "--measured", str(m), "--psd", str(p), "--sigma0", "0.25MPa", "--out", str(out)])
        == 0
    )
    data = json.loads((out / "diagnosis.json").read_text())
    inp = data["inputs"]
    assert inp["sigma0_Pa"] == 0.25e6 == data["engine_settings"]["sigma0_Pa"]
    assert "temperature_C" in inp["assumed"] and "sigma0_Pa" not in inp["assumed"]
    assert inp["temperature_C"] == pytest.approx(60.0)  # the thesis rubber's T_ref
    assert inp["q1_per_m"] == pytest.approx(2e5) and inp["psd_scale"] == 1.0
    assert {f["role"] for f in inp["files"]} == {"measured", "psd"}


def test_an_implausible_fit_is_refitted_within_the_physical_range():
    v = np.logspace(-4, 0, 6)
    ctx = build_context(_curve(v), PSD)
    mu = np.full(6, 0.4)
    r = get("flash_temperature").restricted(ctx, mu)
    hs = {p.name: p for p in r.params}["heat_scale"]
    assert (hs.lo, hs.hi) == pytest.approx((1 / 3, 3.0))
    assert r.null_params(ctx) is None  # heat_scale 1e-3 is outside: no null within
    a = {p.name: p for p in get("adhesion").restricted(ctx, mu).params}["amplitude"]
    assert a.hi == pytest.approx(0.4)
    assert get("load").restricted(ctx, mu) is None  # no physical range declared


def test_flash_beyond_the_shift_table_is_flagged_extrapolated():
    from pipelines.diagnosis.fit.fitting import Candidate
    from pipelines.diagnosis.verdict.search import _flash_extrapolation

    v = np.logspace(-2, 0.5, 6)
    rub = friction.StandardLinearSolid(
        shift=friction.ShiftTable(np.array([20.0, 60.0, 62.0]), np.array([3.0, 0.0, -0.1])), T_ref_C=60.0
    )
    ctx = build_context(_curve(v, T=60.0), PSD, rubber=rub)
    f = get("flash_temperature")
    c = Candidate((f,), [{"zeta_m": 3.0, "heat_scale": 1.0}], np.ones(6), 0.01, 0.01, 0.01)
    verdict = dict(effect="flash_temperature", confidence="high")
    _flash_extrapolation(ctx, c, verdict)  # the flash heats well above 62 C at 3 m/s
    assert verdict["confidence"] == "medium" and "outside the shift table" in verdict["extrapolated"][0]
