"""Levelling (mean, tilt and polynomial form removal) and spike removal.

Both work on :class:`roadscan.HeightMap` and :class:`roadscan.Profile` and return the same
type. Unmeasured points (``unmeasured`` True, NaN heights) never enter a fit and stay
unmeasured in the result.
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage

from .heightmap import HeightMap, Profile

__all__ = ["level", "remove_spikes", "polynomial_form"]


def _unit_coords(n):
    """Grid coordinates mapped to [-1, 1] (conditioning of the normal equations)."""
    if n == 1:
        return np.zeros(1)
    return np.linspace(-1.0, 1.0, n)


def _powers(u, p_max):
    """Columns u**0 ... u**p_max, shape (len(u), p_max + 1)."""
    return u[:, None] ** np.arange(p_max + 1)[None, :]


def polynomial_form(heights_m, unmeasured, degree=1):
    """Least-squares polynomial form of total degree ``degree`` fitted to measured points.

    Fits z(x, y) = sum_{i + j <= degree} c_ij u^i v^j, with u, v the column and row
    coordinates mapped to [-1, 1], minimising sum over measured points of (h - z)^2.
    The normal equations are assembled from separable moment matrices
    ``S = V_pow^T M U_pow`` (M the measured indicator), so the cost is a few matrix
    products over the grid whatever the mask.

    Parameters
    ----------
    heights_m : (ny, nx) or (n,) array
        Heights [m]; values at unmeasured points are ignored.
    unmeasured : bool array of the same shape
    degree : int
        0 = mean, 1 = plane (mean + tilt), 2 = quadratic form, ...

    Returns
    -------
    form : array of the heights' shape
        The fitted polynomial evaluated on the whole grid [m].
    """
    if degree < 0:
        raise ValueError(f"degree must be >= 0, got {degree}")
    h = np.asarray(heights_m, dtype=np.float64)
    one_d = h.ndim == 1
    if one_d:
        h = h[None, :]
        unmeasured = np.asarray(unmeasured)[None, :]
    ny, nx = h.shape
    bad = np.asarray(unmeasured, dtype=bool)
    any_bad = bool(bad.any())
    U = _powers(_unit_coords(nx), 2 * degree)        # (nx, 2d+1)
    V = _powers(_unit_coords(ny), 2 * degree)        # (ny, 2d+1)
    if one_d:
        V = np.zeros((1, 2 * degree + 1))
        V[0, 0] = 1.0
    # (grid @ narrow) first: a transposed narrow matrix on the left takes a slow matmul path
    if any_bad:
        meas = (~bad).astype(np.float64)
        hz = np.where(bad, 0.0, h)
        S = V.T @ (meas @ U)                         # S[j, i] = sum m v^j u^i
    else:
        hz = h
        S = np.outer(V.sum(axis=0), U.sum(axis=0))
    Ud = np.ascontiguousarray(U[:, : degree + 1])
    R = V[:, : degree + 1].T @ (hz @ Ud)             # R[j, i] = sum m h v^j u^i
    terms = [(i, j) for i in range(degree + 1) for j in range(degree + 1)
             if i + j <= degree and (not one_d or j == 0)]
    G = np.array([[S[j + l, i + k] for (k, l) in terms] for (i, j) in terms])
    b = np.array([R[j, i] for (i, j) in terms])
    c = np.linalg.lstsq(G, b, rcond=None)[0]
    C = np.zeros((degree + 1, degree + 1))           # C[j, i]
    for (i, j), cij in zip(terms, c):
        C[j, i] = cij
    form = V[:, : degree + 1] @ C @ U[:, : degree + 1].T
    return form[0] if one_d else form


def level(obj, degree=1):
    """Remove the least-squares polynomial form (mean, tilt, ...) fitted to measured points.

    Parameters
    ----------
    obj : HeightMap or Profile
    degree : int
        0 removes the mean, 1 the mean plane (mean and tilt; for a profile the linear
        trend), higher degrees a polynomial of that total degree.

    Returns
    -------
    HeightMap or Profile
        Same type, heights minus the fitted form; the measured heights then have zero mean.
        ``meta['levelled_degree']`` records the degree.
    """
    if not isinstance(obj, (HeightMap, Profile)):
        raise TypeError(f"expected HeightMap or Profile, got {type(obj).__name__}")
    form = polynomial_form(obj.heights_m, obj.unmeasured, degree)
    meta = dict(obj.meta)
    meta["levelled_degree"] = int(degree)
    return obj.with_heights(obj.heights_m - form, meta=meta)


def _nearest_filled(h, bad):
    """Heights with each unmeasured point replaced by its nearest measured neighbour."""
    if not bad.any():
        return h
    idx = ndimage.distance_transform_edt(bad, return_distances=False, return_indices=True)
    return h[tuple(idx)]


def remove_spikes(obj, threshold=6.0, size=3):
    """Mark spikes (isolated outliers) as unmeasured.

    A point is a spike when it departs from the median of its ``size`` (x ``size``)
    neighbourhood by more than ``threshold`` times the robust standard deviation of those
    departures over the whole map (1.4826 x the median absolute deviation). Unmeasured
    points are replaced by their nearest measured neighbour for the median only.

    Parameters
    ----------
    obj : HeightMap or Profile
    threshold : float
        Multiple of the robust standard deviation of (h - local median); default 6.
    size : int
        Width of the median neighbourhood in points (odd; default 3).

    Returns
    -------
    HeightMap or Profile
        Same type with spikes added to ``unmeasured`` (NaN heights);
        ``meta['spikes_removed']`` holds their number.
    """
    if not isinstance(obj, (HeightMap, Profile)):
        raise TypeError(f"expected HeightMap or Profile, got {type(obj).__name__}")
    h, bad = obj.heights_m, obj.unmeasured
    hf = _nearest_filled(h, bad)
    med = ndimage.median_filter(hf, size=size, mode="nearest")
    dev = hf - med
    d_meas = dev[~bad]
    sigma = 1.4826 * np.median(np.abs(d_meas - np.median(d_meas)))
    if sigma == 0:
        sigma = np.std(d_meas)
    spikes = (~bad) & (np.abs(dev) > threshold * sigma) if sigma > 0 else np.zeros_like(bad)
    n = int(spikes.sum())
    if n and spikes.sum() >= (~bad).sum():
        raise ValueError("spike removal would remove every measured point")
    meta = dict(obj.meta)
    meta["spikes_removed"] = meta.get("spikes_removed", 0) + n
    return obj.with_heights(h, unmeasured=bad | spikes, meta=meta)
