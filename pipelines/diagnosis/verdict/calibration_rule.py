"""The ``"calibration"`` verdict with ``--uncertain`` ranges (20 points or more): the few-point rule.

When no effect fitted together with the calibration of the uncertain inputs adds a held-out
shrink (:func:`.many.decide`), the calibration is the candidate answer. Its rivals are the
effects fitted together with that calibration, the explanations the evidence compares under the
user's own ranges (an effect fitted at the nominal inputs is the same explanation with the
inputs pinned at values the user called uncertain, a point of the calibration+effect model, so
the latter's evidence already accounts for it). They are compared as :mod:`.few` compares them
below 20 points, with the evidence over every point in the form it takes at many points
(:func:`.evidence_check.all_points_evidence`, Schwarz 1978, doi:10.1214/aos/1176344136; prior 1/2
on the calibration, the other half shared by the effects):

- ``"calibration"`` when it is the most probable explanation and no effect's Bayes factor
  against it reaches 3 (Kass & Raftery 1995, doi:10.1080/01621459.1995.10476572: "not worth more
  than a bare mention"); confidence high at posterior >= ``P_NAME``, medium at >= 0.5, else low;
  low when an input sits on a bound of its range or the held-out shrink interval reaches below
  ``MIN_SHRINK``;
- otherwise inconclusive between the most probable explanations (together ``P_NAME``, at most
  three; the calibration among them when the held-out points found no effect that adds to it).

The rule is the few-point one (:func:`.few.decide_few`), so "calibration" means the same from 5
to 60 speeds; it replaces a held-out tie test against effects fitted at the nominal inputs whose
fixed margin (a tenth of the noise) flipped the verdict of one compound between "calibration"
and "inconclusive" as the stated inputs moved within the ranges that contain the truth.
"""

from __future__ import annotations

import numpy as np

from pipelines.diagnosis.fit.evidence import P_NAME, loglik, noise_scale, posteriors

__all__ = ["calibration_by_evidence", "LOG_POSITIVE"]

#: ln 3: the Bayes factor below which an effect is "not worth more than a bare mention"
LOG_POSITIVE = float(np.log(3.0))


def _label(c):
    return "+".join(c.effect_names) or "calibration"


def _schwarz(c, n, noise):
    """ln L(n gap_all^2) - k / 2 ln n: :func:`.evidence_check.all_points_evidence` (the same
    likelihood; written here as that module imports :mod:`.many`, which calls this one)."""
    g = float(c.gap_all)
    if not np.isfinite(g):
        return float("nan")
    return loglik(n * g * g, n, noise_scale(noise)) - 0.5 * c.k * float(np.log(n))


def calibration_by_evidence(v, cal, calpairs, st, intervals, g_ho, min_shrink, prefix=""):
    """The verdict between the calibration alone and each effect fitted with it (module docstring).

    Parameters
    ----------
    v : dict
        The verdict being built (:func:`.many._empty`); filled in place.
    cal : Candidate
        The calibration of the uncertain inputs alone (physical, held-out shrink >= MIN_SHRINK).
    calpairs : list of Candidate
        Each usable effect fitted together with the calibration.
    st : dict
        ``n`` (measured points) and ``noise`` (rms log10) of :func:`.many.decide`.
    intervals : callable
        ``intervals(c)``: the calibrated inputs of a candidate with their 95 % intervals.
    g_ho : float
        The baseline's held-out gap (rms log10).
    min_shrink : float
        The held-out shrink below which the calibration's interval makes its confidence low
        (:data:`.many.MIN_SHRINK`).
    prefix : str, optional
        Reason text put first (an implausible effect refused before).

    Returns
    -------
    verdict : dict
        ``v`` itself: reason and all_points set, and either effect "calibration" with its confidence
        and calibrated inputs, or inconclusive names.
    named : Candidate or None
        ``cal`` when the verdict is ``"calibration"``, else None (inconclusive).
    """
    n, noise = st["n"], st["noise"]
    z_cal = _schwarz(cal, n, noise)
    pool = [c for c in calpairs if len(c.effect_names) == 1 and not c.implausible]
    zs = [(c, _schwarz(c, n, noise)) for c in pool]
    zs = [(c, z) for c, z in zs if np.isfinite(z)]
    p0, ps = posteriors(dict(log_z=z_cal), [dict(log_z=z) for _, z in zs])
    ranked = sorted(((c, z, p) for (c, z), p in zip(zs, ps)), key=lambda t: -t[2])
    v["all_points"] = dict(
        method="posterior probabilities from Schwarz's evidence: ln L (Student-t, the few-point likelihood) "
        "of the training fit over every point - k/2 ln n; prior 1/2 on the calibration",
        reference="Schwarz 1978, doi:10.1214/aos/1176344136; Kass & Raftery 1995, "
        "doi:10.1080/01621459.1995.10476572",
        named_by_heldout=None,
        threshold=P_NAME,
        models=[dict(name="calibration", posterior=p0)]
        + [dict(name=c.name, log_evidence=z, k=c.k, posterior=p) for c, z, p in ranked[:8]],
    )
    lbf = max((z - z_cal for _, z, _ in ranked), default=-np.inf)
    top = ranked[0] if ranked else None
    if (top is None or p0 >= top[2]) and lbf < LOG_POSITIVE:
        lo = cal.shrink_interval[0]
        conf = "high" if p0 >= P_NAME else "medium" if p0 >= 0.5 else "low"
        if cal.at_bound or (np.isfinite(lo) and lo < min_shrink):
            conf = "low"
        v["effect"] = "calibration"
        v["shrink"] = cal.shrink
        v["shrink_interval"] = list(cal.shrink_interval)
        v["at_bound"] = list(cal.at_bound)
        v["confidence"] = conf
        v["calibrated"] = intervals(cal)
        best = "" if top is None else f"; best effect with it {_label(top[0])}, Bayes factor e^{lbf:.1f}"
        v["reason"] = prefix + (
            f"the inputs within their ranges explain the gap: the calibration shrinks the held-out gap "
            f"from {g_ho:.4f} to {cal.gap_heldout:.4f}; over every point it is the most probable "
            f"explanation (posterior {p0:.2f}) and no effect fitted with it reaches a Bayes factor of 3"
            + best
        )
        return v, cal
    order = sorted([("calibration", p0)] + [(_label(c), p) for c, _, p in ranked], key=lambda t: -t[1])
    acc, names = 0.0, []
    for lab, p in order:
        if len(names) >= 3 or acc >= P_NAME:
            break
        names.append(lab)
        acc += p
    if len(names) < 2:
        names.append(next(lab for lab, _ in order if lab not in names))
    v["inconclusive"] = names
    why = (
        f"{_label(top[0])} fitted with the calibration is more probable than it"
        if p0 < top[2]
        else f"an effect fitted with the calibration reaches a Bayes factor of e^{lbf:.1f} >= 3 against it"
    )
    v["reason"] = prefix + (
        "inconclusive over every point: "
        + ", ".join(f"{lab} (posterior {p:.2f})" for lab, p in order[: len(names)])
        + f"; {why}, while the held-out points find no effect that adds to the calibration"
    )
    return v, None
