"""Isotropic surface power spectra C(q) [m^4] for the friction engine.

PSD convention (Persson's, docs: Theory): ``<h^2> = 2 pi integral q C(q) dq``.
Each PSD exposes ``C(q)`` (vectorised, zero outside its band), ``q0_per_m`` (the wave vector
used for the macro-asperity scale ``q_m = zeta_m q0``), ``q_min_per_m`` (lower end of the
friction integrals: the roll-off ``q_roll`` when given, else ``q0``), ``q1_per_m`` (upper
cut-off) and ``with_q1(q1)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["SelfAffinePSD", "TabulatedPSD"]


@dataclass(frozen=True)
class SelfAffinePSD:
    """Self-affine spectrum (Persson's form; see the theory page of the docs).

    ``C(q) = (H / 2 pi) (h0 / q0)^2 (q / q0)^(-2(H+1))`` for ``q0 <= q <= q1`` [m^4],
    ``C = C(q0)`` for ``q_roll <= q < q0`` when ``q_roll_per_m`` is given, zero elsewhere.
    With this prefactor ``2 pi integral_{q0}^{q1} q C dq = (h0^2/2)(1 - (q1/q0)^(-2H))``.

    Parameters
    ----------
    hurst : float
        Hurst exponent H, 0 < H < 1.
    h0_m : float
        Amplitude h0 [m] (about sqrt(2) times the band's rms height when q1 >> q0).
    q0_per_m, q1_per_m : float
        Ends of the power law [1/m].
    q_roll_per_m : float, optional
        Roll-off [1/m], below q0: C is constant between it and q0.

    References
    ----------
    B.N.J. Persson, J. Chem. Phys. 115, 3840 (2001), doi:10.1063/1.1388626, appendix.

    Examples
    --------
    >>> import numpy as np, friction
    >>> psd = friction.SelfAffinePSD(0.85, 5e-4, 2000, 2e5)
    >>> q = np.geomspace(2000, 2e5, 20001)
    >>> h2 = 2 * np.pi * np.trapezoid(q * psd.C(q), q)       # <h^2> = 2 pi int q C dq
    >>> bool(abs(h2 - 0.5 * 5e-4**2 * (1 - 100.0**-1.7)) < 1e-3 * h2)
    True
    """

    hurst: float
    h0_m: float
    q0_per_m: float
    q1_per_m: float
    q_roll_per_m: float | None = None

    def __post_init__(self):
        if not (0 < self.hurst < 1.5 and self.h0_m > 0 and 0 < self.q0_per_m < self.q1_per_m):
            raise ValueError("SelfAffinePSD needs 0 < H, h0 > 0 and 0 < q0 < q1")
        if self.q_roll_per_m is not None and not (0 < self.q_roll_per_m < self.q0_per_m):
            raise ValueError("q_roll_per_m must lie in (0, q0)")

    @property
    def q_min_per_m(self) -> float:
        """Lower end of the spectrum [1/m]: the roll-off if any, else q0."""
        return self.q0_per_m if self.q_roll_per_m is None else self.q_roll_per_m

    def C(self, q_per_m: ArrayLike) -> NDArray[np.float64]:
        """C(q) [m^4]: H/(2 pi) (h0/q0)^2 (q/q0)^(-2(H+1)) on [q0, q1], the plateau C(q0) from
        the roll-off to q0, 0 outside."""
        q = np.asarray(q_per_m, dtype=float)
        H, q0 = self.hurst, self.q0_per_m
        k = H / (2 * np.pi) * (self.h0_m / q0) ** 2
        qq = np.maximum(q, q0)
        out = k * (qq / q0) ** (-2 * (H + 1))
        inside = (q >= self.q_min_per_m * (1 - 1e-12)) & (q <= self.q1_per_m * (1 + 1e-12))
        return np.where(inside, out, 0.0)

    def with_q1(self, q1_per_m: float) -> SelfAffinePSD:
        """The same spectrum cut at another q1 [1/m]."""
        return replace(self, q1_per_m=float(q1_per_m))

    @property
    def band_rms_m(self) -> float:
        """rms height of the band ``q_min..q1`` [m] implied by the model."""
        from scipy.integrate import quad

        v = quad(
            lambda lq: 2 * np.pi * np.exp(2 * lq) * self.C(np.exp(lq)),
            np.log(self.q_min_per_m),
            np.log(self.q1_per_m),
            limit=200,
        )[0]
        return float(np.sqrt(v))


@dataclass(frozen=True, eq=False)
class TabulatedPSD:
    """A measured angular-averaged spectrum, interpolated linearly in (log q, log C).

    ``C(q)`` is zero below the lowest tabulated q and above q1.

    Parameters
    ----------
    q_per_m : array_like, shape (n,)
        Wave vectors [1/m], increasing.
    C_m4 : array_like, shape (n,)
        Spectrum [m^4], > 0, in Persson's normalisation ``<h^2> = 2 pi int q C dq``.
    q0_per_m : float, optional
        Wave vector for ``q_m = zeta_m q0`` (roll-off); default: the lowest q.
    q1_per_m : float, optional
        Upper cut-off; default: the highest q. Beyond the highest tabulated q the spectrum
        continues as the power law fitted (least squares in log-log) to the top decade of the
        data (at least 4 points), which is how ``with_q1(q1 > q_max)`` extends a scan.
    """

    q_per_m: np.ndarray
    C_m4: np.ndarray
    q0_per_m: float | None = None
    q1_per_m: float | None = None
    # (exponent, intercept) of the power law continuing the table above its last point
    _tail: tuple[float, float] = field(init=False, repr=False)

    def __post_init__(self):
        q = np.asarray(self.q_per_m, dtype=float)
        C = np.asarray(self.C_m4, dtype=float)
        if q.ndim != 1 or q.shape != C.shape or q.size < 2:
            raise ValueError("q_per_m and C_m4 must be 1D arrays of equal length >= 2")
        ok = np.isfinite(q) & np.isfinite(C) & (q > 0) & (C > 0)
        q, C = q[ok], C[ok]
        if q.size < 2 or np.any(np.diff(q) <= 0):
            raise ValueError("need >= 2 positive finite points with strictly increasing q")
        object.__setattr__(self, "q_per_m", q)
        object.__setattr__(self, "C_m4", C)
        if self.q0_per_m is None:
            object.__setattr__(self, "q0_per_m", float(q[0]))
        if self.q1_per_m is None:
            object.__setattr__(self, "q1_per_m", float(q[-1]))
        if not (q[0] <= self.q0_per_m < self.q1_per_m):
            raise ValueError("need lowest q <= q0 < q1")
        lq, lC = np.log(q), np.log(C)
        n = max(4, q.size - int(np.searchsorted(lq, lq[-1] - np.log(10.0))))
        n = min(n, q.size)
        slope, icpt = np.polyfit(lq[-n:], lC[-n:], 1)
        object.__setattr__(self, "_tail", (float(slope), float(icpt)))

    @property
    def q_min_per_m(self) -> float:
        """The first tabulated wave vector [1/m]."""
        return float(self.q_per_m[0])

    @property
    def tail_exponent(self) -> float:
        """Exponent of the fitted power-law continuation, ``C ~ q^exponent`` (= -2(H+1))."""
        return self._tail[0]

    def C(self, q_per_m: ArrayLike) -> NDArray[np.float64]:
        """C(q) [m^4] interpolated in (ln q, ln C), continued above the table by the fitted
        power law up to q1, 0 outside [q_min, q1]."""
        q = np.asarray(q_per_m, dtype=float)
        lq = np.log(np.maximum(q, 1e-300))
        lqt = np.log(self.q_per_m)
        inner = np.exp(np.interp(lq, lqt, np.log(self.C_m4)))
        # continuation anchored at the last data point with the fitted slope
        tail = self.C_m4[-1] * np.exp(self._tail[0] * (lq - lqt[-1]))
        out = np.where(q > self.q_per_m[-1], tail, inner)
        q1 = self.q1_per_m
        assert q1 is not None  # set by the constructor
        inside = (q >= self.q_per_m[0] * (1 - 1e-12)) & (q <= q1 * (1 + 1e-12))
        return np.where(inside, out, 0.0)

    def with_q1(self, q1_per_m: float) -> TabulatedPSD:
        """The same table cut (or continued) at another q1 [1/m]."""
        return TabulatedPSD(self.q_per_m, self.C_m4, self.q0_per_m, float(q1_per_m))
