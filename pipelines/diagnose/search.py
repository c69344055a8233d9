"""Which effect explains the gap: bounded fits, held-out ranking, greedy pairs, the verdict.

Fitting: each candidate (one effect, or a pair) has k <= 4 parameters mapped onto the unit cube
(log or linear per parameter, see :class:`effects.Param`). A coarse grid over the cube picks a
start, then ``scipy.optimize.least_squares`` (trust-region reflective, bounded) minimises the
residuals log10(real/sim) on the training points, with forward differences of a fixed step in
the unit cube (the engine's adaptive grid makes tiny steps noisy).

Held-out points: with ``CV_BELOW`` (20) or more points, every third point (indices 1, 4, 7, ...),
never used in a fit. With fewer, k-fold cross-validation over the measured speeds (leave-one-out
up to ``CV_FOLDS`` points; fold i holds points i, i + K, ...): each fold is refitted without its
points (started from the fit on every point) and predicts them; the reported parameters are the
fit on every point. Every fit starts from the effect's "no effect" parameters too and is never
worse than them on its training points; cheap fits of one or two parameters also start from the
three best separated points of the coarse grid (plateaus: limited water, contact correction).
The shrink has a 5-95 % bootstrap interval over the held-out points; parameters fitted onto a
bound of their range are listed (``at_bound``) and lower the verdict's confidence. The ranking
score is the held-out rms times (1 + k / n_train) OCCAM^k, a penalty for free parameters: the
first factor corrects the training fit's optimism, the second prefers the simpler of two
candidates that explain the data about equally well (e.g. a temperature offset over a
relaxation spectrum whose spread went to zero and whose centre shift mimics it). The shrink of
a candidate is 1 - gap_heldout / baseline gap_heldout.

Pairs: the best single effect combined with each other usable effect, started from the two
single fits (greedy forward selection).

Inconclusive: another single effect explaining the held-out points equally well within the
noise (:func:`_rivals`) makes the verdict ``inconclusive`` (no effect named, the competitors
listed), which differs from "no effect".

Verdict (null = no effect named): the baseline gap over all points must be significant against
the noise (chi-square p < 1e-3 and gap > 1.3 x noise, :func:`gap.is_significant`) and the best
candidate must shrink the held-out gap by at least ``MIN_SHRINK``. A pair is preferred to the best
single only when the single leaves a gap still significant against the noise and the pair's
score is lower by at least ``PAIR_GAIN``.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from . import gap as gapmod
from .effects import all_effects

__all__ = ["Candidate", "Diagnosis", "heldout_mask", "fit_candidate", "diagnose_friction"]

MIN_SHRINK = 0.25
MULTI_STARTS = 3
CV_BELOW = 20
CV_FOLDS = 8
N_BOOT = 1000
PAIR_GAIN = 0.85
OCCAM = 1.08
HELDOUT_EVERY = 3


def heldout_mask(n, every=HELDOUT_EVERY):
    """Deterministic held-out subset: indices 1, 1 + every, ... (the end points stay in training)."""
    m = np.zeros(n, bool)
    m[1:n - 1:every] = True
    return m


@dataclass
class Candidate:
    """A fitted effect (or pair) and its errors."""

    effects: tuple
    params: list           # one dict per effect
    pred: np.ndarray       # predicted mu at every row
    gap_train: float
    gap_heldout: float
    gap_all: float
    shrink: float = float("nan")
    score: float = float("nan")
    nfev: int = 0
    seconds: float = 0.0
    r_held: np.ndarray = None          # held-out residuals log10(real/pred) (CV: every point)
    shrink_interval: tuple = (float("nan"), float("nan"))
    at_bound: list = field(default_factory=list)

    @property
    def name(self):
        return "+".join(e.name for e in self.effects)

    @property
    def k(self):
        return sum(len(e.params) for e in self.effects)

    def as_dict(self):
        flat = {}
        for e, p in zip(self.effects, self.params):
            flat.update(p if len(self.effects) == 1 else {f"{e.name}.{k}": v for k, v in p.items()})
        return dict(name=self.name, params=flat, gap_train=self.gap_train,
                    gap_heldout=self.gap_heldout, shrink=self.shrink, gap_all=self.gap_all,
                    score=self.score, n_params=self.k, evaluations=self.nfev,
                    shrink_interval=[None if not np.isfinite(x) else float(x) for x in self.shrink_interval],
                    at_bound=list(self.at_bound), seconds=round(self.seconds, 3))


def _unpack(effects, u):
    out, i = [], 0
    for e in effects:
        out.append({p.name: p.from_unit(u[i + j]) for j, p in enumerate(e.params)})
        i += len(e.params)
    return out


def _pack(effects, params):
    return np.array([p.to_unit(d[p.name]) for e, d in zip(effects, params) for p in e.params], float)


def predict(ctx, effects, params):
    """mu at every row of ``ctx`` with ``effects`` applied in order (pairs compose)."""
    from .model import simulate

    if len(effects) == 1 and effects[0].apply_fn is not None:
        return effects[0].apply(ctx, params[0])
    spec = ctx.base
    for e, p in zip(effects, params):
        spec = e.modify(spec, p, ctx)
    return simulate(spec, ctx)


def _null_u(ctx, effects):
    """Unit-cube point of the effects' "no effect" parameters (None if one has none)."""
    ps = [e.null_params(ctx) for e in effects]
    if any(p is None for p in ps):
        return None
    return np.clip(_pack(effects, ps), 0, 1)


def at_bound(ctx, effects, params, tol=1e-3):
    """Names of fitted parameters on a bound of their range (the no-effect value excepted)."""
    out = []
    for e, p in zip(effects, params):
        null = e.null_params(ctx) or {}
        for pp in e.params:
            u = pp.to_unit(p[pp.name])
            if (u <= tol or u >= 1 - tol) and not (pp.name in null and abs(u - pp.to_unit(null[pp.name])) <= tol):
                out.append(pp.name if len(effects) == 1 else f"{e.name}.{pp.name}")
    return out


def fit_candidate(ctx, real_mu, effects, train, start=None, budget=None):
    """Fit the parameters of ``effects`` (a tuple) on the ``train`` rows; see module docstring.

    ``start``: list of parameter dicts to start from (skips the coarse grid).
    Returns a :class:`Candidate` (errors on all, train and held-out rows filled in).
    """
    from scipy import optimize

    t0 = time.perf_counter()
    effects = tuple(effects)
    k = sum(len(e.params) for e in effects)
    cost = max(e.cost for e in effects)
    y = np.log10(real_mu)
    cache = {}

    def model(u):
        key = tuple(np.round(u, 10))
        if key not in cache:
            try:
                cache[key] = np.log10(predict(ctx, effects, _unpack(effects, u)))
            except (ValueError, ArithmeticError, RuntimeError):
                # e.g. a flash-temperature solve that does not converge at these parameters:
                # the point is unusable for the fit, not a failure of the diagnosis
                cache[key] = np.full(y.size, np.nan)
        return cache[key]

    def resid(u):
        # an unusable point must cost more than any finite one: 1e3 decades (a misfit of
        # 10 decades is possible far from the pole of the WLF shift: --temperature -76)
        r = (y - model(u))[train]
        return np.where(np.isfinite(r), r, 1e3)

    step = 0.02

    def jac(u):
        r0 = resid(u)
        J = np.empty((r0.size, u.size))
        for j in range(u.size):
            du = step if u[j] + step <= 1.0 else -step
            uu = u.copy()
            uu[j] += du
            J[:, j] = (resid(uu) - r0) / du
        return J

    null = _null_u(ctx, effects)
    starts = []
    if start is not None:
        u0 = np.clip(_pack(effects, start), 0, 1)
        starts = [u0]
    else:
        per_dim = {1: 7, 2: 5, 3: 4, 4: 3}.get(k, 2) if cost <= 1 else 3
        axes = [np.linspace(0.05, 0.95, per_dim)] * k
        grid = np.array(np.meshgrid(*axes, indexing="ij")).reshape(k, -1).T
        init = _pack(effects, [{p.name: p.init for p in e.params} for e in effects])
        grid = np.vstack([init, grid]) if cost <= 1 else np.vstack([init])
        if cost > 1:  # expensive: the initial value and the two ends only
            grid = np.vstack([init, np.full(k, 0.15), np.full(k, 0.85)])
        costs = [float(np.sum(resid(g) ** 2)) for g in grid]
        # several starts where the landscape has plateaus (limited water, contact correction):
        # the best grid points that are not neighbours of one another
        order = np.argsort(costs)
        n_starts = MULTI_STARTS if (cost <= 1 and k <= 2) else 1
        for i in order:
            if len(starts) >= n_starts:
                break
            if all(np.max(np.abs(grid[i] - s0)) > 0.2 for s0 in starts):
                starts.append(grid[i])
    max_nfev = budget or (8 if cost > 1 else 30 + 10 * k)
    # never worse than no effect on the training points: the null is the reference
    u, c_best = null, (float(np.sum(resid(null) ** 2)) if null is not None else np.inf)
    for u0 in starts:
        c0 = float(np.sum(resid(u0) ** 2))
        if c0 < c_best:
            u, c_best = u0, c0
        try:
            sol = optimize.least_squares(resid, u0, jac=jac, bounds=(0.0, 1.0), method="trf",
                                         max_nfev=max_nfev, x_scale=0.1, xtol=1e-4, ftol=1e-6)
            c1 = float(np.sum(resid(sol.x) ** 2))
            if c1 < c_best:
                u, c_best = sol.x, c1
        except (ValueError, np.linalg.LinAlgError):
            pass
    params = _unpack(effects, u)
    pred = 10.0 ** model(u)
    held = ~train
    r = y - np.log10(pred)
    rms = lambda m: float(np.sqrt(np.mean(r[m] ** 2))) if m.any() else float("nan")  # noqa: E731
    return Candidate(effects, params, pred, rms(train), rms(held), rms(np.ones_like(train)),
                     nfev=len(cache), seconds=time.perf_counter() - t0)


def _score(c, n_train):
    return c.gap_heldout * (1.0 + c.k / n_train) * OCCAM ** c.k


@dataclass
class Diagnosis:
    """Everything the friction-level diagnosis found (see :func:`diagnose_friction`)."""

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


def diagnose_friction(ctx, real_mu, noise=None, effects=None, pairs=True, log=None):
    """Run the friction-level diagnosis of the rows of ``ctx`` against measured ``real_mu``.

    Parameters
    ----------
    ctx : model.FrictionContext
    real_mu : (n,) measured mu at the rows of ctx
    noise : rms log10 measurement noise, or None to estimate it from the data
    effects : list of Effect (default: every registered friction-level effect)
    pairs : try greedy pairs (best single + each other)

    Returns
    -------
    Diagnosis
    """
    from .model import simulate

    t0 = time.perf_counter()
    say = log or (lambda *_: None)
    real_mu = np.asarray(real_mu, float)
    n = real_mu.size
    cv = n < CV_BELOW
    if cv:
        # few points: k-fold (leave-one-out up to CV_FOLDS points) instead of a fixed split;
        # the reported parameters are fitted on every point
        n_folds = min(n, CV_FOLDS)
        folds = [np.arange(i, n, n_folds) for i in range(n_folds)]
        train = np.ones(n, bool)
        held = np.ones(n, bool)
    else:
        n_folds, folds = 0, []
        train = ~heldout_mask(n)
        held = ~train
    base = simulate(ctx.base, ctx)
    noise_given = noise is not None
    noise = float(noise) if noise_given else gapmod.estimate_noise(ctx.v_m_per_s, real_mu)
    r0 = gapmod.log_ratio(real_mu, base)
    g_all = float(np.sqrt(np.mean(r0 ** 2)))
    g_tr = float(np.sqrt(np.mean(r0[train] ** 2)))
    g_ho = float(np.sqrt(np.mean(r0[held] ** 2)))  # CV: every point is held out once
    p = gapmod.chi2_pvalue(g_all, noise, n)
    significant = gapmod.is_significant(g_all, noise, n)
    say(f"baseline gap {g_all:.4f} (noise {noise:.4f}, p = {p:.2g})")

    usable, skipped = [], []
    for e in (effects if effects is not None else all_effects("friction")):
        miss = e.missing(ctx)
        if miss:
            skipped.append(dict(name=e.name, reason=f"needs {', '.join(miss)} (not given)"))
            continue
        if e.prepare is not None:
            why = e.prepare(ctx)
            if why:
                skipped.append(dict(name=e.name, reason=why))
                continue
        usable.append(e)

    y = np.log10(real_mu)
    if cv:
        n_train = n - int(np.ceil(n / n_folds))
        r0_held = r0
    else:
        n_train = int(train.sum())
        r0_held = r0[held]
    rng = np.random.default_rng(0)
    boot = rng.integers(0, r0_held.size, size=(N_BOOT, r0_held.size))
    den = np.sqrt(np.mean(r0_held[boot] ** 2, axis=1))

    def finish(c):
        c.at_bound = at_bound(ctx, c.effects, c.params)
        if cv:
            rh = np.empty(n)
            small = 3 if max(e.cost for e in c.effects) > 1 else 8 + 2 * c.k
            for f in folds:
                m = np.ones(n, bool)
                m[f] = False
                cf = fit_candidate(ctx, real_mu, c.effects, m, start=c.params, budget=small)
                rh[f] = (y - np.log10(cf.pred))[f]
                c.nfev += cf.nfev
            c.r_held = rh
            c.gap_heldout = float(np.sqrt(np.mean(rh ** 2)))
        else:
            c.r_held = (y - np.log10(c.pred))[held]
        c.score = _score(c, n_train)
        c.shrink = 1.0 - c.gap_heldout / g_ho if g_ho > 0 else float("nan")
        num = np.sqrt(np.mean(c.r_held[boot] ** 2, axis=1))
        sb = 1.0 - num / np.where(den > 0, den, np.nan)
        sb = sb[np.isfinite(sb)]
        if sb.size:
            c.shrink_interval = (float(np.percentile(sb, 5)), float(np.percentile(sb, 95)))
        return c

    cands = []
    timings = {}
    for e in usable:
        c = finish(fit_candidate(ctx, real_mu, (e,), train))
        cands.append(c)
        timings[e.name] = c.seconds
        say(f"  {c.name}: train {c.gap_train:.4f} held-out {c.gap_heldout:.4f} ({c.seconds:.1f} s)")
    singles = sorted(cands, key=lambda c: c.score)
    if pairs and singles and significant:
        first = singles[0]
        for other in singles[1:]:
            c = finish(fit_candidate(ctx, real_mu, first.effects + other.effects, train,
                                     start=first.params + other.params,
                                     budget=12 if max(first.effects[0].cost, other.effects[0].cost) > 1 else 40))
            cands.append(c)
            timings[c.name] = c.seconds
    ranked = sorted(cands, key=lambda c: c.score)

    verdict = dict(effect=None, shrink=None, shrink_interval=None, gap_validate=None, reason="",
                   inconclusive=[], at_bound=[], confidence=None)
    best = None
    if not significant:
        verdict["reason"] = (f"baseline gap {g_all:.4f} is within the noise {noise:.4f} "
                             f"(chi-square p = {p:.3g})")
    elif not singles:
        verdict["reason"] = "no usable effect"
    else:
        s1 = singles[0]
        best = s1
        pair_list = [c for c in ranked if len(c.effects) == 2]
        if pair_list:
            bp = min(pair_list, key=lambda c: c.score)
            still = gapmod.is_significant(s1.gap_all, noise, n, alpha=1e-2, min_ratio=1.2)
            if still and bp.score < PAIR_GAIN * s1.score and bp.shrink > s1.shrink:
                best = bp
        if not (best.shrink >= MIN_SHRINK):
            verdict["reason"] = (f"no effect shrinks the held-out gap by {MIN_SHRINK:.0%} "
                                 f"(best {best.name}: {best.shrink:.0%})")
            best = None
        else:
            rivals = _rivals(best, singles, noise)
            if rivals:
                verdict["inconclusive"] = [best.name] + [r.name for r in rivals]
                verdict["reason"] = ("inconclusive: " + ", ".join(verdict["inconclusive"]) +
                                     " explain the held-out points equally well within the noise")
                best = None
            else:
                lo = best.shrink_interval[0]
                conf = "high"
                weak = np.isfinite(lo) and lo < MIN_SHRINK
                if best.at_bound or weak:
                    conf = "medium"
                if best.at_bound and weak:
                    conf = "low"
                verdict["effect"] = best.name if len(best.effects) == 1 else [e.name for e in best.effects]
                verdict["shrink"] = best.shrink
                verdict["shrink_interval"] = list(best.shrink_interval)
                verdict["at_bound"] = list(best.at_bound)
                verdict["confidence"] = conf
                verdict["reason"] = (f"{best.name} shrinks the held-out gap from {g_ho:.4f} to "
                                     f"{best.gap_heldout:.4f}")
    heldout = (f"{n_folds}-fold cross-validation over the {n} measured speeds (fold i: points i, i + {n_folds}, ...; "
               "each fold refitted without its points)" if cv else
               "every third point (indices 1, 4, 7, ...), never used in a fit")
    return Diagnosis(base, g_all, g_tr, g_ho, noise, noise_given, significant, p, train, ranked,
                     skipped, verdict, best, time.perf_counter() - t0, timings, heldout)


def _rivals(best, singles, noise):
    """Other single effects (not part of ``best``) explaining the held-out points as well within
    the noise: their mean squared held-out residual exceeds the best's by less than a quarter of
    its paired standard error, and their held-out gap by less than a tenth of the noise."""
    out = []
    names = {e.name for e in best.effects}
    for c in singles:
        if c is best or {e.name for e in c.effects} & names or not (c.shrink >= MIN_SHRINK):
            continue
        if c.r_held is None or best.r_held is None or c.r_held.size != best.r_held.size:
            continue
        d = c.r_held ** 2 - best.r_held ** 2
        se = float(np.std(d, ddof=1) / np.sqrt(d.size)) if d.size > 1 else 0.0
        if float(np.mean(d)) <= 0.25 * se and c.gap_heldout <= best.gap_heldout + 0.1 * noise:
            out.append(c)
    return out
