"""Water and the wet-test conditions of :mod:`friction.wet`: viscosity against temperature and
the defaults of a wet friction run, each a physical value with its source.

Viscosity of liquid water (Vogel's equation, the form of Viswanath & Natarajan's data book)::

    eta(T) = A exp(B / (T - C)),  A = 2.939e-5 Pa s,  B = 507.88 K,  C = 149.3 K,  T in kelvin

It gives 1.0034 mPa s at 20 C, 1.774 mPa s at 0 C and 0.653 mPa s at 40 C, within 1 % of the
IAPWS 2008 formulation (1.0016, 1.7914, 0.6527 mPa s at 0.1 MPa) from 0 to 100 C.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = [
    "DEFAULT_BLOCK_SIZE_M",
    "DEFAULT_FOOTPRINT_M",
    "DEFAULT_SOURCES",
    "DEFAULT_WATER_DEPTH_M",
    "DEFAULT_WATER_TEMPERATURE_C",
    "PERCOLATION_CONTACT_FRACTION",
    "WetConditions",
    "water_viscosity_Pa_s",
]

_VOGEL_A_PA_S = 2.939e-5
_VOGEL_B_K = 507.88
_VOGEL_C_K = 149.3

#: water film on the road [m]: ASTM E274/E274M (locked-wheel skid trailer) delivers water ahead
#: of the test tyre for a nominal film of 0.5 mm (0.02 in), the film of the skid numbers that
#: the PIARC experiment and ASTM E1960's IFI are built on
DEFAULT_WATER_DEPTH_M = 0.5e-3
#: water temperature [C]: 20 C, the reference temperature of skid tests (ASTM E274 reports
#: the water and pavement temperatures; CEN/TS 15901 series correct skid numbers to 20 C)
DEFAULT_WATER_TEMPERATURE_C = 20.0
#: contact length along the sliding direction [m]: a passenger-car tyre's footprint is about
#: 0.10-0.15 m long at its rated load (A.N. Gent, J.D. Walter (eds.), *The Pneumatic Tire*,
#: NHTSA DOT HS 810 561 (2006)); 0.12 m
DEFAULT_FOOTPRINT_M = 0.12
#: tread block size [m]: passenger-car tread blocks are 20-30 mm across between grooves (Gent &
#: Walter 2006); 25 mm. The squeeze flow escapes over this length to the grooves.
DEFAULT_BLOCK_SIZE_M = 25e-3
#: fraction of the nominal area in contact at which the non-contact area stops percolating
#: (2D continuum percolation of a randomly rough contact): Dapp, Luecke, Persson and Mueser,
#: Phys. Rev. Lett. 108, 244301 (2012), doi:10.1103/PhysRevLett.108.244301, A/A0 ~ 0.42
PERCOLATION_CONTACT_FRACTION = 0.42

#: every default and its source, as the report shows them
DEFAULT_SOURCES = {
    "water_depth_m": (
        DEFAULT_WATER_DEPTH_M,
        "ASTM E274/E274M: nominal water film 0.5 mm ahead of the test tyre",
    ),
    "water_temperature_C": (DEFAULT_WATER_TEMPERATURE_C, "20 C, the reference temperature of skid tests"),
    "footprint_m": (
        DEFAULT_FOOTPRINT_M,
        "passenger-car footprint 100-150 mm long (Gent & Walter, The Pneumatic Tire, 2006)",
    ),
    "block_size_m": (DEFAULT_BLOCK_SIZE_M, "passenger-car tread blocks 20-30 mm (Gent & Walter 2006)"),
    "percolation_contact_fraction": (
        PERCOLATION_CONTACT_FRACTION,
        "Dapp et al., PRL 108, 244301 (2012): non-contact area percolates at A/A0 ~ 0.42",
    ),
    "shear_stress_Pa": (
        None,
        (
            "no default: the frictional shear stress of the rubber-road contact is an "
            "input; without it adhesion is left out of dry and wet friction"
        ),
    ),
}


def water_viscosity_Pa_s(T_C):
    """Dynamic viscosity of liquid water [Pa s] at ``T_C`` [C] by Vogel's equation.

    ``eta = 2.939e-5 Pa s * exp(507.88 K / (T + 273.15 K - 149.3 K))``, valid for liquid water at
    ambient pressure from 0 to 100 C (within 1 % of IAPWS 2008 there).

    Parameters
    ----------
    T_C : float
        Water temperature [C], 0 to 100.

    Returns
    -------
    float
        Viscosity [Pa s] (1.00e-3 at 20 C).

    Raises
    ------
    ValueError
        Outside 0-100 C (ice or steam: not liquid water at ambient pressure).

    References
    ----------
    D.S. Viswanath, G. Natarajan, *Data Book on the Viscosity of Liquids*, Hemisphere (1989).
    M.L. Huber et al., "New international formulation for the viscosity of H2O", J. Phys. Chem.
    Ref. Data 38, 101 (2009), doi:10.1063/1.3088050 (IAPWS 2008, the check values).
    """
    T = float(T_C)
    if not (0.0 <= T <= 100.0):
        raise ValueError(f"water temperature {T!r} C is outside 0-100 C (liquid water)")
    return _VOGEL_A_PA_S * math.exp(_VOGEL_B_K / (T + 273.15 - _VOGEL_C_K))


@dataclass(frozen=True)
class WetConditions:
    """The water and the tyre of a wet friction run (SI; each default's source in
    :data:`DEFAULT_SOURCES`).

    Attributes
    ----------
    water_depth_m : float
        Water per nominal area on the road [m] (volume / area): 0.5 mm, ASTM E274's film.
    water_temperature_C : float
        Water temperature [C] (20 C); sets the viscosity (:func:`water_viscosity_Pa_s`).
    footprint_m : float
        Contact length along the sliding direction [m] (0.12 m): the dwell time under the
        tyre is ``t_c = footprint / v``.
    block_size_m : float
        Tread block size [m] (25 mm): the length over which the squeezed water escapes to the
        grooves (an equal-area disk of radius ``block / sqrt(pi)``).
    shear_stress_Pa : float or None
        Frictional shear stress tau_f of the adhesive (interfacial) term [Pa]; None leaves
        adhesion out (Persson's theory gives no value; it is a property of the pair).
    percolation_contact_fraction : float
        A/A0 at which the non-contact area percolates (0.42, Dapp et al. 2012): the pools closed
        at that magnification are sealed.
    """

    water_depth_m: float = DEFAULT_WATER_DEPTH_M
    water_temperature_C: float = DEFAULT_WATER_TEMPERATURE_C
    footprint_m: float = DEFAULT_FOOTPRINT_M
    block_size_m: float = DEFAULT_BLOCK_SIZE_M
    shear_stress_Pa: float | None = None
    percolation_contact_fraction: float = PERCOLATION_CONTACT_FRACTION

    def __post_init__(self):
        for name in ("water_depth_m",):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) >= 0):
                raise ValueError(f"{name} must be a finite length >= 0 [m]")
        for name in ("footprint_m", "block_size_m"):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ValueError(f"{name} must be a positive length [m]")
        if self.shear_stress_Pa is not None and not (
            math.isfinite(self.shear_stress_Pa) and self.shear_stress_Pa >= 0
        ):
            raise ValueError("shear_stress_Pa must be a finite stress >= 0 [Pa] or None")
        if not (0 < self.percolation_contact_fraction < 1):
            raise ValueError("percolation_contact_fraction must lie in (0, 1)")
        water_viscosity_Pa_s(self.water_temperature_C)

    @property
    def viscosity_Pa_s(self):
        """Water viscosity [Pa s] at :attr:`water_temperature_C`."""
        return water_viscosity_Pa_s(self.water_temperature_C)

    @property
    def squeeze_radius_m(self):
        """Radius [m] of the disk with the block's area, ``block_size / sqrt(pi)``."""
        return self.block_size_m / math.sqrt(math.pi)
