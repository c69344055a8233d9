"""The FFT behind roadscan's spectra: numpy's for small maps, scipy's on every core for large ones.

Both are pocketfft (the same transform to round-off, checked in ``tests/test_spectrum.py``);
numpy's needs no ``scipy.fft`` import, which took 0.28 s (scipy 1.17), more than the whole
FFT of a 4 Mpx map, while scipy's runs on every core (``workers=-1``) and transforms in place.

Reference: M. Reinecke, pocketfft (numpy.fft and scipy.fft since numpy 1.17 / scipy 1.4).
"""

from __future__ import annotations

import numpy as np

__all__ = ["fft_backend", "NUMPY_FFT_MAX_POINTS"]

_WORKERS = -1
#: maps of up to this many points are transformed with numpy's FFT (pocketfft, one thread):
#: importing ``scipy.fft`` took 0.28 s (scipy 1.17), more than the whole FFT of such a map;
#: larger maps use ``scipy.fft`` (the same pocketfft) on every core
NUMPY_FFT_MAX_POINTS = 1 << 22


class _NumpyFFT:
    """numpy.fft for small maps (no scipy import)."""

    name = "numpy.fft"

    @staticmethod
    def rfft(x, axis=-1):
        return np.fft.rfft(x, axis=axis)

    @staticmethod
    def fft(F, axis):
        return np.fft.fft(F, axis=axis)

    @staticmethod
    def rfft2(x):
        return np.fft.rfft2(x)


class _ScipyFFT:
    """scipy.fft with every core (``workers=-1``) for large maps."""

    name = f"scipy.fft (workers={_WORKERS})"

    @staticmethod
    def rfft(x, axis=-1):
        import scipy.fft as sfft

        return sfft.rfft(x, axis=axis, workers=_WORKERS)

    @staticmethod
    def fft(F, axis):
        import scipy.fft as sfft

        return sfft.fft(F, axis=axis, overwrite_x=True, workers=_WORKERS)  # in place

    @staticmethod
    def rfft2(x):
        import scipy.fft as sfft

        return sfft.rfft2(x, workers=_WORKERS)


def fft_backend(npoints: int) -> type[_NumpyFFT] | type[_ScipyFFT]:
    """The FFT used for ``npoints`` samples: numpy's up to :data:`NUMPY_FFT_MAX_POINTS`,
    scipy's with every core above (``.rfft(x, axis)``, ``.rfft2(x)``, ``.fft(F, axis)``, in place
    for scipy);
    :mod:`benchmarks.bench_psd` takes its floor from the same one.

    Parameters
    ----------
    npoints : int
        Number of samples of the transform.

    Returns
    -------
    class
        An object with ``rfft``, ``rfft2`` and ``fft`` static methods.
    """
    return _NumpyFFT if npoints <= NUMPY_FFT_MAX_POINTS else _ScipyFFT
