"""Directional distribution of a 2D PSD map: power ratio, dominant direction, sectors.

Each lattice point in [q_min, q_max] is weighted by w = C / (mean C of its ring), so the steep
fall of C with q does not let the few lowest rings dominate; weights normalised to sum 1.
From them the tensor M = sum w q^ q^T (q^ = q / |q|, trace 1): its eigenvalues l1 >= l2 give
the anisotropy index (l1 - l2) / (l1 + l2), its principal axis the dominant direction.

Reference: Persson et al., J. Phys.: Condens. Matter 17, R1 (2005) (anisotropic surfaces);
ISO 25178-2 (texture direction Std, an analogous areal parameter).
"""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np

from .bands import row_chunks

if TYPE_CHECKING:
    from .spectrum_types import Spectrum2D

from .rings import _default_range, _grid_of, _half_qx, _mirror_columns, _ring_edges, _ring_index

__all__ = ["anisotropy"]


def anisotropy(
    spec2d: Spectrum2D,
    q_min: float | None = None,
    q_max: float | None = None,
    rings_per_decade: int = 10,
    n_sectors: int = 36,
) -> dict[str, Any]:
    """Directional distribution of a 2D PSD map (for a figure and the summary).

    Each lattice point in [q_min, q_max] (defaults as :func:`angular_average`) is weighted by
    C / (mean C of its ring), so the steep fall of C with q does not let the few lowest rings
    dominate (every lattice point counts alike; weights normalised to sum 1). From these:
    the tensor M = sum w q^ q^T (q^ = q / |q|, trace 1).

    Returns
    -------
    dict
        ``power_ratio_x_to_y`` = M_xx / M_yy (> 1: heights vary more along x, i.e. texture
        ridges run along y); ``dominant_direction_deg``: direction of the principal axis of M
        (the wave-vector direction with most power, degrees from +x in [0, 180));
        ``anisotropy_index`` = (l1 - l2) / (l1 + l2) of M's eigenvalues (0 isotropic, 1 fully
        one-directional); ``sector_angle_deg`` and ``sector_power_fraction``: weights summed
        in ``n_sectors`` sectors of wave-vector direction over [0, 180) (centres, fractions).

    Parameters
    ----------
    spec2d : Spectrum2D
        The 2D spectrum.
    q_min, q_max : float, optional
        Range of |q| [1/m].
    rings_per_decade : int, optional
        Rings for the normalising ring means.
    n_sectors : int, optional
        Direction sectors over 180 degrees.
    """
    qx, qy = np.asarray(spec2d.qx_per_m), np.asarray(spec2d.qy_per_m)
    Lx, Ly, dx, dy = _grid_of(spec2d)
    q_min, q_max = _default_range(Lx, Ly, dx, dy, q_min, q_max)
    half = getattr(spec2d, "half", None)
    if half is not None and getattr(spec2d, "_C", None) is None:
        return _anisotropy_half(half, qy.size, dx, dy, q_min, q_max, rings_per_decade, n_sectors)
    QX, QY = np.meshgrid(qx, qy)
    q = np.hypot(QX, QY).ravel()
    n = _ring_edges(q_min, q_max, rings_per_decade).size - 1
    ring = _ring_index(q, q_min, q_max, n)
    sel = ring >= 0
    r = ring[sel]
    C = np.asarray(spec2d.C_m4).ravel()[sel]
    cnt = np.bincount(r, minlength=n)
    csum = np.bincount(r, weights=C, minlength=n)
    ok = (cnt > 0) & (csum > 0)
    mean_c = np.where(ok, csum / np.maximum(cnt, 1), 1.0)
    w = np.where(ok[r], C / mean_c[r], 0.0)
    w /= w.sum()
    ux, uy = QX.ravel()[sel] / q[sel], QY.ravel()[sel] / q[sel]
    M = np.array([[np.sum(w * ux * ux), np.sum(w * ux * uy)], [np.sum(w * ux * uy), np.sum(w * uy * uy)]])
    ang = np.degrees(np.arctan2(uy, ux)) % 180.0
    sec = np.minimum((ang / 180.0 * n_sectors).astype(int), n_sectors - 1)
    return _summary(M, np.bincount(sec, weights=w, minlength=n_sectors), q_min, q_max)


def _summary(M, sector_power, q_min, q_max):
    """The anisotropy dict of the direction tensor ``M`` (2 x 2) and the weights summed per
    sector of wave-vector direction (``sector_power``, over [0, 180) degrees)."""
    n_sectors = sector_power.size
    evals, evecs = np.linalg.eigh(M)
    v = evecs[:, 1]
    theta = np.degrees(np.arctan2(v[1], v[0])) % 180.0
    return {
        "power_ratio_x_to_y": float(M[0, 0] / M[1, 1]),
        "dominant_direction_deg": float(theta),
        "anisotropy_index": float((evals[1] - evals[0]) / (evals[1] + evals[0])),
        "sector_angle_deg": ((np.arange(n_sectors) + 0.5) * 180.0 / n_sectors).tolist(),
        "sector_power_fraction": (sector_power / sector_power.sum()).tolist(),
        "q_range_per_m": (q_min, q_max),
    }


@lru_cache(maxsize=4)
def _sector_runs(ny, nx, dx, dy, q_min, q_max, n_rings, n_sectors):
    """Runs of equal (ring, sector) along the rows of the rfft half lattice, per band of rows
    (cached per grid): ring of 10-per-decade rings as in :func:`anisotropy`, sector of the
    wave-vector direction in [0, 180) degrees; key = ring * n_sectors + sector, -1 outside
    [q_min, q_max]. Also the number of full-lattice points per key."""
    qx, qy = _half_qx(nx, dx), 2 * np.pi * np.fft.fftfreq(ny, dy)
    nxr = qx.size
    wcol = np.full(nxr, 2.0)
    wcol[list(_mirror_columns(nx))] = 1.0
    bands, count = [], np.zeros(n_rings * n_sectors)
    for sl in row_chunks(ny, nxr):
        QX, QY = np.broadcast_arrays(qx[None, :], qy[sl, None])
        q = np.hypot(QX, QY)
        ring = _ring_index(q.ravel(), q_min, q_max, n_rings).reshape(q.shape)
        with np.errstate(invalid="ignore", divide="ignore"):
            ang = np.degrees(np.arctan2(QY / q, QX / q)) % 180.0
        sec = np.minimum(np.nan_to_num(ang / 180.0 * n_sectors).astype(np.int64), n_sectors - 1)
        key = np.where(ring >= 0, ring * n_sectors + sec, -1)
        flat = key.ravel()
        st = np.flatnonzero(np.concatenate([[True], flat[1:] != flat[:-1]]))
        ok = key >= 0
        count += np.bincount(key[ok], weights=np.broadcast_to(wcol, key.shape)[ok], minlength=count.size)
        edges = tuple((c, key[:, c].copy()) for c in _mirror_columns(nx))
        bands.append((sl, st, flat[st], edges))
    return bands, count


def _anisotropy_half(half, ny, dx, dy, q_min, q_max, rings_per_decade, n_sectors):
    """:func:`anisotropy` on the rfft half lattice (each stored point and its mirror -q have
    the same |q|, ring, direction modulo 180 degrees and q^ q^T): sums of C, C qx^2/q^2,
    C qy^2/q^2 and C qx qy/q^2 per (ring, sector), read band by band; float64."""
    nx = half.nx
    n = _ring_edges(q_min, q_max, rings_per_decade).size - 1
    bands, cnt = _sector_runs(ny, nx, dx, dy, q_min, q_max, n, n_sectors)
    qx, qy = _half_qx(nx, dx), 2 * np.pi * np.fft.fftfreq(ny, dy)
    nk = n * n_sectors
    sums = np.zeros((4, nk))
    P = half.P
    for sl, st, key, edges in bands:
        p = P[sl]
        q = np.hypot(qx[None, :], qy[sl, None])
        q[q == 0] = np.inf
        ux, uy = qx[None, :] / q, qy[sl, None] / q
        ok = key >= 0
        for i, a in enumerate((p, p * ux * ux, p * uy * uy, p * ux * uy)):
            part = np.add.reduceat(a.ravel(), st)[ok]
            sums[i] += 2.0 * np.bincount(key[ok], weights=part, minlength=nk)
            for c, kc in edges:  # columns stored once count once
                sel = kc >= 0
                sums[i] -= np.bincount(kc[sel], weights=a[:, c][sel], minlength=nk)
    cnt_r = cnt.reshape(n, n_sectors).sum(axis=1)
    csum_r = sums[0].reshape(n, n_sectors).sum(axis=1)
    ok = (cnt_r > 0) & (csum_r > 0)
    inv = np.where(ok, cnt_r / np.where(ok, csum_r, 1.0), 0.0)  # 1 / mean C of the ring
    wk = sums * np.repeat(inv, n_sectors)[None, :]  # weights C / mean C
    total = wk[0].sum()
    Mxx, Myy, Mxy = wk[1].sum() / total, wk[2].sum() / total, wk[3].sum() / total
    M = np.array([[Mxx, Mxy], [Mxy, Myy]])
    return _summary(M, wk[0].reshape(n, n_sectors).sum(axis=0), q_min, q_max)
