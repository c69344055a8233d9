"""The simulation side: a specification that effects modify, evaluated at the measured speeds.

A :class:`SimSpec` names everything the friction engine needs (spectrum, rubber, background
temperature offset, load scale, flash or isothermal, contact correction, extra additive terms,
the spectrum of the wet rows). An effect plug-in returns a modified copy
(:func:`dataclasses.replace`), so that two effects compose by applying one after the other.
:func:`simulate` evaluates a spec on a :class:`FrictionContext` (the measured rows and their
conditions): rows are grouped by (T0, sigma0, wet) and each group is one vectorised engine call
at exactly its measured speeds.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

__all__ = ["SimSpec", "FrictionContext", "simulate", "engine"]


def engine():
    """The friction engine's public names (``friction`` package).

    Returns
    -------
    module
        The ``friction`` package, imported on first use (so that this module loads without it).
    """
    import friction

    return friction


@dataclass(frozen=True, eq=False)
class SimSpec:
    """What the simulation assumes.

    Attributes
    ----------
    psd : SelfAffinePSD or TabulatedPSD
        The road spectrum C(q) [m^4].
    rubber : rubber model
        Modulus at its ``T_ref_C``, shifted with temperature.
    T0_shift_C : float
        Added to every row's background temperature [K].
    sigma0_scale : float
        Multiplies every row's nominal pressure.
    flash : dict or None
        None (isothermal) or keyword arguments of :func:`friction.mu_flash`.
    contact_gamma : float or None
        Persson's gamma in S = gamma + (1 - gamma) P^2.
    nu : float
        Poisson's ratio; the engine uses (1 - nu^2) sigma0 in P(q), G(q) and M(q).
    wet_psd : spectrum or None
        The spectrum "felt" on wet rows (cavities filled with water).
    additive : tuple of callable
        Functions ``f(v_m_per_s) -> mu`` added to the engine's mu.
    tol : float
        The engine's accuracy target.
    """

    psd: object
    rubber: object
    T0_shift_C: float = 0.0
    sigma0_scale: float = 1.0
    flash: dict | None = None
    contact_gamma: float | None = None
    nu: float = 0.5
    wet_psd: object = None
    additive: tuple = ()
    tol: float = 1e-3

    def with_(self, **changes):
        return replace(self, **changes)


@dataclass(eq=False)
class FrictionContext:
    """The measured rows, the baseline spec and the optional inputs effects may need.

    Attributes
    ----------
    v_m_per_s, T0_C, sigma0_Pa : ndarray, shape (n,)
        Speed [m/s], background temperature [C] (NaN: the rubber's ``T_ref_C``) and nominal
        pressure [Pa] of each row.
    wet : ndarray of bool, shape (n,)
        Rows the water effect applies to (all rows when the data give no condition column).
    base : SimSpec
        The baseline model effects modify (engine defaults, known inputs set).
    scan : HeightMap or None
        The levelled and filled scan the surface came from.
    inputs : set of str
        Available inputs (``"scan"``, ``"psd"``, ``"rubber"``, ``"master_curve"``...).
    cache : dict
        Shared by effects (e.g. precomputed wet spectra).
    """

    v_m_per_s: np.ndarray
    T0_C: np.ndarray
    sigma0_Pa: np.ndarray
    wet: np.ndarray
    base: SimSpec
    scan: object = None
    spectrum: object = None
    fit: object = None
    inputs: set = field(default_factory=set)
    cache: dict = field(default_factory=dict)

    @property
    def n(self):
        return self.v_m_per_s.size

    def subset(self, idx):
        idx = np.asarray(idx)
        return FrictionContext(
            self.v_m_per_s[idx],
            self.T0_C[idx],
            self.sigma0_Pa[idx],
            self.wet[idx],
            self.base,
            self.scan,
            self.spectrum,
            self.fit,
            self.inputs,
            self.cache,
        )

    @classmethod
    def from_measured(cls, curve, base, **kw):
        wet = curve.wet if curve.has_condition else np.ones(curve.n, bool)
        return cls(curve.v_m_per_s, curve.T0_C, curve.sigma0_Pa, wet, base, **kw)


def _groups(ctx, spec):
    T = np.where(np.isfinite(ctx.T0_C), ctx.T0_C, spec.rubber.T_ref_C) + spec.T0_shift_C
    s = ctx.sigma0_Pa * spec.sigma0_scale
    wet = ctx.wet if spec.wet_psd is not None else np.zeros(ctx.n, bool)
    keys = np.rec.fromarrays([np.round(T, 9), np.round(s, 3), wet])
    uniq, inv = np.unique(keys, return_inverse=True)
    return [(float(u[0]), float(u[1]), bool(u[2]), np.flatnonzero(inv == k)) for k, u in enumerate(uniq)]


def simulate(spec, ctx, full=False):
    """mu at every row of ``ctx`` under ``spec`` (one engine call per condition group).

    Returns the (n,) mu array, or with ``full=True`` also the list of (rows, FrictionResult).

    Parameters
    ----------
    spec : SimSpec
        What the simulation assumes (spectrum, rubber, shifts, flash, additive terms).
    ctx : FrictionContext
        The rows simulated: speed [m/s], T0 [C] (NaN: the rubber's T_ref), sigma0 [Pa], wet.
    full : bool, optional
        Also return the engine results.

    Returns
    -------
    ndarray or tuple
        mu, shape (n,), floored at 1e-12; with ``full`` (mu, [(row indices, FrictionResult)]).
    """
    fr = engine()
    mu = np.empty(ctx.n)
    results = []
    for T0, s0, wet, rows in _groups(ctx, spec):
        psd = spec.wet_psd if wet else spec.psd
        v = ctx.v_m_per_s[rows]
        if spec.flash is not None:
            res = fr.mu_flash(
                psd,
                spec.rubber,
                v,
                sigma0_Pa=s0,
                nu=spec.nu,
                T0_C=T0,
                contact_gamma=spec.contact_gamma,
                **spec.flash,
            )
        else:
            res = fr.mu_isothermal(
                psd,
                spec.rubber,
                v,
                sigma0_Pa=s0,
                nu=spec.nu,
                T0_C=T0,
                tol=spec.tol,
                contact_gamma=spec.contact_gamma,
            )
        m = np.asarray(res.mu, float)
        for f in spec.additive:
            m = m + f(v)
        mu[rows] = m
        results.append((rows, res))
    mu = np.maximum(mu, 1e-12)
    return (mu, results) if full else mu
