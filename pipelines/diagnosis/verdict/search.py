"""Which effect explains the gap: candidates fitted on training points, scored on held-out ones.

Candidates (each fitted by :func:`fitting.fit_candidate`, scored by :func:`cv.evaluate`): every
usable effect alone at the nominal inputs; without uncertain inputs, greedy pairs (the best
single combined with each other usable effect, started from the two single fits; then the best
single restarted from its fit within the best pair, kept when it fits the training points
better); with uncertain inputs (:mod:`.calibration`), the calibration alone and every effect fitted together with it
(started from the calibration's fit and the effect's single fit, besides cold starts). A model
with more free parameters than half its training points is not fitted (listed under
``skipped``). Effects that an uncertain input makes redundant (``fine_roughness`` with q1,
``load`` with sigma0, ``temperature_offset`` with the temperature) are skipped too, except
``fine_roughness`` beyond a default q1 range (its factor multiplies the calibrated q1). The verdict
is :func:`verdict.decide`, then re-checked for equivalence with the uncertain inputs continued
beyond their ranges (:mod:`.equivalence`), after the evidence over every point has ruled on it
(:mod:`.evidence_check`: the few-point rule, posterior >= 0.9, with the held-out verdict as its
check; the module says why two forms of the evidence remain). Below 20 points the candidates are fitted on every point and compared by their evidence instead
(:mod:`.search_few`, :mod:`.few`).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from pipelines.diagnosis import gap as gapmod
from pipelines.diagnosis.effects import all_effects
from pipelines.diagnosis.fit.cv import evaluate, heldout_mask, holdout
from pipelines.diagnosis.fit.fitting import Candidate, at_bound, fit_candidate, predict, too_many_parameters
from pipelines.diagnosis.fit.parallel import fit_map, portable, restore
from pipelines.diagnosis.verdict.explain import pick_pair
from pipelines.diagnosis.verdict.many import MIN_SHRINK, PAIR_GAIN, decide, rivals
from pipelines.diagnosis.verdict.next_measurement import no_pair, propose, withdraw_unseparated
from pipelines.diagnosis.verdict.same_physics import band_end_pool, equivalent_input, same_physics

__all__ = ["Candidate", "Diagnosis", "heldout_mask", "fit_candidate", "diagnose_friction", "predict",
           "at_bound", "MIN_SHRINK", "PAIR_GAIN", "rivals"]


@dataclass
class Diagnosis:
    """Everything the friction-level diagnosis found (see :func:`diagnose_friction`).

    Attributes
    ----------
    baseline_mu : ndarray, shape (n,)
        mu of the nominal model (known inputs set, nothing calibrated) at every row.
    baseline_gap, baseline_gap_train, baseline_gap_heldout : float
        rms of log10(measured / baseline mu) over all, the training and the held-out rows.
    noise : float
        rms log10 scatter of the measurement: as given, else estimated (:func:`gap.estimate_noise`).
    noise_given : bool
        True when ``noise`` was given (``--noise``), False when estimated from the data.
    significant : bool
        Whether the baseline gap exceeds the noise (:func:`gap.is_significant`).
    p_value : float
        Chi-square p-value of the baseline gap under the noise alone (:func:`gap.chi2_pvalue`).
    train : ndarray of bool, shape (n,)
        Rows the reported fits were trained on (every row below 20 points).
    candidates : list of Candidate
        Every fit, best first: by held-out score, or by evidence below 20 points.
    skipped : list
        Effects not tried and why.
    verdict : dict
        The verdict as ``diagnosis.json`` carries it (effect, confidence, reason, evidence, ...).
    best : Candidate or None
        The candidate the verdict names; None when it names none.
    seconds : float
        Wall-clock time of the whole diagnosis [s].
    timings : dict
        Candidate name -> wall-clock time of its fit [s].
    heldout : str
        One-line description of how points were held out, as the report prints it.
    uncertain : dict
        Input name -> :class:`calibration.Uncertain` over its fitted range; empty: none uncertain.
    calibration : Candidate or None
        The calibration of the uncertain inputs fitted alone; None when no input is uncertain.
    cutoff_sensitivity : float or None
        max over measured speeds of d ln mu / d ln q1; None when not computed.
    ctx : FrictionContext
        The context diagnosed (known inputs set in its baseline spec).
    """

    baseline_mu: np.ndarray
    baseline_gap: float
    baseline_gap_train: float
    baseline_gap_heldout: float
    noise: float
    noise_given: bool
    significant: bool
    p_value: float
    train: np.ndarray
    candidates: list
    skipped: list
    verdict: dict
    best: Candidate | None
    seconds: float = 0.0
    timings: dict = field(default_factory=dict)
    heldout: str = ""
    uncertain: dict = field(default_factory=dict)    # key -> calibration.Uncertain (fitted ones)
    calibration: Candidate | None = None
    cutoff_sensitivity: float | None = None
    ctx: object = None


def _usable(ctx, effects, free, ranges, skipped):
    from pipelines.diagnosis.fit.calibration import REDUNDANT

    out = []
    for e in effects:
        miss = e.missing(ctx)
        if miss:
            skipped.append(dict(name=e.name, reason=f"needs {', '.join(miss)} (not given)"))
            continue
        # a default q1 range (a decade either side) leaves fine roughness beyond it to the effect
        red = [k for k in free if REDUNDANT.get(k) == e.name and not (k == "q1" and ranges[k].source == "default")]
        if red:
            skipped.append(dict(name=e.name, reason=f"the same as calibrating the uncertain input {red[0]}"))
            continue
        if e.prepare is not None:
            why = e.prepare(ctx)
            if why:
                skipped.append(dict(name=e.name, reason=why))
                continue
        out.append(e)
    return out


def _flash_extrapolation(ctx, best, verdict):
    """A named fit with flash heating whose hottest flash temperature lies beyond the rubber's
    shift table: the master curve is extrapolated there; ``verdict.extrapolated`` says so and the
    confidence is at most medium."""
    from pipelines.diagnosis.effects import temperature_extrapolated
    from pipelines.diagnosis.model import simulate

    if "flash_temperature" not in {e.name for e in best.effects}:
        return
    spec = ctx.base
    for e, p in zip(best.effects, best.params):
        spec = e.modify(spec, p, ctx)
    try:
        _, res = simulate(spec, ctx, full=True)
    except (ValueError, ArithmeticError, RuntimeError):
        return
    T = [float(np.nanmax(r.T_q_C)) for _, r in res if getattr(r, "T_q_C", None) is not None]
    why = temperature_extrapolated(ctx, max(T)) if T else None
    if why:
        verdict["extrapolated"] = [f"hottest flash temperature {why}"]
        if verdict.get("confidence") == "high":
            verdict["confidence"] = "medium"


def _physical_refit(c, ctx, real_mu, ho, r0_held):
    """An implausible fit refitted with its parameters held in their physical ranges (started
    from its own fit, clipped, on the same training rows); the refit replaces it when every
    effect declares such ranges (:meth:`effects.Effect.restricted`)."""
    effs = tuple(e if e.name == "calibration" else e.restricted(ctx, real_mu) for e in c.effects)
    if any(e is None for e in effs):
        return c
    start = [{p.name: float(np.clip(q[p.name], p.lo, p.hi)) for p in e.params} for e, q in zip(effs, c.params)]
    cache = {}
    budget = 8 if max(e.cost for e in effs) > 1 else None
    r = fit_candidate(ctx, real_mu, effs, ho.train, cache=cache, extra_starts=[start], budget=budget)
    r = evaluate(r, ctx, real_mu, ho, r0_held)
    r.nfev += c.nfev
    return r if not r.implausible else c


def _one_explanation(verdict, best, equiv, train):
    """A named effect that the uncertain inputs continued beyond their ranges reproduce within
    the noise (:mod:`.equivalence`): when those inputs are the effect's own physics (:mod:`.same_physics`:
    fine roughness and q1, load and sigma0, a temperature offset and T0) it stays named; otherwise
    the verdict becomes inconclusive naming both. Returns the named candidate (None when it was
    withdrawn)."""
    if best is None or equiv is None or verdict.get("effect") in (None, "calibration"):
        return best
    eq = equiv(best, rows=train)
    if eq is None:
        return best
    verdict["equivalence"] = dict(equivalent=eq["equivalent"], dloglik=eq["dloglik"], inputs=eq["inputs"],
                                  calibrated=eq["calibrated"])
    if not eq["equivalent"]:
        return best
    names = best.effect_names
    if same_physics(names, eq["inputs"]):
        verdict["reason"] += (f"; {', '.join(eq['inputs']) or 'the uncertain inputs'} continued beyond "
                              f"{'its range' if len(eq['inputs']) == 1 else 'the ranges'} does the same: the "
                              f"same physics, named as the effect")
        return best
    beyond = ", ".join(eq["inputs"]) or "the uncertain inputs"
    verdict["_equivalent_fit"] = (best, eq["fit"])   # the pair the next measurement tells apart
    verdict.update(effect=None, confidence=None, shrink=None, shrink_interval=None, calibrated={}, at_bound=[],
                   inconclusive=["+".join(names), "calibration"],
                   reason=(f"inconclusive: {'+'.join(names)} would explain it, but {beyond} continued beyond "
                           f"the given range does the same within the noise (log-likelihood "
                           f"{eq['dloglik']:+.2f}): the same explanation"))
    return None


def _evidence_rule(ctx, verdict, best, singles, pair_list, cal, calpairs, n, noise, g_all, g_ho, default_only,
                   intervals):
    """The held-out verdict under the evidence over every point (:mod:`.evidence_check`); with
    ``--uncertain`` ranges the calibration and the effects fitted with it, else the nominal fits."""
    from pipelines.diagnosis.fit.evidence import loglik, noise_scale
    from pipelines.diagnosis.verdict.evidence_check import all_points_evidence, check_named

    z_nom = loglik(n * g_all * g_all, n, noise_scale(noise))
    if cal is not None and not default_only:
        if best is None or best.effects[0].name != "calibration":
            return best
        z_cal = all_points_evidence(cal, n, noise)
        return check_named(verdict, best, calpairs, n, noise, z_cal, g_ref=g_ho, base_name="calibration",
                           intervals=intervals)
    # q1's default range alone: the nominal fits, and the effects fitted with q1 calibrated within
    # the measured spectrum (:func:`.same_physics.band_end_pool`; beyond it, fine roughness)
    pool, z_base = band_end_pool(ctx, singles, pair_list, cal, calpairs, n, noise, z_nom)
    return check_named(verdict, best, pool, n, noise, z_base, g_ref=g_ho, rescue=True, intervals=intervals)


def _as_explanation(ctx, real_mu, c, s):
    """An explanation dict (name, candidate, H) of a fitted candidate for :func:`next_measurement`,
    its Hessian from the same evidence (noise scale ``s``) the verdict compares."""
    from pipelines.diagnosis.fit.evidence import model_evidence

    return dict(name="+".join(c.effect_names) or "calibration", candidate=c,
                H=model_evidence(ctx, real_mu, c, s)["H"])


def _few(ctx, real_mu, usable, cal_e, ho, noise, noise_given, timings, say, skipped, ranges, free,
         base, g, t0, sens):
    """The diagnosis on fewer than 20 points: Bayesian comparison (:mod:`.few`)."""
    from dataclasses import replace

    from pipelines.diagnosis.fit.calibration import intervals
    from pipelines.diagnosis.fit.equivalence import equivalence
    from pipelines.diagnosis.verdict.few import decide_few
    from pipelines.diagnosis.verdict.search_few import few_candidates

    cal, cands, s, nu, significant = few_candidates(ctx, real_mu, usable, cal_e, ho, noise, noise_given, timings,
                                                    say)
    p = gapmod.chi2_pvalue(g["g_all"], s, g["n"])
    st = dict(g_all=g["g_all"], noise=s, n=g["n"], significant=significant, p=p, s=s, nu=nu,
              noise_estimate=None if noise_given else noise)
    equiv = (lambda c: equivalence(ctx, real_mu, c, ranges, free, s)) if free else None
    verdict, best, expl = decide_few(ctx, real_mu, cal, cands, st, equiv=equiv,
                                     intervals=lambda c: intervals(c, ctx, real_mu, ho.train, noise))
    if best is not None and verdict.get("effect") not in (None, "calibration"):
        _flash_extrapolation(ctx, best, verdict)
        if verdict.get("extrapolated") and verdict.get("confidence") == "medium":
            verdict["confidence"] = "low"
        verdict["equivalent_input"] = equivalent_input(ctx, best)
    nxt = None
    eq_fit = verdict.pop("_equivalent_fit", None)
    if significant and (verdict.get("inconclusive") or verdict.get("confidence") in (None, "low")):
        pick = pick_pair(ctx, expl, s) or ((expl[0], expl[1:4]) if len(expl) > 1 else None)
        if eq_fit is not None:
            pick = (expl[0], [_as_explanation(ctx, real_mu, eq_fit, s)])
        nxt = propose(ctx, pick[0], pick[1], s, verdict, free) if pick is not None else no_pair(ctx, verdict, free)
    if withdraw_unseparated(verdict, nxt):
        best = None
    verdict["next_measurement"] = nxt
    ranked = sorted(cands + ([cal] if cal else []), key=lambda c: -c.evidence["log_z"])
    fitted = {k: replace(ranges[k], lo=a, hi=b) for k, (a, b) in free.items()}
    return Diagnosis(base, g["g_all"], g["g_tr"], g["g_ho"], noise, noise_given, significant, p, ho.train,
                     ranked, skipped, verdict, best, time.perf_counter() - t0, timings,
                     "linearised leave-one-out (PRESS) residuals of the fit on every point; the verdict is "
                     "a Bayesian model comparison, not a held-out score",
                     uncertain=fitted, calibration=cal, cutoff_sensitivity=sens, ctx=ctx)


def diagnose_friction(ctx, real_mu, noise=None, effects=None, pairs=True, log=None, uncertain=None,
                      default_q1=True, carried=None):
    """Run the friction-level diagnosis of the rows of ``ctx`` against measured ``real_mu``.

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows and the baseline model.
    real_mu : ndarray, shape (n,)
        Measured mu at the rows of ``ctx``.
    noise : float, optional
        Rms log10 measurement noise (None: estimated from the data).
    effects : list of Effect, optional
        Candidates (default: every registered friction-level effect).
    pairs : bool, optional
        Try greedy pairs (best single + each other) when no input is uncertain.
    log : callable, optional
        Called with one progress line (str) per step and fit; None: silent.
    uncertain : dict, optional
        Key -> :class:`pipelines.diagnosis.fit.calibration.Uncertain` (``--uncertain``).
    default_q1 : bool, optional
        Make q1 uncertain over a decade either side where q1 was not declared known and mu is
        carried by the cut-off or a decade of q1 moves it by more than the noise.
    carried : bool, optional
        Whether mu is carried by the cut-off (the band map's flag); None: judged here.

    Returns
    -------
    Diagnosis
        The fits, the verdict and its evidence; ``ctx.base`` is left with the known inputs set.
    """
    from dataclasses import replace

    from pipelines.diagnosis.fit.calibration import apply_known, calibration_effect, free_ranges, intervals
    from pipelines.diagnosis.fit.calibration import default_q1 as add_q1
    from pipelines.diagnosis.fit.equivalence import equivalence
    from pipelines.diagnosis.model import simulate
    from pipelines.diagnosis.verdict.explain import heldout_evidence, top_two

    t0 = time.perf_counter()
    say = log or (lambda *_: None)
    real_mu = np.asarray(real_mu, float)
    n = real_mu.size
    ranges = dict(uncertain or {})
    ctx.base = apply_known(ctx, ranges)
    sens = None
    noise_given = noise is not None
    noise = float(noise) if noise_given else gapmod.estimate_noise(ctx.v_m_per_s, real_mu)
    if default_q1:
        ranges, sens = add_q1(ctx, ranges, carried, noise=noise)
    free = free_ranges(ctx, ranges)
    cal_e = calibration_effect(ctx, ranges)
    ho = holdout(n)
    base = simulate(ctx.base, ctx)
    r0 = gapmod.log_ratio(real_mu, base)
    g_all = float(np.sqrt(np.mean(r0 ** 2)))
    g_tr = float(np.sqrt(np.mean(r0[ho.train] ** 2)))
    r0_held = r0[ho.held]
    g_ho = float(np.sqrt(np.mean(r0_held ** 2)))
    p = gapmod.chi2_pvalue(g_all, noise, n)
    significant = gapmod.is_significant(g_all, noise, n)
    say(f"baseline gap {g_all:.4f} (noise {noise:.4f}, p = {p:.2g})")
    if free:
        say("uncertain inputs: " + ", ".join(f"{k} {a:.4g}..{b:.4g} ({ranges[k].source})" for k, (a, b) in free.items()))

    skipped = []
    usable = _usable(ctx, effects if effects is not None else all_effects("friction"), free, ranges, skipped)
    timings = {}

    def fit(task):
        effs, kw = task
        t1 = time.perf_counter()
        c = fit_candidate(ctx, real_mu, effs, ho.train, cache={}, **kw)
        c = evaluate(c, ctx, real_mu, ho, r0_held)
        if c.implausible:
            c = _physical_refit(c, ctx, real_mu, ho, r0_held)
        c.seconds = time.perf_counter() - t1
        return portable(c, effs)

    def run(tasks):
        """The fits of one stage (independent of one another: on several cores), None where a
        model has too many parameters for its training points (listed under ``skipped``)."""
        ok = []
        for effs, _ in tasks:
            k = sum(len(e.params) for e in effs)
            ok.append(not too_many_parameters(k, ho.n_train))
            if not ok[-1]:
                skipped.append(dict(name="+".join(e.name for e in effs), reason=f"{k} free parameters on "
                                    f"{ho.n_train} training points (at most half as many parameters as points)"))
        fitted = iter(fit_map(fit, [t for t, keep in zip(tasks, ok) if keep],
                              cost=lambda t: max(e.cost for e in t[0])))
        out = []
        for (effs, _), keep in zip(tasks, ok):
            c = restore(next(fitted), effs) if keep else None
            if c is not None:
                timings[c.name] = c.seconds
                say(f"  {c.name}: train {c.gap_train:.4f} held-out {c.gap_heldout:.4f} ({c.seconds:.1f} s)")
            out.append(c)
        return out

    if ho.cv:
        return _few(ctx, real_mu, usable, cal_e, ho, noise, noise_given, timings, say, skipped,
                    ranges, free, base, dict(g_all=g_all, g_tr=g_tr, g_ho=g_ho, p=p, n=n), t0, sens)
    stage = run([((e,), {}) for e in usable] + ([((cal_e,), {})] if cal_e is not None else []))
    singles = [c for c in stage[:len(usable)] if c is not None]
    singles.sort(key=lambda c: c.score)
    pair_list, cal, calpairs = [], None, []
    if cal_e is not None:
        cal = stage[-1]
        if cal is not None and significant:
            by_name = {c.effects[0].name: c for c in singles}
            tasks = []
            for e in usable:
                starts = [cal.params + [e.null_params(ctx) or {p.name: p.init for p in e.params}]]
                if e.name in by_name:
                    starts.append(cal.params + by_name[e.name].params)
                budget = 8 if e.cost > 1 else 20 + 4 * (len(e.params) + len(cal_e.params))
                tasks.append(((cal_e, e), dict(extra_starts=starts, budget=budget)))
            calpairs = [c for c in run(tasks) if c is not None]
    elif pairs and singles and significant:
        first = singles[0]
        pair_list = [c for c in run([
            (first.effects + other.effects, dict(start=first.params + other.params,
                                                 budget=12 if max(first.effects[0].cost, other.effects[0].cost) > 1
                                                 else 40))
            for other in singles[1:]]) if c is not None]
        if pair_list:
            # the best single restarted from its parameters in the best pair: a pair started from
            # the single may only have continued a fit the single's budget stopped (kept when it
            # fits the training points better, never chosen by the held-out points)
            bp = min(pair_list, key=lambda c: c.gap_train)
            (c,) = run([(first.effects, dict(start=bp.params[:1], budget=12 if first.effects[0].cost > 1 else 40))])
            if c is not None and c.gap_train < first.gap_train:
                singles[0] = c
                singles.sort(key=lambda c: c.score)
    ranked = sorted(singles + pair_list + ([cal] if cal else []) + calpairs, key=lambda c: c.score)
    st = dict(g_all=g_all, g_ho=g_ho, noise=noise, n=n, significant=significant, p=p, boot=ho.boot,
              default_only=bool(free) and all(ranges[k].source == "default" for k in free))
    icals = lambda c: intervals(c, ctx, real_mu, ho.train, noise)  # noqa: E731
    equiv = (lambda c, rows=None: equivalence(ctx, real_mu, c, ranges, free, noise, rows=rows)) if free else None
    verdict, best = decide(singles, pair_list, cal, calpairs, st, intervals=icals)
    if significant and verdict.get("effect") != "calibration":
        best = _evidence_rule(ctx, verdict, best, singles, pair_list, cal, calpairs, n, noise, g_all, g_ho,
                              st["default_only"], icals)
    best = _one_explanation(verdict, best, equiv, ho.train)
    expl = None
    if best is not None and cal_e is not None and any(ranges[k].source == "given" for k in free) \
            and verdict.get("effect") not in (None, "calibration"):
        from pipelines.diagnosis.verdict.search_few import second_opinion

        best = second_opinion(ctx, real_mu, usable, cal_e, noise, noise_given, verdict, best, timings)
    if best is not None and verdict.get("effect") not in (None, "calibration"):
        _flash_extrapolation(ctx, best, verdict)
        verdict["equivalent_input"] = equivalent_input(ctx, best)
    if "evidence" not in verdict:
        verdict["evidence"] = heldout_evidence(ho, g_ho, ranked, best)
    for key in ("equivalence", "bayes", "all_points"):
        if key in verdict:
            verdict["evidence"][key] = verdict.pop(key)
    nxt = None
    eq_fit = verdict.pop("_equivalent_fit", None)
    if significant and (verdict.get("inconclusive") or verdict.get("confidence") in (None, "low")):
        pair = top_two(ctx, real_mu, noise, verdict, best, expl, singles, pair_list, cal, calpairs)
        if eq_fit is not None and eq_fit[0] is not None:
            pair = (_as_explanation(ctx, real_mu, eq_fit[0], noise), _as_explanation(ctx, real_mu, eq_fit[1], noise))
        nxt = propose(ctx, pair[0], [pair[1]], noise, verdict, free) if pair is not None else no_pair(ctx, verdict, free)
    if withdraw_unseparated(verdict, nxt):
        best = None
    verdict["next_measurement"] = nxt
    fitted = {k: replace(ranges[k], lo=a, hi=b) for k, (a, b) in free.items()}
    return Diagnosis(base, g_all, g_tr, g_ho, noise, noise_given, significant, p, ho.train, ranked,
                     skipped, verdict, best, time.perf_counter() - t0, timings, ho.description,
                     uncertain=fitted, calibration=cal, cutoff_sensitivity=sens, ctx=ctx)
