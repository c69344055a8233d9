"""Ring geometry of the FFT lattice: log-spaced rings of |q| and their bookkeeping.

Rings are log-spaced from q_min = 2 pi / L (the longer side) to the Nyquist wave vector
q_max = pi / max(dx, dy), ``rings_per_decade`` per decade rounded so that they tile
[q_min, q_max] exactly: edges q_min (q_max / q_min)^(k / n), k = 0 .. n. On the rfft2 half
lattice every column but q_x = 0 (and the Nyquist column of an even n_x) stands for itself and
its mirror -q, so ring sums count it twice.

Reference: Jacobs, Junge, Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017), sec. 2.3.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .bands import row_chunks

__all__: list[str] = []  # helpers of the spectrum modules, private names


def _ring_edges(q_min, q_max, rings_per_decade):
    if not (0 < q_min < q_max):
        raise ValueError(f"need 0 < q_min < q_max, got {q_min}, {q_max}")
    n = max(1, int(np.ceil(rings_per_decade * np.log10(q_max / q_min) - 1e-9)))
    return q_min * (q_max / q_min) ** (np.arange(n + 1) / n)


def _ring_index(q, q_min, q_max, n_rings):
    """Ring number of each |q| (-1 outside [q_min, q_max]); rings log-spaced."""
    qc = np.maximum(q, q_min * 1e-3)
    r = np.floor(np.log(qc / q_min) / np.log(q_max / q_min) * n_rings).astype(np.int64)
    r = np.clip(r, 0, n_rings - 1)  # |q| == q_min or q_max up to round-off
    r[(q < q_min * (1 - 1e-12)) | (q > q_max * (1 + 1e-12)) | (q <= 0)] = -1
    return r


def _half_qx(nx, dx):
    """qx [1/m] of the rfft half lattice's columns as they sit on the full lattice: the
    Nyquist column of an even nx is q_x = -pi/dx there (numpy's fftfreq), the others >= 0."""
    return 2 * np.pi * np.fft.fftfreq(nx, dx)[: nx // 2 + 1]


def _mirror_columns(nx):
    """Columns of the rfft half lattice stored once on the full lattice (q_x = 0 and, for an
    even nx, the Nyquist column); every other column stands for itself and its mirror -q."""
    return (0, nx // 2) if nx % 2 == 0 and nx > 1 else (0,)


@lru_cache(maxsize=8)
def _ring_runs(ny, nx, dx, dy, q_min, q_max, n_rings):
    """Ring bookkeeping on the rfft2 half lattice (cached per grid; a few MB whatever the size).

    Along a row of the half lattice |q| grows with q_x, so the ring number is constant on
    runs of consecutive points: ``starts`` are the flat indices where a run begins and
    ``ring`` its ring (-1 outside [q_min, q_max]), so that ring sums are one
    ``np.add.reduceat`` pass. ``edges`` are (column, rings of its points) of the columns
    stored once (:func:`_mirror_columns`); ``count`` and ``qsum`` are the number of full-
    lattice points per ring and the sum of their |q|.
    """
    qx = 2 * np.pi * np.fft.rfftfreq(nx, dx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, dy)
    nxr = qx.size
    wcol = np.full(nxr, 2.0)
    wcol[list(_mirror_columns(nx))] = 1.0
    starts, rings = [], []
    count = np.zeros(n_rings)
    qsum = np.zeros(n_rings)
    edge_rings = {c: np.empty(ny, dtype=np.int64) for c in _mirror_columns(nx)}
    for sl in row_chunks(ny, nxr):
        q = np.hypot(qx[None, :], qy[sl, None])
        ring = _ring_index(q.ravel(), q_min, q_max, n_rings).reshape(q.shape)
        for c, er in edge_rings.items():
            er[sl] = ring[:, c]
        flat = ring.ravel()
        st = np.flatnonzero(np.concatenate([[True], flat[1:] != flat[:-1]]))
        starts.append(st + sl.start * nxr)
        rings.append(flat[st])
        ok = ring >= 0
        wt = np.broadcast_to(wcol, ring.shape)[ok]
        count += np.bincount(ring[ok], weights=wt, minlength=n_rings)
        qsum += np.bincount(ring[ok], weights=wt * q[ok], minlength=n_rings)
    out = (np.concatenate(starts), np.concatenate(rings), tuple(edge_rings.items()), count, qsum)
    for a in (out[0], out[1], out[3], out[4], *edge_rings.values()):
        a.setflags(write=False)
    return out


def _ring_sums(P, runs, n_rings):
    """Sum over the full lattice of P in each ring, from the rfft half lattice ``P``."""
    starts, ring, edges = runs[0], runs[1], runs[2]
    part = np.add.reduceat(P.ravel(), starts)
    ok = ring >= 0
    csum = 2.0 * np.bincount(ring[ok], weights=part[ok], minlength=n_rings)
    for c, er in edges:
        sel = er >= 0
        csum -= np.bincount(er[sel], weights=P[:, c][sel], minlength=n_rings)
    return csum


def _default_range(Lx, Ly, dx, dy, q_min, q_max):
    q_min = 2 * np.pi / max(Lx, Ly) if q_min is None else float(q_min)
    q_max = np.pi / max(dx, dy) if q_max is None else float(q_max)
    return q_min, q_max


def _grid_of(spec2d):
    """(Lx, Ly, dx, dy) of a 2D map: from its meta when present (exact), else its lattice."""
    qx, qy = np.asarray(spec2d.qx_per_m), np.asarray(spec2d.qy_per_m)
    m = spec2d.meta
    if all(k in m for k in ("dx_m", "dy_m", "nx", "ny")) and (m["nx"], m["ny"]) == (qx.size, qy.size):
        dx, dy = float(m["dx_m"]), float(m["dy_m"])
        return qx.size * dx, qy.size * dy, dx, dy
    Lx, Ly = 2 * np.pi / abs(qx[1] - qx[0]), 2 * np.pi / abs(qy[1] - qy[0])
    return Lx, Ly, Lx / qx.size, Ly / qy.size
