"""Small containers for power spectral densities (no computation here).

PSD convention (Persson's, DESIGN.md section 2): for an isotropic surface
``<h^2> = integral d^2q C(q) = 2 pi integral q C(q) dq``; C [m^4]. A 1D (profile) PSD C1 [m^3]
satisfies ``<h^2> = 2 integral_0^inf C1(q) dq``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Spectrum", "Spectrum2D"]


@dataclass(frozen=True, eq=False)
class Spectrum:
    """An isotropic (angular-averaged) 2D PSD C(q).

    Parameters
    ----------
    q_per_m : (n,) array
        Wave vectors [1/m], increasing (ring centres for an angular average).
    C_m4 : (n,) array
        PSD [m^4], Persson's normalisation.
    count : (n,) int array, optional
        Number of lattice points averaged in each ring (None for models/estimates).
    kind : str
        ``"area"`` (angular average of a 2D map), ``"profile"`` (2D estimate from line
        profiles, conversion named in ``meta['conversion']``), ``"model"`` or ``"extended"``.
    meta : dict
        Provenance: window alpha, spacing, conversion, etc.
    """

    q_per_m: np.ndarray
    C_m4: np.ndarray
    count: np.ndarray = None
    kind: str = "area"
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        q = np.asarray(self.q_per_m, dtype=np.float64)
        C = np.asarray(self.C_m4, dtype=np.float64)
        if q.ndim != 1 or q.shape != C.shape:
            raise ValueError("q_per_m and C_m4 must be 1D arrays of the same length")
        object.__setattr__(self, "q_per_m", q)
        object.__setattr__(self, "C_m4", C)

    @property
    def q_min_per_m(self):
        return float(self.q_per_m[0])

    @property
    def q_max_per_m(self):
        return float(self.q_per_m[-1])


@dataclass(frozen=True, eq=False)
class Spectrum2D:
    """The full 2D PSD map C(qx, qy) [m^4] on the FFT lattice (fftshifted, zero at centre).

    ``qx_per_m`` (nx,) and ``qy_per_m`` (ny,) are the shifted lattice wave vectors [1/m].
    """

    qx_per_m: np.ndarray
    qy_per_m: np.ndarray
    C_m4: np.ndarray
    meta: dict = field(default_factory=dict)
