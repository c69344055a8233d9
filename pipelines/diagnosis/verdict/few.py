"""The verdict on few measured speeds (fewer than 20): Bayesian model comparison.

Held-out errors of four or five training points cannot carry a verdict, so below 20 points the
explanations are compared by their evidence (:mod:`.evidence`): the baseline (the calibration
of the uncertain inputs within their ranges, always fitted: the ranges are its prior; the
nominal model when nothing is uncertain) and each usable effect fitted together with it, every
model fitted on every point. The cross-validated held-out errors are still reported.

Verdict, once the baseline gap is significant against the noise (as :mod:`.verdict`):

- an effect is named when it is the most probable explanation and decided: at least 3 times as
  probable as every other explanation (:func:`.evidence.decisive`; posterior ``P_NAME`` = 0.9
  implies it) and its fit is
  physical and not equivalent to the uncertain inputs continued beyond their ranges
  (:mod:`.equivalence`; else the verdict is inconclusive naming the effect and
  ``"calibration"``, unless those inputs are the effect's own physics, :mod:`.same_physics`). Confidence: high
  at posterior >= 0.99, medium at >= 0.95, else low; low whenever a parameter sits on a bound of its range.
- ``"calibration"`` when the baseline is the most probable explanation, no effect's Bayes factor
  against it reaches 3, and the calibration shrinks the gap over all points by ``MIN_SHRINK``
  (confidence high at posterior >= 0.9, medium at >= 0.5, else low; low on a bound).
- otherwise inconclusive between the most probable explanations (together ``P_NAME``, at most
  three), or no effect when the nominal model is among them.
"""

from __future__ import annotations

import numpy as np

from pipelines.diagnosis.fit.evidence import (
    METHOD,
    P_NAME,
    PRIOR_NULL,
    REFERENCE,
    decisive,
    model_evidence,
    posteriors,
)
from pipelines.diagnosis.verdict.many import MIN_SHRINK, _empty, _refuse
from pipelines.diagnosis.verdict.same_physics import same_physics

__all__ = ["decide_few", "P_NAME"]


def _conf(p, c):
    conf = "high" if p >= 0.99 else "medium" if p >= 0.95 else "low"
    if c is not None and (c.at_bound or getattr(c, "extrapolated", None)):
        conf = "low"
    return conf


def _evidence_json(s, nu, ev_nom, ev0, evs, p0, ps, null_name):
    models = [
        dict(
            name=null_name,
            k=ev0["k"],
            log_evidence=ev0["log_z"],
            log_likelihood=ev0["loglik"],
            log_occam=ev0["occam"],
            rms=float(np.sqrt(ev0["rss"] / max(ev0.get("n", 1), 1))),
            posterior=p0,
        )
    ]
    for e, p in zip(evs, ps):
        models.append(
            dict(
                name=e["label"],
                k=e["k"],
                log_evidence=e["log_z"],
                log_likelihood=e["loglik"],
                log_occam=e["occam"],
                rms=float(np.sqrt(e["rss"] / max(e.get("n", 1), 1))),
                posterior=p,
            )
        )
    models.sort(key=lambda m: -m["posterior"])
    out = dict(
        method=METHOD,
        reference=REFERENCE,
        noise_scale=s,
        noise_dof=nu,
        prior_no_effect=PRIOR_NULL,
        models=models,
    )
    if ev_nom is not None and ev_nom is not ev0:
        out["log_bayes_factor_calibration_vs_nominal"] = ev0["log_z"] - ev_nom["log_z"]
    if len(models) > 1 and models[1]["posterior"] > 0:
        out["log_posterior_odds_top_two"] = float(np.log(models[0]["posterior"] / models[1]["posterior"]))
    return out


def decide_few(ctx, real_mu, cal, cands, st, equiv=None, intervals=None):
    """(verdict dict, named candidate or None, explanations) on few points.

    ``cal``: the calibration alone (None without uncertain inputs); ``cands``: the effects fitted
    on every point (with the calibration when there is one); ``st``: dict(g_all, noise, n,
    significant, p, s, nu) (s, nu: the likelihood's noise scale and degrees of freedom); ``equiv(c)``:
    :func:`equivalence.equivalence` bound to the ranges (None without uncertain inputs); ``intervals(c)``:
    calibrated inputs with intervals. ``explanations``: the explanations ranked by posterior, dicts(name,
    candidate, H, posterior).

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows and the baseline spec (the nominal model's evidence is computed on it).
    real_mu : ndarray, shape (n,)
        Measured mu at every row.
    cal : Candidate or None
        The calibration fitted alone on every point; None: no uncertain input (null: nominal).
    cands : list of Candidate
        Effects fitted on every point.
    st : dict
        g_all (baseline gap, rms log10), noise, n, significant, p (chi-square p-value), s and nu;
        optional noise_estimate (the data's own estimate, reported when it differs from ``noise``).
    equiv : callable, optional
        ``equiv(c)`` -> :func:`equivalence.equivalence` of candidate c; None: not tested.
    intervals : callable, optional
        ``intervals(c)`` -> calibrated inputs of c with their 95 % intervals; None: none reported.

    Returns
    -------
    tuple
        (verdict, named candidate or None, explanations).
    """
    intervals = intervals or (lambda c: {})
    n = np.asarray(real_mu).size
    s, nu = st["s"], st["nu"]
    ev_nom = model_evidence(ctx, real_mu, None, s, nu)
    ev_nom["n"] = n
    null_name = "calibration" if cal is not None else "nominal"
    ev0 = (
        (getattr(cal, "evidence", None) or model_evidence(ctx, real_mu, cal, s, nu))
        if cal is not None
        else ev_nom
    )
    ev0["n"] = n
    evs = []
    for c in cands:
        e = getattr(c, "evidence", None) or model_evidence(ctx, real_mu, c, s, nu)
        e["n"] = n
        e["label"] = "+".join(c.effect_names)
        evs.append(e)
    p0, ps = posteriors(ev0, evs)
    v = _empty()
    v["evidence"] = _evidence_json(s, nu, ev_nom, ev0, evs, p0, ps, null_name)
    expl = [dict(name=null_name, candidate=cal, H=ev0.get("H"), posterior=p0, log_z=ev0["log_z"])]
    expl += [
        dict(name=e["label"], candidate=c, H=e.get("H"), posterior=p, log_z=e["log_z"])
        for e, c, p in zip(evs, cands, ps)
    ]
    expl.sort(key=lambda x: -x["posterior"])
    if not st["significant"]:
        v["reason"] = (
            f"baseline gap {st['g_all']:.4f} is within the noise {st['noise']:.4f} "
            f"(chi-square p = {st['p']:.3g})"
        )
        est = st.get("noise_estimate")
        if est is not None and abs(est - st["noise"]) > 1e-12:
            v["reason"] += (
                f"; the noise scale is the data's estimate {est:.4f} from {n} points, clipped into "
                f"the range of a friction test's repeatability"
            )
        return v, None, expl
    top = expl[0]
    prefix = ""
    decided = decisive(top["posterior"], [x["posterior"] for x in expl[1:]])
    if top["candidate"] is not None and top["name"] != null_name and decided:
        c = top["candidate"]
        if c.implausible:
            prefix = _refuse(v, c)
        else:
            eq = equiv(c) if equiv is not None else None
            if eq is not None:
                v["evidence"]["equivalence"] = dict(
                    equivalent=eq["equivalent"],
                    dloglik=eq["dloglik"],
                    inputs=eq["inputs"],
                    calibrated=eq["calibrated"],
                )
            one = eq is not None and eq["equivalent"] and same_physics(c.effect_names, eq["inputs"])
            if eq is not None and eq["equivalent"] and not one:
                beyond = ", ".join(eq["inputs"]) or "the uncertain inputs"
                v["_equivalent_fit"] = eq["fit"]  # the pair a next measurement tells apart
                v["inconclusive"] = [top["name"], "calibration"]
                v["reason"] = (
                    f"inconclusive: {top['name']} (posterior {top['posterior']:.2f}) does what "
                    f"{beyond} continued beyond {'its range' if len(eq['inputs']) == 1 else 'their ranges'} "
                    f"does, within the noise (log-likelihood {eq['dloglik']:+.2f}): the same explanation"
                )
                return v, None, expl
            names = c.effect_names
            v["effect"] = names[0] if len(names) == 1 else list(names)
            v["shrink"] = c.shrink
            v["shrink_interval"] = list(c.shrink_interval)
            v["at_bound"] = list(c.at_bound)
            v["confidence"] = _conf(top["posterior"], c)
            v["calibrated"] = intervals(c) if cal is not None else {}
            v["reason"] = (
                f"{top['name']} has posterior probability {top['posterior']:.3f} "
                f"(next: {expl[1]['name']} {expl[1]['posterior']:.3f}); gap over all points "
                f"{st['g_all']:.4f} -> {c.gap_all:.4f}"
            )
            if top["posterior"] < P_NAME:
                v["_below_p_name"] = True  # next_measurement.withdraw_unseparated reads it
                odds = top["posterior"] / max(expl[1]["posterior"], 1e-300)
                v["reason"] += (
                    f"; below {P_NAME:g}, but {odds:.1f} times as probable as the next explanation "
                    f"(an explanation is named at 3 times every other)"
                )
            if one:
                v["reason"] += (
                    f"; {', '.join(eq['inputs']) or 'the uncertain inputs'} continued beyond the "
                    f"range does the same: the same physics, named as the effect"
                )
            return v, c, expl
    g_cal = 1.0 - cal.gap_all / st["g_all"] if cal is not None and st["g_all"] > 0 else float("nan")
    # no effect positively supported: every Bayes factor against the baseline below 3 (Kass &
    # Raftery 1995: "not worth more than a bare mention") and the baseline the most probable
    lbf = max((e["log_z"] - ev0["log_z"] for e in evs), default=-np.inf)
    plain = expl[0]["name"] == null_name and lbf < np.log(3.0)
    if cal is not None and plain and not cal.implausible:
        if g_cal >= MIN_SHRINK:
            v["effect"] = "calibration"
            v["shrink"] = cal.shrink
            v["shrink_interval"] = list(cal.shrink_interval)
            v["at_bound"] = list(cal.at_bound)
            v["confidence"] = "low" if cal.at_bound or p0 < 0.5 else "medium" if p0 < P_NAME else "high"
            v["calibrated"] = intervals(cal)
            v["reason"] = prefix + (
                f"the inputs within their ranges explain the gap (posterior {p0:.3f}; gap over all "
                f"points {st['g_all']:.4f} -> {cal.gap_all:.4f}); no effect fitted with them is "
                f"more probable (best {expl[1]['name']}: {expl[1]['posterior']:.3f})"
                if len(expl) > 1
                else ""
            )
            return v, cal, expl
        v["reason"] = prefix + (
            f"no explanation found: the calibration is the most probable (posterior {p0:.3f}) "
            f"but shrinks the gap only {g_cal:.0%}"
        )
        return v, None, expl
    if cal is None and plain:
        v["reason"] = prefix + (
            f"no effect is more probable than the nominal model (posterior {p0:.3f}; best "
            f"{expl[1]['name']} {expl[1]['posterior']:.3f})"
            if len(expl) > 1
            else "no usable effect"
        )
        return v, None, expl
    acc, names = 0.0, []
    for x in expl:
        if len(names) >= 3 or acc >= P_NAME:
            break
        names.append(x["name"])
        acc += x["posterior"]
    if "nominal" in names or len(names) < 2:
        v["reason"] = prefix + (
            "no effect named: the evidence does not decide ("
            + ", ".join(f"{x['name']} {x['posterior']:.2f}" for x in expl[:3])
            + ")"
        )
        return v, None, expl
    v["inconclusive"] = names
    v["reason"] = prefix + (
        "inconclusive: "
        + ", ".join(f"{x['name']} (posterior {x['posterior']:.2f})" for x in expl[: len(names)])
        + f": none reaches posterior {P_NAME:g} on these points"
    )
    return v, None, expl
