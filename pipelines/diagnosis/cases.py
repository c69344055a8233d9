"""Seeded cases for the proof: "real" data from the model with ONE hidden effect, or none.

A case draws (from ``numpy.random.default_rng(seed)``): a surface (a self-affine spectrum, or
a synthetic Gaussian self-affine scan analysed like a measured one; the water effect always gets
a scan), 20 to 40 log-spaced speeds spanning 3 to 7 decades within 1e-6 to 30 m/s, a
multiplicative noise level of 2 to 5 %, and for an effect case the hidden effect's parameters
from the realistic ranges of :data:`RANGES` (the generator's own, not the search bounds).
"real" mu = model with the effect x (1 + noise x N(0, 1)).

:func:`identifiable` is the filter of the issue: a case counts only if its effect moves the
noiseless mu by more than ``2 x`` the noise (rms log10) and no other effect, best fitted to the
noiseless curve, comes within the noise of it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pipelines.diagnosis.effects import all_effects, get
from pipelines.diagnosis.inputs import build_context, surface_from_scan
from pipelines.diagnosis.measured import MeasuredCurve
from pipelines.diagnosis.model import simulate

__all__ = ["RANGES", "Case", "make_case", "identifiable", "draw_cases"]

LOG10E = math.log10(math.e)


def _u(rng, a, b):
    return float(rng.uniform(a, b))


def _logu(rng, a, b):
    return float(np.exp(rng.uniform(np.log(a), np.log(b))))


#: realistic ranges of the hidden effects' parameters (generator side)
RANGES = {
    "flash_temperature": lambda r: dict(zeta_m=_u(r, 2.0, 5.0), heat_scale=_logu(r, 0.5, 2.0)),
    "relaxation_spectrum": lambda r: dict(width_decades=_logu(r, 0.2, 1.5)),
    "temperature_offset": lambda r: dict(dT_C=float(r.choice([-1, 1])) * _u(r, 3.0, 20.0)),
    "fine_roughness": lambda r: dict(q1_factor=_logu(r, 2.0, 30.0)),
    "water": lambda r: dict(fill_fraction=_logu(r, 0.1, 1.0)),
    # adhesion is drawn in the generator's own shapes (see _adhesion_truth), not the effect's
    "adhesion": lambda r: dict(
        amplitude=_logu(r, 0.02, 0.3),
        v_c_m_per_s=_logu(r, 1e-6, 1e-2),
        exponent=_u(r, 0.7, 2.0),
        bell_decades=(None if r.random() < 0.5 else _u(r, 0.5, 1.5)),
    ),
    "load": lambda r: dict(sigma0_scale=(_logu(r, 0.3, 0.6) if r.random() < 0.5 else _logu(r, 1.7, 3.5))),
    "contact_correction": lambda r: dict(contact_gamma=_u(r, 0.2, 0.9)),
}


@dataclass(eq=False)
class Case:
    """One generated case: the blind inputs (curve, psd, scan) and the hidden truth.

    Attributes
    ----------
    seed : int
        Seed of the case's random generator: the same seed gives the same case.
    effect : str or None
        Registered name of the hidden effect; None for a null case (baseline plus noise).
    params : dict
        The hidden effect's parameters drawn from :data:`RANGES`; empty for a null case.
    noise_rel : float
        Relative (multiplicative) noise: mu = truth (1 + noise_rel N(0, 1)), drawn in [0.02, 0.05].
    curve : MeasuredCurve
        The "measured" curve: 20 to 40 speeds over 3 to 7 decades, 0.2 MPa, T0 the rubber's T_ref.
    psd, scan, spectrum, fit : object
        Blind inputs: the spectrum; the synthetic scan, its Spectrum and fit (None without a scan).
    truth_mu, base_mu : ndarray
        Noiseless truth and baseline.
    info : dict
        :func:`identifiable`'s notes (effect_rms, noise_log10, others, why); empty for null cases.
    """

    seed: int
    effect: str | None
    params: dict
    noise_rel: float
    curve: MeasuredCurve
    psd: object
    scan: object = None
    spectrum: object = None
    fit: object = None
    truth_mu: np.ndarray | None = None
    base_mu: np.ndarray | None = None
    info: dict = field(default_factory=dict)

    def context(self):
        return build_context(self.curve, self.psd, scan=self.scan, spectrum=self.spectrum, fit=self.fit)


def _surface(rng, want_scan):
    from friction import SelfAffinePSD

    hurst = _u(rng, 0.7, 0.9)
    if not want_scan:
        q0 = _logu(rng, 1e3, 4e3)
        return SelfAffinePSD(hurst, _logu(rng, 2e-4, 8e-4), q0, q0 * _logu(rng, 30, 300)), None, None, None
    from roadscan.synth import self_affine_surface

    dx = _logu(rng, 4e-5, 1e-4)
    n = 256
    L = n * dx
    hm = self_affine_surface(
        n,
        n,
        dx_m=dx,
        hurst=hurst,
        rms_height_m=_logu(rng, 1.5e-4, 5e-4),
        q_roll_per_m=_u(rng, 3, 6) * 2 * np.pi / L,
        seed=int(rng.integers(2**31)),
        name="case_scan",
    )
    psd, filled, spec, fit = surface_from_scan(hm)
    return psd, filled, spec, fit


def _adhesion_truth(v, p):
    """The generator's adhesion, independent of the effect's own form: either a plateau falling
    as A / (1 + (v/v_c)^n), or Persson's bell A exp(-1/2 (log10(v/v_c)/w)^2) (``bell_decades`` w)."""
    x = np.asarray(v, float) / p["v_c_m_per_s"]
    if p["bell_decades"] is None:
        return p["amplitude"] / (1.0 + x ** p["exponent"])
    return p["amplitude"] * np.exp(-0.5 * (np.log10(x) / p["bell_decades"]) ** 2)


def make_case(seed, effect=None, scan=None):
    """Generate the case of ``seed`` with hidden ``effect`` (a registered name) or none.

    Parameters
    ----------
    seed : int
        Seed of ``numpy.random.default_rng``: the same seed gives the same case.
    effect : str, optional
        Registered name of the hidden effect; None: a null case.
    scan : bool, optional
        Whether to synthesise a 256 x 256 scan (used only for its truth value); None: with
        probability 1/4. The water effect always gets one.

    Returns
    -------
    Case
        The blind inputs, the noisy curve and the hidden truth (``info`` still empty).
    """
    rng = np.random.default_rng(seed)
    want_scan = (effect == "water") or (scan if scan is not None else rng.random() < 0.25)
    psd, hm, spec, fit = _surface(rng, want_scan)
    n = int(rng.integers(20, 41))
    span = _u(rng, 3.0, 7.0)
    lo_max = np.log10(30.0) - span
    lo = _u(rng, -6.0, lo_max)
    v = np.logspace(lo, lo + span, n)
    noise = _u(rng, 0.02, 0.05)
    nanT = np.full(n, np.nan)
    curve = MeasuredCurve(v, np.ones(n), nanT, np.full(n, 0.2e6), np.zeros(n, bool), False, f"case{seed}")
    ctx = build_context(curve, psd, scan=hm, spectrum=spec, fit=fit)
    base = simulate(ctx.base, ctx)
    params = {}
    if effect is None:
        truth = base
    else:
        e = get(effect)
        params = RANGES[effect](rng)
        if e.prepare is not None:
            why = e.prepare(ctx)
            if why:
                raise ValueError(f"case {seed}: {effect} unusable: {why}")
        if effect == "adhesion":
            truth = base + _adhesion_truth(v, params)
        else:
            truth = simulate(e.modify(ctx.base, params, ctx), ctx)
    mu = truth * (1.0 + noise * rng.standard_normal(n))
    mu = np.maximum(mu, 1e-3 * truth)
    curve = MeasuredCurve(v, mu, nanT, np.full(n, 0.2e6), np.zeros(n, bool), False, f"case{seed}")
    return Case(seed, effect, params, noise, curve, psd, hm, spec, fit, truth, base)


def identifiable(case, move=2.0, effects=None):
    """The issue's filter. Returns (ok, info): ok when the hidden effect moves the noiseless mu
    by more than ``move`` x the noise (rms log10 of (1 + noise N)) and every other effect, best
    fitted to the noiseless curve (all points), stays further than the noise from it.

    Parameters
    ----------
    case : Case
        A case of :func:`make_case`; a null case is always identifiable.
    move : float, optional
        Signal threshold in noise units.
    effects : list of Effect, optional
        Rival effects fitted to the noiseless curve; None: every friction-level effect.

    Returns
    -------
    ok : bool
        Whether the case passes the filter.
    info : dict
        effect_rms and noise_log10 (rms log10), others (rival name -> its gap) and why (if not ok).
    """
    from pipelines.diagnosis.verdict.search import fit_candidate

    if case.effect is None:
        return True, {}
    sig = LOG10E * case.noise_rel
    shift = float(np.sqrt(np.mean(np.log10(case.truth_mu / case.base_mu) ** 2)))
    info = dict(effect_rms=shift, noise_log10=sig)
    if shift < move * sig:
        info["why"] = f"effect moves mu by {shift:.4f} < {move} x noise {sig:.4f}"
        return False, info
    ctx = case.context()
    allrows = np.ones(case.curve.n, bool)
    others = {}
    for e in effects or all_effects("friction"):
        if e.name == case.effect or e.missing(ctx):
            continue
        if e.prepare is not None and e.prepare(ctx):
            continue
        c = fit_candidate(ctx, case.truth_mu, (e,), allrows)
        others[e.name] = c.gap_all
        if c.gap_all < sig:
            info.update(
                others=others, why=f"{e.name} explains it within the noise ({c.gap_all:.4f} < {sig:.4f})"
            )
            return False, info
    info["others"] = others
    return True, info


def draw_cases(n_effect, n_null, seed0=0, effects=None, max_tries=6, log=None):
    """``n_effect`` identifiable effect cases and ``n_null`` null cases, reproducibly from
    ``seed0``. Hidden effects cycle through the friction effects; an effect whose draws fail
    the filter ``max_tries`` times in a row gives its turn to the next one (load and water
    often move mu too little, or like another effect, to be told apart).
    Returns (cases, rejected count).

    Parameters
    ----------
    n_effect, n_null : int
        Number of identifiable effect cases and of null cases wanted.
    seed0 : int, optional
        Seeds used are seed0 + 1, seed0 + 2, ... (default 0).
    effects : list of Effect, optional
        Hidden effects cycled through (the filter's rivals stay every friction effect); None: all.
    max_tries : int, optional
        Draws an effect gets per turn before giving it to the next (default 6).
    log : callable, optional
        Called with one line (str) per rejected draw; None: silent.

    Returns
    -------
    cases : list of Case
        The effect cases (fewer when 20 n_effect turns do not find them), then the null cases.
    rejected : int
        Number of draws the filter rejected.
    """
    say = log or (lambda *_: None)
    names = [e.name for e in (effects or all_effects("friction"))]
    cases, rejected, seed, turn = [], 0, seed0, 0
    while len(cases) < n_effect and turn < 20 * max(n_effect, 1):
        name = names[turn % len(names)]
        turn += 1
        for _ in range(max_tries):
            seed += 1
            c = make_case(seed, name)
            ok, info = identifiable(c)
            c.info = info
            if ok:
                cases.append(c)
                break
            rejected += 1
            say(f"  reject seed {seed} ({name}): {info.get('why')}")
    for _ in range(n_null):
        seed += 1
        cases.append(make_case(seed, None))
    return cases, rejected
