"""Rain fill: the surface that sliding rubber feels when water fills the road's cavities.

Thesis section 4.4 and docs: Theory. Water fills every local depression of the height
map that is not connected to the border up to its spill level (Matlab's ``imfill`` on a
grayscale image). That is grayscale morphological reconstruction by erosion, seeded from the
border,

    F = R^epsilon_h(s),   s = h on the border, s = max(h) inside,

i.e. ``skimage.morphology.reconstruction(s, h, method="erosion", footprint=...)``: F is the
smallest function >= h whose only regional minima touch the border. The water depth is
``F - h`` and the wet surface is ``F``.

Connectivity: 4 (a cross footprint; Matlab's default in 2D, and ours) or 8 (a 3x3 footprint;
scikit-image's default). Water escapes diagonally between two touching peaks only with 8, so
8-connected filling is never higher than 4-connected filling.

Limited water (beyond the thesis):

- ``max_depth_m = d``: every point's water level is ``min(F, m_k + d)``, where ``m_k`` is the
  lowest measured height of its depression ``k``; depressions are the connected components
  (same connectivity) of the measured points with ``F > h``.
- ``water_film_m = w`` (volume per area [m^3/m^2] = m): ``d`` is the smallest depth cap whose
  stored volume per area equals ``w``. The volume V(d) is piecewise linear and non-decreasing in
  d (each point contributes ``clip(m_k + d - h, 0, F - h)``), so d is found exactly from the
  sorted breakpoints. When w exceeds the capacity V(inf), every depression is full.

Unmeasured points (dropouts, NaN)
---------------------------------
They are treated as *transparent*: they have no height of their own, so they neither hold water
nor block it. Water passes through them at whatever level their measured surroundings allow
(in the reconstruction their height is set below every measured height), and a dropout on the
border lets water out at the level of its measured neighbours. Consequences:

- a dropout at the bottom of a pit (the usual case for optical profilers, which lose the
  signal in deep, steep cavities) does not drain the pit: the pit still fills to its measured
  rim;
- a dropout in a rim or ridge never invents a barrier: the water level across it is set by the
  measured points on either side, so water is never created by missing data (the fill is a
  lower bound with respect to the unknown heights);
- dropouts stay unmeasured: NaN in the wet map and in the depth map. The wetted fraction and the
  water volume per area are averages over the measured points only (the dropouts are assumed to
  behave like the measured surface); ``meta["measured_fraction"]`` says how much that is.

The depression labelling for the depth cap uses measured points only, so a pit cut in two by a
line of dropouts is capped from the lowest measured point of each part.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage

from .heightmap import HeightMap

__all__ = ["RainFill", "rain_fill", "full_fill", "footprint", "capped_levels", "FLOOD_MIN_POINTS"]


def footprint(connectivity: int) -> NDArray[np.bool_]:
    """Structuring element for 4- (cross) or 8- (3x3 square) connectivity.

    Parameters
    ----------
    connectivity : {4, 8}
        Neighbourhood.

    Returns
    -------
    ndarray of bool, shape (3, 3)
        The structuring element.
    """
    if connectivity == 4:
        return ndimage.generate_binary_structure(2, 1).astype(np.uint8)
    if connectivity == 8:
        return np.ones((3, 3), dtype=np.uint8)
    raise ValueError(f"connectivity must be 4 or 8, got {connectivity!r}")


#: below this many points the fill uses scikit-image by default: the compiled priority-flood is
#: 3 to 4x faster per call, but loading numba and its cached machine code costs about 0.6 s once
#: per process, more than scikit-image needs for a 1-Mpx scan (benchmarks/bench_rainfill.py).
FLOOD_MIN_POINTS = 2**21


def _flood_kernel():
    """The compiled priority-flood, or None when numba is not installed."""
    try:
        from . import _flood
    except ImportError:  # numba missing: the exact scikit-image path below
        return None
    return _flood.priority_flood_fill


def _flood_warm():

    mod = sys.modules.get("roadscan._flood")
    return mod is not None and bool(mod._flood.signatures)


def full_fill(
    heights_m: ArrayLike, connectivity: int = 4, method: Literal["auto", "flood", "reconstruction"] = "auto"
) -> NDArray[np.float64]:
    """Fill every depression to its spill level (grayscale ``imfill``).

    Parameters
    ----------
    heights_m : (ny, nx) float array
        Heights [m]; NaN marks unmeasured points, which are transparent (see module notes).
    connectivity : {4, 8}
    method : {"auto", "flood", "reconstruction"}
        ``"flood"``: the compiled priority-flood (Barnes, Lehman & Mulla 2014, with the plain
        queue of their Priority-Flood+; :mod:`roadscan._flood`, needs numba).
        ``"reconstruction"``: ``skimage.morphology.reconstruction`` (Robinson & Whelan's
        queue algorithm). Both give bit-identical results (every level is one of the heights).
        ``"auto"`` (default) takes the flood for maps of at least :data:`FLOOD_MIN_POINTS`
        points, or whenever it is already loaded in this process, and scikit-image otherwise
        or when numba is not installed.

    Returns
    -------
    filled : (ny, nx) float array
        Water level F >= h [m]; NaN where unmeasured. For a fully measured map this is exactly
        ``reconstruction(seed, h, method="erosion", footprint=footprint(connectivity))`` with
        ``seed = h`` on the border and ``max(h)`` inside.
    """
    h = np.asarray(heights_m, dtype=np.float64)
    if h.ndim != 2:
        raise ValueError(f"heights must be 2D, got shape {h.shape}")
    fp = footprint(connectivity)
    if method not in ("auto", "flood", "reconstruction"):
        raise ValueError(f"method must be 'auto', 'flood' or 'reconstruction', got {method!r}")
    kernel = None
    if method == "flood" or (method == "auto" and (h.size >= FLOOD_MIN_POINTS or _flood_warm())):
        kernel = _flood_kernel()
        if kernel is None and method == "flood":
            raise ImportError("rain fill method 'flood' needs numba (pip install numba)")
    bad = ~np.isfinite(h)
    any_bad = bool(bad.any())
    if kernel is not None:
        # unmeasured points read as -inf inside the kernel: below every measured height
        filled = kernel(h, -np.inf, connectivity)
    else:
        from skimage.morphology import reconstruction

        if any_bad:
            # transparent: below every measured height, so never a barrier and never a store
            lo, hi = np.nanmin(h), np.nanmax(h)
            mask = np.where(bad, lo - (hi - lo) - 1.0, h)
        else:
            mask = h
        seed = np.full_like(mask, mask.max())
        seed[0, :] = mask[0, :]
        seed[-1, :] = mask[-1, :]
        seed[:, 0] = mask[:, 0]
        seed[:, -1] = mask[:, -1]
        filled = reconstruction(seed, mask, method="erosion", footprint=fp)
    if any_bad:
        filled[bad] = np.nan
    return filled


def _depressions(h, filled, connectivity):
    """Label depressions (measured points with F > h); return labels, n, lowest height per label."""
    wet = np.isfinite(h) & (filled > h)
    labels, n = ndimage.label(wet, structure=footprint(connectivity))
    if n == 0:
        return labels, 0, np.zeros(1)
    lowest = ndimage.minimum(h, labels=labels, index=np.arange(1, n + 1))
    # index 0 (dry) -> +inf so a lookup through labels never caps dry points below h
    return labels, n, np.concatenate([[np.inf], np.asarray(lowest, dtype=np.float64)])


def capped_levels(
    h: NDArray[np.float64],
    filled: NDArray[np.float64],
    labels: NDArray[np.integer[Any]],
    lowest: NDArray[np.float64],
    max_depth_m: float,
) -> NDArray[np.float64]:
    """Water level min(F, m_k + d) on wet points, h elsewhere (NaN stays NaN).

    Parameters
    ----------
    h : ndarray
        Heights [m].
    filled : ndarray
        Spill levels F of the full fill [m].
    labels : ndarray of int
        Depression label of every point (0: dry).
    lowest : ndarray
        Lowest height m_k of each depression [m].
    max_depth_m : float
        Depth cap d [m].

    Returns
    -------
    ndarray
        Water levels [m].
    """
    cap = lowest[labels] + max_depth_m
    level = np.where(labels > 0, np.minimum(filled, cap), h)
    return np.maximum(level, h)  # points of a depression above m_k + d stay dry


def _cap_for_film(a, b, n_measured, film_m):
    """Smallest d >= 0 with sum_i clip(d - a_i, 0, b_i - a_i) / n_measured == film_m.

    V(d) * n = sum_i (d - a_i)_+ - (d - b_i)_+ is piecewise linear; evaluate it at the sorted
    breakpoints with cumulative sums and interpolate in the segment where it reaches the target.
    Returns (d, full) where full is True when film_m >= capacity.
    """
    target = film_m * n_measured
    capacity = float(np.sum(b - a))
    if target >= capacity:
        return float(np.max(b)) if b.size else 0.0, True
    if target <= 0:
        return 0.0, False
    A = np.sort(a)
    B = np.sort(b)
    cA = np.concatenate([[0.0], np.cumsum(A)])
    cB = np.concatenate([[0.0], np.cumsum(B)])
    t = np.unique(np.concatenate([A, B]))

    def V(x):
        ka = np.searchsorted(A, x, side="right")
        kb = np.searchsorted(B, x, side="right")
        return (ka * x - cA[ka]) - (kb * x - cB[kb])

    Vt = V(t)
    k = int(np.searchsorted(Vt, target, side="left"))  # first breakpoint with V >= target
    if k == 0:
        return float(t[0]), False
    x0, x1, v0, v1 = t[k - 1], t[k], Vt[k - 1], Vt[k]
    # slope on (x0, x1) = #(a <= x0) - #(b <= x0) > 0 since V rises there
    return float(x0 + (target - v0) * (x1 - x0) / (v1 - v0)), False


@dataclass(frozen=True, eq=False)
class RainFill:
    """Result of :func:`rain_fill`.

    Attributes
    ----------
    wet : HeightMap
        Wet surface max(h, water level) [m]; NaN where unmeasured.
    depth_m : (ny, nx) array
        Water depth [m]: 0 where dry, NaN where unmeasured.
    wetted_fraction : float
        Fraction of measured points under water (depth > 0).
    water_volume_m3_per_m2 : float
        Stored water per unit area [m^3/m^2] = mean depth over measured points.
    connectivity : int
        4 or 8.
    meta : dict
        ``max_depth_m`` (cap used, None for a full fill), ``water_film_m`` (requested),
        ``capacity_m3_per_m2`` (full-fill volume), ``all_full``, ``n_depressions``,
        ``measured_fraction``, ``unmeasured_policy``.
    """

    wet: HeightMap
    depth_m: np.ndarray
    wetted_fraction: float
    water_volume_m3_per_m2: float
    connectivity: int
    meta: dict = field(default_factory=dict)


def rain_fill(
    hm: HeightMap,
    connectivity: int = 4,
    max_depth_m: float | None = None,
    water_film_m: float | None = None,
    method: Literal["auto", "flood", "reconstruction"] = "auto",
) -> RainFill:
    """Fill the depressions of a height map with water (thesis section 4.4, docs: Theory).

    Parameters
    ----------
    hm : HeightMap
        Heights [m] (levelled or not: filling is invariant to a constant offset, not to tilt).
    connectivity : {4, 8}
        Neighbourhood through which water flows; 4 by default (Matlab imfill's default).
    max_depth_m : float, optional
        Depth cap d [m]: water level = min(spill level, lowest point of the depression + d).
    water_film_m : float, optional
        Water available per unit area w [m^3/m^2 = m]; d is the smallest cap whose stored volume
        per area equals w (all depressions full when w exceeds their capacity).
        At most one of ``max_depth_m`` and ``water_film_m``.
    method : {"auto", "flood", "reconstruction"}
        Algorithm of the full fill (identical results; see :func:`full_fill`).

    Returns
    -------
    RainFill

    Notes
    -----
    Unmeasured points are transparent (see the module docstring): they neither hold nor block
    water and stay NaN in ``wet`` and ``depth_m``; fractions and volumes are per measured area.

    Examples
    --------
    >>> from roadscan.io import read
    >>> from roadscan.level import level
    >>> from roadscan.rain import rain_fill
    >>> wet = rain_fill(level(read("sample_scans/asphalt.x3p")))
    >>> 0 < wet.wetted_fraction < 1
    True
    """
    if connectivity not in (4, 8):
        raise ValueError(f"connectivity must be 4 or 8, got {connectivity!r}")
    if max_depth_m is not None and water_film_m is not None:
        raise ValueError("give at most one of max_depth_m and water_film_m")
    for name, val in (("max_depth_m", max_depth_m), ("water_film_m", water_film_m)):
        if val is not None and not (np.isfinite(val) and val >= 0):
            raise ValueError(f"{name} must be a finite number >= 0, got {val!r}")

    h = hm.heights_m
    measured = ~hm.unmeasured
    n_measured = int(measured.sum())
    if n_measured == 0:
        raise ValueError("rain fill needs at least one measured point")
    filled = full_fill(h, connectivity, method=method)
    wet_name = f"{hm.name}_wet" if hm.name else "wet"
    cap_used = None
    all_full = True
    n_dep = None
    if max_depth_m is None and water_film_m is None:
        # full fill: the wet surface is F itself (HeightMap keeps its own copy), and F turns into
        # the depth map in place, so the peak is two maps beside the input
        wet = hm.with_heights(filled, unmeasured=hm.unmeasured, name=wet_name, meta=dict(hm.meta))
        depth = np.subtract(filled, h, out=filled)  # NaN where unmeasured (both NaN there)
        del filled
        capacity = volume = float(np.sum(depth, where=measured) / n_measured)  # no NaN copy
    else:
        full_depth = filled - h
        capacity = float(np.nansum(full_depth) / n_measured)
        del full_depth
        labels, n_dep, lowest = _depressions(h, filled, connectivity)
        if water_film_m is not None:
            sel = labels > 0
            m = lowest[labels[sel]]
            a = h[sel] - m
            b = filled[sel] - m
            cap_used, _ = _cap_for_film(a, b, n_measured, float(water_film_m))
        else:
            assert max_depth_m is not None  # both None took the full fill above
            cap_used = float(max_depth_m)
        level = capped_levels(h, filled, labels, lowest, cap_used)
        # full to the spill level, to rounding: lowest + cap can differ from the spill level by
        # an ulp when the cap equals a depression's depth (a film above the capacity)
        tol = 1e-9 * max(float(np.nanmax(filled) - np.nanmin(h)), np.finfo(float).tiny)
        all_full = bool(np.all(np.abs(level[measured] - filled[measured]) <= tol))
        del labels, filled
        depth = np.where(measured, level - h, np.nan)
        wet = hm.with_heights(
            np.where(measured, level, np.nan), unmeasured=hm.unmeasured, name=wet_name, meta=dict(hm.meta)
        )
        del level
        volume = float(np.nansum(depth) / n_measured)
    wetted = float(np.count_nonzero(depth > 0) / n_measured)  # NaN > 0 is False
    meta = {
        "max_depth_m": cap_used,
        "water_film_m": None if water_film_m is None else float(water_film_m),
        "capacity_m3_per_m2": capacity,
        "all_full": all_full,
        "n_depressions": n_dep,
        "measured_fraction": n_measured / h.size,
        "unmeasured_policy": "transparent: dropouts neither hold nor block water; NaN in outputs",
        "method": "grayscale reconstruction by erosion from the border (imfill)",
    }
    wet.meta["rain_fill"] = dict(meta, connectivity=connectivity)
    return RainFill(
        wet=wet,
        depth_m=depth,
        wetted_fraction=wetted,
        water_volume_m3_per_m2=volume,
        connectivity=int(connectivity),
        meta=meta,
    )
