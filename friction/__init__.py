"""friction: B.N.J. Persson's rubber friction theory on a surface spectrum C(q).

Isothermal (Persson 2001) and flash-temperature (Persson 2006) models as in the thesis
(seeds/000, chapters 2 and 3) with the conventions of DESIGN.md sections 4 and 5: SI units,
Persson's PSD normalisation, ``Im E > 0`` for ``omega > 0``, and temperature shifts relative to
the rubber's reference temperature. This package reads no files and imports neither roadscan
nor pipelines.
"""
from .fitting import fit_prony, fit_wlf
from .flash import mu_flash
from .isothermal import mu_isothermal
from .psd import SelfAffinePSD, TabulatedPSD
from .result import FrictionResult
from .rubber import (WLF, MasterCurve, Prony, ShiftTable, StandardLinearSolid, Thermal,
                     thesis_rubber)
from .rubber_dict import rubber_from_dict

__all__ = ["SelfAffinePSD", "TabulatedPSD", "StandardLinearSolid", "Prony", "MasterCurve", "WLF",
           "ShiftTable", "Thermal", "thesis_rubber", "fit_prony", "fit_wlf", "mu_isothermal",
           "mu_flash", "FrictionResult", "rubber_from_dict"]
