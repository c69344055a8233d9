"""Band-wise reading of large maps: bands of consecutive rows, and the measured heights' range.

Every grid-sized pass of roadscan (levelling, the FFT step, ring bookkeeping, roughness sums,
the fill's statistics, the input checks of ``pipelines.checks.validate``) reads a map in bands of
rows of about :data:`CHUNK_BYTES` of float64, so its temporaries stay in cache and its peak
memory is a band's, not the map's. This module is their one home.

Reference: the memory measurements in ``benchmarks/bench_scale.py``.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "row_chunks",
    "measured_stats",
    "measured_mean_range",
    "MeasuredStats",
    "CHUNK_BYTES",
    "gap_neighbours",
]

#: rows per chunk of the grid-sized passes: about 2 MiB of float64 per chunk, so temporaries
#: stay in cache and the peak memory does not grow with the map
CHUNK_BYTES = 1 << 21


def row_chunks(ny: int, nx: int, chunk_bytes: int = CHUNK_BYTES) -> list[slice]:
    """Slices of consecutive rows, each about ``chunk_bytes`` of float64.

    A band holds ``max(1, chunk_bytes // (8 nx))`` rows of an (ny, nx) grid; the last one
    may be shorter.

    Parameters
    ----------
    ny, nx : int
        Grid shape.
    chunk_bytes : int, optional
        Target size of a band of float64 rows [bytes].

    Returns
    -------
    list of slice
        Consecutive row ranges covering ``0 .. ny``.
    """
    step = max(1, chunk_bytes // (8 * max(nx, 1)))
    return [slice(r, min(r + step, ny)) for r in range(0, ny, step)]


class MeasuredStats(NamedTuple):
    """Number, minimum, maximum [m] and (when asked for) sum [m] of the measured heights.

    Attributes
    ----------
    count : int
        Number of measured heights.
    min, max : float
        Smallest and largest measured height [m].
    sum : float or None
        Sum of the measured heights [m], when asked for.
    """

    count: int  # type: ignore[assignment]  # a field named as tuple.count, which it hides
    min: float
    max: float
    sum: float | None = None

    @property
    def mean(self) -> float:
        """sum / count [m] (needs ``with_sum=True``)."""
        if self.sum is None:
            raise ValueError("the mean needs measured_stats(..., with_sum=True)")
        return self.sum / self.count


def measured_stats(
    h: NDArray[np.floating[Any]],
    unmeasured: NDArray[np.bool_] | None = None,
    chunk_bytes: int = CHUNK_BYTES,
    with_sum: bool = False,
) -> MeasuredStats:
    """Count, min, max (and sum) of the finite heights not marked ``unmeasured``, band by band.

    Parameters
    ----------
    h : array [m]
        A map (ny, nx), a profile (n,) or any array (read as rows of its first axis).
    unmeasured : bool array of ``h``'s shape, optional
        Points to leave out besides the non-finite ones.
    chunk_bytes : int
        Size of a band of rows (:func:`row_chunks`).
    with_sum : bool
        Also the sum (float64, each band's measured points summed as a copy, then the
        bands in order); min and max never copy the band.

    Returns
    -------
    MeasuredStats
        ``count`` 0 with min +inf and max -inf when nothing is measured.
    """
    h2 = h.reshape(1, -1) if h.ndim == 1 else h.reshape(h.shape[0], -1)
    m2 = None if unmeasured is None else np.asarray(unmeasured, dtype=bool).reshape(h2.shape)
    n, lo, hi, total = 0, np.inf, -np.inf, 0.0
    for sl in row_chunks(*h2.shape, chunk_bytes=chunk_bytes):
        band = h2[sl]
        ok = np.isfinite(band)
        if m2 is not None:
            ok &= ~m2[sl]
        k = int(np.count_nonzero(ok))
        if k:
            n += k
            lo = min(lo, float(np.min(band, where=ok, initial=np.inf)))
            hi = max(hi, float(np.max(band, where=ok, initial=-np.inf)))
            if with_sum:
                total += band[ok].sum()
    return MeasuredStats(n, lo, hi, total if with_sum else None)


def measured_mean_range(
    h: NDArray[np.floating[Any]], unmeasured: NDArray[np.bool_]
) -> tuple[float, float, float]:
    """(mean, min, max) [m] of the measured heights of a map, read band by band (float64):
    the reference and the clip range of the biharmonic fill (:mod:`roadscan.inpaint`).

    Parameters
    ----------
    h : ndarray
        Heights [m].
    unmeasured : ndarray of bool
        Points not measured.

    Returns
    -------
    mean, min, max : float
        Of the measured heights [m].
    """
    s = measured_stats(h, unmeasured, with_sum=True)
    return s.mean, s.min, s.max


def gap_neighbours(at: NDArray[np.integer[Any]], size: int) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """For each flattened index in ``at`` (sorted, the unmeasured points of a map of ``size``
    points), the previous and the next index not in ``at`` (the measured points around its run
    of consecutive unmeasured points): -1 before the first, ``size`` after the last. Found on
    the unmeasured points only (their runs), not on every measured point.

    Parameters
    ----------
    at : ndarray of int, shape (k,), k >= 1
        Sorted flattened indices of the unmeasured points.
    size : int
        Number of points of the map.

    Returns
    -------
    p, q : ndarray of int, shape (k,)
        Previous and next measured index of each.
    """
    first = np.empty(at.size, dtype=bool)  # a run of consecutive indices starts
    first[0] = True
    np.not_equal(at[1:], at[:-1] + 1, out=first[1:])
    last = np.empty_like(first)
    last[-1] = True
    last[:-1] = first[1:]
    p = np.maximum.accumulate(np.where(first, at - 1, -1))
    q = np.minimum.accumulate(np.where(last, at + 1, size)[::-1])[::-1]
    return p, q
