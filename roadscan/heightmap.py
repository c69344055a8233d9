"""Height maps and line profiles: the two measured objects roadscan works on.

Heights are in metres, spacings in metres. Unmeasured points (instrument dropouts) are
carried explicitly: ``heights_m`` holds NaN there and ``unmeasured`` is True there; the two
are kept consistent by the constructors.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["HeightMap", "Profile", "require_filled"]


def _clean(heights, unmeasured):
    h = np.array(heights, dtype=np.float64, copy=True)
    bad = ~np.isfinite(h)
    if unmeasured is not None:
        bad |= np.asarray(unmeasured, dtype=bool)
    h[bad] = np.nan
    return h, bad


_M = TypeVar("_M", bound="_Measured")


class _Measured:
    """What height maps and profiles share: the measured fraction and copying with new heights."""

    heights_m: NDArray[np.float64]
    unmeasured: NDArray[np.bool_]

    @property
    def measured_fraction(self) -> float:
        """Fraction of points the instrument measured."""
        return float(1.0 - self.unmeasured.mean())

    def _settle(self, what, ndim, spacings, too_small):
        """The constructors' common part: heights copied to float64 with NaN exactly where
        unmeasured; checked in turn: the dimension, the size (``too_small(h)``: a complaint
        or None), the spacings [m] and at least one measured point."""
        h, bad = _clean(self.heights_m, self.unmeasured)
        if h.ndim != ndim:
            raise ValueError(f"{what} must be {ndim}D, got shape {h.shape}")
        small = too_small(h)
        if small:
            raise ValueError(f"{what} {small}")
        values = [getattr(self, k) for k in spacings]
        _check_spacing(*values)
        if bad.all():
            raise ValueError(f"{what} has no measured points")
        object.__setattr__(self, "heights_m", h)
        object.__setattr__(self, "unmeasured", bad)
        for k, v in zip(spacings, values):
            object.__setattr__(self, k, float(v))

    def with_heights(
        self: _M, heights_m: ArrayLike, unmeasured: ArrayLike | None = None, **changes: Any
    ) -> _M:
        """A copy with new heights (same spacing, name, meta unless changed)."""
        if unmeasured is None:
            unmeasured = self.unmeasured
        # every subclass is a dataclass (HeightMap, Profile), which mypy cannot see on the base
        return replace(self, heights_m=heights_m, unmeasured=unmeasured, **changes)  # type: ignore[type-var]

    def _adopt(self, heights_m, unmeasured=None, meta=None):
        """A copy that takes ``heights_m`` as is: no copy, no scan for non-finite values.

        For roadscan's own steps that build a fresh float64 array of this shape with NaN
        exactly where ``unmeasured`` is True (the caller guarantees it); ``unmeasured``
        defaults to this object's mask, shared, not copied. Saves the constructor's copy and
        its full passes over the map (big scans).
        """
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        object.__setattr__(new, "heights_m", heights_m)
        object.__setattr__(new, "unmeasured", self.unmeasured if unmeasured is None else unmeasured)
        if meta is not None:
            object.__setattr__(new, "meta", meta)
        return new


def _check_spacing(*spacings):
    for s in spacings:
        if not (np.isfinite(s) and s > 0):
            raise ValueError(f"spacing must be positive and finite, got {s!r}")


@dataclass(frozen=True, eq=False)
class HeightMap(_Measured):
    """Heights on a regular grid.

    Parameters
    ----------
    heights_m : (ny, nx) array
        Heights [m]; rows run along y, columns along x. NaN where unmeasured.
    dx_m, dy_m : float
        Spacing along x (columns) and y (rows) [m].
    unmeasured : (ny, nx) bool array, optional
        True where the instrument did not measure. Derived from NaNs when omitted.
    name : str
        A label (usually the file stem).
    meta : dict
        Free-form provenance (source file, units read, instrument...).
    """

    heights_m: NDArray[np.float64]
    dx_m: float
    dy_m: float
    # None (derived from the NaNs) is accepted; after construction it is always the bool mask
    unmeasured: NDArray[np.bool_] = None  # type: ignore[assignment]
    name: str = ""
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        self._settle(
            "height map",
            2,
            ("dx_m", "dy_m"),
            lambda h: f"too small: shape {h.shape}" if min(h.shape) < 2 else None,
        )

    @property
    def shape(self) -> tuple[int, int]:
        """(ny, nx): rows and columns of the grid."""
        return self.heights_m.shape

    @property
    def nx(self) -> int:
        """Points along x (columns)."""
        return self.heights_m.shape[1]

    @property
    def ny(self) -> int:
        """Points along y (rows)."""
        return self.heights_m.shape[0]

    @property
    def size_m(self) -> tuple[float, float]:
        """(L_x, L_y) = (nx dx, ny dy) [m]."""
        return self.nx * self.dx_m, self.ny * self.dy_m

    def x_m(self) -> NDArray[np.float64]:
        """Positions of the columns, x = i dx [m] (i = 0 .. nx-1)."""
        return np.arange(self.nx, dtype=np.float64) * self.dx_m

    def y_m(self) -> NDArray[np.float64]:
        """Positions of the rows, y = j dy [m] (j = 0 .. ny-1)."""
        return np.arange(self.ny, dtype=np.float64) * self.dy_m


@dataclass(frozen=True, eq=False)
class Profile(_Measured):
    """Heights along a line (a road texture laser's output).

    Parameters
    ----------
    heights_m : (n,) array
        Heights [m], NaN where unmeasured (dropouts).
    dx_m : float
        Sampling interval [m].
    unmeasured : (n,) bool array, optional
    name, meta : as for HeightMap.
    """

    heights_m: NDArray[np.float64]
    dx_m: float
    # None (derived from the NaNs) is accepted; after construction it is always the bool mask
    unmeasured: NDArray[np.bool_] = None  # type: ignore[assignment]
    name: str = ""
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        self._settle("profile", 1, ("dx_m",), lambda h: f"too short: {h.size} points" if h.size < 4 else None)

    @property
    def n(self) -> int:
        """Number of points."""
        return self.heights_m.size

    @property
    def length_m(self) -> float:
        """Length n dx [m]."""
        return self.n * self.dx_m

    def x_m(self) -> NDArray[np.float64]:
        """Positions x = i dx [m] (i = 0 .. n-1)."""
        return np.arange(self.n, dtype=np.float64) * self.dx_m


def require_filled(obj: HeightMap | Profile, fill_values: ArrayLike | None = None) -> None:
    """Refuse a map or profile with unmeasured points before an FFT (ValueError, one line).

    With ``fill_values`` (one finite height per unmeasured point, raster order, as
    :func:`roadscan.inpaint.unmeasured_fill` gives them) the map counts as filled.

    Parameters
    ----------
    obj : HeightMap or Profile
        The scan.
    fill_values : ndarray, optional
        Heights for its unmeasured points.

    Returns
    -------
    None
        Raises ValueError when points are unmeasured and not filled.
    """
    if fill_values is not None:
        n = int(np.count_nonzero(obj.unmeasured))
        if np.shape(fill_values) != (n,) or not np.isfinite(fill_values).all():
            raise ValueError(f"fill_values must be {n} finite heights (one per unmeasured point)")
        return
    if obj.unmeasured.any():
        raise ValueError(
            f"{obj.name or type(obj).__name__}: {int(obj.unmeasured.sum())} unmeasured "
            "points; fill them first (roadscan.inpaint.fill_unmeasured)"
        )
