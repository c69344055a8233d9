"""The size limits of the readers: the largest scan a reader accepts (from the available memory
or the ``max_pixels`` option) and the zip-bomb guard, both checked before any array is allocated.

:mod:`roadscan.io._common` re-exports every public name here; the limit is one per process
(:func:`set_max_pixels`, :func:`get_max_pixels`).
"""

from __future__ import annotations

import os

import numpy as np

from ..errors import InputError

__all__ = [
    "PEAK_COPIES",
    "default_max_pixels",
    "get_max_pixels",
    "set_max_pixels",
    "check_declared_size",
    "check_compression_ratio",
]

#: peak memory of an analysis in float64 copies of the scan (at most 6x; margin 8x)
PEAK_COPIES = 8
_MAX_PIXELS = None  # None -> default_max_pixels()


def _available_bytes():
    """Available memory [bytes]: ``MemAvailable`` of /proc/meminfo, else physical pages."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 8 * 1024**3


def default_max_pixels():
    """Largest scan [points] read by default: the available memory over the peak of an analysis,
    ``MemAvailable / (8 bytes x PEAK_COPIES)`` (about 380 Mpx on a machine with 24 GiB free),
    never below 4 Mpx.

    Parameters
    ----------
    None

    Returns
    -------
    int
        Points.
    """
    return max(int(_available_bytes() // (8 * PEAK_COPIES)), 4 * 1024**2)


def get_max_pixels():
    """The current limit [points] (set by ``--max-pixels``; ``None`` means the default).

    Parameters
    ----------
    None

    Returns
    -------
    int or None
        Points, or None for the memory-based default.
    """
    return _MAX_PIXELS


def set_max_pixels(n):
    """Set the reader size limit [points]; ``None`` restores the memory-based default.

    Parameters
    ----------
    n : int or None
        Largest number of points a reader accepts.

    Returns
    -------
    None
    """
    global _MAX_PIXELS
    _MAX_PIXELS = None if n is None else int(n)


def check_declared_size(path, shape, itemsize=8):
    """Refuse, before allocating, a file whose declared size exceeds the limit.

    Parameters
    ----------
    shape : tuple of int or int
        The array shape (or number of points) the file's header declares.
    itemsize : int
        Bytes per point as stored (for the message only).

    Raises
    ------
    InputError
        Negative dimensions, or more points than :func:`get_max_pixels` (default
        :func:`default_max_pixels`), naming the file, the shape and ``--max-pixels``.

    Returns
    -------
    int
        The number of points declared.
    """
    dims = tuple(int(d) for d in np.atleast_1d(shape))
    if any(d < 0 for d in dims):
        raise InputError(path, f"declares a negative size {dims}")
    n = 1
    for d in dims:
        n *= d
    limit = _MAX_PIXELS if _MAX_PIXELS is not None else default_max_pixels()
    if n > limit:
        shape_txt = " x ".join(str(d) for d in dims)
        raise InputError(
            path,
            f"declares {shape_txt} = {n:.3g} points ({n * itemsize / 1e9:.3g} GB), "
            f"above the limit of {limit:.3g} points; raise it with {{max_pixels}} N "
            f"if the machine has the memory",
            "max_pixels",
        )
    return n


def check_compression_ratio(path, declared_bytes, stored_bytes, max_ratio=200.0):
    """Zip-bomb guard: refuse data that claim ``declared_bytes`` uncompressed from only
    ``stored_bytes`` on disk, beyond ``max_ratio`` (real height data compress 2-10x; a scan of
    constant zeros compresses ~1000x), unless the declared size is small (< 64 MiB).

    Parameters
    ----------
    path : str or Path
        File named in the error.
    declared_bytes : int
        Uncompressed size the file declares.
    stored_bytes : int
        Size on disk.
    max_ratio : float, optional
        Largest accepted ratio.

    Returns
    -------
    None
        Raises :class:`roadscan.InputError` beyond the ratio.
    """
    if declared_bytes > 64 * 1024**2 and declared_bytes > max_ratio * max(int(stored_bytes), 1):
        ratio = declared_bytes / max(stored_bytes, 1)
        raise InputError(
            path,
            f"declares {declared_bytes / 1e6:.4g} MB of data stored in "
            f"{stored_bytes / 1e6:.3g} MB (ratio {ratio:.0f}): "
            f"refused as a likely zip bomb",
        )
