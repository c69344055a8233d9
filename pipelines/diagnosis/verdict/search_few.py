"""The candidates of a diagnosis on few measured speeds (fewer than 20, see :mod:`.few`).

The baseline (the calibration of the uncertain inputs, or the nominal model when nothing is
uncertain) is fitted first, on every point; the noise scale of the likelihood follows
(:func:`noise_prior`); then every usable effect is fitted together with the calibration (started
from the calibration's fit, besides cold starts), never skipped for its number of parameters:
the evidence's Occam factor is the penalty (:mod:`.evidence`).

Held-out errors reported for each candidate: linearised leave-one-out (PRESS) residuals
r_i / (1 - h_ii), h the hat matrix J (J^T J + 12 s^2 I)^-1 J^T of the Gauss-Newton fit with the
uniform prior's precision (Allen 1974, Technometrics 16, 125; Cook & Weisberg 1982, *Residuals
and influence in regression*, sec 2.2): a refit per left-out point costs a fit each and, on five
points, says no more.
"""

from __future__ import annotations

import numpy as np

from pipelines.diagnosis.fit.cv import boot_shrink
from pipelines.diagnosis.fit.parallel import fit_map, portable, restore

__all__ = [
    "few_candidates",
    "second_opinion",
    "noise_prior",
    "NOISE_RANGE",
    "PRIOR_NOISE_DOF",
    "GIVEN_NOISE_DOF",
]

#: the range of noise scales a friction test's repeatability takes (rms log10; 1.2 % to 7 %)
NOISE_RANGE = (0.005, 0.03)
#: the weight (degrees of freedom) of the noise scale in the Student-t likelihood
PRIOR_NOISE_DOF = 4.0
#: the weight of a noise given with --noise
GIVEN_NOISE_DOF = 30.0


def noise_prior(noise, given):
    """The likelihood's noise scale and its degrees of freedom.

    Given noise: (noise, 30). Estimated: the data's estimate (smoothing spline) clipped into
    ``NOISE_RANGE``, worth ``PRIOR_NOISE_DOF``: on five points a spline cannot tell curvature from
    scatter, so the estimate is only a guide; the Student-t likelihood then lets each model's own
    residuals set its noise (:mod:`.evidence`).

    Parameters
    ----------
    noise : float
        The noise estimate or the given noise (rms log10).
    given : bool
        Whether it was given (``--noise``).

    Returns
    -------
    s : float
        Noise scale of the likelihood, rms log10: the given noise (at least the evidence's floor
        0.004), or the estimate clipped into ``NOISE_RANGE``.
    nu : float
        Degrees of freedom it is worth: 30 given, 4 estimated.
    """
    from pipelines.diagnosis.fit.evidence import NOISE_FLOOR

    if given:
        return max(float(noise), NOISE_FLOOR), GIVEN_NOISE_DOF
    return float(np.clip(noise, *NOISE_RANGE)), PRIOR_NOISE_DOF


def _press(c, ev, y, s, r0_held, boot, n_eff):
    """Fill in the held-out fields of ``c`` from its PRESS residuals (see module docstring)."""
    r = y - np.log10(c.pred)
    J = ev.get("J")
    if J is not None and J.size:
        A = J.T @ J + 12.0 * s * s * np.eye(J.shape[1])
        h = np.einsum("ij,jk,ik->i", J, np.linalg.pinv(A), J)
        r = r / (1.0 - np.clip(h, 0.0, 0.99))
    c.r_held = r
    c.gap_heldout = float(np.sqrt(np.mean(r**2)))
    g0 = float(np.sqrt(np.mean(r0_held**2)))
    c.shrink = 1.0 - c.gap_heldout / g0 if g0 > 0 else float("nan")
    c.shrink_interval = boot_shrink(r, r0_held, boot)
    c.score = c.gap_heldout * (1.0 + c.k / max(n_eff, 1))
    return c


def few_candidates(ctx, real_mu, usable, cal_e, ho, noise, noise_given, timings, say):
    """The baseline's fit, the effects fitted with it and the likelihood's noise scale.

    Effects are fitted only when the baseline gap is significant against the noise scale s
    (chi-square p < 1e-3 and gap > 1.3 s, :func:`gap.is_significant`).

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows and the baseline spec.
    real_mu : ndarray, shape (n,)
        Measured mu at every row.
    usable : list of Effect
        Effects to fit (each with the calibration when ``cal_e`` is given).
    cal_e : Effect or None
        The calibration pseudo-effect of the uncertain inputs; None: nothing uncertain.
    ho : Holdout
        Its bootstrap resamples ``ho.boot`` give the shrink intervals (every point trains).
    noise : float
        rms log10 noise, given or estimated; :func:`noise_prior` turns it into the scale s.
    noise_given : bool
        Whether the noise was given (``--noise``).
    timings : dict
        Updated in place: candidate name -> wall-clock time of its fit [s].
    say : callable
        Called with one progress line (str) per fit.

    Returns
    -------
    tuple
        (cal, cands, s, nu, significant): the calibration's fit (None without uncertain inputs),
        the effects fitted (each with ``.evidence``), the noise scale and its degrees of freedom,
        and whether the baseline gap is significant.
    """
    import time

    from pipelines.diagnosis import gap as gapmod
    from pipelines.diagnosis.fit.evidence import model_evidence
    from pipelines.diagnosis.fit.fitting import at_bound, fit_candidate
    from pipelines.diagnosis.model import simulate

    y = np.log10(np.asarray(real_mu, float))
    n = y.size
    r0 = y - np.log10(simulate(ctx.base, ctx))
    every = np.ones(n, bool)

    def finish(c, t1, s, nu):
        c.at_bound = at_bound(ctx, c.effects, c.params)
        bad = [
            (nm if len(c.effects) == 1 else f"{e.name}.{nm}", why)
            for e, p in zip(c.effects, c.params)
            for nm, why in e.implausible(ctx, p, real_mu)
        ]
        c.implausible = [b[0] for b in bad]
        c.implausible_why = [b[1] for b in bad]
        c.evidence = model_evidence(ctx, real_mu, c, s, nu)
        _press(c, c.evidence, y, s, r0, ho.boot, n)
        c.seconds = time.perf_counter() - t1
        return c

    def told(c):
        timings[c.name] = c.seconds
        say(f"  {c.name}: rms {c.gap_all:.4f} ln Z {c.evidence['log_z']:.2f} ({c.seconds:.1f} s)")
        return c

    cal = None
    t1 = time.perf_counter()
    s, nu = noise_prior(noise, noise_given)
    if cal_e is not None:
        cal = told(finish(fit_candidate(ctx, real_mu, (cal_e,), every, cache={}), t1, s, nu))
    significant = gapmod.is_significant(float(np.sqrt(np.mean(r0**2))), s, n)
    if not significant:
        return cal, [], s, nu, significant

    def fitted_with(e):
        return (cal_e, e) if cal is not None else (e,)

    def fit(e):
        t1 = time.perf_counter()
        own = e.null_params(ctx) or {p.name: p.init for p in e.params}
        effs = fitted_with(e)
        if cal is not None:
            starts = [cal.params + [own]]
            budget = 8 if e.cost > 1 else 20 + 4 * (len(e.params) + len(cal_e.params))
            c = fit_candidate(ctx, real_mu, effs, every, cache={}, extra_starts=starts, budget=budget)
        else:
            c = fit_candidate(ctx, real_mu, effs, every, cache={})
        shown = [finish(c, t1, s, nu)]
        if shown[0].implausible and e.physical is not None:
            shown += _physical(ctx, real_mu, shown[0], every, finish, s, nu)
        return [portable(c, effs) for c in shown], len(shown) > 1 and not shown[-1].implausible

    cands = []
    for e, (shown, refit_kept) in zip(usable, fit_map(fit, usable, cost=lambda e: e.cost)):
        shown = [restore(c, fitted_with(e)) for c in shown]
        for c in shown:  # an implausible fit is reported before its refit within the physical ranges
            told(c)
        cands.append(shown[-1] if refit_kept else shown[0])
    return cal, cands, s, nu, significant


def _physical(ctx, real_mu, c, every, finish, s, nu):
    """An implausible fit refitted within its effects' physical ranges: ``[refit]``, or ``[]``
    where an effect declares no such range (the caller keeps the refit when it is physical)."""
    import time

    from pipelines.diagnosis.fit.fitting import fit_candidate

    effs = tuple(e if e.name == "calibration" else e.restricted(ctx, real_mu) for e in c.effects)
    if any(e is None for e in effs):
        return []
    t1 = time.perf_counter()
    start = [
        {p.name: float(np.clip(q[p.name], p.lo, p.hi)) for p in e.params} for e, q in zip(effs, c.params)
    ]
    budget = 8 if max(e.cost for e in effs) > 1 else None
    r = fit_candidate(ctx, real_mu, effs, every, cache={}, extra_starts=[start], budget=budget)
    return [finish(r, t1, s, nu)]


def second_opinion(ctx, real_mu, usable, cal_e, noise, noise_given, verdict, best, timings):
    """With uncertain inputs given, an effect named by the held-out third (20 points or more)
    must also be the most probable explanation by the evidence, and decided (3 times as probable
    as every other, :func:`.evidence.decisive`; every model fitted on every point, :mod:`.few`);
    otherwise the verdict becomes inconclusive between it and the most
    probable other. Confidence is low below posterior 0.9, at most medium below 0.99.
    Adds ``bayes`` (the evidence's models and posteriors) to ``verdict``. Returns the named
    candidate or None.

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows and the baseline spec.
    real_mu : ndarray, shape (n,)
        Measured mu at every row.
    usable : list of Effect
        Effects the held-out search tried; each is refitted with the calibration on every point.
    cal_e : Effect
        The calibration pseudo-effect of the given uncertain inputs.
    noise : float
        rms log10 noise, given or estimated.
    noise_given : bool
        Whether the noise was given (``--noise``): it then weighs 30 degrees of freedom, not 4.
    verdict : dict
        The held-out verdict (updated).
    best : Candidate
        The candidate the held-out verdict names.
    timings : dict
        Not used: these refits are not timed into the diagnosis' timings.

    Returns
    -------
    Candidate or None
        The candidate the verdict keeps.
    """
    from pipelines.diagnosis.fit.cv import Holdout
    from pipelines.diagnosis.fit.evidence import P_NAME, decisive
    from pipelines.diagnosis.verdict.few import decide_few
    from pipelines.diagnosis.verdict.many import unname

    n = np.asarray(real_mu).size
    every = np.ones(n, bool)
    ho = Holdout(True, every, every, n, np.random.default_rng(0).integers(0, n, size=(1000, n)))
    cal, cands, s, nu, significant = few_candidates(
        ctx, real_mu, usable, cal_e, ho, noise, noise_given, {}, lambda *_: None
    )
    st = dict(
        g_all=float(np.sqrt(np.mean(np.log10(real_mu / cal.pred) ** 2))),
        noise=s,
        n=n,
        significant=significant,
        p=0.0,
        s=s,
        nu=nu,
    )
    v2, _, expl = decide_few(ctx, real_mu, cal, cands, st)
    verdict["bayes"] = v2["evidence"]
    name = "+".join(best.effect_names)
    top = expl[0]
    if top["name"] == name and decisive(top["posterior"], [x["posterior"] for x in expl[1:]]):
        if top["posterior"] < P_NAME:
            verdict["confidence"] = "low"
            verdict["_below_p_name"] = True  # next_measurement.withdraw_unseparated reads it
        elif top["posterior"] < 0.99 and verdict.get("confidence") == "high":
            verdict["confidence"] = "medium"
        return best
    other = top["name"] if top["name"] != name else expl[1]["name"]
    unname(
        verdict,
        [name, other],
        f"inconclusive: {name} shrinks the held-out gap, but the evidence of every point does "
        f"not single it out ({top['name']} posterior {top['posterior']:.2f}, "
        f"{expl[1]['name']} {expl[1]['posterior']:.2f})",
    )
    return None
