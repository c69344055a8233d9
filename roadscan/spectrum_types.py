"""Small containers for power spectral densities (no computation here beyond rebuilding the
full 2D map from its rfft half lattice).

PSD convention (Persson's, docs: Theory): for an isotropic surface
``<h^2> = integral d^2q C(q) = 2 pi integral q C(q) dq``; C [m^4]. A 1D (profile) PSD C1 [m^3]
satisfies ``<h^2> = 2 integral_0^inf C1(q) dq``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["Spectrum", "Spectrum2D", "HalfLattice", "NORMALISATION_2D", "NORMALISATION_1D"]

#: the normalisations written into every spectrum's ``meta`` (:mod:`roadscan.spectrum`,
#: :mod:`roadscan.profile_spectrum`)
NORMALISATION_2D = "C = (dx dy)^2 |FFT2(w h)|^2 / ((2 pi)^2 A <w^2>) [m^4] (Persson; docs: Theory)"
NORMALISATION_1D = "C1 = dx^2 |FFT(w h)|^2 / (2 pi L <w^2>) [m^3]; <h^2> = 2 int_0^inf C1 dq"


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
    count: NDArray[np.int64] | None = None
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
    def q_min_per_m(self) -> float:
        """The smallest wave vector [1/m]."""
        return float(self.q_per_m[0])

    @property
    def q_max_per_m(self) -> float:
        """The largest wave vector [1/m]."""
        return float(self.q_per_m[-1])


def _full_from_half(P, nx):
    """The full (ny, nx) lattice from the rfft2 half (C(-q) = C(q) for real heights),
    fftshifted so that q = 0 is at the centre."""
    ny, nxr = P.shape
    full = np.empty((ny, nx))
    full[:, :nxr] = P
    if nx > nxr:
        rows = (-np.arange(ny)) % ny
        cols = nx - np.arange(nxr, nx)
        full[:, nxr:] = P[rows][:, cols]
    return np.fft.fftshift(full)


@dataclass(frozen=True, eq=False)
class HalfLattice:
    """A 2D PSD stored on the rfft2 half lattice: ``C = scale * P`` at the unshifted lattice
    points with q_x >= 0 (columns 0 .. nx // 2), the rest following from C(-q) = C(q).
    Half the memory of the full map, which is built only when asked for.

    Parameters
    ----------
    P : ndarray
        Unscaled |FFT2|^2 on the half lattice.
    scale : float
        Factor making P a PSD [m^4].
    nx : int
        Columns of the full lattice.
    """

    P: np.ndarray  # (ny, nx // 2 + 1), unscaled |FFT2(w h)|^2
    scale: float  # C [m^4] = scale * P
    nx: int  # columns of the full lattice

    def full(self) -> NDArray[np.float64]:
        """The fftshifted (ny, nx) map C [m^4]."""
        C = _full_from_half(self.P, self.nx)
        C *= self.scale
        return C

    def block(self, rows: ArrayLike, cols: ArrayLike) -> NDArray[np.float64]:
        """C [m^4] at the fftshifted row and column indices ``rows`` x ``cols`` (1D integer
        arrays), read from the half lattice (the same values as ``full()[np.ix_(rows, cols)]``)."""
        ny, nxr = self.P.shape
        uy = (np.asarray(rows) - ny // 2) % ny  # unshifted indices
        ux = (np.asarray(cols) - self.nx // 2) % self.nx
        mirrored = ux >= nxr
        r = np.where(mirrored[None, :], ((-uy) % ny)[:, None], uy[:, None])
        c = np.where(mirrored, self.nx - ux, ux)[None, :]
        return self.P[r, c] * self.scale


class Spectrum2D:
    """The full 2D PSD map C(qx, qy) [m^4] on the FFT lattice (fftshifted, zero at centre).

    ``qx_per_m`` (nx,) and ``qy_per_m`` (ny,) are the shifted lattice wave vectors [1/m].
    ``C_m4`` is either given, or (from :func:`roadscan.spectrum.psd_area` and ``psd_2d``)
    built from the rfft2 half lattice ``half`` the first time it is read and then kept;
    :meth:`central` reads the part around q = 0 without building the whole map.

    Parameters
    ----------
    qx_per_m, qy_per_m : ndarray
        Shifted lattice wave vectors [1/m].
    C_m4 : ndarray, optional
        The map [m^4] (else built from ``half``).
    meta : dict, optional
        Window, normalisation, spacing.
    half : HalfLattice, optional
        The half-lattice storage.
    """

    __slots__ = ("_C", "half", "meta", "qx_per_m", "qy_per_m")

    def __init__(
        self,
        qx_per_m: NDArray[np.float64],
        qy_per_m: NDArray[np.float64],
        C_m4: NDArray[np.float64] | None = None,
        meta: dict[str, Any] | None = None,
        *,
        half: HalfLattice | None = None,
    ) -> None:
        if C_m4 is None and half is None:
            raise ValueError("Spectrum2D needs C_m4 or its half lattice")
        self.qx_per_m = qx_per_m
        self.qy_per_m = qy_per_m
        self.meta = {} if meta is None else meta
        self.half = half
        self._C = C_m4

    @property
    def C_m4(self) -> NDArray[np.float64]:
        """The fftshifted (ny, nx) map C [m^4] (built from the half lattice on first read)."""
        if self._C is None:
            assert self.half is not None  # the constructor asks for one of the two
            self._C = self.half.full()
        return self._C

    def central(
        self, q_limit_per_m: float
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """(qx, qy, C) on the lattice points with |qx| and |qy| <= ``q_limit_per_m`` [1/m]."""
        qx, qy = np.asarray(self.qx_per_m), np.asarray(self.qy_per_m)
        ix = np.flatnonzero(np.abs(qx) <= q_limit_per_m)
        iy = np.flatnonzero(np.abs(qy) <= q_limit_per_m)
        if self._C is not None or self.half is None:
            C = np.asarray(self._C)[np.ix_(iy, ix)]
        else:
            C = self.half.block(iy, ix)
        return qx[ix], qy[iy], C

    def __repr__(self):
        return (
            f"Spectrum2D({np.size(self.qy_per_m)} x {np.size(self.qx_per_m)}, "
            f"{'map' if self._C is not None else 'half lattice'})"
        )
