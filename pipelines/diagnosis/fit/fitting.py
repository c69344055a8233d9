"""Bounded least-squares fit of one candidate (an effect, a pair, or the calibration of uncertain
inputs with or without an effect) on a subset of the measured rows.

Each candidate has k parameters mapped onto the unit cube (log or linear per parameter, see
:class:`effects.Param`). Starts: with ``start`` given, that point (greedy pairs start from their
two single fits); otherwise *cold* starts chosen on the training rows alone: a coarse grid over
the cube for k <= 4 (7, 5, 4, 3 points a side), a scrambled Sobol sample of at least 16 k points
for k >= 5, the effect's initial values, and its "no effect" point; the best of these (three for one or
two parameters, two for more, one for an expensive effect; each fold of a cross-validation
chooses its own) that are not
neighbours of one another start ``scipy.optimize.least_squares`` (trust-region reflective,
bounded) on the residuals log10(real/sim), with forward differences of a fixed step (0.02) in
the unit cube (the engine's adaptive grid makes tiny steps noisy). The fit is never worse than
"no effect" on its training rows. Evaluations are cached by unit-cube point and the cache may
be shared between the folds of a cross-validation: a model evaluation gives mu at *every* row,
so the grid of a fold costs nothing, while each fold still chooses its own starts from its own
training rows (no start from a fit that saw the fold's held-out rows).

Refusal: a model with more free parameters than half its training rows is not fitted
(:func:`too_many_parameters`; Burnham & Anderson 2002, *Model selection and multimodel
inference*, sec 2.4: below n / k of about 2 a least-squares fit interpolates the noise).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Candidate", "predict", "at_bound", "fit_candidate", "too_many_parameters", "unpack", "pack"]

MULTI_STARTS = 3
STEP = 0.02


def too_many_parameters(k, n_train):
    """True when ``k`` free parameters exceed half of ``n_train`` training rows.

    Parameters
    ----------
    k : int
        Number of free parameters of the candidate (summed over its effects).
    n_train : int
        Number of training rows the fit would see.

    Returns
    -------
    bool
        True when 2 k > n_train: the candidate is not fitted.
    """
    return 2 * int(k) > int(n_train)


@dataclass
class Candidate:
    """A fitted effect (or pair, or calibration) and its errors.

    Attributes
    ----------
    effects : tuple of Effect
        The effects fitted together.
    params : list of dict
        One dict per effect: parameter name (which carries its unit) -> fitted value.
    pred : ndarray
        Predicted mu at every row.
    gap_train, gap_heldout, gap_all : float
        rms of log10(measured / predicted mu) over the training, held-out and all rows (NaN
        when no row is held out).
    shrink : float
        1 - gap_heldout / the baseline's gap_heldout, set when the candidate is scored (NaN until then).
    score : float
        gap_heldout (1 + k / n_train), times 1.08^k with a hold-out (:func:`cv.evaluate`); lower
        ranks first.
    nfev : int
        Model evaluations this fit added to its cache (points already cached are free).
    seconds : float
        Wall-clock time of the fit [s].
    r_held : ndarray or None
        log10(measured / predicted mu) at the held-out rows (few points: at every point); None
        until evaluated.
    shrink_interval : tuple of float
        5-95 % bootstrap interval.
    at_bound, implausible, implausible_why : list
        Parameters on a bound, outside the physical range, and why.
    n_train : int
        Number of rows the fit was trained on.
    """

    effects: tuple
    params: list  # one dict per effect
    pred: np.ndarray  # predicted mu at every row
    gap_train: float
    gap_heldout: float
    gap_all: float
    shrink: float = float("nan")
    score: float = float("nan")
    nfev: int = 0
    seconds: float = 0.0
    r_held: np.ndarray | None = None  # held-out residuals log10(real/pred) (CV: every point)
    shrink_interval: tuple = (float("nan"), float("nan"))
    at_bound: list = field(default_factory=list)
    implausible: list = field(default_factory=list)
    implausible_why: list = field(default_factory=list)
    n_train: int = 0

    @property
    def name(self):
        return "+".join(e.name for e in self.effects)

    @property
    def k(self):
        return sum(len(e.params) for e in self.effects)

    @property
    def effect_names(self):
        """The physical effects in this candidate (the calibration pseudo-effect left out)."""
        return [e.name for e in self.effects if e.name != "calibration"]

    def as_dict(self):
        flat = {}
        for e, p in zip(self.effects, self.params):
            flat.update(p if len(self.effects) == 1 else {f"{e.name}.{k}": v for k, v in p.items()})
        return dict(
            name=self.name,
            params=flat,
            gap_train=self.gap_train,
            gap_heldout=self.gap_heldout,
            shrink=self.shrink,
            gap_all=self.gap_all,
            score=self.score,
            n_params=self.k,
            evaluations=self.nfev,
            shrink_interval=[None if not np.isfinite(x) else float(x) for x in self.shrink_interval],
            at_bound=list(self.at_bound),
            implausible=list(self.implausible),
            seconds=round(self.seconds, 3),
        )


def unpack(effects, u):
    """Unit-cube vector -> one parameter dict per effect.

    Parameters
    ----------
    effects : tuple of Effect
        The effects, in order: their parameters take consecutive entries of ``u``.
    u : ndarray, shape (k,)
        Point of the unit cube, k the total number of parameters; each entry is clipped to [0, 1]
        and mapped onto its parameter's bounds (log or linear, :class:`effects.Param`).

    Returns
    -------
    list of dict
        One dict per effect: parameter name -> value in the parameter's unit.
    """
    out, i = [], 0
    for e in effects:
        out.append({p.name: p.from_unit(u[i + j]) for j, p in enumerate(e.params)})
        i += len(e.params)
    return out


def pack(effects, params):
    """One parameter dict per effect -> unit-cube vector.

    Parameters
    ----------
    effects : tuple of Effect
        The effects, in order.
    params : list of dict
        One dict per effect: parameter name -> value in the parameter's unit.

    Returns
    -------
    ndarray, shape (k,)
        Unit-cube coordinates, not clipped (a value outside its bounds lies outside [0, 1]).
    """
    return np.array([p.to_unit(d[p.name]) for e, d in zip(effects, params) for p in e.params], float)


def predict(ctx, effects, params):
    """mu at every row of ``ctx`` with ``effects`` applied in order (pairs compose).

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows (speed, temperature, pressure, wet) and the baseline spec ``ctx.base``.
    effects : tuple of Effect
        Applied in order to ``ctx.base``; a single effect with its own ``apply_fn`` computes mu
        directly.
    params : list of dict
        One dict per effect: parameter name -> value.

    Returns
    -------
    ndarray, shape (n,)
        Simulated mu (dimensionless) at every row of ``ctx``.
    """
    from pipelines.diagnosis.model import simulate

    if len(effects) == 1 and effects[0].apply_fn is not None:
        return effects[0].apply(ctx, params[0])
    spec = ctx.base
    for e, p in zip(effects, params):
        spec = e.modify(spec, p, ctx)
    return simulate(spec, ctx)


def null_u(ctx, effects):
    """Unit-cube point of the effects' "no effect" parameters (None if one has none)."""
    ps = [e.null_params(ctx) for e in effects]
    if any(p is None for p in ps):
        return None
    return np.clip(pack(effects, ps), 0, 1)


def at_bound(ctx, effects, params, tol=1e-3):
    """Names of fitted parameters on a bound of their range (the no-effect value excepted).

    Parameters
    ----------
    ctx : FrictionContext
        The context the fit was made on (it gives each effect's no-effect parameters).
    effects : tuple of Effect
        The fitted effects.
    params : list of dict
        Their fitted parameters, one dict per effect.
    tol : float, optional
        Distance to a bound in the unit cube that counts as on it.

    Returns
    -------
    list of str
        Parameter names (``effect.param`` for more than one effect) within ``tol`` of 0 or 1.
    """
    out = []
    for e, p in zip(effects, params):
        null = e.null_params(ctx) or {}
        for pp in e.params:
            u = pp.to_unit(p[pp.name])
            if (u <= tol or u >= 1 - tol) and not (
                pp.name in null and abs(u - pp.to_unit(null[pp.name])) <= tol
            ):
                out.append(pp.name if len(effects) == 1 else f"{e.name}.{pp.name}")
    return out


def _cold_points(ctx, effects, k, cost):
    init = pack(effects, [{p.name: p.init for p in e.params} for e in effects])
    if cost > 1:  # expensive: the initial value and two corners only
        return np.vstack([init, np.full(k, 0.15), np.full(k, 0.85)])
    if k <= 4:
        per_dim = {1: 7, 2: 5, 3: 4, 4: 3}[k]
        axes = [np.linspace(0.05, 0.95, per_dim)] * k
        grid = np.array(np.meshgrid(*axes, indexing="ij")).reshape(k, -1).T
    else:
        from scipy.stats import qmc

        grid = 0.05 + 0.9 * qmc.Sobol(k, scramble=True, seed=k).random_base2(int(np.ceil(np.log2(16 * k))))
    return np.vstack([init, grid])


def fit_candidate(
    ctx, real_mu, effects, train, start=None, budget=None, cache=None, extra_starts=(), max_starts=None
):
    """Fit the parameters of ``effects`` (a tuple) on the ``train`` rows; see module docstring.

    ``start``: list of parameter dicts to start from (skips the cold starts).
    ``extra_starts``: parameter-dict lists of fits on the same training rows, tried instead of the
    cold grid (with the initial values).
    ``cache``: a dict shared between fits of the same ``effects`` on the same rows.
    ``max_starts``: at most this many local fits (cross-validation folds use one).
    Returns a :class:`Candidate` (errors on all, train and held-out rows filled in).

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows and the baseline spec.
    real_mu : ndarray, shape (n,)
        Measured mu at every row of ``ctx`` (positive: the residuals are log10(real / sim)).
    effects : tuple of Effect
        The effects fitted together.
    train : ndarray of bool, shape (n,)
        Rows whose residuals the fit minimises.
    start : list of dict, optional
        One parameter dict per effect, the only start; None: cold (or ``extra_starts``) starts.
    budget : int, optional
        ``max_nfev`` of each local fit; None: 8 for an expensive effect (cost > 1), else 30 + 10 k.
    cache : dict, optional
        Unit-cube point -> log10 mu at every row, shared by fits of the same effects on the same
        context; None: a new one.
    extra_starts : sequence of list of dict, optional
        Fits on the same training rows, tried with the initial values instead of the cold grid.
    max_starts : int, optional
        Most local fits; None: 3 for k <= 2, else 2, 1 for an expensive effect (+1 with
        ``extra_starts``).

    Returns
    -------
    Candidate
        params, pred, the three gaps, nfev, seconds and n_train set; :func:`cv.evaluate` does the rest.
    """
    from pipelines.diagnosis.fit.stats import jacobian, multistart_lsq

    t0 = time.perf_counter()
    effects = tuple(effects)
    k = sum(len(e.params) for e in effects)
    cost = max(e.cost for e in effects)
    y = np.log10(real_mu)
    cache = {} if cache is None else cache
    n0 = len(cache)

    def model(u):
        key = tuple(np.round(u, 10))
        if key not in cache:
            try:
                cache[key] = np.log10(predict(ctx, effects, unpack(effects, u)))
            except (ValueError, ArithmeticError, RuntimeError):
                # e.g. a flash-temperature solve that does not converge at these parameters:
                # the point is unusable for the fit, not a failure of the diagnosis
                cache[key] = np.full(y.size, np.nan)
        return cache[key]

    def resid(u):
        # an unusable point must cost more than any finite one: 1e3 decades
        r = (y - model(u))[train]
        return np.where(np.isfinite(r), r, 1e3)

    def jac(u):
        return jacobian(resid, u, step=STEP)

    null = null_u(ctx, effects)
    starts = []
    if start is not None:
        starts = [np.clip(pack(effects, start), 0, 1)]
    else:
        # warm starts (fits on the same training rows) replace the cold grid
        grid = (
            _cold_points(ctx, effects, k, cost)[:1] if extra_starts else _cold_points(ctx, effects, k, cost)
        )
        for s in extra_starts:
            grid = np.vstack([np.clip(pack(effects, s), 0, 1), grid])
        costs = [float(np.sum(resid(g) ** 2)) for g in grid]
        order = np.argsort(costs)
        n_starts = (MULTI_STARTS if k <= 2 else 2) if cost <= 1 else 1
        n_starts += bool(extra_starts) and cost <= 1
        n_starts = n_starts if max_starts is None else min(n_starts, max_starts)
        for i in order:
            if len(starts) >= n_starts:
                break
            if all(np.max(np.abs(grid[i] - s0)) > 0.2 for s0 in starts):
                starts.append(grid[i])
    max_nfev = budget or (8 if cost > 1 else 30 + 10 * k)
    c_null = float(np.sum(resid(null) ** 2)) if null is not None else np.inf
    u, _ = multistart_lsq(
        resid,
        starts,
        u_best=null,
        c_best=c_null,
        jac=jac,
        method="trf",
        max_nfev=max_nfev,
        x_scale=0.1,
        xtol=1e-4,
        ftol=1e-6,
    )
    params = unpack(effects, u)
    pred = 10.0 ** model(u)
    held = ~train
    r = y - np.log10(pred)
    rms = lambda m: float(np.sqrt(np.mean(r[m] ** 2))) if m.any() else float("nan")  # noqa: E731
    return Candidate(
        effects,
        params,
        pred,
        rms(train),
        rms(held),
        rms(np.ones_like(train)),
        nfev=len(cache) - n0,
        seconds=time.perf_counter() - t0,
        n_train=int(train.sum()),
    )
