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
        Hold-out scheme.
    g_ho : float
        Baseline held-out gap.
    ranked : list of Candidate
        Candidates, best first.
    best : Candidate or None
        The named one.
    top : int, optional
        How many are listed.

    Returns
    -------
    dict
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
        Model context.
    real_mu : ndarray
        Measured mu.
    noise : float
        Noise.
    verdict : dict
        The verdict.
    best : Candidate or None
        Named candidate.
    expl : list or None
        Explanations ranked by posterior (few points).
    singles, pairs, cal, calpairs : list or Candidate
        The candidates.

    Returns
    -------
    tuple of dict or None
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
        Model context.
    expl : list of dict
        Explanations ranked by posterior.
    s : float
        Noise scale.
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
