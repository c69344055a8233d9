"""The verdict of a friction-level diagnosis from its fitted, held-out-scored candidates.

Without uncertain inputs: the baseline gap over all points must be significant against the noise
(chi-square p < 1e-3 and gap > 1.3 x noise, :func:`gap.is_significant`) and the best-scored
candidate must shrink the held-out gap by at least ``MIN_SHRINK``. A pair is preferred to the
best single only when the single leaves a gap still significant against the noise and the pair's
score is lower by at least ``PAIR_GAIN``. Another single explaining the held-out points equally
well within the noise (:func:`rivals`) makes the verdict inconclusive.

With uncertain inputs (:mod:`.calibration`) the reference is the calibrated model: an effect is
named only when, fitted together with the calibration, it shrinks the calibrated model's
held-out gap by ``MIN_SHRINK`` more (its paired bootstrap interval above 0) while the calibrated
gap is still significant against the noise; among effects that do so equally well, the one whose
fit at the nominal inputs is clearly the best is preferred (the nominal values are the most likely
within their ranges), else the verdict is inconclusive. Otherwise, when the calibration alone shrinks the
baseline's held-out gap by ``MIN_SHRINK``, the verdict is ``"calibration"`` (``calibrated``: the
fitted inputs with approximate 95 % intervals), or inconclusive when an effect alone explains
the held-out points as well (``inconclusive`` then names it and ``"calibration"``); with ranges
the user gave, the calibration is weighed against the effects fitted with it by the evidence over
every point instead (:mod:`.calibration_rule`, the few-point rule). When only
the default q1 range is uncertain (no ``--uncertain``), the inputs as given are believed first:
the verdict at them (as without uncertain inputs) stands when it names an effect, with confidence
low when calibrating q1 alone explains the held-out points as well; otherwise the calibrated
verdict applies.

Never named: a fit with a parameter outside its physical range (``implausible``, see
:mod:`.effects`). Confidence: high; low when the shrink interval reaches below ``MIN_SHRINK`` or
a parameter sits on a bound of its range; medium when a temperature is extrapolated beyond the
shift table.
"""

from __future__ import annotations

import numpy as np

from pipelines.diagnosis import gap as gapmod
from pipelines.diagnosis.fit.cv import boot_shrink

__all__ = ["decide", "rivals", "MIN_SHRINK", "PAIR_GAIN"]

MIN_SHRINK = 0.25
PAIR_GAIN = 0.85


def rivals(best, pool, noise, names=None, margin=0.1, tie=0.0):
    """Candidates of ``pool`` (not sharing an effect with ``best``) explaining the held-out points
    as well within the noise: their mean squared held-out residual exceeds the best's by less than
    a quarter of its paired standard error (or their held-out gaps differ by at most ``tie`` x the
    noise), and their held-out gap by less than ``margin`` x the noise.

    Parameters
    ----------
    best : Candidate
        The best-scored candidate, with held-out residuals ``r_held``.
    pool : list of Candidate
        Candidates to compare; those shrinking the held-out gap by less than ``MIN_SHRINK`` are skipped.
    noise : float
        rms log10 noise of the measurement, the unit of ``margin`` and ``tie``.
    names : iterable of str, optional
        Effect names a rival must not share; None: the effects of ``best``.
    margin : float, optional
        Largest excess of a rival's held-out gap over the best's, in units of the noise.
    tie : float, optional
        Held-out gaps within ``tie`` x noise count as equal whatever the standard error (0: off).

    Returns
    -------
    list of Candidate
        The rivals, in the order of ``pool``.
    """
    out = []
    names = set(best.effect_names) if names is None else names
    for c in pool:
        if c is best or set(c.effect_names) & names or not (c.shrink >= MIN_SHRINK):
            continue
        if c.r_held is None or best.r_held is None or c.r_held.size != best.r_held.size:
            continue
        d = c.r_held**2 - best.r_held**2
        se = float(np.std(d, ddof=1) / np.sqrt(d.size)) if d.size > 1 else 0.0
        same = float(np.mean(d)) <= 0.25 * se or c.gap_heldout <= best.gap_heldout + tie * noise
        if same and c.gap_heldout <= best.gap_heldout + margin * noise:
            out.append(c)
    return out


def _empty():
    return dict(
        effect=None,
        shrink=None,
        shrink_interval=None,
        gap_validate=None,
        reason="",
        inconclusive=[],
        at_bound=[],
        confidence=None,
        implausible=[],
        implausible_why=[],
        calibrated={},
        extrapolated=[],
        equivalent_input=None,
    )


def unname(v, inconclusive, reason=None):
    """Withdraw the name of verdict ``v`` in place: no effect, confidence, shrink, calibrated
    inputs, bounds or equivalent input; ``inconclusive`` the explanations left (empty: none) and
    ``reason`` the new reason (None: the caller sets it)."""
    v.update(
        effect=None,
        confidence=None,
        shrink=None,
        shrink_interval=None,
        calibrated={},
        at_bound=[],
        equivalent_input=None,
        inconclusive=list(inconclusive),
    )
    if reason is not None:
        v["reason"] = reason


def _tried(cands):
    names = sorted({c.name for c in cands})
    return f"{len(names)} candidates ({', '.join(names)})" if names else "no candidate"


def _null_reason(cands, s1):
    """What was tried and the best held-out shrink found (not only the best-scored candidate's)."""
    if not cands:
        return "no usable effect"
    top = max(cands, key=lambda c: c.shrink if np.isfinite(c.shrink) else -np.inf)
    return (
        f"no effect shrinks the held-out gap by {MIN_SHRINK:.0%} after the penalty for free parameters; "
        f"tried {_tried(cands)}; best held-out shrink {top.name} {top.shrink:.0%} with {top.k} parameters"
        + ("" if s1 is None or s1 is top else f", best score {s1.name} ({s1.shrink:.0%})")
    )


def _confidence(c, lo):
    conf = "high"
    if getattr(c, "extrapolated", None):
        conf = "medium"
    if (np.isfinite(lo) and lo < MIN_SHRINK) or c.at_bound:
        conf = "low"
    return conf


def _name(v, best, g_ref, ref="baseline", interval=None, calibrated=None):
    lo = (interval or best.shrink_interval)[0]
    names = best.effect_names
    v["effect"] = names[0] if len(names) == 1 else list(names)
    v["shrink"] = best.shrink
    v["shrink_interval"] = list(best.shrink_interval)
    v["at_bound"] = list(best.at_bound)
    v["confidence"] = _confidence(best, lo)
    v["calibrated"] = calibrated or {}
    v["reason"] = (
        f"{'+'.join(names)} shrinks the {ref} held-out gap from {g_ref:.4f} to {best.gap_heldout:.4f}"
    )


def _nominal_tiebreak(group, singles, noise, best, riv):
    """Effects that explain what the calibrated inputs leave equally well: the one whose fit at
    the nominal inputs is clearly better than every other's (no rival there) is preferred, since
    the nominal inputs are the most likely values within their ranges. Returns (best, rivals)."""
    nominal = {c.effects[0].name: c for c in singles}
    fits = [nominal.get(c.effect_names[0]) for c in group]
    if any(f is None for f in fits):
        return best, riv
    top = min(range(len(group)), key=lambda i: fits[i].gap_heldout)
    if not fits[top].shrink >= MIN_SHRINK or fits[top].implausible:
        return best, riv
    # clearly better: every other nominal fit is a quarter of the noise worse, or no fit at all
    if any(
        f is not fits[top] and f.shrink >= MIN_SHRINK and f.gap_heldout < fits[top].gap_heldout + 0.25 * noise
        for f in fits
    ):
        return best, riv
    return group[top], []


def _plausible_nominal(best, singles, cal, noise, boot):
    """The same effect fitted at the nominal inputs, when that fit is physical, explains the
    held-out points as well (within a tenth of the noise) and also shrinks the calibrated model's
    held-out gap by MIN_SHRINK (its paired interval above 0); else ``best`` (the calibrated inputs
    may trade off against an effect's parameters, e.g. q1 against the flash heating)."""
    for c in singles:
        if (
            c.effect_names == best.effect_names
            and not c.implausible
            and c.gap_heldout <= best.gap_heldout + 0.1 * noise
        ):
            c.beyond = 1.0 - c.gap_heldout / cal.gap_heldout if cal.gap_heldout > 0 else float("nan")
            c.beyond_interval = boot_shrink(c.r_held, cal.r_held, boot)
            if c.beyond >= MIN_SHRINK and c.beyond_interval[0] > 0:
                return c
    return best


def _refuse(v, best):
    v["implausible"] = list(best.implausible)
    v["implausible_why"] = list(best.implausible_why)
    return f"{best.name} would explain it but is not physical ({'; '.join(best.implausible_why)}); "


def decide(singles, pairs, cal, calpairs, st, intervals=None):
    """The verdict dict and the named candidate (or None).

    ``singles``/``pairs``: physical effects at the nominal inputs; ``cal``: the calibration alone
    (None without uncertain inputs); ``calpairs``: calibration+effect candidates; ``st``: dict of
    g_all, g_ho, noise, n, significant, p, boot (bootstrap indices); ``intervals(c)`` gives the
    calibrated inputs of a candidate with their intervals.

    Parameters
    ----------
    singles, pairs : list of Candidate
        Effects at the nominal inputs.
    cal : Candidate or None
        The calibration of the uncertain inputs fitted alone; None: no input uncertain.
    calpairs : list of Candidate
        Each effect fitted together with the calibration.
    st : dict
        g_all, g_ho (baseline gaps, rms log10), noise, n, significant, p, boot; default_only (bool).
    intervals : callable, optional
        ``intervals(c)`` -> calibrated inputs of c with their 95 % intervals; None: none reported.

    Returns
    -------
    verdict : dict
        effect, confidence, reason, shrink and the other fields of ``diagnosis.json``'s verdict.
    named : Candidate or None
        The candidate named; None when the gap is within the noise or nothing explains it.
    """
    v = _empty()
    every = list(singles) + list(pairs) + ([cal] if cal else []) + list(calpairs)
    g_all, noise = st["g_all"], st["noise"]
    if not st["significant"]:
        v["reason"] = (
            f"baseline gap {g_all:.4f} is within the noise {noise:.4f} (chi-square p = {st['p']:.3g})"
        )
        return v, None
    if cal is None:
        return _plain(v, singles, pairs, st, every)
    if st.get("default_only"):
        # only the honest default range of q1 is uncertain (no --uncertain): the inputs as given
        # are believed first; an effect named at them keeps its name, with confidence low when
        # calibrating q1 alone closes the gap as well
        v0, b0 = _plain(_empty(), singles, pairs, st, every)
        if b0 is not None:
            # fine roughness is q1 continued (:mod:`.same_physics`): q1's calibration is no rival to it
            if (
                b0.effect_names != ["fine_roughness"]
                and cal.shrink >= MIN_SHRINK
                and cal.gap_heldout <= b0.gap_heldout + 0.1 * noise
            ):
                v0["confidence"] = "low"
                v0["reason"] += "; calibrating q1 within its default range explains it as well"
            return v0, b0
    return _calibrated(v, singles, cal, calpairs, st, every, intervals or (lambda c: {}))


def _plain(v, singles, pairs, st, every):
    noise, n = st["noise"], st["n"]
    if not singles:
        v["reason"] = "no usable effect"
        return v, None
    s1 = singles[0]
    best = s1
    if pairs:
        bp = min(pairs, key=lambda c: c.score)
        still = gapmod.is_significant(s1.gap_all, noise, n, alpha=1e-2, min_ratio=1.2)
        if still and bp.score < PAIR_GAIN * s1.score and bp.shrink > s1.shrink:
            best = bp
    if not (best.shrink >= MIN_SHRINK):
        v["reason"] = _null_reason(every, s1)
        return v, None
    riv = rivals(best, singles, noise)
    if riv:
        v["inconclusive"] = [best.name] + [r.name for r in riv]
        v["reason"] = (
            "inconclusive: "
            + ", ".join(v["inconclusive"])
            + " explain the held-out points equally well within the noise"
        )
        return v, None
    if best.implausible:
        v["reason"] = _refuse(v, best) + "no effect named"
        return v, None
    _name(v, best, st["g_ho"])
    return v, best


def _calibrated(v, singles, cal, calpairs, st, every, intervals):
    noise, g_ho = st["noise"], st["g_ho"]
    still = gapmod.is_significant(cal.gap_heldout, noise, cal.r_held.size, alpha=1e-2, min_ratio=1.2)
    adds = []
    for c in calpairs:
        c.beyond = 1.0 - c.gap_heldout / cal.gap_heldout if cal.gap_heldout > 0 else float("nan")
        c.beyond_interval = boot_shrink(c.r_held, cal.r_held, st["boot"])
        if still and c.beyond >= MIN_SHRINK and c.beyond_interval[0] > 0:
            adds.append(c)
    prefix = ""
    if adds:
        best = min(adds, key=lambda c: c.score)
        # beyond a calibration, two effects whose held-out gaps differ by a few hundredths of the
        # noise are equal whatever their paired scatter
        riv = rivals(best, adds, noise, margin=0.15, tie=0.05)
        if riv:
            best, riv = _nominal_tiebreak([best] + riv, singles, noise, best, riv)
        if riv:
            v["inconclusive"] = [best.effect_names[0]] + [r.effect_names[0] for r in riv]
            v["reason"] = (
                "inconclusive: " + ", ".join(v["inconclusive"]) + " each explain what the calibrated "
                "inputs leave, equally well within the noise"
            )
            return v, None
        if best.implausible:
            best = _plausible_nominal(best, singles, cal, noise, st["boot"])
        if not best.implausible:
            _name(
                v,
                best,
                cal.gap_heldout,
                ref="calibrated model's",
                interval=best.beyond_interval,
                calibrated=intervals(best),
            )
            v["reason"] += (
                f" ({best.beyond:.0%} beyond the calibration of "
                f"{', '.join(p.name for p in cal.effects[0].params)})"
            )
            return v, best
        prefix = _refuse(v, best)
    if cal.shrink >= MIN_SHRINK and not cal.implausible and not st.get("default_only", True):
        # ranges the user gave: the calibration against the effects fitted with it, by the
        # evidence over every point (the few-point rule, :mod:`.calibration_rule`)
        from pipelines.diagnosis.verdict.calibration_rule import calibration_by_evidence

        return calibration_by_evidence(v, cal, calpairs, st, intervals, g_ho, MIN_SHRINK, prefix=prefix)
    if cal.shrink >= MIN_SHRINK and not cal.implausible:
        # an effect that is one of the calibrated inputs (fine_roughness for q1, ...) is no rival
        same = {"q1_per_m": "fine_roughness", "sigma0_Pa": "load", "temperature_C": "temperature_offset"}
        riv = rivals(
            cal, singles, noise, names={same[p.name] for p in cal.effects[0].params if p.name in same}
        )
        if riv:
            v["inconclusive"] = [r.name for r in riv] + ["calibration"]
            v["reason"] = prefix + (
                "inconclusive: "
                + ", ".join(v["inconclusive"])
                + " explain the held-out points equally well within the noise"
            )
            return v, None
        v["effect"] = "calibration"
        v["shrink"] = cal.shrink
        v["shrink_interval"] = list(cal.shrink_interval)
        v["at_bound"] = list(cal.at_bound)
        v["confidence"] = _confidence(cal, cal.shrink_interval[0])
        v["calibrated"] = intervals(cal)
        tried = ", ".join(c.effect_names[0] for c in calpairs) or "none"
        top = max(calpairs, key=lambda c: c.beyond, default=None)
        v["reason"] = prefix + (
            f"the inputs within their ranges explain the gap: the calibration shrinks the held-out gap from "
            f"{g_ho:.4f} to {cal.gap_heldout:.4f}; no effect fitted with it ({tried}) adds a significant "
            f"held-out shrink" + ("" if top is None else f" (best {top.effect_names[0]}: {top.beyond:.0%})")
        )
        return v, cal
    v["reason"] = (
        prefix
        + _null_reason(every, singles[0] if singles else None)
        + (f"; the calibration of the uncertain inputs shrinks it {cal.shrink:.0%}")
    )
    return v, None
