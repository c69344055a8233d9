"""Rubber models: complex modulus E(omega, T) [Pa] and thermal properties.

Conventions (docs: Theory)
---------------------------------
* Sign: ``Im E(omega) > 0`` for ``omega > 0`` (energy is dissipated). The thesis prints the
  standard linear solid with the opposite sign; we use its complex conjugate.
* ``omega`` is an angular frequency [rad/s]; a master curve measured in Hz is used at
  ``omega = 2 pi f``.
* Temperature enters only through a horizontal shift relative to the rubber's reference
  temperature ``T_ref_C``: ``E(omega, T) = E_ref(omega aT(T) / aT(T_ref))`` ("relative" form).
  The thesis's eq 3.7, ``E(omega, T) = E(omega aT(T), T0)`` ("literal" form), is available to the
  friction engine through :func:`log10_shift`.

The shift factors themselves, :class:`WLF` and :class:`ShiftTable`, live in
``friction._shift_factors`` and are re-exported here.

References: B.N.J. Persson, J. Chem. Phys. 115 (2001) 3840; the thesis (seeds/000), eqs 2.4, 3.7.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._shift_factors import WLF, ShiftTable

# WLF and ShiftTable are documented once, as friction.WLF and friction.ShiftTable
__all__ = [
    "Thermal",
    "StandardLinearSolid",
    "Prony",
    "MasterCurve",
    "thesis_rubber",
    "log10_shift",
    "EXTRAPOLATE",
]

EXTRAPOLATE = ("powerlaw", "hold")  # MasterCurve beyond its measured frequencies


# --------------------------------------------------------------------------- shift of a rubber
def log10_shift(
    rubber: Rubber,
    T_C: ArrayLike,
    wlf_form: Literal["relative", "literal"] = "relative",
    T0_C: float | None = None,
) -> NDArray[np.float64]:
    """Decimal log of the factor multiplying omega in ``E(omega, T) = E_ref(omega * factor)``.

    ``relative``: ``log10 aT(T) - log10 aT(T_ref)`` (docs: Theory, default).
    ``literal``: thesis eq 3.7, ``E(omega, T) = E(omega aT(T), T0)``, i.e.
    ``log10 aT(T) + log10 aT(T0) - log10 aT(T_ref)`` (equals ``log10 aT(T)`` when T0 = T_ref).
    A rubber without a shift (``shift=None``) is temperature independent (factor 1).

    Parameters
    ----------
    rubber : rubber model
        A rubber with ``shift`` (WLF, ShiftTable or None) and ``T_ref_C``.
    T_C : array_like
        Temperature [C].
    wlf_form : {"relative", "literal"}, optional
        Which form of the shift (see above).
    T0_C : float, optional
        Background temperature of the literal form [C] (default ``T_ref_C``).

    Returns
    -------
    ndarray
        log10 of the frequency factor, shaped like ``T_C``.

    References
    ----------
    M.L. Williams, R.F. Landel, J.D. Ferry, J. Am. Chem. Soc. 77, 3701 (1955),
    doi:10.1021/ja01619a008.
    """
    T = np.asarray(T_C, dtype=float)
    if rubber.shift is None:
        return np.zeros_like(T)
    ref = rubber.shift.log10_aT(rubber.T_ref_C)
    if wlf_form == "relative":
        return rubber.shift.log10_aT(T) - ref
    if wlf_form == "literal":
        T0 = rubber.T_ref_C if T0_C is None else T0_C
        return rubber.shift.log10_aT(T) + rubber.shift.log10_aT(T0) - ref
    raise ValueError(f"wlf_form must be 'relative' or 'literal', not {wlf_form!r}")


# --------------------------------------------------------------------------- thermal
@dataclass(frozen=True)
class Thermal:
    """Thermal properties of the rubber (defaults: typical tread rubber, docs: Theory).

    rho_kg_m3 : density [kg/m^3]; c_v_J_kgK : specific heat [J/(kg K)];
    conductivity_W_mK : heat conductivity lambda [W/(m K)]. ``diffusivity_m2_s`` is
    ``D = lambda / (rho c_v)`` [m^2/s].

    Parameters
    ----------
    rho_kg_m3 : float, optional
        Density [kg/m^3].
    c_v_J_kgK : float, optional
        Specific heat [J/(kg K)].
    conductivity_W_mK : float, optional
        Heat conductivity lambda [W/(m K)].
    """

    rho_kg_m3: float = 1200.0
    c_v_J_kgK: float = 1500.0
    conductivity_W_mK: float = 0.25

    def __post_init__(self):
        for k in ("rho_kg_m3", "c_v_J_kgK", "conductivity_W_mK"):
            if not (np.isfinite(getattr(self, k)) and getattr(self, k) > 0):
                raise ValueError(f"Thermal.{k} must be positive")

    @property
    def diffusivity_m2_s(self) -> float:
        """Thermal diffusivity D = lambda / (rho c_v) [m^2/s]."""
        return self.conductivity_W_mK / (self.rho_kg_m3 * self.c_v_J_kgK)

    @property
    def heat_capacity_J_m3K(self) -> float:
        """Volumetric heat capacity rho c_v [J/(m^3 K)]."""
        return self.rho_kg_m3 * self.c_v_J_kgK


# --------------------------------------------------------------------------- moduli
class Rubber:
    """The base of every rubber model (:class:`Prony`, :class:`StandardLinearSolid`,
    :class:`MasterCurve`): ``modulus(omega, T_C)`` from the model's ``modulus_ref(omega)`` at
    ``T_ref_C`` and its temperature shift."""

    T_ref_C: float
    shift: WLF | ShiftTable | None

    def modulus_ref(self, omega_rad_s: ArrayLike) -> NDArray[np.complex128]:
        """Complex modulus E [Pa] at T_ref and angular frequency omega [rad/s]."""
        raise NotImplementedError

    def modulus(self, omega_rad_s: ArrayLike, T_C: ArrayLike | None = None) -> NDArray[np.complex128]:
        """Complex modulus E [Pa] at angular frequency ``omega`` [rad/s] and temperature T [C].

        ``E(omega, T) = E_ref(omega aT(T) / aT(T_ref))``; ``T_C=None`` means T_ref.
        Broadcasts ``omega`` against ``T_C``. ``Im E > 0`` for ``omega > 0``.
        """
        w = np.asarray(omega_rad_s, dtype=float)
        if T_C is None:
            return self.modulus_ref(w)
        f = 10.0 ** log10_shift(self, T_C)
        return self.modulus_ref(w * f)


@dataclass(frozen=True, eq=False)
class Prony(Rubber):
    """Generalized Maxwell (Prony) series at the reference temperature:

    ``E(omega) = E_inf + sum_i E_i (i omega tau_i) / (1 + i omega tau_i)`` [Pa],
    so ``E(0) = E_inf`` (rubbery), ``E(inf) = E_inf + sum E_i`` (glassy),
    ``Im E = sum E_i omega tau_i / (1 + omega^2 tau_i^2) > 0``.

    Parameters
    ----------
    E_inf_Pa : float
        Relaxed (rubbery) modulus [Pa].
    E_i_Pa : array_like
        Modulus of each term [Pa].
    tau_i_s : array_like
        Relaxation time of each term [s].
    T_ref_C : float, optional
        Reference temperature of the moduli [C].
    shift : WLF, ShiftTable or None, optional
        Temperature shift (default: the thesis WLF).
    thermal : Thermal, optional
        Thermal properties for the flash-temperature model.

    References
    ----------
    N.W. Tschoegl, The Phenomenological Theory of Linear Viscoelastic Behavior, Springer (1989),
    doi:10.1007/978-3-642-73602-5.
    """

    E_inf_Pa: float
    E_i_Pa: np.ndarray
    tau_i_s: np.ndarray
    T_ref_C: float = 60.0
    shift: WLF | ShiftTable | None = field(default_factory=WLF.thesis)
    thermal: Thermal = field(default_factory=Thermal)

    def __post_init__(self):
        Ei = np.atleast_1d(np.asarray(self.E_i_Pa, dtype=float))
        ti = np.atleast_1d(np.asarray(self.tau_i_s, dtype=float))
        if Ei.ndim != 1 or Ei.shape != ti.shape:
            raise ValueError("E_i_Pa and tau_i_s must be 1D arrays of equal length")
        if np.any(Ei < 0) or np.any(ti <= 0) or not self.E_inf_Pa >= 0:
            raise ValueError("Prony terms need E_i >= 0, tau_i > 0, E_inf >= 0")
        object.__setattr__(self, "E_i_Pa", Ei)
        object.__setattr__(self, "tau_i_s", ti)

    def modulus_ref(self, omega_rad_s: ArrayLike) -> NDArray[np.complex128]:
        """E(omega) = E_inf + sum_i E_i i omega tau_i / (1 + i omega tau_i) [Pa] at T_ref."""
        w = np.asarray(omega_rad_s, dtype=float)
        out = np.full(w.shape, complex(self.E_inf_Pa))
        for Ei, ti in zip(self.E_i_Pa, self.tau_i_s):  # loop over terms, not over data
            iwt = 1j * (w * ti)
            out = out + Ei * iwt / (1.0 + iwt)
        return out


@dataclass(frozen=True, eq=False)
class StandardLinearSolid(Rubber):
    """The thesis's standard linear solid (conjugated to ``Im E > 0``, docs: Theory):

    ``E(omega) = E1 (1 + i omega tau) / (1 + a1 + i omega tau)`` [Pa];
    ``E(0) = E1 / (1 + a1)``, ``E(inf) = E1``. A one-term Prony series with
    ``E_inf = E1/(1+a1)``, ``E_1 = E1 a1/(1+a1)``, ``tau_1 = tau/(1+a1)`` (see :meth:`as_prony`).
    Defaults: the thesis rubber (E1 = 1e9 Pa, a1 = 1000, tau = 1e-3 s, T_ref = 60 C,
    WLF C1 = 8.86, C2 = 51.5 K, T_s = Tg + 50 = 20 C, Tg = -30 C: :meth:`WLF.thesis`).

    Parameters
    ----------
    E1_Pa : float, optional
        Glassy modulus E(inf) [Pa].
    a1 : float, optional
        Ratio of glassy to rubbery modulus minus one.
    tau_s : float, optional
        Time constant tau [s].
    T_ref_C : float, optional
        Reference temperature [C].
    shift : WLF, ShiftTable or None, optional
        Temperature shift (default: the thesis WLF).
    thermal : Thermal, optional
        Thermal properties.

    References
    ----------
    B.N.J. Persson, J. Chem. Phys. 115, 3840 (2001), doi:10.1063/1.1388626.
    """

    E1_Pa: float = 1e9
    a1: float = 1000.0
    tau_s: float = 1e-3
    T_ref_C: float = 60.0
    shift: WLF | ShiftTable | None = field(default_factory=WLF.thesis)
    thermal: Thermal = field(default_factory=Thermal)

    def __post_init__(self):
        if not (self.E1_Pa > 0 and self.a1 > 0 and self.tau_s > 0):
            raise ValueError("StandardLinearSolid needs E1 > 0, a1 > 0, tau > 0")

    def modulus_ref(self, omega_rad_s: ArrayLike) -> NDArray[np.complex128]:
        """E(omega) = E1 (1 + i omega tau) / (1 + a1 + i omega tau) [Pa] at T_ref."""
        iwt = 1j * (np.asarray(omega_rad_s, dtype=float) * self.tau_s)
        return self.E1_Pa * (1.0 + iwt) / (1.0 + self.a1 + iwt)

    def as_prony(self) -> Prony:
        """The same modulus as a one-term Prony series."""
        b = 1.0 + self.a1
        return Prony(
            self.E1_Pa / b,
            np.array([self.E1_Pa * self.a1 / b]),
            np.array([self.tau_s / b]),
            self.T_ref_C,
            self.shift,
            self.thermal,
        )


@dataclass(frozen=True, eq=False)
class MasterCurve(Rubber):
    """Measured master curve E'(f), E''(f) [Pa] at ``T_ref_C``, f in Hz (used at omega = 2 pi f).

    Interpolation is linear in (log f, log E') and (log f, log E''). Outside the measured range
    (``extrapolate``):

    * ``"powerlaw"`` (default): E' is held at its end value (rubbery/glassy plateau) and E''
      continues as a power law with the slope of the last decade of data, clipped to [0, 1] at
      the low end and [-1, 0] at the high end (a Maxwell-like tail: E'' -> 0 as omega -> 0);
    * ``"hold"``: E' and E'' are both held at their end values.

    ``E(0) = E'(f_min)``. :meth:`f_range_Hz` gives the measured range.

    Parameters
    ----------
    f_Hz : array_like
        Frequencies [Hz].
    E_storage_Pa, E_loss_Pa : array_like
        Storage and loss moduli E', E'' at ``T_ref_C`` [Pa].
    T_ref_C : float, optional
        Temperature of the master curve [C].
    shift : WLF, ShiftTable or None, optional
        Temperature shift (None: temperature independent).
    thermal : Thermal, optional
        Thermal properties.
    extrapolate : {"powerlaw", "hold"}, optional
        Behaviour outside the measured frequencies.
    """

    f_Hz: np.ndarray
    E_storage_Pa: np.ndarray
    E_loss_Pa: np.ndarray
    T_ref_C: float = 20.0
    shift: WLF | ShiftTable | None = None
    thermal: Thermal = field(default_factory=Thermal)
    extrapolate: str = "powerlaw"
    # log-log slopes of E'' continued below and above the measured range (set from the data)
    _slopes: tuple[float, float] = field(init=False, repr=False)

    def __post_init__(self):
        if self.extrapolate not in EXTRAPOLATE:
            raise ValueError(f"extrapolate must be one of {', '.join(EXTRAPOLATE)}, not {self.extrapolate!r}")
        f = np.asarray(self.f_Hz, dtype=float)
        E1 = np.asarray(self.E_storage_Pa, dtype=float)
        E2 = np.asarray(self.E_loss_Pa, dtype=float)
        if f.ndim != 1 or f.shape != E1.shape or f.shape != E2.shape or f.size < 2:
            raise ValueError("master curve needs three 1D arrays of equal length >= 2")
        if not (np.all(f > 0) and np.all(E1 > 0) and np.all(E2 > 0)):
            raise ValueError("master curve values must be positive (f, E', E'')")
        o = np.argsort(f)
        f, E1, E2 = f[o], E1[o], E2[o]
        keep = np.concatenate([[True], np.diff(f) > 0])
        f, E1, E2 = f[keep], E1[keep], E2[keep]
        object.__setattr__(self, "f_Hz", f)
        object.__setattr__(self, "E_storage_Pa", E1)
        object.__setattr__(self, "E_loss_Pa", E2)
        lf, l2 = np.log(f), np.log(E2)
        n = max(2, int(np.searchsorted(lf, lf[0] + np.log(10.0))) + 1)
        m = max(2, lf.size - int(np.searchsorted(lf, lf[-1] - np.log(10.0))))
        s_lo = np.polyfit(lf[:n], l2[:n], 1)[0] if n > 2 else (l2[1] - l2[0]) / (lf[1] - lf[0])
        s_hi = np.polyfit(lf[-m:], l2[-m:], 1)[0] if m > 2 else (l2[-1] - l2[-2]) / (lf[-1] - lf[-2])
        slopes = (float(np.clip(s_lo, 0, 1)), float(np.clip(s_hi, -1, 0)))
        object.__setattr__(self, "_slopes", slopes if self.extrapolate == "powerlaw" else (0.0, 0.0))

    def f_range_Hz(self) -> tuple[float, float]:
        """(lowest, highest) measured frequency [Hz] at ``T_ref_C``."""
        return float(self.f_Hz[0]), float(self.f_Hz[-1])

    def modulus_ref(self, omega_rad_s: ArrayLike) -> NDArray[np.complex128]:
        """E' and E'' interpolated in log-log at f = omega / 2 pi [Pa] at T_ref; outside the
        measured range E' is held and E'' continued by the end slopes (``extrapolate``)."""
        w = np.asarray(omega_rad_s, dtype=float)
        lf = np.log(self.f_Hz)
        with np.errstate(divide="ignore"):
            x = np.log(w / (2 * np.pi))
        xc = np.clip(x, lf[0], lf[-1])
        Es = np.exp(np.interp(xc, lf, np.log(self.E_storage_Pa)))
        l2 = np.interp(xc, lf, np.log(self.E_loss_Pa))
        s_lo, s_hi = self._slopes
        with np.errstate(invalid="ignore"):
            l2 = (
                l2
                + np.where(x < lf[0], s_lo * (x - lf[0]), 0.0)
                + np.where(x > lf[-1], s_hi * (x - lf[-1]), 0.0)
            )
        with np.errstate(over="ignore", invalid="ignore"):
            El = np.where(w > 0, np.exp(l2), 0.0)
        return Es + 1j * El


def thesis_rubber() -> StandardLinearSolid:
    """The default rubber: the thesis's SLS at T_ref = 60 C with WLF (Tg = -30 C) and the
    default thermal properties (rho 1200 kg/m^3, c_v 1500 J/(kg K), lambda 0.25 W/(m K)).

    Returns
    -------
    StandardLinearSolid
        E1 = 1e9 Pa, a1 = 1000, tau = 1e-3 s at T_ref = 60 C.

    Parameters
    ----------
    None

    References
    ----------
    B.N.J. Persson, J. Chem. Phys. 115, 3840 (2001), doi:10.1063/1.1388626.
    """
    return StandardLinearSolid()
