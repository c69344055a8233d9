"""Shared pieces of the readers: units, spacings, regular grids, and turning bad input into
:class:`roadscan.errors.InputError`.

Conventions (all readers)
-------------------------
- Heights are returned in metres; spacings are metres.
- ``units`` is the unit of the heights of a file that carries no units of its own
  ("m", "mm", "um" or "nm"); a file that states its units (X3P, Gwyddion, CAPTIF, vendor
  formats) is read in its own units; a contradicting ``units`` follows :mod:`roadscan.io.calibration`.
  The x (and y) columns of a text file without unit titles are in ``units`` too, a reading
  checked by :mod:`roadscan.io.text_units`.
- ``spacing`` is ``None``, a number DX (then DY = DX), a pair (DX, DY), or the CLI string
  ``"DX"`` / ``"DX,DY"``, always in metres.

The size limits (largest scan, zip-bomb guard) live in ``roadscan.io._size_limits`` and are
re-exported here.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..errors import InputError, OptionNote
from ..heightmap import HeightMap, Profile
from ._size_limits import (
    check_compression_ratio,
    check_declared_size,
    default_max_pixels,
    get_max_pixels,
    set_max_pixels,
)

__all__ = [
    "UNIT_FACTORS",
    "parse_units",
    "unit_factor",
    "parse_spacing",
    "resolve_spacing",
    "check_file",
    "make_heightmap",
    "make_profile",
    "regular_axis",
    "NO_SPACING",
    "default_max_pixels",
    "get_max_pixels",
    "set_max_pixels",
    "check_declared_size",
    "check_compression_ratio",
]

#: metres per unit of the heights
UNIT_FACTORS = {
    "m": 1.0,
    "mm": 1e-3,
    "um": 1e-6,
    "µm": 1e-6,
    "μm": 1e-6,
    "micron": 1e-6,
    "nm": 1e-9,
}

NO_SPACING = OptionNote("no spacing: pass {spacing} DX[,DY] in metres", "spacing")


def parse_units(text, path=None):
    """Metres per unit of a units string: "m" -> 1, "mm" -> 1e-3, "um" -> 1e-6, "nm" -> 1e-9.

    Raises
    ------
    InputError
        For any other string (naming ``path`` when given).

    Parameters
    ----------
    text : str
        ``"m"``, ``"mm"``, ``"um"`` or ``"nm"``.
    path : str or Path, optional
        File named in the error.

    Returns
    -------
    float
        Metres per unit.
    """
    key = str(text).strip()
    if key in UNIT_FACTORS:
        return UNIT_FACTORS[key]
    if key.lower() in UNIT_FACTORS:
        return UNIT_FACTORS[key.lower()]
    raise InputError(path, f"unknown units {text!r}: use m, mm, um or nm")


def unit_factor(units, path=None, default="m"):
    """Like :func:`parse_units`, with ``None`` meaning ``default``.

    Parameters
    ----------
    units : str or None
        Units string, or None for ``default``.
    path : str or Path, optional
        File named in the error.
    default : str, optional
        Unit when ``units`` is None.

    Returns
    -------
    float
        Metres per unit.
    """
    return parse_units(default if units is None else units, path)


def _positive(value, path, what):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(path, f"{what} {value!r} is not a number") from None
    if not np.isfinite(v) or v <= 0:
        raise InputError(path, f"{what} must be positive and finite, got {value!r}")
    return v


def parse_spacing(text, path=None):
    """Parse the CLI spacing ``"DX"`` or ``"DX,DY"`` [m] into ``(dx_m, dy_m)``.

    A single number gives a square grid (DY = DX). Non-numeric or non-positive values raise
    :class:`InputError`.

    Parameters
    ----------
    text : str
        ``"DX"`` or ``"DX,DY"`` in metres.
    path : str or Path, optional
        File named in the error.

    Returns
    -------
    tuple of float
        (dx_m, dy_m).
    """
    parts = [p for p in str(text).replace(";", ",").split(",")]
    if len(parts) not in (1, 2) or any(not p.strip() for p in parts):
        raise InputError(path, f"bad spacing {text!r}: use DX or DX,DY in metres")
    vals = [_positive(p.strip(), path, "spacing") for p in parts]
    return (vals[0], vals[-1])


def resolve_spacing(spacing, path=None):
    """Normalise the ``spacing`` argument of the readers to ``None`` or ``(dx_m, dy_m)``.

    Parameters
    ----------
    spacing : None, float, tuple or str
        As the readers take it.
    path : str or Path, optional
        File named in the error.

    Returns
    -------
    tuple of float or None
        (dx_m, dy_m).
    """
    if spacing is None:
        return None
    if isinstance(spacing, str):
        return parse_spacing(spacing, path)
    if np.ndim(spacing) == 0:
        v = _positive(spacing, path, "spacing")
        return (v, v)
    vals = list(np.ravel(spacing))
    if len(vals) not in (1, 2):
        raise InputError(path, f"bad spacing {spacing!r}: give DX or (DX, DY) in metres")
    vals = [_positive(v, path, "spacing") for v in vals]
    return (vals[0], vals[-1])


def check_file(path):
    """Raise :class:`InputError` unless ``path`` is an existing, non-empty regular file.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    Path
        The path.
    """
    p = Path(path)
    if not p.exists():
        raise InputError(path, "no such file")
    if p.is_dir():
        raise InputError(path, "is a directory, not a height file")
    if not os.access(p, os.R_OK):
        raise InputError(path, "permission denied")
    if p.stat().st_size == 0:
        raise InputError(path, "empty file")
    return p


def make_heightmap(path, heights_m, dx_m, dy_m, unmeasured=None, meta=None):
    """Build a :class:`HeightMap`, turning shape/NaN/spacing problems into :class:`InputError`.

    Parameters
    ----------
    path : str or Path
        The file read (for messages and the name).
    heights_m : ndarray
        Heights [m], NaN unmeasured.
    dx_m, dy_m : float
        Spacings [m].
    unmeasured : ndarray of bool, optional
        Mask of unmeasured points.
    meta : dict, optional
        Reader metadata.

    Returns
    -------
    HeightMap
    """
    h = np.asarray(heights_m)
    if h.ndim != 2:
        raise InputError(path, f"expected a 2D height array, got shape {h.shape}")
    if h.size and not np.issubdtype(h.dtype, np.number) and h.dtype != bool:
        raise InputError(path, f"heights are not numbers (dtype {h.dtype})")
    if np.iscomplexobj(h):
        raise InputError(path, "heights are complex numbers")
    h = h.astype(np.float64, copy=False)
    bad = ~np.isfinite(h)
    if unmeasured is not None:
        bad = bad | np.asarray(unmeasured, dtype=bool)
    if h.size and bad.all():
        raise InputError(path, "no measured points (all heights NaN or masked)")
    try:
        return HeightMap(
            h,
            dx_m,
            dy_m,
            unmeasured=unmeasured,
            name=Path(path).stem,
            meta={"source": str(path), **(meta or {})},
        )
    except ValueError as exc:
        raise InputError(path, str(exc)) from None


def make_profile(path, heights_m, dx_m, unmeasured=None, meta=None):
    """Build a :class:`Profile`, turning problems into :class:`InputError`.

    Parameters
    ----------
    path : str or Path
        The file read.
    heights_m : ndarray
        Heights [m], NaN unmeasured.
    dx_m : float
        Spacing [m].
    unmeasured : ndarray of bool, optional
        Mask of unmeasured points.
    meta : dict, optional
        Reader metadata.

    Returns
    -------
    Profile
    """
    h = np.asarray(heights_m, dtype=np.float64)
    bad = ~np.isfinite(h)
    if unmeasured is not None:
        bad = bad | np.asarray(unmeasured, dtype=bool)
    if h.size and bad.all():
        raise InputError(path, "no measured points (all heights NaN)")
    try:
        return Profile(
            h, dx_m, unmeasured=unmeasured, name=Path(path).stem, meta={"source": str(path), **(meta or {})}
        )
    except ValueError as exc:
        raise InputError(path, str(exc)) from None


def regular_axis(x, path=None, what="x", tol=0.25):
    """Place sorted, distinct coordinates on a regular grid.

    The coordinates may miss some grid nodes (gaps of several steps) and carry rounding noise
    from printing (e.g. 0.0375 mm printed as 0.037 or 0.038). The step is estimated from the
    smallest gap, each gap is rounded to a whole number of steps, and the step is then refined by
    least squares of x against the node index, twice.

    Parameters
    ----------
    x : (n,) array, strictly increasing
    tol : float
        Largest accepted distance of a coordinate from its grid node, in steps.

    Returns
    -------
    x0 : float
        Coordinate of node 0.
    dx : float
        Step (same units as ``x``).
    index : (n,) int array
        Node of each coordinate; ``index[-1] + 1`` is the number of nodes.

    Raises
    ------
    InputError
        Fewer than 2 values, repeated values, values off a regular grid, or values that would
        fill under half of the grid's nodes (scattered values fit a fine enough grid).
    """
    x = np.asarray(x, dtype=np.float64)
    if x.size < 2:
        raise InputError(path, f"need at least 2 distinct {what} values, got {x.size}")
    if not np.all(np.isfinite(x)):
        raise InputError(path, f"{what} coordinates contain NaN or infinity")
    gaps = np.diff(x)
    if np.any(gaps <= 0):
        raise InputError(path, f"{what} coordinates repeat or are not increasing")
    dx = gaps.min()
    for _ in range(3):
        steps = np.rint(gaps / dx).astype(np.int64)
        if np.any(steps < 1):
            raise InputError(path, f"{what} coordinates are not on a regular grid")
        index = np.concatenate([[0], np.cumsum(steps)])
        if index[-1] + 1 > 2 * x.size:
            raise InputError(
                path,
                f"{what} coordinates are not on a regular grid "
                f"({x.size} values would fill under half of {index[-1] + 1} nodes)",
            )
        dx, x0 = np.polyfit(index.astype(np.float64), x, 1)
        if not dx > 0:
            raise InputError(path, f"{what} coordinates are not on a regular grid")
    resid = np.abs(x - (x0 + dx * index))
    if resid.max() > tol * dx:
        raise InputError(
            path, f"{what} coordinates are not on a regular grid (off by {resid.max() / dx:.2f} steps)"
        )
    return float(x0), float(dx), index
