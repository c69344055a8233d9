"""Filling unmeasured points (instrument dropouts) before any FFT.

Measured on a 1000 x 1000 random-walk surface with 2.3 % clustered dropouts (2 cores):
scikit-image ``inpaint_biharmonic`` (one global sparse solve, ``split_into_regions=False``)
0.12 s and the most accurate (rms error 0.034 of the surface's rms at the filled points);
OpenCV Navier-Stokes ``cv2.inpaint(..., INPAINT_NS)`` 0.04 s, rms error 0.053; OpenCV Telea
0.2 s with errors as large as the surface's rms on float32 data, so it is not offered.
Biharmonic is the default; ``"ns"`` is the fast alternative. Profiles are filled by linear interpolation (ends
held at the nearest measured value).

The biharmonic system is scikit-image's. Maps of up to :data:`DIRECT_MAX_POINTS` points solve it
with :mod:`roadscan._biharmonic` (numpy dense blocks per dropout cluster; no scipy import, which
took a third of ``roadscan analyse``'s time on the sample), larger maps with scikit-image's
sparse solve band by band; both equal one global ``inpaint_biharmonic`` to round-off (tests).
"""

from __future__ import annotations

from typing import Literal, TypeVar

import numpy as np
from numpy.typing import NDArray

from .bands import measured_mean_range, row_chunks
from .heightmap import HeightMap, Profile

_Scan = TypeVar("_Scan", HeightMap, Profile)

__all__ = ["fill_unmeasured", "unmeasured_fill", "METHODS"]

METHODS = ("biharmonic", "ns")


def _fill_profile(h, bad):
    x = np.arange(h.size)
    return np.where(bad, np.interp(x, x[~bad], h[~bad]), h)


#: rows per band of the banded biharmonic fill (bands grow to hold whole dropout clusters)
_BAND_ROWS = 256
#: maps up to this many points are filled by :mod:`roadscan._biharmonic` (numpy only, the same
#: system as scikit-image's to 1e-13); larger ones by scikit-image band by band, whose sparse
#: solve scales better with many large dropout clusters
DIRECT_MAX_POINTS = 1 << 22


def _bands(bad):
    """Groups of dropout clusters, each a band of rows solved on its own.

    Two unmeasured points are coupled by the biharmonic stencil (13 points, radius 2) when
    |dx| + |dy| <= 2; clusters are the connected components of the mask dilated by one
    point (4-neighbourhood) and then 8-connected, which joins every coupled pair (as
    scikit-image's ``split_into_regions``). Clusters are grouped by their first row into bands
    of about ``_BAND_ROWS`` rows; a band reaches down to its lowest cluster's last row.

    Returns
    -------
    labels : int32 array of the clusters; n : their number;
    groups : list of [first row, end row, labels of its clusters]
    """
    from scipy import ndimage

    from ._biharmonic import grow4

    grown = grow4(bad)
    labels, n = ndimage.label(grown, structure=np.ones((3, 3), dtype=bool))
    del grown
    boxes = ndimage.find_objects(labels)
    starts = np.array([b[0].start for b in boxes])
    stops = np.array([b[0].stop for b in boxes])
    order = np.argsort(starts, kind="stable")
    groups, cur = [], None
    for k in order:
        if cur is not None and starts[k] < cur[0] + _BAND_ROWS:
            cur[1] = max(cur[1], stops[k])
            cur[2].append(k + 1)
        else:
            cur = [starts[k], stops[k], [k + 1]]
            groups.append(cur)
    return labels, n, groups


def _two_free_points(mask, reach):
    """Two points of ``mask``'s grid out of reach (|dx| + |dy| > 2) of every True point, or
    None. A whole row (or column) 2 away from any masked row does; else a dilation decides."""
    for axis in (1, 0):
        c = np.concatenate([[0], np.cumsum(mask.any(axis=axis))])
        i = np.arange(c.size - 1)
        busy = c[np.minimum(i + 3, c.size - 1)] - c[np.maximum(i - 2, 0)]  # masked lines within 2
        idle = np.flatnonzero(busy == 0)
        if idle.size and mask.shape[axis] >= 2:
            i = int(idle[0])
            return ((i, 0), (i, 1)) if axis == 1 else ((0, i), (1, i))
    from scipy import ndimage

    free = np.argwhere(~ndimage.binary_dilation(mask, structure=reach))
    return (tuple(free[0]), tuple(free[1])) if len(free) >= 2 else None


def _biharmonic_banded(h, bad, values):
    """scikit-image biharmonic inpainting, solved band by band; the filled heights go to
    ``values`` (one per unmeasured point, raster order). False if it cannot be banded.

    The result equals one global ``inpaint_biharmonic(np.where(bad, ref, h) - ref, bad) + ref``
    (ref the mean of the measured heights) to the round-off of the sparse solves: the global
    system is block-diagonal over the clusters of :func:`_bands`; each band is solved on its
    rows plus a margin of 2 (so no cluster point sees an artificial edge), the whole width
    (so the map's own edges are the same), and with the global clip range: scikit-image clips
    the result to the range of the known values it is given, so two points of the band out
    of reach of the band's clusters carry the global minimum and maximum. Memory: the cluster
    labels (int32) plus one band; float64 throughout.
    """
    from scipy import ndimage
    from skimage.restoration import inpaint_biharmonic

    ny, nx = h.shape
    ref, lo, hi = measured_mean_range(h, bad)
    lo, hi = lo - ref, hi - ref
    labels, n, groups = _bands(bad)
    where = np.flatnonzero(bad)  # raster positions of the values
    reach = ndimage.generate_binary_structure(2, 1)
    reach = ndimage.iterate_structure(reach, 2)  # |dx| + |dy| <= 2
    member = np.zeros(n + 1, dtype=bool)
    for r0, r1, labs in groups:
        a, b = max(r0 - 2, 0), min(r1 + 2, ny)
        member[labs] = True
        mask = member[labels[a:b]] & bad[a:b]
        member[labs] = False
        crop = h[a:b] - ref
        crop[bad[a:b]] = 0.0
        free = _two_free_points(mask, reach)
        if free is None:  # no room for the clip range: one solve
            return False
        crop[free[0]], crop[free[1]] = lo, hi
        filled = inpaint_biharmonic(crop, mask)
        values[np.searchsorted(where, a * nx + np.flatnonzero(mask))] = filled[mask] + ref
    return True


def _map_values(h, bad, method):
    """The filled heights at ``bad`` (raster order) of a map; ``h`` is not changed."""
    if method not in METHODS:
        raise ValueError(f"unknown fill method {method!r}; choose one of {METHODS}")
    if method == "biharmonic":
        if h.size <= DIRECT_MAX_POINTS:
            from ._biharmonic import biharmonic_fill_values

            try:
                return biharmonic_fill_values(h, bad, measured_mean_range(h, bad))
            except np.linalg.LinAlgError:  # a singular block: scikit-image's sparse LU
                pass
        values = np.empty(int(np.count_nonzero(bad)))
        if _biharmonic_banded(h, bad, values):
            return values
        from skimage.restoration import inpaint_biharmonic

        ref = np.nanmean(h)
        filled = inpaint_biharmonic(np.where(bad, ref, h) - ref, bad) + ref
    else:
        import cv2

        ref = np.nanmean(h)
        scale = np.nanstd(h) or 1.0
        work = np.where(bad, 0.0, (h - ref) / scale).astype(np.float32)
        filled = cv2.inpaint(work, bad.astype(np.uint8), 3, cv2.INPAINT_NS).astype(np.float64) * scale + ref
    return filled[bad]


def unmeasured_fill(
    obj: HeightMap | Profile, method: Literal["biharmonic", "ns"] = "biharmonic"
) -> NDArray[np.float64]:
    """The values :func:`fill_unmeasured` puts at the unmeasured points, without the filled copy.

    Returns
    -------
    values : (n_unmeasured,) float64 array
        Heights [m] for the points where ``obj.unmeasured`` is True, in raster (C) order:
        ``h[obj.unmeasured] = values`` fills the map (and :func:`roadscan.spectrum.psd_area`
        takes them as ``fill_values``). The biharmonic fill works band by band of rows
        (float64); its memory is a band plus the cluster labels (int32), not the map.

    Parameters
    ----------
    obj : HeightMap or Profile
        The scan [m].
    method : str, optional
        ``"biharmonic"`` (default).
    """
    if not isinstance(obj, (HeightMap, Profile)):
        raise TypeError(f"expected HeightMap or Profile, got {type(obj).__name__}")
    bad = obj.unmeasured
    if not bad.any():
        return np.empty(0)
    if isinstance(obj, Profile):
        return _fill_profile(obj.heights_m, bad)[bad]
    return _map_values(obj.heights_m, bad, method)


def fill_unmeasured(obj: _Scan, method: Literal["biharmonic", "ns"] = "biharmonic") -> tuple[_Scan, float]:
    """Fill unmeasured points so the object can be Fourier transformed.

    Parameters
    ----------
    obj : HeightMap or Profile
    method : {"biharmonic", "ns"}
        For height maps: scikit-image biharmonic inpainting (default; smooth, accurate) or
        OpenCV Navier-Stokes inpainting (faster, less accurate). Profiles always use linear interpolation.

    Returns
    -------
    filled : HeightMap or Profile
        Same type, no unmeasured points; measured heights unchanged.
        ``meta['filled_fraction']`` and ``meta['fill_method']`` record what was done.
    filled_fraction : float
        Fraction of points that were filled (0 to 1).
    """
    if not isinstance(obj, (HeightMap, Profile)):
        raise TypeError(f"expected HeightMap or Profile, got {type(obj).__name__}")
    bad = obj.unmeasured
    frac = float(bad.mean())
    meta = dict(obj.meta)
    if isinstance(obj, HeightMap) and method not in METHODS:
        raise ValueError(f"unknown fill method {method!r}; choose one of {METHODS}")
    meta["fill_method"] = "linear" if isinstance(obj, Profile) else method
    filled = obj.heights_m
    if frac:
        filled = filled.copy()
        filled[bad] = unmeasured_fill(obj, method)
    meta["filled_fraction"] = frac
    none = np.zeros_like(bad)
    if not frac or _all_finite(filled):  # nothing to fill (shared), or a fresh array: no copy
        return obj._adopt(filled, unmeasured=none, meta=meta), frac
    return obj.with_heights(filled, unmeasured=none, meta=meta), frac


def _all_finite(a):
    a2 = a.reshape(1, -1) if a.ndim == 1 else a
    return all(np.isfinite(a2[sl]).all() for sl in row_chunks(*a2.shape))
