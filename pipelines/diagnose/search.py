"""Which effect explains the gap: bounded fits, held-out ranking, greedy pairs, the verdict.

Fitting: each candidate (one effect, or a pair) has k <= 4 parameters mapped onto the unit cube
(log or linear per parameter, see :class:`effects.Param`). A coarse grid over the cube picks a
start, then ``scipy.optimize.least_squares`` (trust-region reflective, bounded) minimises the
residuals log10(real/sim) on the training points, with forward differences of a fixed step in
the unit cube (the engine's adaptive grid makes tiny steps noisy).

Held-out points: every third point (indices 1, 4, 7, ...), never used in a fit. The ranking
score is the held-out rms times (1 + k / n_train) OCCAM^k, a penalty for free parameters: the
first factor corrects the training fit's optimism, the second prefers the simpler of two
candidates that explain the data about equally well (e.g. a temperature offset over a
relaxation spectrum whose spread went to zero and whose centre shift mimics it). The shrink of
a candidate is 1 - gap_heldout / baseline gap_heldout.

Pairs: the best single effect combined with each other usable effect, started from the two
single fits (greedy forward selection).

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
from scipy import optimize

from . import gap as gapmod
from .effects import all_effects

__all__ = ["Candidate", "Diagnosis", "heldout_mask", "fit_candidate", "diagnose_friction"]

MIN_SHRINK = 0.25
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
                    seconds=round(self.seconds, 3))


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


def fit_candidate(ctx, real_mu, effects, train, start=None, budget=None):
    """Fit the parameters of ``effects`` (a tuple) on the ``train`` rows; see module docstring.

    ``start``: list of parameter dicts to start from (skips the coarse grid).
    Returns a :class:`Candidate` (errors on all, train and held-out rows filled in).
    """
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
        r = (y - model(u))[train]
        return np.where(np.isfinite(r), r, 10.0)

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

    if start is not None:
        u0 = np.clip(_pack(effects, start), 0, 1)
    else:
        per_dim = {1: 7, 2: 5, 3: 4, 4: 3}.get(k, 2) if cost <= 1 else 3
        axes = [np.linspace(0.05, 0.95, per_dim)] * k
        grid = np.array(np.meshgrid(*axes, indexing="ij")).reshape(k, -1).T
        init = _pack(effects, [{p.name: p.init for p in e.params} for e in effects])
        grid = np.vstack([init, grid]) if cost <= 1 else np.vstack([init])
        if cost > 1:  # expensive: the initial value and the two ends only
            grid = np.vstack([init, np.full(k, 0.15), np.full(k, 0.85)])
        costs = [float(np.sum(resid(g) ** 2)) for g in grid]
        u0 = grid[int(np.argmin(costs))]
    max_nfev = budget or (8 if cost > 1 else 30 + 10 * k)
    try:
        sol = optimize.least_squares(resid, u0, jac=jac, bounds=(0.0, 1.0), method="trf",
                                     max_nfev=max_nfev, x_scale=0.1, xtol=1e-4, ftol=1e-6)
        u = sol.x
        if np.sum(resid(u) ** 2) > np.sum(resid(u0) ** 2):
            u = u0
    except (ValueError, np.linalg.LinAlgError):
        u = u0
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
    train = ~heldout_mask(n)
    held = ~train
    base = simulate(ctx.base, ctx)
    noise_given = noise is not None
    noise = float(noise) if noise_given else gapmod.estimate_noise(ctx.v_m_per_s, real_mu)
    r0 = gapmod.log_ratio(real_mu, base)
    g_all = float(np.sqrt(np.mean(r0 ** 2)))
    g_tr = float(np.sqrt(np.mean(r0[train] ** 2)))
    g_ho = float(np.sqrt(np.mean(r0[held] ** 2)))
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

    n_train = int(train.sum())
    cands = []
    timings = {}
    for e in usable:
        c = fit_candidate(ctx, real_mu, (e,), train)
        cands.append(c)
        timings[e.name] = c.seconds
        say(f"  {c.name}: train {c.gap_train:.4f} held-out {c.gap_heldout:.4f} ({c.seconds:.1f} s)")
    for c in cands:
        c.score = _score(c, n_train)
        c.shrink = 1.0 - c.gap_heldout / g_ho if g_ho > 0 else float("nan")
    singles = sorted(cands, key=lambda c: c.score)
    if pairs and singles and significant:
        first = singles[0]
        for other in singles[1:]:
            c = fit_candidate(ctx, real_mu, first.effects + other.effects, train,
                              start=first.params + other.params,
                              budget=12 if max(first.effects[0].cost, other.effects[0].cost) > 1 else 40)
            c.score = _score(c, n_train)
            c.shrink = 1.0 - c.gap_heldout / g_ho if g_ho > 0 else float("nan")
            cands.append(c)
            timings[c.name] = c.seconds
    ranked = sorted(cands, key=lambda c: c.score)

    verdict = dict(effect=None, shrink=None, gap_validate=None, reason="")
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
            verdict["effect"] = best.name if len(best.effects) == 1 else [e.name for e in best.effects]
            verdict["shrink"] = best.shrink
            verdict["reason"] = (f"{best.name} shrinks the held-out gap from {g_ho:.4f} to "
                                 f"{best.gap_heldout:.4f}")
    return Diagnosis(base, g_all, g_tr, g_ho, noise, noise_given, significant, p, train, ranked,
                     skipped, verdict, best, time.perf_counter() - t0, timings)
