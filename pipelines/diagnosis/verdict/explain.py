"""The explanations behind a verdict: the evidence it rests on and the two most probable ones
(the pair :mod:`.next_measurement` tells apart)."""

from __future__ import annotations

import numpy as np

__all__ = ["heldout_evidence", "top_two", "pick_pair"]


def _f(x):
    return None if x is None or not np.isfinite(x) else float(x)


def heldout_evidence(ho, g_ho, ranked, best, top=6):
    """``verdict.evidence`` of a held-out verdict (20 points or more): the method and the held-out
    numbers of the best-scored candidates.

    Parameters
    ----------
    ho : Holdout
        The hold-out scheme; its description opens ``method``.
    g_ho : float
        The baseline's held-out gap, rms of log10(measured / simulated mu) at the held-out rows.
    ranked : list of Candidate
        Candidates, best first.
    best : Candidate or None
        The candidate the verdict names; None: ``named`` is None.
    top : int, optional
        Number of best-ranked candidates listed (default 6).

    Returns
    -------
    dict
        method, reference, baseline_gap_heldout, named and candidates (name, k, gap_heldout,
        shrink, shrink_interval, score; non-finite numbers as None).
    """
    rows = [
        dict(
            name=c.name,
            k=c.k,
            gap_heldout=_f(c.gap_heldout),
            shrink=_f(c.shrink),
            shrink_interval=[_f(x) for x in c.shrink_interval],
            score=_f(c.score),
            shrink_beyond_calibration=_f(getattr(c, "beyond", None)),
        )
        for c in ranked[:top]
    ]
    return dict(
        method="held-out error: " + ho.description + "; shrink of the held-out gap with a paired "
        "5-95 % bootstrap interval; score = held-out rms x (1 + k / n_train) x 1.08^k",
        reference="Hastie, Tibshirani & Friedman 2009, The elements of statistical learning, 2nd ed., "
        "sec 7.10; Efron & Tibshirani 1993, An introduction to the bootstrap",
        baseline_gap_heldout=_f(g_ho),
        named=None if best is None else best.name,
        candidates=rows,
    )


def _by_name(name, singles, pairs, cal, calpairs):
    if name == "calibration":
        return cal
    for c in calpairs:
        if "+".join(c.effect_names) == name:
            return c
    for c in list(singles) + list(pairs):
        if c.name == name:
            return c
    return None


def top_two(ctx, real_mu, noise, verdict, best, expl, singles, pairs, cal, calpairs):
    """The two most probable explanations as dicts(name, candidate, H), or None.

    Few points (``expl`` given, ranked by posterior): its first two. Held-out verdicts: the
    inconclusive pair; else the named (or best-scored) candidate and the best-scored one that
    does not share its effects (the calibration when the named fit carries it).

    Parameters
    ----------
    ctx : FrictionContext
        The context the candidates were fitted on.
    real_mu : ndarray, shape (n,)
        Measured mu at every row.
    noise : float
        rms log10 noise: the scale of the evidence whose Hessian H is returned.
    verdict : dict
        The verdict so far (its ``inconclusive`` names, if any, are the pair).
    best : Candidate or None
        The candidate the verdict names; None: the best-scored one leads.
    expl : list or None
        Explanations ranked by posterior (few points).
    singles, pairs, cal, calpairs : list or Candidate
        The held-out search's fits: single effects, greedy pairs, the calibration alone (or None)
        and each effect with the calibration.

    Returns
    -------
    tuple of dict or None
        Two dicts (name, candidate, H: the Gauss-Newton Hessian in the unit cube); None without two.
    """
    from pipelines.diagnosis.fit.evidence import model_evidence

    if expl is not None:
        return (expl[0], expl[1]) if len(expl) > 1 else None
    pool = sorted(
        list(singles) + list(pairs) + ([cal] if cal else []) + list(calpairs), key=lambda c: c.score
    )
    inc = verdict.get("inconclusive") or []
    cands = [_by_name(n, singles, pairs, cal, calpairs) for n in inc[:2]]
    if len(cands) < 2 or any(c is None for c in cands):
        first = best if best is not None else (pool[0] if pool else None)
        if first is None:
            return None
        names = set(first.effect_names)
        # an alternative at its effect's no-effect point is the calibration itself, not another one
        other = next(
            (c for c in pool if c is not first and not set(c.effect_names) & names and not _at_null(ctx, c)),
            None,
        )
        if other is None:
            return None
        cands = [first, other]
    out = []
    for c in cands:
        ev = model_evidence(ctx, real_mu, c, noise)
        out.append(dict(name="+".join(c.effect_names) or "calibration", candidate=c, H=ev["H"]))
    return tuple(out)


def _at_null(ctx, c):
    """Whether a calibration+effect fit sits at its effect's "no effect" point (it is then the
    calibration itself, not a distinct explanation)."""
    from pipelines.diagnosis.fit.fitting import null_u, pack

    if c is None:
        return False
    effs = [(e, p) for e, p in zip(c.effects, c.params) if e.name != "calibration"]
    if not effs:
        return False
    es, ps = zip(*effs)
    nu = null_u(ctx, es)
    return nu is not None and float(np.max(np.abs(np.clip(pack(es, ps), 0, 1) - nu))) <= 0.02


def pick_pair(ctx, expl, s, n_alt=3):
    """The most probable explanation of ``expl`` (ranked by posterior) and, ranked, up to
    ``n_alt`` next ones that are not it at their no-effect point (:func:`next_measurement`
    takes the first that differs from it by a noise sigma). None when there is none.

    Parameters
    ----------
    ctx : FrictionContext
        The context the explanations were fitted on (their no-effect points).
    expl : list of dict
        Explanations ranked by posterior.
    s : float
        Noise scale of the evidence, rms log10 (not used by the choice itself).
    n_alt : int, optional
        Alternatives kept at most.

    Returns
    -------
    tuple or None
        (the most probable explanation, list of alternatives).
    """
    if not expl:
        return None
    a = expl[0]
    alts = [b for b in expl[1:] if a["candidate"] is None or not _at_null(ctx, b["candidate"])]
    alts = [
        b for b in alts if not (_at_null(ctx, a["candidate"]) and b["name"] in ("calibration", "nominal"))
    ]
    return (a, alts[:n_alt]) if alts else None
