"""friction.wet: wet rubber friction on a rough road versus speed.

Sealing of water in the pools the contact closes (Persson, Tartaglino, Albohr, Tosatti, PRB 71,
035428 (2005)), squeeze-out of the film under a tread block during the dwell time (averaged
Reynolds flow with Persson's contact pressure, PRL 99, 125502 (2007); Lorenz & Persson, EPJE
32, 281 (2010)), the adhesive term water removes, and the loss of contact when the film left
exceeds the texture; at the footprint's front the water's inertia carries part of the load
(Horne & Dreher, NASA TN D-2056 (1963)). The dry model (isothermal or flash) is the engine's;
this package adds only what water changes. Modules: ``water`` (viscosity, conditions and their sources),
``gap`` (u(p) and p_cont(u)), ``squeeze``, ``inertia``, ``sealing``, ``adhesion``, ``model``.
"""

from .model import WetFriction, wet_friction
from .sealing import sealing_wave_vector
from .water import DEFAULT_SOURCES, WetConditions, water_viscosity_Pa_s

__all__ = [
    "DEFAULT_SOURCES",
    "WetConditions",
    "WetFriction",
    "sealing_wave_vector",
    "water_viscosity_Pa_s",
    "wet_friction",
]
