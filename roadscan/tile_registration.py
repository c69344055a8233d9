"""Registration of overlapping tiles for :func:`roadscan.stitch.stitch` (its step 1).

Every pair of tiles whose nominal footprints overlap is registered by masked normalised
cross-correlation computed by FFT (Padfield 2012, as implemented by
:func:`skimage.registration.phase_cross_correlation` with masks) on high-passed tiles (each
minus its Gaussian smoothing, sigma = 2 samples), then refined to a subpixel offset by upsampled
phase correlation (Guizar-Sicairos et al. 2008) on the exactly overlapping windows (plane
removed, Tukey-windowed). The overlap graph must connect every tile to tile 0.

References: D. Padfield, IEEE Trans. Image Process. 21, 2706 (2012); M. Guizar-Sicairos,
S. T. Thurman, J. R. Fienup, Opt. Lett. 33, 156 (2008).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from skimage.registration import phase_cross_correlation

from .errors import InputError
from .level import polynomial_form
from .windows import tukey  # scipy.signal's, without importing scipy.signal

__all__ = ["register_pair", "overlap_rect", "check_connected", "plane_removed", "highpass"]


def plane_removed(z: NDArray[np.float64], ok: NDArray[np.bool_]) -> NDArray[np.float64]:
    """z minus its least-squares plane over the points ``ok``; unmeasured -> 0.

    Parameters
    ----------
    z : ndarray
        Tile heights [m].
    ok : ndarray of bool
        Measured points.

    Returns
    -------
    ndarray
    """
    if np.count_nonzero(ok) < 3:
        return np.zeros_like(z)
    return np.where(ok, z - polynomial_form(z, ~ok, degree=1), 0.0)


def highpass(z: NDArray[np.float64], ok: NDArray[np.bool_], sigma: float = 2.0) -> NDArray[np.float64]:
    """z minus its Gaussian-smoothed version (normalised convolution over measured points).

    A plane passes through the smoothing unchanged, so relative tilts vanish and the
    correlation peak of a self-affine surface (otherwise very broad) becomes sharp.

    Parameters
    ----------
    z : ndarray
        Tile heights [m].
    ok : ndarray of bool
        Measured points.
    sigma : float, optional
        Gaussian width [points].

    Returns
    -------
    ndarray
    """
    okf = ok.astype(float)
    num = ndimage.gaussian_filter(np.where(ok, z, 0.0), sigma, mode="constant")
    den = ndimage.gaussian_filter(okf, sigma, mode="constant")
    with np.errstate(invalid="ignore", divide="ignore"):
        smooth = np.where(den > 1e-6, num / den, 0.0)
    return np.where(ok, z - smooth, 0.0)


def overlap_rect(
    shape_i: tuple[int, ...], shape_j: tuple[int, ...], t: tuple[int, ...]
) -> tuple[int, int, int, int]:
    """Overlap of tile i (origin 0) and tile j at integer offset t=(dr, dc), in i's coordinates.

    Parameters
    ----------
    shape_i, shape_j : tuple of int
        Tile shapes.
    t : tuple of int
        Offset (rows, columns) of tile j.

    Returns
    -------
    r0, r1, c0, c1 : int
        The overlap rectangle in tile i.
    """
    r0, c0 = max(0, t[0]), max(0, t[1])
    r1, c1 = min(shape_i[0], t[0] + shape_j[0]), min(shape_i[1], t[1] + shape_j[1])
    return r0, r1, c0, c1


def register_pair(
    zi: NDArray[np.float64],
    oki: NDArray[np.bool_],
    zj: NDArray[np.float64],
    okj: NDArray[np.bool_],
    t0: tuple[int, ...],
    m: int,
    hpi: NDArray[np.float64],
    hpj: NDArray[np.float64],
) -> tuple[NDArray[np.float64], bool]:
    """Offset T (float row, col) of tile j relative to tile i, starting from integer t0.

    ``zi, zj`` are plane-levelled tiles, ``hpi, hpj`` their high-passed versions (used for
    the integer search). Returns (T, registered).

    Parameters
    ----------
    zi, zj : ndarray
        Plane-levelled tiles [m].
    oki, okj : ndarray of bool
        Their measured points.
    t0 : tuple of int
        Starting offset.
    m : int
        Search margin [points].
    hpi, hpj : ndarray
        Their high-passed versions.

    Returns
    -------
    T : ndarray, shape (2,)
        Offset (rows, columns).
    registered : bool
        Whether the correlation found it.
    """
    r0, r1, c0, c1 = overlap_rect(zi.shape, zj.shape, t0)
    R0, R1 = max(0, r0 - m), min(zi.shape[0], r1 + m)
    C0, C1 = max(0, c0 - m), min(zi.shape[1], c1 + m)
    ref = hpi[R0:R1, C0:C1]
    ref_ok = oki[R0:R1, C0:C1]
    mov = np.zeros_like(ref)
    mov_ok = np.zeros_like(ref_ok)
    sl = (slice(r0 - R0, r1 - R0), slice(c0 - C0, c1 - C0))
    sj = (slice(r0 - t0[0], r1 - t0[0]), slice(c0 - t0[1], c1 - t0[1]))
    mov[sl] = hpj[sj]
    mov_ok[sl] = okj[sj]
    # masked normalised cross-correlation: ref[c] = mov[c - s]  =>  T = t0 + s
    s = phase_cross_correlation(ref, mov, reference_mask=ref_ok, moving_mask=mov_ok, overlap_ratio=0.5)
    s = np.rint(np.asarray(s[0] if isinstance(s, tuple) else s, dtype=float)).astype(int)
    if np.any(np.abs(s) > m):
        return np.asarray(t0, float), False
    t = (int(t0[0] + s[0]), int(t0[1] + s[1]))
    # subpixel refinement on the exactly overlapping windows
    r0, r1, c0, c1 = overlap_rect(zi.shape, zj.shape, t)
    if r1 - r0 < 4 or c1 - c0 < 4:
        return np.asarray(t, float), True
    a = zi[r0:r1, c0:c1]
    b = zj[r0 - t[0] : r1 - t[0], c0 - t[1] : c1 - t[1]]
    ok = oki[r0:r1, c0:c1] & okj[r0 - t[0] : r1 - t[0], c0 - t[1] : c1 - t[1]]
    if ok.sum() < 16:
        return np.asarray(t, float), True
    w = np.outer(tukey(a.shape[0], 0.5), tukey(a.shape[1], 0.5))
    a = plane_removed(a, ok) * w
    b = plane_removed(b, ok) * w
    d = phase_cross_correlation(a, b, upsample_factor=20)[0]
    if np.all(np.abs(d) < 1.0):
        return np.asarray(t, float) + d, True
    return np.asarray(t, float), True


def check_connected(n: int, pairs: Sequence[tuple[Any, ...]], labels: Sequence[str], how: str = "") -> None:
    """Raise InputError naming a tile cut off from tile 0 in the overlap graph (``how`` is
    appended to the message).

    Parameters
    ----------
    n : int
        Number of tiles.
    pairs : list of tuple
        Registered pairs (i, j, ...): tile indices first, anything after.
    labels : list of str
        Tile names.
    how : str, optional
        Appended to the message.

    Returns
    -------
    None
    """
    if pairs:
        ii = [p[0] for p in pairs]
        jj = [p[1] for p in pairs]
        g = coo_matrix((np.ones(len(pairs)), (ii, jj)), shape=(n, n))
        _, comp = connected_components(g, directed=False)
    else:
        comp = np.arange(n)
    if np.all(comp == comp[0]):
        return
    degree = np.zeros(n, int)
    for i, j, _ in pairs:
        degree[i] += 1
        degree[j] += 1
    isolated = np.nonzero(degree == 0)[0]
    if isolated.size:
        k = int(isolated[0])
        raise InputError(labels[k], f"tile {labels[k]} does not overlap any other tile{how}")
    k = int(np.nonzero(comp != comp[0])[0][0])
    raise InputError(
        labels[k],
        f"tile {labels[k]} and its neighbours do not overlap the tiles connected to {labels[0]}{how}",
    )
