"""Issue 36: with only q1's default range uncertain, an effect fitted with q1 calibrated between
the scan's reliable band end and its measured end is that effect (a water film on a scan is
named or left open against its true rival, not an effect fitted at the nominal q1); beyond the
measured end it is fine roughness (not compared); with a tabulated --psd nothing changes; a
water film and an explanation that lowers mu alike are told apart by a dry measurement."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from pipelines.diagnosis.effects import get
from pipelines.diagnosis.fit.evidence import loglik, noise_scale
from pipelines.diagnosis.fit.fitting import fit_candidate
from pipelines.diagnosis.inputs import build_context, scan_surface
from pipelines.diagnosis.measured import MeasuredCurve
from pipelines.diagnosis.model import simulate
from pipelines.diagnosis.verdict.next_measurement import next_measurement
from pipelines.diagnosis.verdict.same_physics import band_end_pool, measured_end
from pipelines.diagnosis.verdict.search import diagnose_friction


def _scan_surface():
    from roadscan.synth import self_affine_surface

    hm = self_affine_surface(
        192, 192, dx_m=6e-5, hurst=0.8, rms_height_m=5e-4, q_roll_per_m=4 * 2 * np.pi / (192 * 6e-5), seed=36
    )
    return scan_surface(hm)


@pytest.fixture(scope="module")
def surface():
    return _scan_surface()


def _ctx(v, surface):
    psd, filled, spec, fit = surface
    return build_context(_curve(v), psd, scan=filled, spectrum=spec, fit=fit)


def _cand(name, q1, gap, k):
    """A stand-in of a fitted candidate: the calibration of q1 (alone or with effect ``name``)."""
    cal = SimpleNamespace(name="calibration")
    effects = [cal] + ([SimpleNamespace(name=name)] if name else [])
    return SimpleNamespace(
        effects=effects,
        params=[{"q1_per_m": q1}] + ([{}] if name else []),
        effect_names=[name] if name else [],
        gap_all=gap,
        k=k,
    )


def test_the_calibrated_q1_decides_which_fits_are_compared(surface):
    v = np.logspace(-4, 0, 24)
    ctx = _ctx(v, surface)
    q1, end = float(ctx.base.psd.q1_per_m), measured_end(ctx)
    q = np.sort(surface[2].q_per_m)
    assert end == pytest.approx(q[-1] * np.sqrt(q[-1] / q[-2]))  # the last bin's upper edge
    assert end > 1.2 * q1  # a scan: the reliable band ends below the measured spectrum
    n, noise, z_nom = 24, 0.01, -80.0
    mid, beyond, below = np.sqrt(q1 * end), 2 * end, q1 / 2
    cal = _cand(None, mid, 0.011, 1)
    inside = _cand("water", mid, 0.010, 2)
    outside = _cand("adhesion", beyond, 0.009, 5)
    under = _cand("temperature_offset", below, 0.009, 2)
    single = SimpleNamespace(effect_names=["load"])
    pool, z_base = band_end_pool(ctx, [single], [], cal, [inside, outside, under], n, noise, z_nom)
    assert pool == [single, inside]
    # "no effect": the nominal model and the calibration alone, half the prior each (Schwarz's
    # evidence of the calibration computed here from the likelihood, not by the module)
    z_cal = loglik(n * 0.011**2, n, noise_scale(noise)) - 0.5 * np.log(n)
    assert z_base == pytest.approx(np.logaddexp(z_nom, z_cal) - np.log(2.0))
    # the calibration beyond the measured spectrum is fine roughness: no baseline
    pool, z_base = band_end_pool(ctx, [single], [], _cand(None, beyond, 0.011, 1), [inside], n, noise, z_nom)
    assert z_base == z_nom and pool == [single, inside]
    # a tabulated spectrum: its last wave vector is q1, only the nominal fits are compared
    psd_ctx = build_context(_curve(v), _table(q1))
    assert measured_end(psd_ctx) == pytest.approx(q1)
    pool, z_base = band_end_pool(psd_ctx, [single], [], _cand(None, q1, 0.011, 1), [inside], n, noise, z_nom)
    assert pool == [single] and z_base == z_nom


def _curve(v):
    n = v.size
    return MeasuredCurve(v, np.ones(n), np.full(n, np.nan), np.full(n, 2e5), np.zeros(n, bool), False, "t")


def _table(q1):
    import friction

    q = np.geomspace(q1 / 100, q1, 40)
    return friction.TabulatedPSD(q, 1e-30 * (q / q1) ** -3.6)


def test_a_water_film_and_a_contact_correction_are_told_apart_on_a_dry_road(surface):
    """Both lower mu by a nearly constant factor over the measured speeds; only the water film
    leaves a dry road's mu alone, so the proposal is a dry measurement."""
    v = np.logspace(-4, 0, 20)
    ctx = _ctx(v, surface)
    w = get("water")
    assert w.prepare(ctx) is None
    mu = simulate(w.modify(ctx.base, {"fill_fraction": 0.6}, ctx), ctx)
    every = np.ones(v.size, bool)
    a = fit_candidate(ctx, mu, (w,), every)
    b = fit_candidate(ctx, mu, (get("contact_correction"),), every)
    # the two fits agree on the wet rows within the noise ...
    gap = np.sqrt(
        np.mean(np.log10(w.apply(ctx, a.params[0]) / get("contact_correction").apply(ctx, b.params[0])) ** 2)
    )
    assert gap < 0.02
    nxt = next_measurement(
        ctx,
        dict(name="water", candidate=a, H=np.eye(1) * 1e4),
        dict(name="contact_correction", candidate=b, H=np.eye(1) * 1e4),
        0.01,
    )
    # ... and a dry measurement separates them by several noise sigmas
    assert nxt is not None and nxt["condition"] == "dry" and "dry road" in nxt["sentence"]
    assert max(nxt["separation_sigma"]) > 3


def test_a_water_film_on_a_scan_is_not_named_as_another_effect(surface):
    """A world whose rubber feels the scan's measured spectrum to its last wave vector (beyond the
    reliable band the tool integrates to), with a water film: the effect fitted with q1
    calibrated within the measured spectrum is compared, so the verdict names water or leaves it
    open against an explanation that fits as well, never another effect alone."""
    v = np.logspace(-4, 0.5, 27)
    ctx = _ctx(v, surface)
    w = get("water")
    assert w.prepare(ctx) is None
    world = ctx.base.with_(psd=ctx.base.psd.with_q1(float(np.max(surface[2].q_per_m))))
    rng = np.random.default_rng(36)
    mu = simulate(w.modify(world, {"fill_fraction": 0.6}, ctx), ctx) * np.exp(
        0.02 * rng.standard_normal(v.size)
    )
    effs = [get(k) for k in ("water", "adhesion", "temperature_offset")]
    d = diagnose_friction(ctx, mu, noise=0.0087, effects=effs)
    assert "q1" in d.uncertain and d.uncertain["q1"].source == "default"
    ver = d.verdict
    assert ver["effect"] == "water" or "water" in ver["inconclusive"], ver["reason"]
