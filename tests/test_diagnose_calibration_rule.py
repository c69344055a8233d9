"""Issue 36, real compounds at three settings: with ``--uncertain`` ranges the "calibration"
verdict is the few-point rule over every point (not a held-out tie against effects fitted at the
nominal inputs), q1 is uncertain by default wherever the data feel it, a temperature offset is
different physics from a calibration of q1 and the pressure, and every low or inconclusive
verdict says what to measure next (another quantity when no speed separates the explanations)."""

from __future__ import annotations

import numpy as np
import pytest

import friction
from pipelines.diagnosis.effects import get
from pipelines.diagnosis.fit.calibration import (
    calibration_effect,
    cutoff_sensitivity,
    default_q1,
    parse_uncertain,
)
from pipelines.diagnosis.fit.fitting import Candidate
from pipelines.diagnosis.inputs import build_context
from pipelines.diagnosis.measured import MeasuredCurve
from pipelines.diagnosis.verdict.many import decide
from pipelines.diagnosis.verdict.next_measurement import OTHER_QUANTITY, unseparated
from pipelines.diagnosis.verdict.same_physics import distinct

PSD = friction.SelfAffinePSD(0.8, 5e-4, 2000.0, 5e4)
N, NOISE = 24, 0.01


def _ctx(v, psd=PSD):
    n = v.size
    return build_context(
        MeasuredCurve(v, np.ones(n), np.full(n, np.nan), np.full(n, 2e5), np.zeros(n, bool), False, "t"), psd
    )


def _cand(effects, params, gap, held, shrink=0.8, at_bound=()):
    """A fitted candidate whose rms residual over all N points is ``gap`` and whose held-out
    residuals are ``held`` (8 points)."""
    return Candidate(
        tuple(effects),
        params,
        np.ones(N),
        gap,
        float(np.sqrt(np.mean(held**2))),
        gap,
        shrink=shrink,
        score=gap,
        r_held=held,
        shrink_interval=(shrink - 0.05, shrink + 0.05),
        at_bound=list(at_bound),
    )


def _schwarz_here(gap, k, nu=4.0):
    """ln L (Student-t, NU = 4, noise scale NOISE) - k/2 ln N, written out here independently."""
    rss = N * gap * gap
    return -0.5 * (nu + N) * np.log1p(rss / (nu * NOISE**2)) - 0.5 * k * np.log(N)


def _world(gap_temperature_pair, nominal_temperature_gap):
    """The calibration of sigma0 alone (k = 1, rms 0.0105 over every point), the temperature
    offset fitted with it (k = 2) and, at the nominal inputs, a temperature offset alone."""
    ctx = _ctx(np.logspace(-4, 0, N))
    cal_e = calibration_effect(ctx, parse_uncertain("sigma0=0.15MPa:0.45MPa"))
    t = get("temperature_offset")
    rng = np.random.default_rng(5)
    held = 0.0105 * rng.standard_normal(8)
    cal = _cand((cal_e,), [{"sigma0_Pa": 2.5e5}], 0.0105, held)
    pair = _cand((cal_e, t), [{"sigma0_Pa": 2.5e5}, {"dT_C": 2.0}], gap_temperature_pair, held * 0.999)
    nominal = _cand((t,), [{"dT_C": 5.0}], 0.011, held * (nominal_temperature_gap / 0.0105))
    st = dict(g_all=0.1, g_ho=0.1, noise=NOISE, n=N, significant=True, p=1e-9, boot=None, default_only=False)
    return cal, pair, nominal, st


@pytest.mark.parametrize("nominal_gap", [0.0105, 0.0112, 0.02])
def test_calibration_verdict_does_not_flip_with_an_effect_at_the_nominal_inputs(nominal_gap):
    """An effect fitted at the nominal inputs within a tenth of the noise of the calibration made
    the verdict inconclusive, a little further "calibration": with the user's ranges the rival
    is the effect fitted with the calibration, so the verdict is the same for all three."""
    cal, pair, nominal, st = _world(0.0104, nominal_gap)
    v, best = decide([nominal], [], cal, [pair], st, intervals=lambda c: {})
    assert best is cal and v["effect"] == "calibration" and not v["inconclusive"], v["reason"]
    # the posterior of the calibration, from the Schwarz evidence written out in this test
    z0, z1 = _schwarz_here(0.0105, 1), _schwarz_here(0.0104, 2)
    p0 = 0.5 * np.exp(z0) / (0.5 * np.exp(z0) + 0.5 * np.exp(z1))
    models = v["all_points"]["models"]
    assert models[0]["name"] == "calibration" and models[0]["posterior"] == pytest.approx(p0, rel=1e-6)
    assert v["confidence"] == ("high" if p0 >= 0.9 else "medium" if p0 >= 0.5 else "low")


def test_an_effect_with_a_bayes_factor_of_three_makes_the_calibration_inconclusive():
    """The effect fitted with the calibration fits every point better by more than a Bayes factor
    of 3 (its held-out shrink beyond the calibration is not there): inconclusive, both named."""
    cal, pair, nominal, st = _world(0.0092, 0.02)
    assert _schwarz_here(0.0092, 2) - _schwarz_here(0.0105, 1) > np.log(3.0)  # the premise, independently
    v, best = decide([nominal], [], cal, [pair], st, intervals=lambda c: {})
    assert best is None and v["effect"] is None
    assert set(v["inconclusive"]) == {"calibration", "temperature_offset"}, v["reason"]


def test_the_rule_uses_the_evidence_of_the_held_out_check():
    """The calibration rule's evidence is the one :mod:`.evidence_check` weighs named effects by."""
    from pipelines.diagnosis.verdict.calibration_rule import _schwarz
    from pipelines.diagnosis.verdict.evidence_check import all_points_evidence

    cal, pair, _, _ = _world(0.0104, 0.02)
    for c in (cal, pair):
        assert _schwarz(c, N, NOISE) == pytest.approx(all_points_evidence(c, N, NOISE), rel=1e-12)
        assert _schwarz(c, N, NOISE) == pytest.approx(_schwarz_here(c.gap_all, c.k), rel=1e-12)


def test_a_calibration_on_a_bound_is_low_confidence():
    cal, pair, nominal, st = _world(0.0104, 0.02)
    cal.at_bound = ["sigma0_Pa"]
    v, _ = decide([nominal], [], cal, [pair], st, intervals=lambda c: {})
    assert v["effect"] == "calibration" and v["confidence"] == "low"


def test_same_physics_only_against_a_calibration_of_the_effects_own_input():
    assert distinct("temperature_offset", "calibration", ["q1", "sigma0", "psd_scale"])
    assert not distinct("temperature_offset", "calibration", ["temperature", "sigma0"])
    assert not distinct("fine_roughness", "calibration", ["q1"]) and distinct(
        "fine_roughness", "calibration", []
    )
    assert not distinct("load", "nominal", ["q1"])
    assert not distinct("fine_roughness", "calibration")  # no inputs said: any calibration counts


def test_q1_is_uncertain_by_default_where_a_decade_of_it_moves_mu_beyond_the_noise():
    """Below the band map's cut-off flag the data may still feel q1: a decade of it moves log10 mu
    by d ln mu / d ln q1 (computed here); q1 is uncertain when that exceeds the noise."""
    ctx = _ctx(np.logspace(-4, 0, 6))
    s = cutoff_sensitivity(ctx)
    assert s > 0
    r, _ = default_q1(ctx, {}, carried=False, noise=0.5 * s)
    assert r["q1"].source == "default" and r["q1"].lo == pytest.approx(PSD.q1_per_m / 10)
    r, _ = default_q1(ctx, {}, carried=False, noise=2.0 * s)
    assert "q1" not in r
    r, _ = default_q1(ctx, {}, carried=False)  # no noise: the cut-off flag alone decides
    assert "q1" not in r


def test_no_separating_speed_names_the_other_quantity():
    ctx = _ctx(np.logspace(-4, 0, 6))
    nxt = unseparated(
        "calibration", ["water"], ctx, inputs=["sigma0"], why="sigma0_Pa at the end of its range"
    )
    assert (
        nxt["separable"] is False
        and nxt["speeds_m_per_s"] == []
        and nxt["between"] == ["calibration", "water"]
    )
    assert OTHER_QUANTITY["sigma0"] in nxt["sentence"] and OTHER_QUANTITY["water"] in nxt["sentence"]
    assert "sigma0_Pa at the end of its range" in nxt["sentence"]
    alone = unseparated("calibration", [], ctx, inputs=["q1", "psd_scale"])
    assert alone["between"] == ["calibration"]
    assert OTHER_QUANTITY["q1"] in alone["sentence"] and OTHER_QUANTITY["psd_scale"] in alone["sentence"]
