"""Levelling (mean, tilt and polynomial form removal) and spike removal.

Both work on :class:`roadscan.HeightMap` and :class:`roadscan.Profile` and return the same
type. Unmeasured points (``unmeasured`` True, NaN heights) never enter a fit and stay
unmeasured in the result.
"""

from __future__ import annotations

from typing import TypeVar

import numpy as np
from numpy.typing import NDArray

from .bands import row_chunks
from .heightmap import HeightMap, Profile

_Scan = TypeVar("_Scan", HeightMap, Profile)

__all__ = ["level", "remove_spikes", "polynomial_form", "fit_polynomial", "PolynomialForm"]


def _unit_coords(n):
    """Grid coordinates mapped to [-1, 1] (conditioning of the normal equations)."""
    if n == 1:
        return np.zeros(1)
    return np.linspace(-1.0, 1.0, n)


def _powers(u, p_max):
    """Columns u**0 ... u**p_max, shape (len(u), p_max + 1)."""
    return u[:, None] ** np.arange(p_max + 1)[None, :]


class PolynomialForm:
    """A fitted polynomial form z(x, y) = sum_{i + j <= d} c_ij u^i v^j on a grid (u, v the
    column and row coordinates mapped to [-1, 1]); :meth:`rows` evaluates it on a band of
    rows, so callers never need the whole form in memory.

    Parameters
    ----------
    C : ndarray
        Coefficients c_ij.
    U, V : ndarray
        Column and row coordinates mapped to [-1, 1].
    """

    def __init__(self, C: NDArray[np.float64], U: NDArray[np.float64], V: NDArray[np.float64]) -> None:
        self.C, self.U, self.V = C, U, V  # C[j, i]; U (nx, d+1); V (ny, d+1)
        self.U = np.asfortranarray(U)  # columns u^i contiguous

    def rows(
        self, sl: slice, out: NDArray[np.float64] | None = None, minus: NDArray[np.float64] | None = None
    ) -> NDArray[np.float64]:
        """The form on rows ``sl`` (a slice), shape (rows, nx) [m]; with ``minus`` (heights
        of those rows) the difference ``minus - form`` instead, into ``out`` if given."""
        # broadcasting, not a matmul with an inner dimension of d + 1: the BLAS call costs
        # more than the arithmetic, and its threads fight the FFT's on a small machine
        a = np.einsum("rj,ji->ri", self.V[sl], self.C)  # coefficient of u^i per row
        if minus is None:
            out = np.multiply(np.ones(self.U.shape[0]), a[:, :1], out=out)  # u^0 = 1
            for i in range(1, a.shape[1]):
                out += a[:, i, None] * self.U[:, i]
            return out
        out = np.subtract(minus, a[:, :1], out=out)
        for i in range(1, a.shape[1]):
            out -= a[:, i, None] * self.U[:, i]
        return out

    def full(self) -> NDArray[np.float64]:
        """The form on the whole grid [m]."""
        return self.rows(slice(None))


def fit_polynomial(
    heights_m: NDArray[np.float64], unmeasured: NDArray[np.bool_], degree: int = 1
) -> PolynomialForm:
    """Least-squares polynomial form of total degree ``degree`` fitted to measured points.

    Same fit as :func:`polynomial_form` (which see), returned as a :class:`PolynomialForm`.
    The moment sums S[j, i] = sum m v^j u^i and R[j, i] = sum m h v^j u^i (m the measured
    indicator) are accumulated over bands of rows (float64 throughout), so the memory used
    is a few rows whatever the size of the map; the normal equations are then solved once.

    Parameters
    ----------
    heights_m : ndarray
        Heights [m].
    unmeasured : ndarray of bool
        Points not measured.
    degree : int, optional
        Total degree of the polynomial.

    Returns
    -------
    PolynomialForm
        The fitted form.
    """
    if degree < 0:
        raise ValueError(f"degree must be >= 0, got {degree}")
    h = np.asarray(heights_m, dtype=np.float64)
    one_d = h.ndim == 1
    bad = np.asarray(unmeasured, dtype=bool)
    if one_d:
        h, bad = h[None, :], bad[None, :]
    ny, nx = h.shape
    U = _powers(_unit_coords(nx), 2 * degree)  # (nx, 2d+1)
    V = _powers(_unit_coords(ny), 2 * degree)  # (ny, 2d+1)
    if one_d:
        V = np.zeros((1, 2 * degree + 1))
        V[0, 0] = 1.0
    Ud = np.ascontiguousarray(U[:, : degree + 1])
    Vd = V[:, : degree + 1]
    S = np.zeros((2 * degree + 1, 2 * degree + 1))
    R = np.zeros((degree + 1, degree + 1))
    for sl in row_chunks(ny, nx):
        b = bad[sl]
        if b.any():
            hz = np.where(b, 0.0, h[sl])
            m = (~b).astype(np.float64)
            mu = np.stack([m.dot(U[:, i]) for i in range(U.shape[1])], axis=1)
            S += np.einsum("rj,ri->ji", V[sl], mu)  # S[j, i] = sum m v^j u^i
        else:
            hz = h[sl]
            S += np.outer(V[sl].sum(axis=0), U.sum(axis=0))
        rs = np.stack([hz.dot(Ud[:, i]) for i in range(degree + 1)], axis=1)
        R += np.einsum("rj,ri->ji", Vd[sl], rs)  # R[j, i] = sum m h v^j u^i
    terms = [
        (i, j)
        for i in range(degree + 1)
        for j in range(degree + 1)
        if i + j <= degree and (not one_d or j == 0)
    ]
    G = np.array([[S[j + m, i + k] for (k, m) in terms] for (i, j) in terms])
    rhs = np.array([R[j, i] for (i, j) in terms])
    c = np.linalg.lstsq(G, rhs, rcond=None)[0]
    C = np.zeros((degree + 1, degree + 1))  # C[j, i]
    for (i, j), cij in zip(terms, c):
        C[j, i] = cij
    return PolynomialForm(C, Ud, np.ascontiguousarray(Vd))


def polynomial_form(
    heights_m: NDArray[np.float64], unmeasured: NDArray[np.bool_], degree: int = 1
) -> NDArray[np.float64]:
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
    unmeasured : ndarray of bool
        Unmeasured points, same shape as the heights.
    degree : int
        0 = mean, 1 = plane (mean + tilt), 2 = quadratic form, ...

    Returns
    -------
    form : array of the heights' shape
        The fitted polynomial evaluated on the whole grid [m].
    """
    form = fit_polynomial(heights_m, unmeasured, degree).full()
    return form[0] if np.ndim(heights_m) == 1 else form


def level(obj: _Scan, degree: int = 1) -> _Scan:
    """Remove the least-squares polynomial form (mean, tilt, ...) fitted to measured points.

    The form is fitted by :func:`fit_polynomial` and subtracted band by band of rows into one
    new float64 array (the input is not changed): the memory used is the result plus a few
    rows, and the precision is float64 throughout.

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
    h, bad = obj.heights_m, obj.unmeasured
    form = fit_polynomial(h, bad, degree)
    meta = dict(obj.meta)
    meta["levelled_degree"] = int(degree)
    h2 = h[None, :] if h.ndim == 1 else h
    bad2 = bad[None, :] if bad.ndim == 1 else bad
    out = np.empty(h2.shape)
    consistent = True  # NaN exactly where unmeasured
    for sl in row_chunks(*h2.shape):
        form.rows(sl, out=out[sl], minus=h2[sl])
        consistent = consistent and np.array_equal(np.isfinite(out[sl]), ~bad2[sl])
    out = out.reshape(h.shape)
    if not consistent:  # e.g. an overflow: let the constructor mark it
        return obj.with_heights(out, meta=meta)
    return obj._adopt(out, meta=meta)


def _nearest_filled(h, bad):
    """Heights with each unmeasured point replaced by its nearest measured neighbour."""
    if not bad.any():
        return h
    from scipy import ndimage

    idx = np.empty((bad.ndim,) + bad.shape, dtype=np.int32)  # scipy's own index type
    ndimage.distance_transform_edt(bad, return_distances=False, return_indices=True, indices=idx)
    out = h.copy()
    out[bad] = h[tuple(i[bad] for i in idx)]
    return out


def remove_spikes(obj: _Scan, threshold: float = 6.0, size: int = 3) -> _Scan:
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
    from scipy import ndimage

    hf = _nearest_filled(h, bad)
    dev = ndimage.median_filter(hf, size=size, mode="nearest")
    np.subtract(hf, dev, out=dev)  # h - local median
    del hf
    d_meas = dev[~bad]
    spread = np.abs(d_meas - np.median(d_meas))
    sigma = 1.4826 * np.median(spread, overwrite_input=True)
    del spread
    if sigma == 0:
        sigma = np.std(d_meas)
    del d_meas
    spikes = (~bad) & (np.abs(dev) > threshold * sigma) if sigma > 0 else np.zeros_like(bad)
    n = int(spikes.sum())
    if n and spikes.sum() >= (~bad).sum():
        raise ValueError("spike removal would remove every measured point")
    meta = dict(obj.meta)
    meta["spikes_removed"] = meta.get("spikes_removed", 0) + n
    return obj.with_heights(h, unmeasured=bad | spikes, meta=meta)
