"""Uncertain inputs: model inputs known only within a range, calibrated on the training points.

``--uncertain q1=LO:HI,sigma0=LO:HI,psd_scale=LO:HI,temperature=LO:HI`` (any subset)::

    ``q1``          the spectrum's upper cut-off [1/m] (the engine continues C(q) as its fitted
                    power law beyond the tabulated data, ``psd.with_q1``)
    ``sigma0``      the nominal pressure, with units as ``--sigma0`` (``0.15MPa:0.3MPa``)
    ``psd_scale``   a factor on C(q) (instrument level; h_rms scales as its square root)
    ``temperature`` the background temperature T0 [C] of every row (a shift of all rows by the same
                    amount when rows carry their own T0_C)

``q1=known`` (or ``q1=Q:Q``) declares q1 known. The calibration is a pseudo-effect named
``calibration`` whose parameters are the uncertain inputs within their ranges, its "no effect"
point the nominal inputs (clipped into the ranges). The baseline of the verdict becomes the
calibrated model; each effect is fitted together with it (:mod:`.search`).

Honest default: where mu is carried by the spectrum's cut-off (d ln mu / d ln q1 above
:data:`bandmap.CUTOFF_FLAG` at some measured speed) and q1 was not declared known, q1 is
uncertain over a decade either side of its nominal value (Persson 2006, J. Phys.: Condens.
Matter 18, 7789: mu then depends on where the spectrum is cut, which a scan cannot see).

Redundant effects are skipped: ``fine_roughness`` when q1 is calibrated (a larger q1 is that
effect), ``load`` with sigma0, ``temperature_offset`` with the temperature.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pipelines.diagnosis.effects import Effect, Param
from roadscan.errors import InputError

__all__ = [
    "Uncertain",
    "parse_uncertain",
    "calibration_effect",
    "default_q1",
    "REDUNDANT",
    "scale_psd",
    "intervals",
]

KEYS = ("q1", "sigma0", "psd_scale", "temperature")
#: the registered effect each uncertain input makes redundant
REDUNDANT = {"q1": "fine_roughness", "sigma0": "load", "temperature": "temperature_offset"}
PARAM = {"q1": "q1_per_m", "sigma0": "sigma0_Pa", "psd_scale": "psd_scale", "temperature": "temperature_C"}
DEFAULT_Q1_DECADES = 1.0


@dataclass(frozen=True)
class Uncertain:
    """One uncertain input: ``key`` (of :data:`KEYS`), range [lo, hi] in SI (temperature in C),
    ``source`` "given" or "default"; lo == hi means known (fixed at that value).

    Attributes
    ----------
    key : str
        One of ``"q1"``, ``"sigma0"``, ``"psd_scale"``, ``"temperature"``.
    lo, hi : float
        Range (SI; temperature in C).
    source : str
        ``"given"`` (``--uncertain``), ``"default"`` (the default q1 range) or ``"known"``
        (``q1=known``, lo and hi NaN).
    """

    key: str
    lo: float
    hi: float
    source: str = "given"

    @property
    def known(self):
        return self.lo == self.hi


def _number(text, key, whole):
    try:
        x = float(text)
    except ValueError:
        raise InputError(None, f"--uncertain {whole!r}: {key} bound {text!r} is not a number") from None
    if not np.isfinite(x):
        raise InputError(None, f"--uncertain {whole!r}: {key} bound {text!r} is not finite")
    return x


def parse_uncertain(text):
    """``"q1=1e4:1e6,sigma0=0.15MPa:0.3MPa"`` -> dict key -> :class:`Uncertain` (InputError, one
    line, on an unknown key, a missing ``:``, a repeated key, LO > HI or a non-physical bound).

    Parameters
    ----------
    text : str
        The ``--uncertain`` value.

    Returns
    -------
    dict
        Input name -> :class:`Uncertain`, bounds in SI (sigma0 in Pa, q1 in 1/m, temperature in C);
        empty for None or an empty string.
    """
    from pipelines.settings.friction import parse_pressure

    out = {}
    if text is None:
        return out
    for item in str(text).split(","):
        item = item.strip()
        if not item:
            continue
        if "=" not in item:
            raise InputError(
                None, f"--uncertain {text!r}: {item!r} is not KEY=LO:HI (keys: {', '.join(KEYS)})"
            )
        key, rng = (s.strip() for s in item.split("=", 1))
        if key not in KEYS:
            raise InputError(None, f"--uncertain {text!r}: unknown input {key!r} (keys: {', '.join(KEYS)})")
        if key in out:
            raise InputError(None, f"--uncertain {text!r}: {key} given twice")
        if key == "q1" and rng.lower() == "known":
            out[key] = Uncertain(key, np.nan, np.nan, "known")
            continue
        if rng.count(":") != 1:
            raise InputError(None, f"--uncertain {text!r}: {key} range {rng!r} is not LO:HI")
        a, b = (s.strip() for s in rng.split(":"))
        if key == "sigma0":
            lo, hi = (
                parse_pressure(a, flag="--uncertain sigma0"),
                parse_pressure(b, flag="--uncertain sigma0"),
            )
        else:
            lo, hi = _number(a, key, text), _number(b, key, text)
        if lo > hi:
            raise InputError(None, f"--uncertain {text!r}: {key} range {rng!r} has LO > HI")
        if key in ("q1", "psd_scale") and not lo > 0:
            raise InputError(None, f"--uncertain {text!r}: {key} bounds must be positive")
        if key == "q1" and lo < 1e-4:
            raise InputError(None, f"--uncertain {text!r}: q1 below 1e-4 1/m (a wavelength above 63 km)")
        if key == "psd_scale" and hi > 1e6:
            raise InputError(None, f"--uncertain {text!r}: psd_scale above 1e6 is no instrument level")
        if key == "temperature" and (lo <= -273.15 or hi > 1000):
            raise InputError(None, f"--uncertain {text!r}: temperature must lie in (-273.15, 1000] C")
        out[key] = Uncertain(key, lo, hi, "given")
    return out


def scale_psd(psd, s):
    """The spectrum with C(q) multiplied by ``s`` (h0 by sqrt(s) for a self-affine law).

    Parameters
    ----------
    psd : spectrum
        TabulatedPSD or SelfAffinePSD.
    s : float
        Dimensionless factor on C(q); 1 returns ``psd`` itself.

    Returns
    -------
    spectrum
        A TabulatedPSD with C_m4 times ``s``, or the self-affine law with h0_m times sqrt(s).
    """
    from dataclasses import replace

    from friction.psd import TabulatedPSD

    if s == 1.0:
        return psd
    if isinstance(psd, TabulatedPSD):
        return TabulatedPSD(psd.q_per_m, psd.C_m4 * s, psd.q0_per_m, psd.q1_per_m)
    return replace(psd, h0_m=psd.h0_m * float(np.sqrt(s)))


def nominal(ctx):
    """The nominal inputs of a context: dict key -> value (SI; temperature in C)."""
    T = ctx.T0_C[np.isfinite(ctx.T0_C)]
    return dict(
        q1=float(ctx.base.psd.q1_per_m),
        sigma0=float(np.median(ctx.sigma0_Pa)),
        psd_scale=1.0,
        temperature=float(np.median(T)) if T.size else float(ctx.base.rubber.T_ref_C),
    )


def cutoff_sensitivity(ctx, n_max=8, step=1.25):
    """max over (at most ``n_max``) measured speeds of d ln mu / d ln q1 (one-sided difference
    with the spectrum cut at q1 / ``step``, as :mod:`.bandmap`)."""
    from pipelines.diagnosis.model import simulate

    idx = np.unique(np.linspace(0, ctx.n - 1, min(n_max, ctx.n)).round().astype(int))
    sub = ctx.subset(idx)
    a = simulate(ctx.base, sub)
    b = simulate(ctx.base.with_(psd=ctx.base.psd.with_q1(ctx.base.psd.q1_per_m / step)), sub)
    return float(np.max(np.log(a / b) / np.log(step)))


def default_q1(ctx, ranges, carried=None, noise=None):
    """Add the default q1 range (a decade either side) when q1 was not declared known and the
    measured mu depends on it: mu is carried by the cut-off (``carried``: the band map's verdict;
    None: d ln mu / d ln q1 above the band map's flag at a measured speed), or, with ``noise``
    given, a decade of q1 moves log10 mu at a measured speed by more than the noise
    (d log10 mu / d log10 q1 = d ln mu / d ln q1 > noise / ``DEFAULT_Q1_DECADES``): the data can
    then feel where the roughness ends, an input the spectrum only assumes (its last wave vector).
    Returns (ranges, sensitivity or None).

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows and the baseline spec (its spectrum gives the nominal q1 [1/m]).
    ranges : dict
        Input name -> :class:`Uncertain` so far; a ``"q1"`` entry (known or not) is kept as is.
    carried : bool, optional
        The band map's verdict that mu is carried by the cut-off; None: computed here.
    noise : float, optional
        Rms log10 noise of the measured mu (None: the cut-off flag alone decides).

    Returns
    -------
    ranges : dict
        ``ranges``, with q1 over [q1 / 10, 10 q1] (source ``"default"``) added when mu depends on it.
    sensitivity : float or None
        max d ln mu / d ln q1 over up to 8 measured speeds; None when not computed.
    """
    from pipelines.diagnosis.report.bandmap import CUTOFF_FLAG

    if "q1" in ranges:
        return ranges, None
    sens = None
    if carried is None or (not carried and noise is not None):
        sens = cutoff_sensitivity(ctx)
        felt = noise is not None and sens * DEFAULT_Q1_DECADES > float(noise)
        carried = (sens > CUTOFF_FLAG if carried is None else bool(carried)) or felt
    if carried:
        q1 = float(ctx.base.psd.q1_per_m)
        f = 10.0**DEFAULT_Q1_DECADES
        ranges = dict(ranges, q1=Uncertain("q1", q1 / f, q1 * f, "default"))
    return ranges, sens


def free_ranges(ctx, ranges):
    """The ranges that are fitted (not known), with q1's lower end kept above 1.5 q0."""
    out = {}
    for k, u in ranges.items():
        if u.source == "known" or u.known:
            continue
        lo, hi = u.lo, u.hi
        if k == "q1":
            lo = max(lo, 1.5 * float(ctx.base.psd.q0_per_m))
            if not hi > lo:
                continue
        out[k] = (lo, hi)
    return out


def apply_known(ctx, ranges):
    """The base spec with known inputs (degenerate ranges) set: returns the new base spec."""
    spec = ctx.base
    u = ranges.get("q1")
    if u is not None and u.known and np.isfinite(u.lo):
        spec = spec.with_(psd=spec.psd.with_q1(u.lo))
    return spec


def calibration_effect(ctx, ranges):
    """The ``calibration`` pseudo-effect over the free uncertain inputs (None when none is free).

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows and the baseline spec (its nominal inputs start the fit).
    ranges : dict
        Input name -> :class:`Uncertain`; known ones are left out of the fit.

    Returns
    -------
    Effect or None
        One parameter per free input (``q1_per_m``, ``sigma0_Pa``, ``psd_scale`` log scale;
        ``temperature_C`` linear), its no-effect point the nominal inputs clipped into the ranges.
    """
    free = free_ranges(ctx, ranges)
    if not free:
        return None
    nom = nominal(ctx)
    params = []
    for k in KEYS:
        if k in free:
            lo, hi = free[k]
            scale = "lin" if k == "temperature" else "log"
            params.append(Param(PARAM[k], lo, hi, float(np.clip(nom[k], lo, hi)), scale))
    null = {p.name: p.init for p in params}

    def modify(spec, p, c):
        psd, wet = spec.psd, spec.wet_psd
        if "q1_per_m" in p:
            psd = psd.with_q1(p["q1_per_m"])
            wet = wet.with_q1(p["q1_per_m"]) if wet is not None else None
        if "psd_scale" in p:
            psd = scale_psd(psd, p["psd_scale"])
            wet = scale_psd(wet, p["psd_scale"]) if wet is not None else None
        spec = spec.with_(psd=psd, wet_psd=wet)
        if "sigma0_Pa" in p:
            spec = spec.with_(sigma0_scale=spec.sigma0_scale * p["sigma0_Pa"] / nom["sigma0"])
        if "temperature_C" in p:
            spec = spec.with_(T0_shift_C=spec.T0_shift_C + p["temperature_C"] - nom["temperature"])
        return spec

    return Effect(
        name="calibration",
        level="friction",
        params=tuple(params),
        modify=modify,
        null=lambda c: dict(null),
        plausible=_plausible_temperature,
        description="uncertain inputs calibrated within their ranges",
    )


def _plausible_temperature(ctx, p, real_mu):
    from pipelines.diagnosis.effects import temperature_extrapolated

    if "temperature_C" not in p:
        return []
    why = temperature_extrapolated(ctx, p["temperature_C"])
    return [("temperature_C", why)] if why else []


def intervals(c, ctx, real_mu, train, noise, z=1.96):
    """Approximate 95 % intervals of the calibration parameters of candidate ``c``: the Gauss-
    Newton covariance s^2 (J^T J)^-1 in the unit cube at the fit (s^2 = max(RSS / (n - k), noise^2),
    J by forward differences of step 0.02), mapped back through each parameter's scale and clipped
    to its range. Returns dict name -> dict(value, interval, range).

    Parameters
    ----------
    c : Candidate
        A fitted candidate; without a ``calibration`` effect the result is empty.
    ctx : FrictionContext
        The context it was fitted on.
    real_mu : ndarray, shape (n,)
        Measured mu at every row.
    train : ndarray of bool, shape (n,)
        The rows it was fitted on (J and the residuals are taken there).
    noise : float
        rms of log10(measured / simulated mu) expected from the measurement: the floor of s.
    z : float, optional
        Standard-normal quantile: 1.96 gives 95 %.

    Returns
    -------
    dict
        Parameter name -> dict(value, interval=[lo, hi], range=[lo, hi]) in the parameter's unit.
    """
    from pipelines.diagnosis.fit.fitting import pack, predict

    i0, cal = 0, None
    for e, p in zip(c.effects, c.params):
        if e.name == "calibration":
            cal = (e, p)
            break
        i0 += len(e.params)
    if cal is None:
        return {}
    from pipelines.diagnosis.fit.fitting import unpack
    from pipelines.diagnosis.fit.stats import gauss_newton_cov, jacobian

    u = pack(c.effects, c.params)
    y = np.log10(real_mu)[train]
    base = np.log10(predict(ctx, c.effects, [dict(p) for p in c.params]))[train]
    J = jacobian(lambda uu: np.log10(predict(ctx, c.effects, unpack(c.effects, uu)))[train], u, f0=base)
    cov = gauss_newton_cov(J, y - base, noise)
    e, p = cal
    out = {}
    for j, pp in enumerate(e.params):
        sd = float(np.sqrt(max(cov[i0 + j, i0 + j], 0.0)))
        uj = u[i0 + j]
        lo, hi = pp.from_unit(uj - z * sd), pp.from_unit(uj + z * sd)
        out[pp.name] = dict(value=p[pp.name], interval=[lo, hi], range=[pp.lo, pp.hi])
    return out
