"""Steps and seams far above the texture: a stitching fault or a plate edge, not roughness.

A 2 mm step across a 0.2 mm-rms scan adds a ``1/q^2`` tail to the spectrum (a step's Fourier
transform falls as ``1/q``) and pulls the fitted Hurst exponent towards 0.5 (H 0.42 on one real stitched scan)
without a word. The step is found in the scan's median profiles:

- ``m_x[j]``: the median over rows of column ``j`` (in up to 4 bands of rows, so that a seam
  across part of the scan, as between two tiles of a grid, is seen in its band), ``m_y[i]``
  likewise over columns;
- ``sigma``: the local texture's rms, robustly (``1.4826 MAD``) from what the band-wise
  median profiles leave, ``h - m_x - m_y`` (the step itself goes with the median profiles, and so
  do the texture's longest wavelengths: ``sigma`` is below the scan's ``S_q``);
- a step at ``j`` when ``|m_x[j+1] - m_x[j]| > 5 sigma`` and more than 10 times the robust
  spread of all adjacent differences of ``m_x`` (a texture's median profile changes by a
  fraction of ``sigma`` from one column to the next: medians over many rows).

Line profiles: block medians over windows of 64 samples replace the median profiles (a chip
edge is a jump of one or two samples, a plate edge or seam shifts the level for good), after the
profiler's reference plates are cut by :func:`roadscan.trim.road_section`.

:func:`find_steps` returns one warning line per direction (the largest step, where it is, how
many there are); the caller prints and records them (``summary.json`` ``warnings``).

Reference: ISO 25178-2:2012 (``S_q``); P. J. Huber, Robust Statistics (1981) (MAD scale).
"""

from __future__ import annotations

import warnings
from itertools import pairwise

import numpy as np

from .heightmap import HeightMap, Profile
from .order_stats import median
from .units import length as _fmt

__all__ = ["find_steps", "STEP_SIGMAS", "OUTLIER_FACTOR"]

#: a step is larger than this many texture rms
STEP_SIGMAS = 5.0
#: and this many times the robust spread of adjacent median differences
OUTLIER_FACTOR = 10.0
_MAX_SIDE = 1024
_BLOCK = 64


def _mad_sigma(v):
    """1.4826 median(|v - median(v)|) of the finite values (0 for none)."""
    v = v[np.isfinite(v)]
    if v.size == 0:
        return 0.0
    d = np.abs(v - median(v, overwrite=True))  # v is a copy already
    return 1.4826 * median(d, overwrite=True)


def _jumps(profiles, sigma):
    """(largest step, index, count) over the rows of ``profiles`` (bands x positions), or None.

    Adjacent differences above the limit are outliers; a run of them with the same sign is one
    step (a step inside a block of a profile splits over two differences), sized by their sum.
    """
    if not sigma > 0:  # no measured local texture (or NaN): no step can be judged against it
        return None
    d = np.nan_to_num(np.diff(profiles, axis=1), nan=0.0)
    spread = _mad_sigma(d.ravel())
    limit = max(STEP_SIGMAS * sigma, OUTLIER_FACTOR * spread)
    if limit <= 0:
        return None
    half = np.abs(d) > 0.5 * limit  # parts of a split step
    best, count = None, 0
    for band in range(d.shape[0]):
        idx = np.flatnonzero(half[band])
        if idx.size == 0:
            continue
        runs = np.split(idx, np.flatnonzero((np.diff(idx) != 1) | (np.diff(np.sign(d[band, idx])) != 0)) + 1)
        for run in runs:
            size = abs(float(d[band, run].sum()))
            if size > limit:
                count += 1
                j = int(run[np.argmax(np.abs(d[band, run]))])
                if best is None or size > best[0]:
                    best = (size, j)
    return None if best is None else (best[0], best[1], count)


def _band_profiles(z, axis, n_other):
    """(band edges, median profiles): medians along ``axis`` in up to 4 bands of the other
    direction (axis 0: one profile along x per band of rows)."""
    bands = max(1, min(4, n_other // 32))
    edges = np.linspace(0, n_other, bands + 1).astype(int)
    take = (lambda a, b: z[a:b]) if axis == 0 else (lambda a, b: z[:, a:b])
    return edges, np.array([_nanmedian(take(a, b), axis) for a, b in pairwise(edges)])


def _nanmedian(x, axis):
    """``np.nanmedian(x, axis=axis)`` of a 2D array, equal to it bit for bit (the middle
    value, or the half sum of the two middle values, of each line's measured points; NaN for a
    line without any), from one sort: numpy's own goes through masked arrays for lines shorter
    than 600 points, 4-8 times slower on a 250 x 1000 band."""
    s = np.sort(x, axis=axis)  # NaN sort last
    n = np.count_nonzero(~np.isnan(x), axis=axis)
    lo = np.take_along_axis(s, np.expand_dims(np.maximum(n - 1, 0) // 2, axis), axis)
    hi = np.take_along_axis(s, np.expand_dims(np.minimum(n // 2, x.shape[axis] - 1), axis), axis)
    med = (lo.squeeze(axis) + hi.squeeze(axis)) / 2
    med[n == 0] = np.nan
    return med


def _spread(band_profiles, n_other, axis):
    """The band profiles back on the grid (each band's profile repeated over its rows or
    columns)."""
    edges, prof = band_profiles
    idx = np.repeat(np.arange(len(edges) - 1), np.diff(edges))
    return prof[idx] if axis == 0 else prof[idx].T


def _map_steps(hmap):
    h = hmap.heights_m
    sy = max(1, int(np.ceil(h.shape[0] / _MAX_SIDE)))
    sx = max(1, int(np.ceil(h.shape[1] / _MAX_SIDE)))
    z = h[::sy, ::sx]
    ny, nx = z.shape
    if min(ny, nx) < 8:
        return []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows/columns
        profs = {0: _band_profiles(z, 0, ny), 1: _band_profiles(z, 1, nx)}
        # the local texture: what the band-wise median profiles (steps included) leave
        r = z - _spread(profs[0], ny, axis=0)
        r_rows = _band_profiles(r, 1, nx)
        r -= _spread(r_rows, nx, axis=1)
        sigma = _mad_sigma(r.ravel())
        out = []
        for axis, step, name in ((0, hmap.dx_m * sx, "x"), (1, hmap.dy_m * sy, "y")):
            found = _jumps(profs[axis][1], sigma)
            if found:
                out.append(_line(found, sigma, step, name))
    return out


def _profile_steps(prof):
    from .trim import road_section

    road = road_section(prof)
    h = road.heights_m
    n = h.size // _BLOCK
    if n < 4:
        return []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        blocks = _nanmedian(h[: n * _BLOCK].reshape(n, _BLOCK), 1)
        sigma = _mad_sigma(h[: n * _BLOCK] - np.repeat(blocks, _BLOCK))
    found = _jumps(blocks[None, :], sigma)
    return [_line(found, sigma, road.dx_m * _BLOCK, "x")] if found else []


def _line(found, sigma, step_m, axis):
    size, j, count = found
    more = f" ({count} such steps)" if count > 1 else ""
    return (
        f"a step of {_fmt(size)} along {axis} at {axis} = {_fmt((j + 1) * step_m)}{more}, "
        f"{size / sigma:.3g} times the local texture's rms {_fmt(sigma)}: a stitching fault or a "
        f"plate edge, not roughness (the spectrum and H include it; crop it out)"
    )


def find_steps(obj: HeightMap | Profile) -> list[str]:
    """Warning lines (possibly none) for steps or seams far above the texture of ``obj``.

    Parameters
    ----------
    obj : HeightMap or Profile

    Returns
    -------
    list of str
    """
    if isinstance(obj, HeightMap):
        return _map_steps(obj)
    if isinstance(obj, Profile):
        return _profile_steps(obj)
    return []
