"""Small signal-processing helpers written on numpy alone, so that importing roadscan does not
load ``scipy.signal`` (about a second of start-up on a busy 2-core machine).

Each function reproduces the scipy.signal function named in its docstring to float round-off
(checked against scipy.signal in ``tests/test_windows.py``).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["tukey", "tukey_cached", "butter2_lowpass", "filtfilt2"]


def tukey(n: int, alpha: float = 0.5) -> NDArray[np.float64]:
    """Symmetric Tukey (tapered cosine) window of ``n`` points, as ``scipy.signal.windows.tukey``.

    w[k] = 1/2 (1 + cos(pi (2 k / (alpha (n - 1)) - 1))) for k <= alpha (n - 1) / 2, 1 in the
    middle, mirrored at the end; alpha <= 0 is rectangular, alpha >= 1 the Hann window.

    Parameters
    ----------
    n : int
        Points.
    alpha : float, optional
        Taper fraction.

    Returns
    -------
    ndarray, shape (n,)
        The window.
    """
    n = int(n)
    if n <= 0:
        return np.ones(0)
    if n == 1 or alpha <= 0:
        return np.ones(n)
    if alpha >= 1.0:
        return 0.5 + 0.5 * np.cos(np.linspace(-np.pi, np.pi, n))
    k = np.arange(n)
    width = int(np.floor(alpha * (n - 1) / 2.0))
    k1, k3 = k[: width + 1], k[n - width - 1 :]
    w = np.ones(n)
    w[: width + 1] = 0.5 * (1 + np.cos(np.pi * (-1 + 2.0 * k1 / alpha / (n - 1))))
    w[n - width - 1 :] = 0.5 * (1 + np.cos(np.pi * (-2.0 / alpha + 1 + 2.0 * k3 / alpha / (n - 1))))
    return w


@lru_cache(maxsize=16)
def tukey_cached(n: int, alpha: float) -> NDArray[np.float64]:
    """:func:`tukey` (``alpha`` <= 0: rectangular), cached and read-only: the spectra window
    the same grid sizes again and again.

    Parameters
    ----------
    n : int
        Points.
    alpha : float
        Taper fraction.

    Returns
    -------
    ndarray, shape (n,)
        The window (read-only).
    """
    w = tukey(n, alpha) if alpha > 0 else np.ones(n)
    w.setflags(write=False)
    return w


def butter2_lowpass(wn: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Second-order Butterworth low-pass, digital (bilinear transform with pre-warping).

    ``wn`` is the cut-off as a fraction of the Nyquist frequency (0 < wn < 1), as in
    ``scipy.signal.butter(2, wn)``. With K = tan(pi wn / 2):
    b = K^2 (1, 2, 1) / D, a = (1, 2 (K^2 - 1) / D, (1 - sqrt2 K + K^2) / D), D = 1 + sqrt2 K + K^2.

    Returns
    -------
    b, a : (3,) arrays (a[0] = 1)

    Parameters
    ----------
    wn : float
        Cut-off as a fraction of Nyquist.
    """
    if not 0 < wn < 1:
        raise ValueError(f"cut-off must be within (0, 1) of Nyquist, got {wn}")
    K = np.tan(np.pi * wn / 2.0)
    s2 = np.sqrt(2.0)
    D = 1.0 + s2 * K + K * K
    b0 = K * K / D
    return (
        np.array([b0, 2.0 * b0, b0]),
        np.array([1.0, 2.0 * (K * K - 1.0) / D, (1.0 - s2 * K + K * K) / D]),
    )


def _lfilter2(b, a, x, z0, z1):
    """Direct form II transposed, second order, along the last axis (vectorised over rows)."""
    b0, b1, b2 = b
    _, a1, a2 = a
    y = np.empty_like(x)
    for i in range(x.shape[-1]):
        xi = x[..., i]
        yi = b0 * xi + z0
        z0 = b1 * xi - a1 * yi + z1
        z1 = b2 * xi - a2 * yi
        y[..., i] = yi
    return y


def filtfilt2(b: NDArray[np.float64], a: NDArray[np.float64], x: ArrayLike) -> NDArray[np.float64]:
    """Zero-phase forward-backward filter of a second-order section along the last axis, as
    ``scipy.signal.sosfiltfilt`` (and ``filtfilt``) with their defaults: odd extension by
    9 = 3 (2 + 1) samples at each end and the steady-state initial conditions scaled by the
    first sample of each pass. Needs more than 9 samples.

    Parameters
    ----------
    b, a : ndarray, shape (3,)
        Filter coefficients.
    x : ndarray
        Signal, filtered along the last axis.

    Returns
    -------
    ndarray
        The filtered signal.
    """
    x = np.asarray(x, dtype=np.float64)
    pad = 9
    if x.shape[-1] <= pad:
        raise ValueError(f"need more than {pad} samples, got {x.shape[-1]}")
    left = 2 * x[..., :1] - x[..., pad:0:-1]
    right = 2 * x[..., -1:] - x[..., -2 : -pad - 2 : -1]
    ext = np.concatenate([left, x, right], axis=-1)
    # steady state: (I - A^T) zi = b[1:] - a[1:] b[0], A the companion matrix of a
    M = np.array([[1.0 + a[1], -1.0], [a[2], 1.0]])
    zi = np.linalg.solve(M, b[1:] - a[1:] * b[0])
    x0 = ext[..., 0]
    y = _lfilter2(b, a, ext, zi[0] * x0, zi[1] * x0)
    y = y[..., ::-1]
    y0 = y[..., 0]
    y = _lfilter2(b, a, y, zi[0] * y0, zi[1] * y0)
    return y[..., ::-1][..., pad:-pad]
