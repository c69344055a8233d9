"""Surface level: k-fold fits over blocks, per-family gaps, the verdict.

Gap. For a set S of blocks, family f with entries j, the residual of a prediction m(theta) is
z_fj = (mean_{b in S} d_bj - m_j(theta)) / (sigma_fj / sqrt(|S|)), sigma_fj the per-block noise
of the entry (:mod:`pipelines.diagnosis.surface.level`). A family's gap g_f is the rms of z over its
entries (and folds); the total gap is sqrt(mean_f g_f^2): every family weighs the same,
whatever its number of entries. Under "model right, noise only" g_f^2 is about 1.

Held out in space (k-fold). Each block in turn is held out: the effect's parameters are fitted
(bounded least squares on the family-weighted z of the other blocks, started from the effect's
"no effect" parameters and a coarse grid; a result worse than the start on the training blocks
is rejected) and the residual of the held-out block is scored. Held-out family gaps pool every
fold. The systematic part of a gap is E = mean_f max(g_f^2 - 1, 0) (the noise's own share
removed); the shrink of a candidate is 1 - sqrt(E_after / E_before), with a bootstrap interval
over folds; ``shrink_raw`` = 1 - G_after / G_before on the total gaps.

Verdict. "No effect" when no family's baseline gap is significant (chi-square over its
held-out z, p < 1e-3, and g_f > 1.5) or no candidate shrinks the systematic gap by
``MIN_SHRINK``. Every pair of single effects is fitted (started from the two single fits). A pair replaces the
best single when the single leaves a significant family and the pair's score is lower by ``PAIR_GAIN`` and its
shrink higher by ``PAIR_MIN_GAIN``. "Inconclusive" (no effect named, the competitors listed) when another
single explains the gap as well within the fold-to-fold scatter.
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from pipelines.diagnosis.fit.fitting import pack
from pipelines.diagnosis.fit.fitting import unpack as _unpack
from pipelines.diagnosis.surface.blocks import spectrum_shape

__all__ = ["surface_search", "MIN_SHRINK"]

MIN_SHRINK = 0.4
PAIR_GAIN = 0.85
PAIR_MIN_GAIN = 0.15
OCCAM = 1.05
SIG_P = 1e-3
SIG_RATIO = 1.5
AT_BOUND_TOL = 1e-3


def _predict(ctx, effs, params):
    pred = dict(ctx.twin_mean, spec_rings=ctx.twin_rings.copy())
    for e, p in zip(effs, params):
        pred = e.apply_fn(ctx, p, pred)
    pred["spectrum"] = spectrum_shape(ctx.geo.band_matrix @ pred["spec_rings"])
    return pred


def _z(ctx, pred, blocks):
    """dict family -> z vector for the mean over ``blocks`` (indices)."""
    n = len(blocks)
    return {
        f: (ctx.meas[f][blocks].mean(axis=0) - pred[f]) / (ctx.sigma[f] / np.sqrt(n)) for f in ctx.families
    }


def _train_resid(ctx, pred, blocks):
    z = _z(ctx, pred, blocks)
    return np.concatenate([z[f] / np.sqrt(z[f].size) for f in ctx.families])


def _pack(effs, params):
    return np.clip(pack(effs, params), 0, 1)


def _fit(ctx, effs, blocks, starts):
    """Bounded least squares from several starts; never worse than the first start (the null)."""
    from pipelines.diagnosis.fit.stats import multistart_lsq

    def res(u):
        return _train_resid(ctx, _predict(ctx, effs, _unpack(effs, u)), blocks)

    return multistart_lsq(res, starts, diff_step=1e-3, max_nfev=100)[0]


def _starts(ctx, effs, blocks, extra=None):
    null = _pack(effs, [e.null_params(ctx) or {p.name: p.init for p in e.params} for e in effs])
    k = null.size
    per = {1: 9, 2: 5}.get(k, 3)
    grid = np.array(np.meshgrid(*([np.linspace(0.02, 0.98, per)] * k), indexing="ij")).reshape(k, -1).T
    costs = [
        float(np.sum(_train_resid(ctx, _predict(ctx, effs, _unpack(effs, g)), blocks) ** 2)) for g in grid
    ]
    order = np.argsort(costs)[:3]
    out = [null] + ([extra] if extra is not None else []) + [grid[i] for i in order]
    return out


def _evaluate(ctx, effs, starts_all=None):
    """Fit on all blocks (reported parameters) and k-fold (held-out z per fold)."""
    B = ctx.n_blocks
    allb = np.arange(B)
    u_all = _fit(ctx, effs, allb, _starts(ctx, effs, allb, starts_all))
    folds = []
    for k in range(B):
        tr = np.delete(allb, k)
        u = _fit(
            ctx,
            effs,
            tr,
            [_pack(effs, [e.null_params(ctx) or {p.name: p.init for p in e.params} for e in effs]), u_all]
            + _starts(ctx, effs, tr)[1:2],
        )
        folds.append(_z(ctx, _predict(ctx, effs, _unpack(effs, u)), [k]))
        folds[-1]["_train"] = _train_resid(ctx, _predict(ctx, effs, _unpack(effs, u)), tr)
    return u_all, folds


def _family_sq(ctx, folds):
    """(n_folds, n_families) sums of z^2 and entry counts."""
    S = np.array([[float(np.sum(fz[f] ** 2)) for f in ctx.families] for fz in folds])
    n = np.array([fz[f].size for f in ctx.families for fz in folds[:1]], float)
    return S, n


def _gaps(S, n):
    g2 = S.sum(axis=0) / (n * S.shape[0])
    return g2


def _systematic(g2):
    return float(np.mean(np.maximum(g2 - 1.0, 0.0)))


def _shrink(g2_before, g2_after):
    eb, ea = _systematic(g2_before), _systematic(g2_after)
    return 1.0 - np.sqrt(ea / eb) if eb > 0 else float("nan")


def surface_search(ctx, rng_seed=0):
    """Run every usable surface effect (and greedy pairs); returns a dict with the baseline,
    the candidates (best first) and the verdict (see module docstring).

    Parameters
    ----------
    ctx : SurfaceContext
        The blocks' measured descriptors, the twins' prediction and noise (:func:`level.descriptors`).
    rng_seed : int, optional
        Seed of the 400 bootstrap resamples of the blocks behind the shrink intervals (default 0).

    Returns
    -------
    dict
        baseline_gap (held-out, in noise units), families, candidates (best first), skipped,
        verdict, best (the named candidate's dict or None) and significant.
    """
    from pipelines.diagnosis.effects import all_effects

    fams = ctx.families
    B = ctx.n_blocks
    base_pred = _predict(ctx, (), [])
    base_folds = [_z(ctx, base_pred, [k]) for k in range(B)]
    S0, nent = _family_sq(ctx, base_folds)
    g2_0 = _gaps(S0, nent)
    fam_p = [float(stats.chi2.sf(S0[:, i].sum(), nent[i] * B)) for i in range(len(fams))]
    fam_sig = [bool(p < SIG_P and np.sqrt(g) > SIG_RATIO) for p, g in zip(fam_p, g2_0)]
    G0 = float(np.sqrt(np.mean(g2_0)))
    n_train = float(np.sum(nent) * (B - 1))

    usable, skipped = [], []
    for e in all_effects("surface"):
        miss = sorted(set(e.requires) - ctx.inputs)
        if miss:
            skipped.append(dict(name=e.name, reason=f"needs {', '.join(miss)} (a line profile has none)"))
            continue
        usable.append(e)

    rng = np.random.default_rng(rng_seed)
    boot = rng.integers(0, B, size=(400, B))

    def candidate(effs, start=None):
        u_all, folds = _evaluate(ctx, effs, start)
        S, _ = _family_sq(ctx, folds)
        g2 = _gaps(S, nent)
        G = float(np.sqrt(np.mean(g2)))
        k = sum(len(e.params) for e in effs)
        params = _unpack(effs, u_all)
        flat, at_bound = {}, []
        for e, p in zip(effs, params):
            for pp in e.params:
                key = pp.name if len(effs) == 1 else f"{e.name}.{pp.name}"
                flat[key] = p[pp.name]
                u = pp.to_unit(p[pp.name])
                null = (e.null_params(ctx) or {}).get(pp.name)
                if (u <= AT_BOUND_TOL or u >= 1 - AT_BOUND_TOL) and not (
                    null is not None and abs(u - pp.to_unit(null)) <= AT_BOUND_TOL
                ):
                    at_bound.append(key)
        gtr = float(np.sqrt(np.mean([np.sum(f["_train"] ** 2) for f in folds]) / len(fams)))
        bs = []
        for idx in boot:
            a, b = _gaps(S0[idx], nent), _gaps(S[idx], nent)
            bs.append(_shrink(a, b))
        bs = np.array(bs, float)
        bs = bs[np.isfinite(bs)]
        return dict(
            name="+".join(e.name for e in effs),
            params=flat,
            n_params=k,
            gap_train=gtr,
            gap_heldout=G,
            shrink=_shrink(g2_0, g2),
            shrink_raw=1 - G / G0 if G0 > 0 else None,
            shrink_interval=[float(np.percentile(bs, 5)), float(np.percentile(bs, 95))]
            if bs.size
            else [None, None],
            score=G * (1 + k / n_train) * OCCAM**k,
            family_gaps={f: float(np.sqrt(g)) for f, g in zip(fams, g2)},
            at_bound=at_bound,
            _effs=effs,
            _u=u_all,
            _g2=g2,
            _fold=S.sum(axis=1) / np.sum(nent),
            _params=params,
        )

    singles = sorted((candidate((e,)) for e in usable), key=lambda c: c["score"])
    cands = list(singles)
    if singles and any(fam_sig):
        # every pair (not only the best single's): when two families are off, the best single
        # alone may be no better than the others, and a greedy pair would start from noise
        for i, a in enumerate(singles):
            for b in singles[i + 1 :]:
                cands.append(candidate(a["_effs"] + b["_effs"], np.concatenate([a["_u"], b["_u"]])))
    cands.sort(key=lambda c: c["score"])

    verdict = dict(
        effect=None,
        shrink=None,
        shrink_interval=None,
        gap_validate=None,
        reason="",
        inconclusive=[],
        at_bound=[],
        confidence=None,
    )
    best = None
    if not any(fam_sig):
        verdict["reason"] = (
            "no descriptor family's held-out gap is beyond its noise "
            f"(largest {max(np.sqrt(g2_0)):.2f} noise units)"
        )
    elif not singles:
        verdict["reason"] = "no usable effect"
    else:
        s1 = singles[0]
        best = s1
        pairs = [c for c in cands if "+" in c["name"]]
        if pairs:
            bp = min(pairs, key=lambda c: c["score"])
            left = _left_significant(s1, nent, B)
            # a pair must beat the single clearly; when no single reaches MIN_SHRINK, a pair that
            # does only needs a lower score
            gain = PAIR_GAIN if s1["shrink"] >= MIN_SHRINK else 1.0
            if left and bp["score"] < gain * s1["score"] and bp["shrink"] > s1["shrink"] + PAIR_MIN_GAIN:
                best = bp
        if not (best["shrink"] >= MIN_SHRINK):
            verdict["reason"] = (
                f"no effect shrinks the systematic held-out gap by {MIN_SHRINK:.0%} "
                f"(best {best['name']}: {best['shrink']:.0%})"
            )
            best = None
        else:
            rivals = _rivals(best, singles, B)
            if rivals:
                verdict["inconclusive"] = [best["name"]] + [r["name"] for r in rivals]
                verdict["reason"] = (
                    "inconclusive: "
                    + ", ".join(verdict["inconclusive"])
                    + " explain the gap equally well within the block-to-block scatter"
                )
                best = None
            else:
                names = [e.name for e in best["_effs"]]
                lo = best["shrink_interval"][0]
                conf = "high"
                if best["at_bound"] or (lo is not None and lo < MIN_SHRINK):
                    conf = "medium"
                if best["at_bound"] and (lo is not None and lo < MIN_SHRINK):
                    conf = "low"
                verdict.update(
                    effect=names[0] if len(names) == 1 else names,
                    shrink=best["shrink"],
                    shrink_interval=best["shrink_interval"],
                    at_bound=best["at_bound"],
                    confidence=conf,
                    reason=(
                        f"{best['name']} shrinks the systematic held-out gap by "
                        f"{best['shrink']:.0%} (total {G0:.2f} -> {best['gap_heldout']:.2f} noise units)"
                    ),
                )
    families = {
        f: dict(
            gap_baseline=float(np.sqrt(g2_0[i])),
            p_value=fam_p[i],
            significant=fam_sig[i],
            n_entries=int(nent[i]),
            gap_after=None if best is None else best["family_gaps"][f],
            shrink=(
                None
                if best is None
                else (1 - best["family_gaps"][f] / np.sqrt(g2_0[i]) if g2_0[i] > 0 else None)
            ),
        )
        for i, f in enumerate(fams)
    }
    return dict(
        baseline_gap=G0,
        families=families,
        candidates=cands,
        skipped=skipped,
        verdict=verdict,
        best=best,
        significant=any(fam_sig),
    )


def _left_significant(c, nent, B):
    g2 = c["_g2"]
    for i, g in enumerate(g2):
        if np.sqrt(g) > SIG_RATIO and stats.chi2.sf(g * nent[i] * B, nent[i] * B) < SIG_P:
            return True
    return False


def _rivals(best, singles, B):
    """Other single effects whose held-out gap is within the fold-to-fold standard error of the
    best's (and which also shrink the gap by MIN_SHRINK): equally good explanations."""
    out = []
    for c in singles:
        if c is best or c["name"] == best["name"] or not (c["shrink"] >= MIN_SHRINK):
            continue
        if set(c["name"].split("+")) & set(best["name"].split("+")):
            continue
        d = c["_fold"] - best["_fold"]
        se = float(np.std(d, ddof=1) / np.sqrt(d.size)) if d.size > 1 else 0.0
        if float(np.mean(d)) <= se:
            out.append(c)
    return out
