"""The registry of candidate unmodelled effects (plug-ins).

Each module in this package registers one :class:`Effect` with :func:`register` when imported;
:func:`all_effects` imports every module of the package (``pkgutil``), so adding an effect is
adding a module: nothing else changes.

An effect has a ``level`` ("friction" or "surface"), a few named parameters, each with bounds,
an initial value and a scale ("log" or "lin"; the search works on the unit interval mapped onto
the bounds), ``requires`` (inputs it needs, e.g. ``{"scan"}``; missing ones skip it with a
reason), an optional ``prepare(context) -> str | None`` (precompute; a returned string skips the
effect with that reason) and ``modify(spec, params, context) -> spec``. For the friction level
``apply(context, params)`` evaluates the modified baseline (mu at the measured rows); an effect
may instead give ``apply_fn(context, params) -> mu`` directly. Surface-level effects give
``apply_fn(context, params, pred) -> pred``: ``pred`` maps each descriptor family (and
``spec_rings``, the ring-level log10 spectrum) to the twin's prediction, the effect returns the
modified prediction (see :mod:`pipelines.diagnosis.surface.level`), so that effects compose in pairs.
``null(context) -> params`` gives the parameters at which the effect is no effect (every effect
has one within its bounds: fits start there and keep it unless the training data improve). ``cost`` > 1 marks
expensive effects (the search spends fewer evaluations on them).

Physical plausibility: the bounds of a parameter are where the fit may go; ``plausible(context,
params, real_mu) -> [(name, why), ...]`` names the fitted parameters outside the range where
they are physical (flash heating beyond a factor 3 of the model's own, an adhesion amplitude
above the measured mu, a temperature outside the shift table, ...). A verdict never names an
implausible fit (:mod:`pipelines.diagnosis.verdict.many`).
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["Param", "Effect", "register", "all_effects", "get", "temperature_extrapolated"]


@dataclass(frozen=True)
class Param:
    """One effect parameter: ``name`` (with units), bounds, initial value, ``scale`` log|lin.

    Attributes
    ----------
    name : str
        Name as reported; a dimensional one ends in its unit (``"dT_C"``, ``"v_c_m_per_s"``).
    lo, hi : float
        Range the fit may explore, in the parameter's unit (lo > 0 for a log scale).
    init : float
        Value in [lo, hi] that every cold start set of the fit includes.
    scale : str
        How the unit interval maps onto [lo, hi]: ``"log"`` (geometric, the default) or ``"lin"``.
    """

    name: str
    lo: float
    hi: float
    init: float
    scale: str = "log"

    def to_unit(self, x):
        if self.scale == "log":
            return (np.log(x) - np.log(self.lo)) / (np.log(self.hi) - np.log(self.lo))
        return (x - self.lo) / (self.hi - self.lo)

    def from_unit(self, u):
        u = float(np.clip(u, 0.0, 1.0))
        if self.scale == "log":
            return float(np.exp(np.log(self.lo) + u * (np.log(self.hi) - np.log(self.lo))))
        return float(self.lo + u * (self.hi - self.lo))


@dataclass(frozen=True, eq=False)
class Effect:
    """A candidate unmodelled effect (see the package docstring).

    Attributes
    ----------
    name : str
        Registry name, as the verdict and the reports print it (``"+"`` joins a pair's names).
    level : str
        ``"friction"`` or ``"surface"``.
    params : tuple of Param
        The fitted parameters, in the order of the unit-cube vector.
    modify : callable, optional
        Changes the model spec (friction level).
    apply_fn : callable, optional
        Computes mu or descriptors directly.
    requires : frozenset of str
        Inputs it needs (``"scan"``...).
    prepare : callable, optional
        ``prepare(context) -> str or None`` precomputes once; a returned string skips the effect.
    cost : float
        Model evaluation cost relative to the baseline's; above 1 the fits spend fewer evaluations.
    description : str
        One-line description for the report's list of effects.
    null : callable, optional
        Its no-effect parameters.
    plausible, physical : callable, optional
        ``plausible(context, params, real_mu) -> [(name, why)]`` of fitted parameters outside their
        physical range; ``physical(context, real_mu) -> {name: (lo, hi)}``, that range itself.
    """

    name: str
    level: str
    params: tuple
    modify: Callable | None = None
    apply_fn: Callable | None = None
    requires: frozenset = frozenset()
    prepare: Callable | None = None
    cost: float = 1.0
    description: str = ""
    null: Callable | None = None
    plausible: Callable | None = None
    physical: Callable | None = None

    def restricted(self, context, real_mu):
        """This effect with each parameter's bounds narrowed to its physical range
        (``physical(context, real_mu) -> {name: (lo, hi)}``), or None when it declares none. The
        search refits an implausible fit within them: the parameters of an effect can trade off
        (flash: zeta_m against the heating), so a physical fit may explain the data as well."""
        if self.physical is None:
            return None
        from dataclasses import replace

        rng = self.physical(context, real_mu)
        params = []
        for p in self.params:
            lo, hi = rng.get(p.name, (p.lo, p.hi))
            lo, hi = max(lo, p.lo), min(hi, p.hi)
            if not hi > lo:
                return None
            params.append(Param(p.name, lo, hi, float(np.clip(p.init, lo, hi)), p.scale))
        null = self.null_params(context)
        keep = null is not None and all(pp.lo <= null[pp.name] <= pp.hi for pp in params)
        return replace(self, params=tuple(params), null=self.null if keep else None)

    def implausible(self, context, params, real_mu):
        """[(parameter name, why)] of fitted parameters outside their physical range."""
        return [] if self.plausible is None else list(self.plausible(context, params, real_mu))

    def null_params(self, context):
        """The parameters at which the effect is no effect (its reachable "no effect" limit), or
        None when it has none."""
        return None if self.null is None else self.null(context)

    def missing(self, context):
        """Inputs this effect needs that the context lacks (empty when usable)."""
        return sorted(set(self.requires) - set(context.inputs))

    def apply(self, context, params, spec=None):
        """Predicted curve (friction: mu at the context's rows) for parameter dict ``params``."""
        if self.apply_fn is not None:
            return self.apply_fn(context, params)
        from pipelines.diagnosis.model import simulate

        spec = context.base if spec is None else spec
        return simulate(self.modify(spec, params, context), context)


def temperature_extrapolated(context, T_C):
    """A one-line reason when a temperature [C] lies outside the rubber's shift table (the
    master curve is then extrapolated in temperature), else None (also for a WLF shift).

    Parameters
    ----------
    context : FrictionContext
        Model context (its rubber).
    T_C : float
        Background temperature [C] the fit puts the rubber at.

    Returns
    -------
    str or None
        The reason, naming the table's range in C; None inside it or without a table.
    """
    shift = getattr(context.base.rubber, "shift", None)
    T = getattr(shift, "T_C", None)
    if T is None or not np.size(T):
        return None
    lo, hi = float(np.min(T)), float(np.max(T))
    if not (lo - 1e-9 <= float(T_C) <= hi + 1e-9):
        return f"{float(T_C):.3g} C is outside the shift table's {lo:.3g}..{hi:.3g} C (extrapolated)"
    return None


_REGISTRY: dict = {}


def register(effect):
    """Add ``effect`` to the registry (called at import of its module); returns it.

    Parameters
    ----------
    effect : Effect
        The effect to register; its level must be ``"friction"`` or ``"surface"`` (else ValueError).

    Returns
    -------
    Effect
        ``effect`` itself, so that a module can write ``EFFECT = register(Effect(...))``.
    """
    if effect.level not in ("friction", "surface"):
        raise ValueError(f"effect {effect.name}: level must be friction or surface")
    _REGISTRY[effect.name] = effect
    return effect


def _load_all():
    for mod in pkgutil.iter_modules(__path__):
        if not mod.name.startswith("_"):
            importlib.import_module(f"{__name__}.{mod.name}")


def all_effects(level=None):
    """Every registered effect (of ``level`` if given), in name order.

    Parameters
    ----------
    level : str, optional
        ``"friction"`` or ``"surface"``.

    Returns
    -------
    list of Effect
        Sorted by name; importing every module of the package first registers them all.
    """
    _load_all()
    return [e for _, e in sorted(_REGISTRY.items()) if level is None or e.level == level]


def get(name):
    """The registered effect called ``name`` (KeyError when there is none).

    Parameters
    ----------
    name : str
        Registry name, e.g. ``"flash_temperature"`` or ``"water"``.

    Returns
    -------
    Effect
        The registered effect with that name.
    """
    _load_all()
    return _REGISTRY[name]
