"""Tests of the sim-to-real gap diagnosis (pipelines/diagnose, issue 5)."""

from __future__ import annotations

import json
import re
from typing import ClassVar

import numpy as np
import pytest

import friction
from pipelines.cli.app import main as cli
from pipelines.diagnosis import gap as gapmod
from pipelines.diagnosis.effects import _REGISTRY, Effect, Param, all_effects, register
from pipelines.diagnosis.effects.relaxation_spectrum import lognormal_prony
from pipelines.diagnosis.inputs import build_context, write_psd_csv
from pipelines.diagnosis.measured import read_measured
from pipelines.diagnosis.model import SimSpec, simulate
from pipelines.diagnosis.report.bandmap import band_map
from pipelines.diagnosis.verdict.search import diagnose_friction, heldout_mask
from pipelines.output.report import write_csv
from roadscan.errors import InputError

PSD = friction.SelfAffinePSD(0.8, 5e-4, 2000.0, 2e5)


def _curve_file(tmp_path, v, mu, name="mu.csv", extra=()):
    cols = [v, mu] + [c for _, c in extra]
    return write_csv(tmp_path / name, ["v_m_per_s", "mu"] + [h for h, _ in extra], cols)


# ----------------------------------------------------------------------------- gap and noise
def test_gap_is_rms_of_log10_ratio():
    real = np.array([1.0, 2.0, 3.0])
    assert gapmod.gap(real, real) == 0.0
    assert gapmod.gap(1.1 * real, real) == pytest.approx(np.log10(1.1), rel=1e-12)
    assert gapmod.gap(real * np.array([10, 0.1, 1]), real) == pytest.approx(np.sqrt(2 / 3))


def test_noise_estimate_is_unbiased_within_20_percent():
    rng = np.random.default_rng(5)
    ratios = []
    for _ in range(40):
        n = int(rng.integers(20, 41))
        v = np.logspace(-5, 1.3, n)
        lv = np.log10(v)
        truth = 10 ** (np.log10(0.05 + 1.5 * np.exp(-((lv + 1) ** 2) / 3)) + 0.05 * lv)
        sig = rng.uniform(0.02, 0.05)
        mu = truth * (1 + sig * rng.standard_normal(n))
        ratios.append(gapmod.estimate_noise(v, mu) / (np.log10(np.e) * sig))
    assert 0.85 < np.mean(ratios) < 1.2


def test_chi2_significance():
    assert not gapmod.is_significant(0.02, 0.02, 30)
    assert gapmod.is_significant(0.05, 0.02, 30)
    # p-value is the chi-square survival function at n gap^2/noise^2
    assert gapmod.chi2_pvalue(0.02, 0.02, 30) == pytest.approx(0.466, abs=0.01)


def test_bands_cover_all_points_once():
    v = np.logspace(-5.3, 0.7, 25)
    bands = gapmod.decade_bands(v)
    total = sum(m.sum() for *_, m in bands)
    assert total == v.size
    assert np.all(np.sum([m for *_, m in bands], axis=0) == 1)
    # whole decades, and no band of fewer than 3 points (merged into a neighbour)
    for a, b, m in bands:
        ratio = np.log10(b / a)
        assert ratio >= 1 - 1e-9 and np.isclose(ratio, round(ratio))
        assert m.sum() >= 3
        assert np.all((v[m] >= a * (1 - 1e-12)) & (v[m] <= b * (1 + 1e-12)))
    assert len(bands) >= 5


def test_heldout_mask_deterministic_every_third():
    m = heldout_mask(10)
    assert list(np.flatnonzero(m)) == [1, 4, 7]


# ----------------------------------------------------------------------------- physics pieces
def test_band_map_integrand_integrates_to_engine_mu():
    """Independent check: 1/2 q^4 C P M with M from a separate phi quadrature of Im E must
    integrate over ln q to the engine's mu."""
    spec = SimSpec(PSD, friction.thesis_rubber())
    bands = gapmod.decade_bands(np.logspace(-6, 1, 30))
    out, (q, f, _vc) = band_map(spec, bands)
    mu_int = np.trapezoid(f, np.log(q), axis=1)
    mu_eng = np.array([o["mu_at_centre"] for o in out])
    np.testing.assert_allclose(mu_int, mu_eng, rtol=0.01)
    for o in out:
        assert PSD.q_min_per_m <= o["q_min_per_m"] < o["q_max_per_m"] <= PSD.q1_per_m * 1.0001
        assert o["omega_min_rad_s"] == pytest.approx(o["q_min_per_m"] * o["v_min_m_per_s"])


def test_lognormal_prony_keeps_limits_and_narrow_width_is_the_sls():
    sls = friction.thesis_rubber()
    w = np.logspace(-3, 12, 50)
    p = lognormal_prony(sls, 1.2)
    assert p.modulus_ref(np.array([1e-12])).real[0] == pytest.approx(
        sls.modulus_ref(np.array([1e-12])).real[0], rel=1e-6
    )
    assert p.modulus_ref(np.array([1e20])).real[0] == pytest.approx(1e9, rel=1e-6)
    assert np.all(p.modulus_ref(w).imag > 0)
    narrow = lognormal_prony(sls, 1e-4)
    np.testing.assert_allclose(narrow.modulus_ref(w), sls.modulus_ref(w), rtol=1e-3)
    # a spread lowers the loss peak
    assert p.modulus_ref(w).imag.max() < 0.7 * sls.modulus_ref(w).imag.max()


# ----------------------------------------------------------------------------- input
def test_measured_csv_per_row_columns_take_precedence(tmp_path):
    path = tmp_path / "mu.csv"
    path.write_text(
        "v_m_per_s,mu,T0_C,sigma0_Pa,condition\n"
        "1e-3,0.5,,,dry\n1e-2,0.6,40,,wet\n1e-1,0.7,,3e5,dry\n1,0.8,,,\n10,0.9,20,1e5,wet\n"
    )
    c = read_measured(path, sigma0_Pa=2e5, T0_C=50.0)
    np.testing.assert_allclose(c.T0_C, [50, 40, 50, 50, 20])
    np.testing.assert_allclose(c.sigma0_Pa, [2e5, 2e5, 3e5, 2e5, 1e5])
    assert list(c.wet) == [False, True, False, False, True] and c.has_condition


def test_per_row_temperature_reaches_the_engine(tmp_path):
    v = np.logspace(-4, 0, 6)
    path = tmp_path / "mu.csv"
    path.write_text("v_m_per_s,mu,T0_C\n" + "".join(f"{x},1,{t}\n" for x, t in zip(v, [60, 40] * 3)))
    curve = read_measured(path)
    ctx = build_context(curve, PSD)
    mu = simulate(ctx.base, ctx)
    r = friction.thesis_rubber()
    at60 = friction.mu_isothermal(PSD, r, v, T0_C=60).mu
    at40 = friction.mu_isothermal(PSD, r, v, T0_C=40).mu
    np.testing.assert_allclose(mu[::2], at60[::2], rtol=1e-6)
    np.testing.assert_allclose(mu[1::2], at40[1::2], rtol=1e-6)


@pytest.mark.parametrize(
    "text, msg",
    [
        ("v,mu\n1,2\n", "missing column 'v_m_per_s'"),
        ("v_m_per_s,mu\n1,2\n2,x\n", "not a number"),
        ("v_m_per_s,mu\n" + "".join(f"{i + 1},-1\n" for i in range(6)), "mu must be positive"),
        ("v_m_per_s,mu\n1,1\n2,1\n", "only 2 data rows"),
    ],
)
def test_bad_measured_input_is_one_line_error(tmp_path, text, msg):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=re.escape(msg)):
        read_measured(path)


def test_cli_bad_input_exit_2(tmp_path, capsys):
    path = tmp_path / "bad.csv"
    path.write_text("speed,mu\n1,2\n")
    psd = write_psd_csv(tmp_path / "psd.csv", np.geomspace(2e3, 2e5, 30), PSD.C(np.geomspace(2e3, 2e5, 30)))
    assert cli(["diagnose", "--measured", str(path), "--psd", str(psd), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "v_m_per_s" in err
    assert cli(["diagnose", "--out", str(tmp_path / "o")]) == 2


# ----------------------------------------------------------------------------- registry
def test_registry_has_the_issue_effects_and_skips_water_without_scan():
    names = {e.name for e in all_effects("friction")}
    assert {
        "flash_temperature",
        "relaxation_spectrum",
        "temperature_offset",
        "fine_roughness",
        "water",
        "adhesion",
        "load",
        "contact_correction",
    } <= names
    assert {"rolloff", "noise_floor", "height_skew", "anisotropy", "seams"} <= {
        e.name for e in all_effects("surface")
    }
    v = np.logspace(-4, 0, 12)
    ctx = build_context(read_measured_like(v), PSD)
    mu = simulate(ctx.base, ctx) * 1.0
    d = diagnose_friction(
        ctx, mu, noise=0.01, effects=[e for e in all_effects("friction") if e.name in ("water", "load")]
    )
    assert [s["name"] for s in d.skipped] == ["water"] and "scan" in d.skipped[0]["reason"]


def read_measured_like(v, mu=None):
    from pipelines.diagnosis.measured import MeasuredCurve

    n = v.size
    return MeasuredCurve(
        v,
        np.ones(n) if mu is None else mu,
        np.full(n, np.nan),
        np.full(n, 2e5),
        np.zeros(n, bool),
        False,
        "t",
    )


def test_a_new_plug_in_is_found_and_used_without_touching_others():
    """A multiplicative scale effect registered at run time is fitted and named."""
    e = register(
        Effect(
            name="zz_scale",
            level="friction",
            params=(Param("factor", 0.2, 5.0, 1.0, "log"),),
            modify=lambda s, p, c: s.with_(additive=s.additive),
            apply_fn=lambda ctx, p: simulate(ctx.base, ctx) * p["factor"],
        )
    )
    try:
        assert "zz_scale" in {x.name for x in all_effects("friction")}
        v = np.logspace(-5, 0.5, 24)
        ctx = build_context(read_measured_like(v), PSD)
        rng = np.random.default_rng(0)
        mu = simulate(ctx.base, ctx) * 1.8 * (1 + 0.02 * rng.standard_normal(v.size))
        # q1 declared known: a level change is what a q1 calibration would explain too
        d = diagnose_friction(
            ctx, mu, effects=[e, *[x for x in all_effects("friction") if x.name == "load"]], default_q1=False
        )
        assert d.verdict["effect"] == "zz_scale"
        assert d.best.params[0]["factor"] == pytest.approx(1.8, rel=0.03)
        assert d.verdict["shrink"] > 0.9
    finally:
        _REGISTRY.pop("zz_scale", None)


# ----------------------------------------------------------------------------- end to end
def test_cli_friction_level_contract(tmp_path):
    from pipelines.diagnosis.cases import make_case

    c = make_case(11, "temperature_offset", scan=False)
    q = np.geomspace(c.psd.q_min_per_m, c.psd.q1_per_m, 60)
    psd = write_psd_csv(tmp_path / "psd.csv", q, c.psd.C(q))
    mu = _curve_file(tmp_path, c.curve.v_m_per_s, c.curve.mu)
    other = _curve_file(tmp_path, c.curve.v_m_per_s[::2], c.truth_mu[::2], "other.csv")
    out = tmp_path / "out"
    assert (
        cli(
            [
                "diagnose",
                "--measured",
                str(mu),
                "--psd",
                str(psd),
                "--validate",
                str(other),
                "--out",
                str(out),
            ]
        )
        == 0
    )
    d = json.loads((out / "diagnosis.json").read_text())
    for k in ("level", "baseline_gap", "noise", "where", "effects", "verdict"):
        assert k in d
    assert d["level"] == "friction"
    assert all({"v_min_m_per_s", "v_max_m_per_s", "gap"} <= set(w) for w in d["where"])
    assert all({"name", "params", "gap_train", "gap_heldout", "shrink"} <= set(e) for e in d["effects"])
    scores = [e["score"] for e in d["effects"]]
    assert scores == sorted(scores)
    assert {"effect", "shrink", "gap_validate"} <= set(d["verdict"])
    if d["verdict"]["effect"] is not None:
        assert d["verdict"]["gap_validate"] < d["verdict"]["gap_validate_baseline"]
    html = (out / "report.html").read_text()
    assert html.count("data:image/png;base64,") >= 3 and "http://" not in html and "https://" not in html
    assert any(s["name"] == "water" for s in d["skipped"])


def test_cli_surface_level_finds_a_rolloff(tmp_path):
    from roadscan.synth import self_affine_surface

    hm = self_affine_surface(
        256, 256, dx_m=5e-5, hurst=0.8, rms_height_m=3e-4, q_roll_per_m=8 * 2 * np.pi / (256 * 5e-5), seed=2
    )
    path = tmp_path / "scan.npy"
    np.save(path, hm.heights_m)
    out = tmp_path / "s"
    assert cli(["diagnose", "--scan", str(path), "--spacing", "5e-5", "--out", str(out)]) == 0
    d = json.loads((out / "diagnosis.json").read_text())
    assert d["level"] == "surface"
    assert all({"q_min_per_m", "q_max_per_m", "gap"} <= set(w) for w in d["where"])
    assert d["verdict"]["effect"] == "rolloff" and d["verdict"]["shrink"] > 0.5


def test_surface_level_null_on_a_pure_self_affine_scan(tmp_path):
    from pipelines.diagnosis.surface.level import run_surface
    from roadscan.synth import self_affine_surface

    hm = self_affine_surface(256, 256, dx_m=5e-5, hurst=0.75, rms_height_m=3e-4, seed=9)
    d = run_surface(hm, tmp_path)
    assert d["verdict"]["effect"] is None


#: the effect kinds of the proof test: those tests/test_diagnose_blind.py does not name (it keeps
#: temperature offset, adhesion and contact correction); load and water are left out, their
#: draws mostly fail the identifiability filter (4 of 4 tries each from this seed)
PROOF_KINDS = ("fine_roughness", "flash_temperature", "relaxation_spectrum")


def test_proof_small_blind_cases_meet_the_goals():
    """A small version of benchmarks/bench_diagnose.py: seeded cases with one hidden effect
    (identifiable ones only, one per kind of PROOF_KINDS) and a null case, diagnosed blind.
    Every case kept must be right; the rates over whole seed sets (>= 85-90 % named right, null
    false positives) are measured by benchmarks/bench_diagnose.py and bench_diagnose_blind.py."""
    from pipelines.diagnosis.cases import draw_cases

    effs = [e for e in all_effects("friction") if e.name in PROOF_KINDS]
    cases, _ = draw_cases(len(PROOF_KINDS), 1, seed0=424242, effects=effs, max_tries=4)
    hits, shrink, fp, n_null = 0, [], 0, 0
    for c in cases:
        d = diagnose_friction(c.context(), c.curve.mu)
        got = d.verdict["effect"]
        if c.effect is None:
            n_null += 1
            fp += got not in (None, "calibration")  # calibration is no named effect (issue 19)
        else:
            # fine roughness answered by calibrating q1 (uncertain by default) is right (issue 19)
            hits += got == c.effect or (
                c.effect == "fine_roughness"
                and got == "calibration"
                and "q1_per_m" in d.verdict["calibrated"]
            )
            shrink.append(d.verdict["shrink"] or 0.0)
    n_eff = len(cases) - n_null
    assert n_eff == len(PROOF_KINDS) and n_null == 1
    assert sorted(c.effect for c in cases if c.effect) == sorted(PROOF_KINDS)
    assert hits == n_eff
    assert np.median(shrink) >= 0.7
    assert fp == 0


# ----------------------------------------------------------------------------- surface level, issue 11
def test_l_moment_ratios_match_analytic_values():
    from pipelines.diagnosis.surface.blocks import l_moment_ratios

    rng = np.random.default_rng(3)
    t3, t4 = l_moment_ratios(rng.standard_normal(200_000))
    assert abs(t3) < 0.005 and t4 == pytest.approx(0.1226, abs=0.005)  # Hosking 1990, table 1
    t3, t4 = l_moment_ratios(rng.exponential(size=200_000))
    assert t3 == pytest.approx(1 / 3, abs=0.005) and t4 == pytest.approx(1 / 6, abs=0.005)
    # location and scale do not change the ratios; a sign flip flips tau3 only
    x = rng.gamma(2.0, size=20_000)
    a, b = l_moment_ratios(x), l_moment_ratios(-3 * x + 7)
    assert b[0] == pytest.approx(-a[0], abs=1e-9) and b[1] == pytest.approx(a[1], abs=1e-9)


def test_seam_score_sees_a_seam_not_a_direction():
    """A step along a lattice line makes one line of the block jump together (line score ratio
    of 10^2 and more); a directional (stretched) texture hardly moves it but moves the signed
    anisotropy components, which stay near 0 for the isotropic texture."""
    from scipy.ndimage import zoom

    from pipelines.diagnosis.surface import blocks as bl
    from roadscan.heightmap import HeightMap
    from roadscan.synth import self_affine_surface

    big = self_affine_surface(256, 256, dx_m=5e-5, hurst=0.8, rms_height_m=3e-4, seed=4).heights_m
    h = big[:128, :128].copy()
    geo = bl.geometry(HeightMap(h, 5e-5, 5e-5), n_blocks=1)
    plain = bl.describe(h, geo, rain=False)
    seam = h.copy()
    seam[:, 64:] += 0.2 * h.std()
    stepped = bl.describe(seam, geo, rain=False)["seams"][0, 0]
    aniso = zoom(big[:128, :50], (1, 3), order=3)[:, :128]
    directional = bl.describe(aniso, geo, rain=False)
    assert stepped > plain["seams"][0, 0] + 1.5
    assert directional["seams"][0, 0] < plain["seams"][0, 0] + 0.6 < stepped
    assert np.hypot(*directional["anisotropy"][0]) > 0.5 > 0.05 > np.hypot(*plain["anisotropy"][0])
    # stretched along x: power at small q_x, so M_yy > M_xx (a < 0)
    assert directional["anisotropy"][0, 0] < -0.5


def test_curvature_skewness_sees_the_height_law_not_linear_filters():
    """The L-skewness of the curvature is ~0 for a Gaussian field, smoothed or not, and takes the
    sign of g'' for a monotone map h -> g(h) (here exp: convex, sharp peaks)."""
    from scipy.ndimage import gaussian_filter

    from pipelines.diagnosis.surface.blocks import curvature_l_skewness
    from roadscan.synth import self_affine_surface

    h = self_affine_surface(256, 256, dx_m=5e-5, hurst=0.8, rms_height_m=3e-4, seed=8).heights_m
    z = h / h.std()
    assert abs(curvature_l_skewness(z)) < 0.01
    assert abs(curvature_l_skewness(gaussian_filter(z, 2.0))) < 0.02
    peaks = curvature_l_skewness(np.exp(0.8 * z))
    assert peaks < -0.02 and curvature_l_skewness(-np.exp(0.8 * z)) == pytest.approx(-peaks)


def test_every_surface_effect_has_a_reachable_no_effect_limit():
    from pipelines.diagnosis.surface.search import _predict

    class Ctx:  # the attributes effects read
        ring_q = np.geomspace(1e3, 1e5, 40)
        twin_rings = -12 - 3.6 * np.log10(ring_q / 1e3)
        twin_mean: ClassVar[dict] = dict(
            height=np.array([0.0, 0.12, 0.0]),
            anisotropy=np.array([0.0, 0.0]),
            seams=np.array([0.9]),
            rain=np.array([-0.1, -0.1, -0.1, 0.2]),
            spectrum=np.zeros(7),
        )
        skew_table: ClassVar[dict] = dict(
            s=np.array([-1.0, 0.0, 1.0]),
            height=np.array([[-0.1, 0.13, 0.03], [0.0, 0.12, 0.0], [0.1, 0.13, -0.03]]),
            rain=np.array([[0.1] * 4, [0.0] * 4, [-0.1] * 4]),
        )

        class fit:
            hurst = 0.8

        class geo:
            band_matrix = np.kron(np.eye(8), np.full((1, 5), 0.2))

    ctx = Ctx()
    base = _predict(ctx, (), [])
    for e in all_effects("surface"):
        null = e.null_params(ctx)
        assert null is not None, e.name
        for p in e.params:  # the null lies inside the bounds
            assert p.lo <= null[p.name] <= p.hi, (e.name, p.name)
        pred = _predict(ctx, (e,), [null])
        for f in ("spectrum", "height", "anisotropy", "seams", "rain"):
            assert np.allclose(pred[f], base[f], atol=2e-3), (e.name, f)


def test_surface_level_names_anisotropy_with_family_gaps(tmp_path):
    from scipy.ndimage import zoom

    from pipelines.diagnosis.surface.level import run_surface
    from roadscan.heightmap import HeightMap
    from roadscan.synth import self_affine_surface

    big = self_affine_surface(512, 512, dx_m=5e-5, hurst=0.8, rms_height_m=3e-4, seed=21).heights_m
    h = zoom(big[:256, :90], (1, 3), order=3)[:, :256]
    d = run_surface(HeightMap(h, 5e-5, 5e-5, name="aniso"), tmp_path)
    v = d["verdict"]
    assert v["effect"] == "anisotropy" and v["shrink"] >= 0.5
    assert d["families"]["anisotropy"]["significant"] and d["families"]["anisotropy"]["gap_baseline"] > 5
    assert set(d["families"]) == {"spectrum", "height", "anisotropy", "seams", "rain"}
    lo, hi = v["shrink_interval"]
    assert lo <= v["shrink"] + 1e-9 and hi >= v["shrink"] - 1e-9
    assert isinstance(d["at_bound"], list) and d["inconclusive"] == [] and v["inconclusive"] == []
    e = next(x for x in d["effects"] if x["name"] == "anisotropy")
    assert e["family_gaps"]["anisotropy"] < 0.3 * d["families"]["anisotropy"]["gap_baseline"]
    html = (tmp_path / "report.html").read_text()
    assert "descriptor family" in html and "Shrink interval" in html


@pytest.mark.parametrize("kind", ["flat", "tiny", "one_speed"])
def test_diagnose_refuses_unusable_input_in_one_line(tmp_path, capsys, kind):
    if kind == "flat":
        np.save(tmp_path / "s.npy", np.full((100, 100), 1e-3))
        args = ["--scan", str(tmp_path / "s.npy"), "--spacing", "1e-4"]
    elif kind == "tiny":
        np.save(tmp_path / "s.npy", np.random.default_rng(0).random((3, 3)))
        args = ["--scan", str(tmp_path / "s.npy"), "--spacing", "1e-4"]
    else:
        f = _curve_file(tmp_path, np.full(20, 0.01), np.linspace(0.5, 0.7, 20))
        q = np.geomspace(1e3, 1e5, 30)
        psd = write_psd_csv(tmp_path / "psd.csv", q, 1e-20 * (q / 1e3) ** -3.6)
        args = ["--measured", str(f), "--psd", str(psd)]
    assert cli(["diagnose", *args, "--out", str(tmp_path / "o")]) == 2
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(err) == 1 and ("flat" in err[0] or "too small" in err[0] or "distinct speed" in err[0]), err
    assert not (tmp_path / "o" / "diagnosis.json").exists()


# ----------------------------------------------------------------------------- friction level, issue 11
def _ctx_for(v, psd=PSD):
    from pipelines.diagnosis.measured import MeasuredCurve

    n = v.size
    curve = MeasuredCurve(v, np.ones(n), np.full(n, np.nan), np.full(n, 0.2e6), np.zeros(n, bool), False, "t")
    return build_context(curve, psd)


def test_every_friction_effect_reaches_no_effect():
    """At its null parameters every effect gives the baseline mu (flash heating included)."""
    v = np.logspace(-4, 0.5, 8)
    ctx = _ctx_for(v)
    base = simulate(ctx.base, ctx)
    for e in all_effects("friction"):
        if e.missing(ctx) or (e.prepare is not None and e.prepare(ctx)):
            continue
        null = e.null_params(ctx)
        assert null is not None, e.name
        for p in e.params:
            assert p.lo <= null[p.name] <= p.hi, (e.name, p.name)
        mu = e.apply(ctx, null)
        assert np.max(np.abs(np.log(mu / base))) < 5e-3, (e.name, np.max(np.abs(np.log(mu / base))))


def test_few_points_are_compared_by_evidence_and_fits_never_beat_by_no_effect():
    v = np.logspace(-5, 0, 9)
    ctx = _ctx_for(v)
    truth = simulate(ctx.base.with_(T0_shift_C=-12.0), ctx)
    rng = np.random.default_rng(2)
    mu = truth * np.exp(0.01 * rng.standard_normal(v.size))
    # the one-parameter effects (flash and adhesion are slower to fit; their no-effect limits are
    # checked above)
    effs = [e for e in all_effects("friction") if e.cost <= 1 and len(e.params) == 1]
    d = diagnose_friction(ctx, mu, noise=0.005, effects=effs, pairs=False)
    # below 20 points: Bayesian evidence decides, PRESS (linearised leave-one-out) residuals are reported
    assert "leave-one-out" in d.heldout and d.train.all()
    assert d.verdict["evidence"]["models"][0]["name"] == "temperature_offset"
    assert d.verdict["effect"] == "temperature_offset"
    lo, hi = d.verdict["shrink_interval"]
    assert lo <= d.verdict["shrink"] <= hi and d.verdict["shrink"] > 0.7
    # PRESS residuals r_i / (1 - h_ii) are never smaller than the fit's own residuals
    for c in d.candidates:
        assert c.r_held.size == v.size
        assert c.gap_heldout >= c.gap_train * (1 - 1e-12), c.name
        assert c.gap_train <= d.baseline_gap * (1 + 1e-9), c.name  # never worse than no effect
    best = d.best
    fitted = dict(zip([e.name for e in best.effects], best.params))  # may be calibrated with q1
    assert fitted["temperature_offset"]["dT_C"] == pytest.approx(-12.0, abs=1.0)


def test_at_bound_lists_a_parameter_pushed_onto_its_range():
    from pipelines.diagnosis.effects import get
    from pipelines.diagnosis.verdict.search import at_bound

    ctx = _ctx_for(np.logspace(-4, 0, 6))
    e = get("temperature_offset")
    assert at_bound(ctx, (e,), [{"dT_C": 30.0}]) == ["dT_C"]
    assert at_bound(ctx, (e,), [{"dT_C": 7.0}]) == []
    f = get("flash_temperature")  # the no-effect value at a bound is not "at bound"
    assert at_bound(ctx, (f,), [{"zeta_m": 3.0, "heat_scale": 1e-3}]) == []
    assert at_bound(ctx, (f,), [{"zeta_m": 8.0, "heat_scale": 1.0}]) == ["zeta_m"]


def test_cutoff_sensitivity_matches_the_integrand_at_q1():
    """d mu / d ln q1 = (d mu / d ln q) at q = q1 (Leibniz: P(q) below q1 does not depend on q1),
    an independent check of band_map's finite difference."""
    spec = SimSpec(psd=PSD, rubber=friction.thesis_rubber())
    bands = [(1e-3, 1e-2), (1.0, 10.0)]
    bm, (q, f, vc) = band_map(spec, bands)
    res = friction.mu_isothermal(PSD, spec.rubber, vc, sigma0_Pa=0.2e6)
    for i, b in enumerate(bm):
        leibniz = f[i, -1] / res.mu[i]
        assert b["dlnmu_dlnq1"] == pytest.approx(leibniz, rel=0.25, abs=0.02)
        assert b["carried_by_cutoff"] == (b["dlnmu_dlnq1"] > 0.3 or b["q_peak_per_m"] >= q[-2])
