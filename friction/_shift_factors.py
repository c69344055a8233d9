"""Temperature shift factors of a rubber's master curve: ``log10 aT(T)`` as a WLF equation or a
table.

A shift factor ``aT`` multiplies the angular frequency: ``E(omega, T) = E(omega aT(T), T_s)``
(time-temperature superposition); :func:`friction.rubber.log10_shift` turns it into the factor
relative to the rubber's reference temperature (docs: Theory). Re-exported by
:mod:`friction.rubber` and :mod:`friction`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["WLF", "ShiftTable"]


@dataclass(frozen=True)
class WLF:
    """Williams-Landel-Ferry shift factor.

    Standard form (``T_g_C=None``): ``log10 aT = -C1 (T - T_s) / (C2 + T - T_s)``.
    Thesis form (``T_g_C`` given): ``log10 aT = -C1 (T - T_s) / (C2 + T - T_g)``; the thesis uses
    ``log10 aT = -8.86 (T - Tg - 50) / (51.5 + T - Tg)`` with Tg = -30 C, T_s = Tg + 50 = 20 C, so
    that aT(60 C) = 10^-2.504. This equals a standard WLF with ``C2 + T_s - T_g`` (101.5 K) in
    place of C2. :meth:`thesis` builds it. Where the denominator vanishes (far below T_s) it is
    clipped at 1e-3 K.

    Parameters
    ----------
    C1 : float
        Dimensionless constant.
    C2_K : float
        Constant [K].
    T_s_C : float
        Temperature where aT = 1 [C].
    T_g_C : float, optional
        Glass temperature of the thesis form [C].

    References
    ----------
    M.L. Williams, R.F. Landel, J.D. Ferry, J. Am. Chem. Soc. 77, 3701 (1955),
    doi:10.1021/ja01619a008.
    """

    C1: float = 8.86
    C2_K: float = 51.5
    T_s_C: float = 20.0
    T_g_C: float | None = None

    @classmethod
    def thesis(cls, T_g_C: float = -30.0) -> WLF:
        """The thesis's WLF: C1 = 8.86, C2 = 51.5 K, T_s = Tg + 50, denominator at Tg."""
        return cls(8.86, 51.5, T_g_C + 50.0, T_g_C)

    def log10_aT(self, T_C: ArrayLike) -> NDArray[np.float64]:
        """log10 aT(T) = -C1 (T - T_s) / (C2 + T - T_d), T_d = T_g if given else T_s [T in C]."""
        T = np.asarray(T_C, dtype=float)
        Td = self.T_s_C if self.T_g_C is None else self.T_g_C
        return -self.C1 * (T - self.T_s_C) / np.maximum(self.C2_K + T - Td, 1e-3)


@dataclass(frozen=True, eq=False)
class ShiftTable:
    """Tabulated shift factors ``log10 aT(T)``: linear interpolation in T, linear
    extrapolation from the end segments.

    Parameters
    ----------
    T_C : (n,) array
        Temperatures [C] (any order; sorted internally, must be distinct).
    log10_aT_values : (n,) array
        Decimal logarithm of the shift factor at each temperature.
    """

    T_C: np.ndarray
    log10_aT_values: np.ndarray

    def __post_init__(self):
        T = np.asarray(self.T_C, dtype=float)
        a = np.asarray(self.log10_aT_values, dtype=float)
        if T.ndim != 1 or T.shape != a.shape or T.size < 2:
            raise ValueError("ShiftTable needs two 1D arrays of equal length >= 2")
        if not (np.all(np.isfinite(T)) and np.all(np.isfinite(a))):
            raise ValueError("ShiftTable values must be finite")
        o = np.argsort(T)
        if np.any(np.diff(T[o]) <= 0):
            raise ValueError("ShiftTable temperatures must be distinct")
        object.__setattr__(self, "T_C", T[o])
        object.__setattr__(self, "log10_aT_values", a[o])

    def log10_aT(self, T_C: ArrayLike) -> NDArray[np.float64]:
        """log10 aT at T [C]: linear interpolation of the table, linear continuation outside."""
        T = np.asarray(T_C, dtype=float)
        Tt, at = self.T_C, self.log10_aT_values
        s0 = (at[1] - at[0]) / (Tt[1] - Tt[0])
        s1 = (at[-1] - at[-2]) / (Tt[-1] - Tt[-2])
        y = np.interp(T, Tt, at)
        y = np.where(T < Tt[0], at[0] + s0 * (T - Tt[0]), y)
        return np.where(T > Tt[-1], at[-1] + s1 * (T - Tt[-1]), y)
