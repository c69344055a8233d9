"""friction: B.N.J. Persson's rubber friction theory on a surface spectrum C(q).

Isothermal (Persson 2001) and flash-temperature (Persson 2006) models as in the thesis
(chapters 2 and 3) with the conventions of the documentation's Theory page: SI units,
Persson's PSD normalisation, ``Im E > 0`` for ``omega > 0``, and temperature shifts relative to
the rubber's reference temperature. This package reads no files and imports neither roadscan
nor pipelines.

Imports are on demand: ``import friction`` loads nothing heavy; each public name below loads
its submodule when first used (``fit_prony``/``fit_wlf`` bring in ``scipy.optimize`` only then).
"""

import lazy_loader

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

#: public name -> the submodule that defines it, loaded on first use (``lazy_loader``, the
#: mechanism scikit-image uses; PEP 562)
_HOMES = {
    "fitting": ["fit_prony", "fit_wlf"],
    "flash": ["mu_flash"],
    "isothermal": ["mu_isothermal"],
    "psd": ["SelfAffinePSD", "TabulatedPSD"],
    "result": ["FrictionResult"],
    "rubber": [
        "WLF",
        "MasterCurve",
        "Prony",
        "ShiftTable",
        "StandardLinearSolid",
        "Thermal",
        "thesis_rubber",
    ],
    "rubber_dict": ["rubber_from_dict"],
}
__getattr__, _, _ = lazy_loader.attach(__name__, submod_attrs=_HOMES)


def __dir__():
    return sorted(set(globals()) | set(__all__))
