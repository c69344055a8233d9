"""Synthetic self-affine (fractal) surfaces by Fourier filtering.

The target spectrum (Persson's normalisation, docs: Theory) is

    C(q) = K q^(-2(H+1))            for q_roll <= q <= q1
    C(q) = K q_roll^(-2(H+1))       for q0 <= q < q_roll  (roll-off plateau, if q_roll given)
    C(q) = 0                        otherwise (and at q = 0),

with K fixed by the requested rms height: rms^2 = sum over the FFT lattice of C (2 pi)^2 / A.
White Gaussian noise is Fourier transformed (which gives Hermitian-symmetric complex Gaussian
amplitudes), multiplied by sqrt(C / K) and transformed back. With
``gaussian_amplitudes=False`` every amplitude is set to exactly sqrt(C) with a random phase
("random-phase" surface: the periodogram equals C on every lattice point). The result is
rescaled so that its rms is exactly ``rms_height_m``; its mean is zero.

Reference: Jacobs, Junge, Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017), sec. 3.
"""

from __future__ import annotations

import numpy as np
import scipy.fft as sfft
from numpy.typing import ArrayLike, NDArray

from .errors import InputError
from .heightmap import HeightMap

__all__ = ["self_affine_surface", "model_psd"]


def model_psd(
    q_per_m: ArrayLike,
    hurst: float,
    prefactor_m4: float = 1.0,
    q0_per_m: float = 0.0,
    q1_per_m: float = np.inf,
    q_roll_per_m: float | None = None,
) -> NDArray[np.float64]:
    """The piecewise self-affine spectrum above, C [m^4] at wave vectors ``q_per_m`` [1/m].

    ``prefactor_m4`` is K in C = K q^(-2(H+1)) (units m^4 when q is in 1/m, times m^(-2(H+1))).

    Parameters
    ----------
    q_per_m : array_like
        Wave vectors [1/m].
    hurst : float
        Hurst exponent H.
    prefactor_m4 : float, optional
        K.
    q0_per_m, q1_per_m : float, optional
        Band of the power law [1/m] (zero outside).
    q_roll_per_m : float, optional
        Roll-off: C constant below it.

    Returns
    -------
    ndarray
        C [m^4].
    """
    q = np.asarray(q_per_m, dtype=np.float64)
    qr = q0_per_m if q_roll_per_m is None else q_roll_per_m
    # q = 0 (and a tiny q_roll below the lattice) give 0^-x or overflow: those points lie
    # outside [q0, q1] or are replaced by q itself, and are set to 0 below
    with np.errstate(divide="ignore", over="ignore"):
        c = np.where(q >= qr, q, qr) ** (-2.0 * (hurst + 1.0))
    inside = (q >= q0_per_m) & (q <= q1_per_m) & (q > 0)
    return np.where(inside, prefactor_m4 * c, 0.0)


def self_affine_surface(
    nx: int,
    ny: int | None = None,
    dx_m: float = 55.4e-6,
    hurst: float = 0.8,
    rms_height_m: float = 0.5e-3,
    q_roll_per_m: float | None = None,
    q0_per_m: float | None = None,
    q1_per_m: float | None = None,
    seed: int = 0,
    gaussian_amplitudes: bool = True,
    dy_m: float | None = None,
    name: str = "synthetic",
) -> HeightMap:
    """A periodic self-affine height map with exactly the requested rms height.

    Parameters
    ----------
    nx, ny : int
        Grid size (ny defaults to nx). Rows run along y.
    dx_m, dy_m : float
        Spacing [m] (dy defaults to dx). Default 55.4 um, the thesis's scan.
    hurst : float
        Hurst exponent H (0 < H < 1): C ~ q^(-2(H+1)).
    rms_height_m : float
        Realised rms height [m] (exact after rescaling).
    q_roll_per_m : float, optional
        Roll-off wave vector [1/m]: C is flat between q0 and q_roll.
    q0_per_m : float, optional
        Lowest wave vector with power [1/m] (default: every lattice wave vector > 0).
    q1_per_m : float, optional
        Highest wave vector with power [1/m] (default: Nyquist, pi / max(dx, dy)).
    seed : int
        Seed of ``numpy.random.default_rng``; the same seed gives the same surface.
    gaussian_amplitudes : bool
        True: Gaussian random field. False: random phases, amplitudes exactly sqrt(C).

    Returns
    -------
    HeightMap
        ``meta['model']`` holds the parameters and the prefactor K [m^4 m^-2(H+1)] of the
        expected spectrum (see :func:`model_psd`).
    """
    ny = nx if ny is None else ny
    dy_m = dx_m if dy_m is None else dy_m
    if not (0.0 < hurst < 1.5):
        raise ValueError(f"hurst should be in (0, 1), got {hurst}")
    q0 = 0.0 if q0_per_m is None else float(q0_per_m)
    q1 = np.pi / max(dx_m, dy_m) if q1_per_m is None else float(q1_per_m)
    rng = np.random.default_rng(seed)
    F = sfft.rfft2(rng.standard_normal((ny, nx)))
    if not gaussian_amplitudes:
        mag = np.abs(F)
        F = np.where(mag > 0, F / np.where(mag > 0, mag, 1.0), 0.0)
    qx = 2 * np.pi * sfft.rfftfreq(nx, dx_m)
    qy = 2 * np.pi * sfft.fftfreq(ny, dy_m)
    q = np.hypot(qx[None, :], qy[:, None])
    shape = model_psd(q, hurst, 1.0, q0, q1, q_roll_per_m)
    h = sfft.irfft2(F * np.sqrt(shape), s=(ny, nx))
    h -= h.mean()
    std = h.std()
    if std == 0:
        raise InputError(
            None, "no lattice wave vector lies inside [{q0}, {q1}]: empty spectrum", ("q0", "q1")
        )
    h *= rms_height_m / std
    # prefactor: rms^2 = sum_full_lattice K shape (2 pi)^2 / A (rfft half counted with weights)
    w = np.full(qx.size, 2.0)
    w[0] = 1.0
    if nx % 2 == 0:
        w[-1] = 1.0
    area = nx * dx_m * ny * dy_m
    K = rms_height_m**2 / ((shape * w[None, :]).sum() * (2 * np.pi) ** 2 / area)
    meta = {
        "model": {
            "hurst": hurst,
            "prefactor_m4": float(K),
            "q0_per_m": q0,
            "q1_per_m": q1,
            "q_roll_per_m": q_roll_per_m,
            "rms_height_m": rms_height_m,
            "seed": seed,
            "gaussian_amplitudes": bool(gaussian_amplitudes),
        },
        "source": "roadscan.synth.self_affine_surface",
    }
    return HeightMap(h, dx_m, dy_m, name=name, meta=meta)
