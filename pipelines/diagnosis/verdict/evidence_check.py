"""The held-out verdict (20 speeds or more) checked against the evidence over every point.

Why two regimes remain, and how they are one rule. Below 20 speeds the explanations are
compared by their Laplace evidence (:mod:`.few`): a held-out third of 3-6 points cannot carry a
verdict. From 20 speeds up the held-out error decides (:mod:`.many`), the rule the withheld-effect
benchmark was validated on; it costs no Hessian per candidate (a Laplace evidence costs about
2k more model runs for each of 10-20 candidates, and a diagnosis must stay under 30 s). But a
held-out third of 7-13 points can favour a fit by chance: a fit that misses the training points
more than five other explanations can still win the held-out score (a water world, seed 8004 of
the blind generator: calibration+flash_temperature rms 0.029 on the training points against
0.020-0.022 for five others, 0.016 held out, named with confidence high). So the held-out
verdict is checked against the evidence the few-point regime uses, in the form the Laplace
evidence takes at many points (Schwarz 1978, Ann. Stat. 6, 461, doi:10.1214/aos/1176344136;
Kass & Raftery 1995, J. Am. Stat. Assoc. 90, 773, doi:10.1080/01621459.1995.10476572, sec 4.1)

    ln Z_M  ~  ln L(RSS_M) - k_M / 2 ln n,

with the same Student-t likelihood and noise scale as :mod:`pipelines.diagnosis.fit.evidence`
(:func:`~pipelines.diagnosis.fit.evidence.loglik`), RSS_M over all n points at the candidate's
training fit (its held-out points count against a fit that misses them, as in the held-out
score). Posterior probabilities as in :func:`pipelines.diagnosis.fit.evidence.posteriors`
(prior 1/2 on the baseline: the nominal model, or the calibration of the uncertain inputs;
the other half shared by the single effects tried). The rule is the few-point one (:mod:`.few`):

- an effect is named when it is decided: at least 3 times as probable as every other explanation
  (the baseline included; posterior ``P_NAME`` = 0.9 implies it; below 0.9 confidence low;
  :func:`pipelines.diagnosis.fit.evidence.decisive`); the held-out error is the
  check: the name of the held-out verdict (:func:`.many.decide`) stands when it is decided;
  otherwise the evidence's most probable explanation is named when it is decided, is
  physical, shrinks the held-out gap by ``MIN_SHRINK`` and the held-out points find it no worse
  than their best (within a tenth of the noise); otherwise the held-out name is withdrawn:
  inconclusive between the most probable explanations (together ``P_NAME``, at most three), or
  no effect when the baseline is among them. The same holds when the held-out verdict named
  nothing (held-out rivals the evidence separates), except with ``--uncertain`` ranges, where the
  calibration's verdicts and :func:`.search_few.second_opinion` stand.
- with only q1's default range uncertain (no ``--uncertain``), the nominal fits are compared,
  and on a scan the effects fitted with q1 calibrated between the reliable band's end and the
  measured spectrum's (the input's uncertainty; "no effect" is then the nominal model or that
  calibration alone); q1 calibrated beyond the measured spectrum is fine roughness, so an effect
  fitted with it is a pair (:func:`.same_physics.band_end_pool`). Candidates of one label (an
  effect at the nominal inputs and with the calibration) add their posteriors.
- a named pair gives way to its better single effect unless its evidence is larger by
  ``LOG_STRONG`` = ln 20 (Kass & Raftery's "strong", 2 ln B > 6): the few-point regime names no
  pair.

So from 5 to 60 speeds an effect is named only at posterior >= 0.9 of the same likelihood and
prior; the regimes differ in the evidence's form (Laplace below 20 speeds, Schwarz from 20 up,
the latter's large-n limit) and in the held-out check that only the many-point regime can afford.
``tests/test_diagnose_same_physics.py`` checks that 19 and 20 speeds of one world give the same
verdict for every friction-level effect kind.
"""

from __future__ import annotations

import numpy as np

from pipelines.diagnosis.fit.evidence import P_NAME, loglik, noise_scale

__all__ = ["LOG_STRONG", "all_points_evidence", "check_named", "evidence_posteriors"]

#: ln of the Bayes factor that overturns a held-out verdict (Kass & Raftery 1995: "strong")
LOG_STRONG = float(np.log(20.0))


def all_points_evidence(c, n, noise):
    """Schwarz's approximation of a candidate's log evidence over every point.

    Parameters
    ----------
    c : Candidate
        A fitted candidate; ``c.gap_all`` is its rms log10 residual over all ``n`` points.
    n : int
        Number of measured points, the n of the likelihood and of the penalty k / 2 ln n.
    noise : float
        Rms log10 noise; the likelihood's scale is at least
        :data:`pipelines.diagnosis.fit.evidence.NOISE_FLOOR`.

    Returns
    -------
    float
        ln L(n gap_all^2) - k / 2 ln n (nan when the fit has no finite gap).
    """
    g = float(c.gap_all)
    if not np.isfinite(g):
        return float("nan")
    return loglik(n * g * g, n, noise_scale(noise)) - 0.5 * c.k * float(np.log(n))


def _label(c):
    return "+".join(c.effect_names) or "calibration"


def evidence_posteriors(pool, z_base, n, noise, extra=None):
    """Posterior probabilities over every point of the baseline and the single effects of ``pool``.

    Parameters
    ----------
    pool : list of Candidate
        Fitted explanations of one kind (effects at the nominal inputs, or each with the
        calibration); pairs are left out, except ``extra``.
    z_base : float
        The baseline's log evidence (:func:`all_points_evidence`; the nominal model has k = 0).
    n : int
        Number of measured points, passed to :func:`all_points_evidence`.
    noise : float
        rms of log10(measured / simulated mu) of the measurement, the likelihood's scale.
    extra : Candidate, optional
        A pair to rank with the singles (a named pair).

    Returns
    -------
    p0 : float
        The baseline's posterior.
    ranked : list of (Candidate, float, float)
        (candidate, log evidence, posterior), most probable first.
    """
    from pipelines.diagnosis.fit.evidence import posteriors

    cands = [c for c in pool if len(c.effect_names) == 1 and not c.implausible]
    if extra is not None and extra not in cands:
        cands.append(extra)
    zs = [all_points_evidence(c, n, noise) for c in cands]
    keep = [(c, z) for c, z in zip(cands, zs) if np.isfinite(z)]
    p0, ps = posteriors(dict(log_z=z_base), [dict(log_z=z) for _, z in keep])
    ranked = sorted(((c, z, p) for (c, z), p in zip(keep, ps)), key=lambda t: -t[2])
    return p0, ranked


def _parsimony(verdict, best, pool, n, noise, g_ref):
    """A named pair whose evidence over every point does not exceed its best single's by
    ``LOG_STRONG`` gives way to that single (when it is physical and shrinks the held-out gap by
    ``MIN_SHRINK``)."""
    from pipelines.diagnosis.verdict.many import MIN_SHRINK, _name

    if len(best.effect_names) < 2 or g_ref is None:
        return best
    subs = [
        c
        for c in pool
        if c is not best
        and len(c.effect_names) == 1
        and c.effect_names[0] in best.effect_names
        and not c.implausible
        and c.shrink >= MIN_SHRINK
    ]
    if not subs:
        return best
    one = max(subs, key=lambda c: all_points_evidence(c, n, noise))
    dz = all_points_evidence(best, n, noise) - all_points_evidence(one, n, noise)
    if not dz <= LOG_STRONG:
        return best
    _name(verdict, one, g_ref)
    verdict["reason"] += (
        f"; the pair {best.name} fits every point better by a Bayes factor of only "
        f"e^{dz:.1f} (a strong one is 20): the single effect is named"
    )
    return one


def _record(verdict, p0, ranked, base_name, named):
    verdict["all_points"] = dict(
        method=(
            "posterior probabilities from Schwarz's evidence: ln L (Student-t, the few-point "
            "likelihood) of the training fit over every point - k/2 ln n; prior 1/2 on the baseline"
        ),
        reference=(
            "Schwarz 1978, doi:10.1214/aos/1176344136; Kass & Raftery 1995, "
            "doi:10.1080/01621459.1995.10476572"
        ),
        named_by_heldout=named,
        threshold=P_NAME,
        models=[dict(name=base_name, posterior=p0)]
        + [dict(name=c.name, log_evidence=z, k=c.k, posterior=p) for c, z, p in ranked[:8]],
    )


def _merged(ranked):
    """Posterior per explanation: an effect fitted at the nominal inputs and with the calibration
    of a default q1 range is one explanation (their posteriors add). Returns [(label, p, the
    candidate of higher evidence, its log evidence)], most probable first."""
    out = {}
    for c, z, p in ranked:
        lab = _label(c)
        q, top, zt = out.get(lab, (0.0, c, z))
        out[lab] = (q + p, top if zt >= z else c, max(zt, z))
    return sorted(((lab, q, c, z) for lab, (q, c, z) in out.items()), key=lambda t: -t[1])


def _decided(merged, p0):
    """Whether the first of ``merged`` is decided against the baseline (posterior ``p0``) and every
    other explanation: 3 times as probable as each (:func:`.evidence.decisive`)."""
    from pipelines.diagnosis.fit.evidence import decisive

    if not merged:
        return False
    return decisive(merged[0][1], [p0] + [m[1] for m in merged[1:]])


def check_named(
    verdict, best, pool, n, noise, z_base, g_ref=None, base_name="nominal", rescue=False, intervals=None
):
    """The held-out verdict under the evidence over every point (see the module docstring).

    Parameters
    ----------
    verdict : dict
        The verdict of :func:`.many.decide`; changed in place when the evidence withdraws the
        name or names another explanation. Its ``all_points`` entry (moved into
        ``verdict.evidence`` by the caller) lists the posteriors.
    best : Candidate or None
        The named candidate.
    pool : list of Candidate
        The explanations compared (effects at the nominal inputs, and each with the calibration
        of the uncertain inputs when they are compared too).
    n : int
        Number of measured points, passed to :func:`all_points_evidence`.
    noise : float
        rms of log10(measured / simulated mu) of the measurement, the likelihood's scale.
    z_base : float
        The baseline's log evidence over every point (:func:`all_points_evidence`).
    g_ref : float, optional
        The baseline held-out gap (the reference of a verdict the evidence names; None: the
        evidence only withdraws names).
    base_name : str, optional
        The baseline's name ("nominal" or "calibration").
    rescue : bool, optional
        Let the evidence name an explanation when the held-out verdict named none.
    intervals : callable, optional
        ``intervals(c)``: the calibrated inputs of a candidate with their intervals.

    Returns
    -------
    Candidate or None
        The named candidate after the check, or None.
    """
    from pipelines.diagnosis.verdict.many import MIN_SHRINK, _name, unname

    if best is not None and not best.effect_names:
        return best
    if best is not None:
        best = _parsimony(verdict, best, pool, n, noise, g_ref)
    pair = best if best is not None and len(best.effect_names) > 1 else None
    p0, ranked = evidence_posteriors(pool, z_base, n, noise, extra=pair)
    _record(verdict, p0, ranked, base_name, None if best is None else best.name)
    merged = _merged(ranked)
    name0 = None if best is None else _label(best)
    p_best = next((q for lab, q, _, _ in merged if lab == name0), 0.0)
    decided = _decided(merged, p0)
    if best is not None and (p_best >= P_NAME or (decided and merged[0][0] == name0)):
        if p_best < P_NAME:
            verdict["confidence"] = "low"
            verdict["_below_p_name"] = True  # next_measurement.withdraw_unseparated reads it
            verdict["reason"] += (
                f"; over every point its posterior is {p_best:.2f}, below {P_NAME:g}, but at least 3 "
                f"times that of every other explanation"
            )
        return best
    # the evidence's own choice, checked by the held-out points: it shrinks the held-out gap by
    # MIN_SHRINK and the held-out points find it no worse than the best of them (within 0.1 noise)
    held = [c.gap_heldout for c in pool if np.isfinite(c.gap_heldout)]
    if merged and g_ref is not None and (best is not None or rescue) and decided and held:
        lab, p, c, _ = merged[0]
        if c.shrink >= MIN_SHRINK and c.gap_heldout <= min(held) + 0.1 * noise:
            verdict.update(inconclusive=[], implausible=[], implausible_why=[])
            cal = "calibration" in c.effects[0].name
            _name(verdict, c, g_ref, calibrated=intervals(c) if cal and intervals is not None else None)
            verdict["reason"] += (
                f"; the most probable explanation over every point (posterior {p:.3f}"
                + (f"; the held-out score preferred {name0}, posterior {p_best:.2f}" if name0 else "")
                + ")"
            )
            if p < P_NAME:
                verdict["confidence"] = "low"
                verdict["_below_p_name"] = True
                verdict["reason"] += "; at least 3 times as probable as every other explanation"
            return c
    if best is None:
        return None
    acc, names = 0.0, []
    order = sorted([(base_name, p0)] + [(m[0], m[1]) for m in merged], key=lambda t: -t[1])
    for lab, q in order:
        if len(names) >= 3 or acc >= P_NAME:
            break
        names.append(lab)
        acc += q
    listed = ", ".join(f"{lab} {q:.2f}" for lab, q in order[:3])
    unname(verdict, [])
    if base_name in names or len(names) < 2:
        verdict["reason"] = (
            f"no effect named: {name0} wins the held-out points but its posterior over "
            f"every point is {p_best:.2f} < {P_NAME:g} ({listed})"
        )
        return None
    verdict["inconclusive"] = names
    verdict["reason"] = (
        f"inconclusive: {name0} wins the held-out points, but over every point "
        f"{listed}: none reaches posterior {P_NAME:g}"
    )
    return None
