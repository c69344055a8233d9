"""Gaussian S- and L-filters: ISO 16610-61 (areal) and ISO 16610-21 (profile).

The weighting function of the linear Gaussian filter with nesting index (cut-off wavelength)
lambda_c [m] is

    s(x) = 1 / (alpha lambda_c) exp(-pi (x / (alpha lambda_c))^2),  alpha = sqrt(ln 2 / pi),

in each direction (the areal filter is the product of two profile filters), whose transfer
function exp(-pi (alpha lambda_c / lambda)^2) passes 50 % of the amplitude of a sine of
wavelength lambda = lambda_c. The S-filter keeps the low-pass (removes scales below its
nesting index); the L-filter keeps the high-pass z - s * z (removes scales above it).

End effects and unmeasured points: masked, normalised convolution (the "zero-order" end
correction of ISO 16610-28): the weights are renormalised over the measured points that fall
inside the field, (s * (w z)) / (s * w) with w = 1 where measured, 0 elsewhere (and outside
the field). Near an edge the mean line is then a one-sided weighted mean instead of being
pulled towards zero; no point is discarded and no mirror image is invented. Unmeasured points
stay unmeasured.

The convolution is done by FFT on a zero-padded grid (pad >= 0.75 lambda_c, where the
Gaussian weight is below 2e-4 of its peak), with the exact continuous transfer function.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .heightmap import HeightMap, Profile

_Scan = TypeVar("_Scan", HeightMap, Profile)

__all__ = ["ALPHA", "END_EFFECTS", "gaussian_lowpass", "apply_filters", "gaussian_transmission"]

#: ISO 16610-21 / -61 Gaussian constant
ALPHA = math.sqrt(math.log(2.0) / math.pi)
#: how the edges and unmeasured points are handled (recorded with every filtered result)
END_EFFECTS = (
    "masked normalised Gaussian convolution: weights renormalised over the measured "
    "points inside the field (ISO 16610-28 zero-order end correction), no padding "
    "by mirroring or extrapolation"
)


def gaussian_transmission(wavelength_m: ArrayLike, cutoff_m: float) -> NDArray[np.float64]:
    """Amplitude transmission of the Gaussian low-pass, exp(-pi (alpha lambda_c / lambda)^2).

    Parameters
    ----------
    wavelength_m : array_like
        Wavelengths [m].
    cutoff_m : float
        Cut-off wavelength lambda_c [m].

    Returns
    -------
    ndarray
        Transmission between 0 and 1.

    References
    ----------
    ISO 16610-21:2011 (Gaussian profile filter); ISO 16610-61:2015 (areal).
    """
    return np.exp(-np.pi * (ALPHA * cutoff_m / np.asarray(wavelength_m, dtype=float)) ** 2)


def _transfer(n, d, cutoff_m):
    """Transfer function on the rfft/fft frequencies of a padded axis of n points, spacing d."""
    return None if cutoff_m is None else np.exp(-np.pi * (ALPHA * cutoff_m * np.fft.fftfreq(n, d)) ** 2)


def _padded(n, d, cutoff_m):
    from scipy import fft

    return fft.next_fast_len(n + 2 * int(math.ceil(0.75 * cutoff_m / d)) + 2, real=True)


def _smooth(a, spacings, cutoff_m):
    """Gaussian convolution of ``a`` (1D or 2D, zero outside) by FFT, same shape."""
    from scipy import fft

    shape = [_padded(n, d, cutoff_m) for n, d in zip(a.shape, spacings)]
    if a.ndim == 1:
        h = np.exp(-np.pi * (ALPHA * cutoff_m * fft.rfftfreq(shape[0], spacings[0])) ** 2)
        return fft.irfft(fft.rfft(a, shape[0]) * h, shape[0])[: a.shape[0]]
    hy = _transfer(shape[0], spacings[0], cutoff_m)
    hx = np.exp(-np.pi * (ALPHA * cutoff_m * fft.rfftfreq(shape[1], spacings[1])) ** 2)
    F = fft.rfft2(a, shape, workers=-1)
    F *= hy[:, None]
    F *= hx[None, :]
    return fft.irfft2(F, shape, workers=-1)[: a.shape[0], : a.shape[1]]


def gaussian_lowpass(
    heights_m: ArrayLike, spacings_m: Sequence[float], cutoff_m: float, unmeasured: ArrayLike | None = None
) -> NDArray[np.float64]:
    """The Gaussian mean surface (or line) of ``heights_m`` for nesting index ``cutoff_m`` [m].

    Masked, normalised convolution (module docstring): (s * (w z)) / (s * w). A fully measured
    rectangle needs only the separable normalisation, the outer product of two 1D ones.

    Parameters
    ----------
    heights_m : ndarray, shape (n,) or (ny, nx)
        Heights [m], NaN where unmeasured.
    spacings_m : sequence of float
        Grid spacings [m], (dx,) or (dy, dx).
    cutoff_m : float
        Nesting index lambda_c [m].
    unmeasured : bool array, optional

    Returns
    -------
    ndarray
        Filtered heights of the input's shape [m], NaN where unmeasured.
    """
    z = np.asarray(heights_m, dtype=np.float64)
    bad = ~np.isfinite(z)
    if unmeasured is not None:
        bad |= np.asarray(unmeasured, dtype=bool)
    w = (~bad).astype(np.float64)
    num = _smooth(np.where(bad, 0.0, z), spacings_m, cutoff_m)
    if not bad.any():  # separable: the product of the axes' smoothed ones
        ones = [_smooth(np.ones(n), (d,), cutoff_m) for n, d in zip(z.shape, spacings_m)]
        dens = ones[0] if len(ones) == 1 else ones[0][:, None] * ones[1][None, :]
    else:
        dens = _smooth(w, spacings_m, cutoff_m)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = num / np.maximum(dens, 1e-300)
    out[bad] = np.nan
    return out


def apply_filters(obj: _Scan, s_filter_m: float | None = None, l_filter_m: float | None = None) -> _Scan:
    """S-filter then L-filter (ISO 25178-2 S-L surface, ISO 21920 profile) of a levelled
    HeightMap or Profile; same type out, unmeasured points kept.

    z_S = s_S * z (S-filter, low-pass at ``s_filter_m``), then z_SL = z_S - s_L * z_S
    (L-filter, high-pass at ``l_filter_m``). Either may be None (not applied).

    Raises
    ------
    ValueError when a nesting index is not positive, when S >= L, or when a nesting index
    is shorter than two sampling intervals (S) or longer than the field (L).

    Parameters
    ----------
    obj : HeightMap or Profile
        Levelled scan [m].
    s_filter_m : float, optional
        S-filter nesting index [m].
    l_filter_m : float, optional
        L-filter nesting index [m].

    Returns
    -------
    HeightMap or Profile
        The filtered scan.

    References
    ----------
    ISO 25178-2:2021; ISO 16610-61:2015.
    """
    for name, v in (("S-filter", s_filter_m), ("L-filter", l_filter_m)):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} nesting index must be a positive length in m, got {v!r}")
    if s_filter_m is not None and l_filter_m is not None and s_filter_m >= l_filter_m:
        raise ValueError(
            f"S-filter nesting index {s_filter_m:g} m must be shorter than the L-filter's {l_filter_m:g} m"
        )
    spacings: tuple[float, ...]
    if isinstance(obj, Profile):
        spacings, size = (obj.dx_m,), obj.length_m
    elif isinstance(obj, HeightMap):
        spacings, size = (obj.dy_m, obj.dx_m), max(obj.size_m)
    else:
        raise TypeError(f"expected HeightMap or Profile, got {type(obj).__name__}")
    if s_filter_m is not None and s_filter_m < 2 * max(spacings) * (1 - 1e-9):
        raise ValueError(
            f"S-filter nesting index {s_filter_m:g} m is shorter than two sampling "
            f"intervals ({2 * max(spacings):g} m)"
        )
    if l_filter_m is not None and l_filter_m > size * (1 + 1e-9):
        raise ValueError(f"L-filter nesting index {l_filter_m:g} m is longer than the scan ({size:g} m)")
    z, bad = obj.heights_m, obj.unmeasured
    if s_filter_m is not None:
        z = gaussian_lowpass(z, spacings, s_filter_m, bad)
    if l_filter_m is not None:
        z = z - gaussian_lowpass(z, spacings, l_filter_m, bad)
    return obj.with_heights(z, unmeasured=bad)
