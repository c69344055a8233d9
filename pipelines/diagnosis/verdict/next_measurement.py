"""What to measure next: where the two most probable explanations differ most against the noise.

For each of the two explanations (fitted models), mu is predicted on a grid of speeds (the
measured range continued half a decade either way, within 1e-7..30 m/s) and, where the rubber
has a shift table, of temperatures across the table (else at the measured temperature). The
expected separation of a new measurement at (v, T) in noise sigmas is

    z = |log10 mu_a - log10 mu_b| / sqrt(s^2 + var_a + var_b)

with s the noise and var the predictive variance of each model, g^T (H + 12 I)^-1 g (g = d log10
mu / d u at (v, T), H the Gauss-Newton Hessian of its fit, 12 I the precision of a uniform prior
on the unit cube: the parameters' uncertainty after the data; Laplace approximation as in
:mod:`.evidence`). The proposal: the point of largest z and the next best at least half a decade
away at the same temperature (the optimal design of a discrimination experiment; Box & Hill 1967,
Technometrics 9, 57).

When no speed or temperature separates them (or no explanation of different physics is left),
:func:`unseparated` says so and names the other quantity that would (``OTHER_QUANTITY``: a dry
road, a finer scan, the rubber's temperature, the contact pressure ...), so that every
inconclusive or low-confidence verdict says what to measure next.

A water film acts on wet rows only: when every measured row is wet and one of the two
explanations is ``water``, the grid holds dry rows too (same speeds and temperatures), so a dry
measurement is proposed where it separates the two best (``condition`` "dry"), e.g. water from a
contact correction, which lower mu alike over the measured speeds but not on a dry road.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "next_measurement",
    "propose",
    "no_pair",
    "unseparated",
    "withdraw_unseparated",
    "OTHER_QUANTITY",
    "N_SPEEDS",
]

N_SPEEDS = 13
N_TEMPS = 3
MIN_APART_DECADES = 0.5
#: the most repeats per proposed speed; a pair that 10 repeats cannot separate by a combined 3
#: sigmas gets no proposal
MAX_REPEATS = 10


def _grid(ctx, dry=False):
    """The grid context (speeds x temperatures, and a dry copy of it when ``dry``); returns
    (context, speeds, [(temperature, wet)], whether the rubber has a shift table)."""
    from pipelines.diagnosis.model import FrictionContext

    v0, v1 = float(ctx.v_m_per_s.min()), float(ctx.v_m_per_s.max())
    v = np.geomspace(max(v0 / 10**0.5, 1e-7), min(v1 * 10**0.5, 30.0), N_SPEEDS)
    T = ctx.T0_C[np.isfinite(ctx.T0_C)]
    T_meas = float(np.median(T)) if T.size else float(ctx.base.rubber.T_ref_C)
    table = getattr(getattr(ctx.base.rubber, "shift", None), "T_C", None)
    temps = [T_meas]
    has_table = table is not None and np.size(table) > 1
    if has_table:
        temps = sorted(
            set(np.round(np.linspace(float(np.min(table)), float(np.max(table)), N_TEMPS), 1)) | {T_meas}
        )
    wet = bool(np.all(ctx.wet)) and ctx.n > 0
    conds = [(T, wet) for T in temps] + ([(T, False) for T in temps] if dry and wet else [])
    vv = np.tile(v, len(conds))
    TT = np.repeat(np.asarray([T for T, _ in conds], float), v.size)
    n = vv.size
    g = FrictionContext(
        vv,
        TT,
        np.full(n, float(np.median(ctx.sigma0_Pa))),
        np.repeat(np.asarray([w for _, w in conds], bool), v.size),
        ctx.base,
        ctx.scan,
        ctx.spectrum,
        ctx.fit,
        ctx.inputs,
        ctx.cache,
    )
    return g, v, conds, has_table


def _has_water(expl):
    c = expl.get("candidate")
    return c is not None and "water" in c.effect_names


def _predict(gctx, expl):
    """(mean log10 mu, variance) of one explanation on the grid context."""
    from pipelines.diagnosis.fit.evidence import _log10_model
    from pipelines.diagnosis.fit.fitting import pack
    from pipelines.diagnosis.fit.stats import jacobian
    from pipelines.diagnosis.model import simulate

    if expl.get("candidate") is None:
        return np.log10(simulate(gctx.base, gctx)), np.zeros(gctx.n)
    c = expl["candidate"]
    f = _log10_model(gctx, c.effects)
    u = np.clip(pack(c.effects, c.params), 0, 1)
    m = f(u)
    H = expl.get("H")
    if H is None or not np.size(H):
        return m, np.zeros(gctx.n)
    G = jacobian(f, u, f0=m)
    G = np.where(np.isfinite(G), G, 0.0)
    cov = np.linalg.inv(H + 12.0 * np.eye(H.shape[0]))
    return m, np.einsum("ij,jk,ik->i", G, cov, G)


def _separation(g, v, temps, ma, va, mb, vb, s):
    z = np.abs(ma - mb) / np.sqrt(s * s + va + vb)
    return np.where(np.isfinite(z), z, 0.0).reshape(len(temps), v.size)


def next_measurement(ctx, a, b, noise):
    """Where to measure to tell explanation ``a`` from ``b``.

    ``a``: dict(name, candidate (fitting.Candidate or None: the nominal model), H (its
    Gauss-Newton Hessian in the unit cube)); ``b``: such a dict, or a list of them ranked by
    probability (the first whose predictions differ from ``a``'s by a noise sigma somewhere is
    taken, else the most different); ``noise``: rms log10 noise. Returns dict(between,
    speeds_m_per_s, temperature_C (None without a shift table), separation_sigma (per speed),
    separation_sigma_combined, repeats (measurements per speed for a combined 3 sigma, at most
    10), sentence, method) or None when a prediction fails or when even ``MAX_REPEATS`` repeats
    at the two best speeds would not separate the pair by a combined 3 sigmas (the same noise
    scale and parameter uncertainty as the evidence, :mod:`.evidence`).

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows: their speed range, temperature, pressure and rubber set the grid of
        candidate measurements.
    a : dict
        The most probable explanation.
    b : dict or list of dict
        The alternative(s), ranked by probability.
    noise : float
        rms of log10(measured / simulated mu) of one measurement: a sigma of the separation.

    Returns
    -------
    dict or None
        ``between``, ``speeds_m_per_s``, ``temperature_C`` and the expected separation.
    """
    from pipelines.diagnosis.fit.evidence import noise_scale

    alts = list(b) if isinstance(b, (list, tuple)) else [b]
    g, v, temps, has_table = _grid(ctx, dry=_has_water(a) or any(_has_water(x) for x in alts))
    s = noise_scale(noise)
    try:
        ma, va = _predict(g, a)
    except (ValueError, ArithmeticError, RuntimeError, np.linalg.LinAlgError):
        return None
    best = None
    for cand in alts:
        try:
            mb, vb = _predict(g, cand)
        except (ValueError, ArithmeticError, RuntimeError, np.linalg.LinAlgError):
            continue
        z = _separation(g, v, temps, ma, va, mb, vb, s)
        if best is None or z.max() > best[1].max():
            best = (cand, z)
        if z.max() >= 1.0:
            best = (cand, z)
            break
    if best is None:
        return None
    b, z = best
    it, i1 = np.unravel_index(int(np.argmax(z)), z.shape)
    far = np.abs(np.log10(v) - np.log10(v[i1])) >= MIN_APART_DECADES
    i2 = int(np.argmax(np.where(far, z[it], -1.0))) if far.any() else None
    idx = sorted([i1] + ([i2] if i2 is not None else []))
    speeds = [float(v[i]) for i in idx]
    sep = [float(z[it, i]) for i in idx]
    comb = float(np.sqrt(np.sum(np.square(sep))))
    reps = int(min(MAX_REPEATS, max(1, np.ceil(9.0 / max(comb**2, 1e-12)))))
    T = float(temps[it][0]) if has_table else None
    dry = not temps[it][1] and bool(np.all(ctx.wet))
    where = " and ".join(f"{x:.3g}" for x in speeds) + " m/s" + (f" at {T:.3g} C" if T is not None else "")
    where += " on a dry road (no water)" if dry else ""
    times = "" if reps == 1 else f" ({reps} times each)"
    sentence = (
        f"measure at {where}{times}: {a['name']} and {b['name']} differ there by "
        + " and ".join(f"{x:.2g}" for x in sep)
        + " noise sigmas"
    )
    if comb * np.sqrt(MAX_REPEATS) < 3.0:
        return None  # no speed or temperature of the grid separates them: no measurement to propose
    if max(sep) < 1.0:
        sentence = (
            f"no speed from {v[0]:.3g} to {v[-1]:.3g} m/s separates {a['name']} and {b['name']} by a "
            f"noise sigma (at most {max(sep):.2g} at {where}): measure another condition or repeat "
            "points to lower the noise"
        )
    return dict(
        between=[a["name"], b["name"]],
        separable=True,
        speeds_m_per_s=speeds,
        temperature_C=T,
        condition="dry" if dry else None,
        separation_sigma=sep,
        separation_sigma_combined=comb,
        repeats=reps,
        sentence=sentence,
        method="largest expected separation of the two most probable explanations in noise sigmas "
        "(model uncertainty included), over speeds and the shift table's temperatures (and a dry "
        "road when water is one of them and every measured row is wet); repeats "
        "for a combined separation of 3 sigmas (at most 10)",
    )


#: the measurement of another quantity that tells an explanation (or an uncertain input) apart
#: where mu(v) cannot: what each one changes besides mu at the measured speeds
OTHER_QUANTITY = {
    "q1": "a finer scan of the road (roughness beyond the last wave vector of the spectrum)",
    "fine_roughness": "a finer scan of the road (roughness beyond the last wave vector of the spectrum)",
    "psd_scale": "a repeated or longer scan of the road (the level of the spectrum)",
    "sigma0": "the nominal contact pressure (load over the apparent contact area)",
    "load": "a run at another nominal pressure",
    "temperature": "the temperature of the rubber during the test",
    "temperature_offset": "the temperature of the rubber during the test, or a run at another temperature",
    "flash_temperature": "the temperature rise of the contact (a thermal camera at the trailing edge)",
    "water": "a run on a dry road",
    "contact_correction": "a run at another nominal pressure (how the contact area grows with load)",
    "adhesion": "a run on a lubricated road (the adhesive contribution removed)",
    "relaxation_spectrum": "a DMA sweep of the rubber at the frequencies the contact excites",
}


def _needs(name, inputs=()):
    """The other quantities that bear on explanation ``name`` ("+"-joined effects, "calibration":
    its ``inputs``)."""
    keys = list(inputs) if name == "calibration" else name.split("+")
    return [OTHER_QUANTITY[k] for k in keys if k in OTHER_QUANTITY]


def unseparated(a, alts, ctx, inputs=(), why=None):
    """``next_measurement`` when no speed or temperature of the grid tells explanation ``a`` from
    the alternatives ``alts`` (:func:`next_measurement` returned None: even ``MAX_REPEATS``
    repeats at the two best speeds stay below a combined 3 noise sigmas, the same noise and
    parameter uncertainty as the evidence), or when no alternative of different physics is left:
    which other quantity would separate them, and why the speeds this rig measures do not.

    Parameters
    ----------
    a : str
        The most probable explanation's name.
    alts : list of str
        The alternatives tried (empty: none of different physics).
    ctx : FrictionContext
        Model context (the measured speeds).
    inputs : iterable of str, optional
        The ``--uncertain`` keys the calibration fits.
    why : str, optional
        Why the verdict is of low confidence (an input on a bound of its range ...).

    Returns
    -------
    dict
        ``between``, ``separable`` (False), ``speeds_m_per_s`` (empty), ``measure`` (the other
        quantities), ``sentence`` and ``method``; the keys of :func:`next_measurement` are kept.
    """
    v0, v1 = float(ctx.v_m_per_s.min()), float(ctx.v_m_per_s.max())
    lo, hi = max(v0 / 10**0.5, 1e-7), min(v1 * 10**0.5, 30.0)
    needs = []
    for n in [a, *alts]:
        needs += [x for x in _needs(n, inputs) if x not in needs]
    if alts:
        head = (
            f"no speed from {lo:.3g} to {hi:.3g} m/s (nor a temperature of the shift table) separates "
            f"{a} from {' or '.join(alts)} by 3 noise sigmas, even with {MAX_REPEATS} repeats: they "
            "predict the same mu wherever mu(v) is measured"
        )
    else:
        head = (
            f"no explanation of other physics than {a} fits: measuring mu at other speeds would only "
            "narrow its fitted values"
        )
    if why:
        head += f" ({why})"
    tail = "; to tell them apart measure " if alts else "; to firm it up measure "
    sentence = head + (
        tail + ", or ".join(needs) if needs else "; no other measurement is known to separate them"
    )
    return dict(
        between=[a, *alts],
        separable=False,
        speeds_m_per_s=[],
        temperature_C=None,
        condition=None,
        separation_sigma=[],
        separation_sigma_combined=None,
        repeats=None,
        measure=needs,
        sentence=sentence,
        method="no point of the grid of speeds (and temperatures) separates the explanations by a combined "
        f"3 noise sigmas with {MAX_REPEATS} repeats (model uncertainty included); the other quantity "
        "each explanation changes is proposed instead",
    )


def _low_why(verdict):
    """Why a verdict is of low confidence, in words (None when it is not said by a bound)."""
    b = verdict.get("at_bound") or []
    if b:
        return f"{', '.join(b)} at the end of {'its range' if len(b) == 1 else 'their ranges'}"
    return None


def propose(ctx, a, alts, s, verdict, inputs=()):
    """next_measurement between ``a`` and the first of ``alts`` that is different physics
    (:func:`.same_physics.distinct`, given the calibrated ``inputs``); when no measurement on the
    grid separates them, or none is different physics, the other quantity that would
    (:func:`unseparated`), the verdict's reason saying so.

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows (their speeds, temperature and pressure set the grid searched).
    a : dict
        The most probable explanation (name, candidate, H).
    alts : list of dict
        The alternatives, ranked.
    s : float
        Noise scale of the evidence, rms log10: one sigma of the separation.
    verdict : dict
        The verdict (its reason is extended; its ``at_bound`` says why confidence is low).
    inputs : iterable of str, optional
        The ``--uncertain`` keys the calibration fits.

    Returns
    -------
    dict
        :func:`next_measurement` or :func:`unseparated`.
    """
    from pipelines.diagnosis.verdict.same_physics import distinct

    alts = [b for b in alts if distinct(a["name"], b["name"], inputs)]
    if not alts:
        return unseparated(a["name"], [], ctx, inputs, _low_why(verdict))
    nxt = next_measurement(ctx, a, alts, s)
    if nxt is None:
        names = [b["name"] for b in alts[:3]]
        verdict["reason"] += (
            f"; no speed or temperature separates {a['name']} from "
            f"{' or '.join(names)} by 3 noise sigmas, even with repeated points"
        )
        return unseparated(a["name"], names, ctx, inputs, _low_why(verdict))
    return nxt


def withdraw_unseparated(verdict, nxt):
    """Withdraw a name decided below posterior 0.9 that no measurement can tell from its runner-up.

    Below posterior :data:`~pipelines.diagnosis.fit.evidence.P_NAME` an explanation is named at 3
    times the probability of every other (:func:`~pipelines.diagnosis.fit.evidence.decisive`;
    the verdict carries ``_below_p_name``). When ``nxt`` finds no speed or temperature where it and
    its runner-up differ by 3 noise sigmas, even with repeats, the two predict the same mu
    wherever mu(v) can be measured: they fit equally well, and odds of 3 between them rest on the
    noise of these points. The verdict becomes inconclusive between the two; ``nxt`` (the other
    quantity to measure) stays. The same model uncertainty decides separation here and in
    :func:`next_measurement`.

    Parameters
    ----------
    verdict : dict
        The verdict (changed in place; its ``_below_p_name`` flag is removed in every case).
    nxt : dict or None
        Its next_measurement (:func:`propose` or :func:`no_pair`).

    Returns
    -------
    bool
        True when the name was withdrawn.
    """
    if not verdict.pop("_below_p_name", False) or nxt is None or nxt.get("separable", True):
        return False
    pair = list(nxt.get("between") or [])
    name = verdict.get("effect")
    name = name if isinstance(name, str) or name is None else "+".join(name)
    if len(pair) < 2 or pair[0] != name:
        return False
    from pipelines.diagnosis.verdict.many import unname

    unname(
        verdict,
        pair[:2],
        f"inconclusive: {pair[0]} is the most probable explanation below posterior 0.9, but no "
        f"speed or temperature separates it from {pair[1]} by 3 noise sigmas, even with repeated "
        "points: the two predict the same mu wherever mu(v) can be measured, so the odds between "
        "them on these points rest on their noise",
    )
    return True


def no_pair(ctx, verdict, inputs):
    """next_measurement of a low or inconclusive verdict with no pair of fitted explanations to
    compare (:func:`unseparated` of its named or first inconclusive explanation).

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows (their speed range and temperature are named in the proposal).
    verdict : dict
        The verdict: its named or first inconclusive explanation, and ``at_bound`` for the why.
    inputs : iterable of str
        The ``--uncertain`` keys the calibration fits.

    Returns
    -------
    dict
        :func:`unseparated`: the other quantity to measure, ``separable`` False.
    """
    inc = list(verdict.get("inconclusive") or [])
    a = inc[0] if inc else (verdict.get("effect") or "calibration")
    a = a if isinstance(a, str) else "+".join(a)
    return unseparated(a, inc[1:], ctx, inputs, _low_why(verdict))
