"""friction: B.N.J. Persson's rubber friction theory on a surface spectrum C(q).

Isothermal (Persson 2001) and flash-temperature (Persson 2006) models as in the thesis
(chapters 2 and 3) with the conventions of the documentation's Theory page: SI units,
Persson's PSD normalisation, ``Im E > 0`` for ``omega > 0``, and temperature shifts relative to
the rubber's reference temperature. This package reads no files and imports neither roadscan
nor pipelines.

Imports are on demand: ``import friction`` loads nothing heavy; each public name below loads
its submodule when first used (``fit_prony``/``fit_wlf`` bring in ``scipy.optimize`` only then).
"""

from importlib import import_module

__all__ = [
    "SelfAffinePSD",
    "TabulatedPSD",
    "StandardLinearSolid",
    "Prony",
    "MasterCurve",
    "WLF",
    "ShiftTable",
    "Thermal",
    "thesis_rubber",
    "fit_prony",
    "fit_wlf",
    "mu_isothermal",
    "mu_flash",
    "FrictionResult",
    "rubber_from_dict",
]

_LAZY = {
    "fit_prony": ".fitting",
    "fit_wlf": ".fitting",
    "mu_flash": ".flash",
    "mu_isothermal": ".isothermal",
    "SelfAffinePSD": ".psd",
    "TabulatedPSD": ".psd",
    "FrictionResult": ".result",
    "WLF": ".rubber",
    "MasterCurve": ".rubber",
    "Prony": ".rubber",
    "ShiftTable": ".rubber",
    "StandardLinearSolid": ".rubber",
    "Thermal": ".rubber",
    "thesis_rubber": ".rubber",
    "rubber_from_dict": ".rubber_dict",
}


def __getattr__(name):
    if name in _LAZY:
        value = getattr(import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
