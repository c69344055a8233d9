"""Same physics, one name: an effect that is a model input continued (roughness beyond the scan's
last wave vector is a larger q1; a load dependence is another nominal pressure sigma0; a
temperature offset is another background temperature T0) is named as the effect, with the input
value it amounts to (``verdict.equivalent_input``).

The equivalence test (:mod:`pipelines.diagnosis.fit.equivalence`) finds such an effect
reproduced by the uncertain inputs continued beyond their ranges; when the inputs it moves are
the effect's own input, the two are one explanation told twice, not two explanations the data
cannot tell apart: the verdict keeps the effect, its confidence from the evidence, and says
which input value it means ("fine_roughness: the rubber feels roughness to q1 = 1.07e6 1/m,
beyond the scan's 2.3e5"). Inconclusive stays for different physics fitting equally well.
"""

from __future__ import annotations

import numpy as np

__all__ = ["SAME_PHYSICS", "same_physics", "equivalent_input", "distinct", "measured_end", "band_end_pool"]

#: effect -> the uncertain input (``--uncertain`` key) that is the same physics
SAME_PHYSICS = {"fine_roughness": "q1", "load": "sigma0", "temperature_offset": "temperature"}


def same_physics(names, moved):
    """Whether a candidate of effects ``names`` and the uncertain inputs ``moved`` beyond their
    ranges by the equivalence fit are one explanation: one effect, and every moved input its own.

    Parameters
    ----------
    names : list of str
        The candidate's physical effects (the calibration left out).
    moved : list of str
        ``--uncertain`` keys the extended calibration moved beyond their ranges.

    Returns
    -------
    bool
        True for one effect of :data:`SAME_PHYSICS` whose moved inputs are at most its own input.
    """
    if len(names) != 1 or names[0] not in SAME_PHYSICS:
        return False
    return set(moved) <= {SAME_PHYSICS[names[0]]}


def _spec(ctx, cand):
    spec = ctx.base
    for e, p in zip(cand.effects, cand.params):
        spec = e.modify(spec, p, ctx)
    return spec


def equivalent_input(ctx, cand):
    """The input value a same-physics effect amounts to, or None for other effects.

    q1 [1/m] of the spectrum the fit integrates (the effect's factor on the possibly calibrated
    q1), sigma0 [Pa] (nominal x every scale on it) or T0 [C] (nominal + every shift), against
    the nominal value of the inputs as given or assumed.

    Parameters
    ----------
    ctx : FrictionContext
        Model context (its base spec holds the nominal inputs).
    cand : Candidate
        The fitted candidate naming the effect (alone or with the calibration).

    Returns
    -------
    dict or None
        ``effect``, ``input`` (``q1_per_m``, ``sigma0_Pa`` or ``temperature_C``), ``value``,
        ``nominal`` and ``sentence``.
    """
    from pipelines.diagnosis.fit.calibration import nominal

    names = cand.effect_names
    if len(names) != 1 or names[0] not in SAME_PHYSICS:
        return None
    name = names[0]
    try:
        spec = _spec(ctx, cand)
    except (ValueError, ArithmeticError, RuntimeError):
        return None
    nom = nominal(ctx)
    if name == "fine_roughness":
        q1, q1_0 = float(spec.psd.q1_per_m), float(ctx.base.psd.q1_per_m)
        where = "beyond" if q1 > q1_0 else "within"
        return dict(
            effect=name,
            input="q1_per_m",
            value=q1,
            nominal=q1_0,
            sentence=f"{name}: the rubber feels roughness to q1 = {q1:.3g} 1/m, {where} the "
            f"spectrum's last wave vector {q1_0:.3g} 1/m",
        )
    if name == "load":
        s = float(nom["sigma0"] * spec.sigma0_scale)
        return dict(
            effect=name,
            input="sigma0_Pa",
            value=s,
            nominal=float(nom["sigma0"]),
            sentence=f"{name}: the contact behaves as at a nominal pressure sigma0 = "
            f"{s / 1e6:.3g} MPa, not {nom['sigma0'] / 1e6:.3g} MPa",
        )
    T = float(nom["temperature"] + spec.T0_shift_C)
    if not np.isfinite(T):
        return None
    return dict(
        effect=name,
        input="temperature_C",
        value=T,
        nominal=float(nom["temperature"]),
        sentence=f"{name}: the rubber behaves as at T0 = {T:.3g} C, not {nom['temperature']:.3g} C",
    )


def distinct(a, b, calibrated=None):
    """Whether explanations named ``a`` and ``b`` (``"+"``-joined effect names, ``"calibration"``
    or ``"nominal"``) are different physics, so that a measurement separating them says which
    one holds: not when one is a same-physics effect and the other the nominal model or a
    calibration of that effect's own input (a measurement would then only pin the input's value,
    not choose an explanation). A temperature offset against a calibration of q1, sigma0 and the
    spectrum's level is different physics.

    Parameters
    ----------
    a, b : str
        The explanations' names: ``"+"``-joined effect names, ``"calibration"`` or ``"nominal"``.
    calibrated : iterable of str, optional
        The ``--uncertain`` keys the calibration fits (None: any calibration counts as the
        effect's own input).

    Returns
    -------
    bool
        False for equal names or a same-physics effect against its own input; True otherwise.
    """
    keys = None if calibrated is None else set(calibrated)
    for x, y in ((a, b), (b, a)):
        if x in SAME_PHYSICS and (
            y == "nominal" or (y == "calibration" and (keys is None or SAME_PHYSICS[x] in keys))
        ):
            return False
    return a != b


def measured_end(ctx):
    """The finest wave vector the surface input measured [1/m]: the upper edge of the last bin of
    the scan's spectrum (a binned average: its log-spaced bins reach half a bin beyond their
    centres, q_n sqrt(q_n / q_(n-1))), or the last wave vector of a tabulated ``--psd`` (point
    values of C(q)), else the model's q1.

    Parameters
    ----------
    ctx : FrictionContext
        Model context (``spectrum``: the scan's measured spectrum, None for ``--psd``).

    Returns
    -------
    float
        The finest measured wave vector q [1/m].
    """
    q = np.sort(np.asarray(getattr(ctx.spectrum, "q_per_m", []), float).ravel())
    if q.size >= 2 and q[-2] > 0:
        return float(q[-1] * np.sqrt(q[-1] / q[-2]))
    q = getattr(ctx.base.psd, "q_per_m", None)
    if q is not None and np.size(q):
        return float(np.max(q))
    return float(ctx.base.psd.q1_per_m)


def band_end_pool(ctx, singles, pairs, cal, calpairs, n, noise, z_nom):
    """The explanations the evidence over every point compares when only q1's default range is
    uncertain, and the log evidence of "no effect".

    A scan's reliable band ends below the last wave vector it measured (the spectrum's finest,
    :func:`measured_end`). Where q1 is calibrated between the two, the calibration only says how
    much of the measured but unreliable top of the spectrum the contact feels, an uncertainty of
    the input: "no effect" is then the nominal model or the calibration alone (each half of its
    prior, so their evidences average), and an effect fitted with that calibration is the effect
    itself (its label, one parameter more in the Schwarz penalty), e.g. a water film on a scan
    whose reliable band ends below the roughness the contact feels. Where the calibration takes
    q1 beyond the measured spectrum it is roughness the scan did not measure, the same physics
    as ``fine_roughness`` (whose nominal fit is compared already), and below the reliable band
    it is a claim that measured roughness is not felt: the calibration alone is then no
    baseline and an effect fitted with it is that effect plus another, a pair, not compared. With
    a tabulated ``--psd`` the two ends coincide and the nominal fits alone are compared.

    Parameters
    ----------
    ctx : FrictionContext
        The context fitted: its nominal q1 and the measured spectrum's end bound the calibration.
    singles, pairs : list of Candidate
        Fits at the nominal inputs.
    cal : Candidate or None
        The calibration of q1 alone.
    calpairs : list of Candidate
        Each effect fitted with the calibration.
    n : int
        Number of measured points (every one counts in the evidence).
    noise : float
        rms of log10(measured / simulated mu) of the measurement: the evidence's noise scale.
    z_nom : float
        Log evidence of the nominal model over every point.

    Returns
    -------
    pool : list of Candidate
        ``singles`` and ``pairs``, plus the single effects fitted with a q1 within the measured band.
    z_base : float
        Log evidence of "no effect".
    """
    from pipelines.diagnosis.verdict.evidence_check import all_points_evidence

    pool = list(singles) + list(pairs)
    if cal is None:
        return pool, z_nom
    lo, end = float(ctx.base.psd.q1_per_m), measured_end(ctx)

    def within(c):
        q1 = c.params[0].get("q1_per_m") if c.effects[0].name == "calibration" else None
        return q1 is not None and lo < end and lo * (1 - 1e-9) <= q1 <= end

    z_base = z_nom
    z_cal = all_points_evidence(cal, n, noise)
    if within(cal) and np.isfinite(z_cal):
        z_base = float(np.logaddexp(z_nom, z_cal) - np.log(2.0))
    pool += [c for c in calpairs if len(c.effect_names) == 1 and within(c)]
    return pool, z_base
