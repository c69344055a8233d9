"""Compiled priority-flood depression filling (the fast path of :func:`roadscan.rain.full_fill`).

Priority-Flood with a plain queue for the cells inside a depression (Barnes, Lehman and Mulla
2014, "Priority-Flood: An Optimal Depression-Filling and Watershed-Labeling Algorithm",
Computers & Geosciences 62, 117-127, Algorithm 2 "Priority-Flood+"). Written here from the
paper; compiled with numba (``cache=True``: the machine code is stored beside this file, so the
compile cost is paid once per installation, not per run).

The border cells are seeded at their own height; repeatedly the lowest open cell c is closed,
and every unvisited neighbour n gets the level max(h_n, level_c): a neighbour at or below the
level goes on a plain stack (it lies in a depression being filled at exactly that level, so
its order does not matter), a higher one on the priority queue. The level of a cell is then the
lowest, over all paths to the border, of the highest height on the path: the same values as
grayscale reconstruction by erosion from the border (each level is one of the heights, so the
results are bit-identical, not merely close).

Memory: the output (float64, n), a binary heap of (float64 key, int32 index) and a stack of
int32, both grown by doubling from the border's size; no other per-pixel storage (an unvisited
cell is marked by +inf in the output, and every effective height is finite).
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray

__all__ = ["priority_flood_fill"]


@njit(cache=True, nogil=True)
def _grow(a, n):
    """``a`` (its first ``n`` entries) in an array twice as long (compiled per dtype)."""
    b = np.empty(2 * a.size, dtype=a.dtype)
    b[:n] = a[:n]
    return b


@njit(cache=True, nogil=True, inline="always")
def _push(hk, hi, hn, z, i):
    """Put cell ``i`` at level ``z`` on the binary min-heap (keys ``hk``, cells ``hi``, ``hn``
    entries; grown when full): sift up from the end. Returns (hk, hi, hn + 1)."""
    if hn == hk.size:
        hk = _grow(hk, hn)
        hi = _grow(hi, hn)
    j = hn
    while j > 0:
        p = (j - 1) >> 1
        if hk[p] <= z:
            break
        hk[j] = hk[p]
        hi[j] = hi[p]
        j = p
    hk[j] = z
    hi[j] = i
    return hk, hi, hn + 1


@njit(cache=True, nogil=True, inline="always")
def _pop(hk, hi, hn):
    """Drop the root of the heap of ``hn`` entries: its last entry sifts down from the root,
    each step swapping with the lower child. Returns hn - 1."""
    hn -= 1
    z, zi = hk[hn], hi[hn]
    j, ch = 0, 1
    while ch < hn:
        ch += 1 if ch + 1 < hn and hk[ch + 1] < hk[ch] else 0
        if hk[ch] >= z:
            break
        hk[j], hi[j] = hk[ch], hi[ch]
        j, ch = ch, 2 * ch + 1
    hk[j], hi[j] = z, zi
    return hn


@njit(cache=True, nogil=True)
def _flood(h, low, conn8, out):
    """Fill ``h`` (ny, nx float64, C order; NaN/inf read as ``low``) into ``out`` (ny*nx)."""
    ny, nx = h.shape
    hf = h.ravel()
    n = ny * nx
    inf = np.inf
    for i in range(n):
        out[i] = inf
    cap = 2 * (ny + nx) + 1024
    hk = np.empty(cap, dtype=np.float64)  # heap keys (levels)
    hi = np.empty(cap, dtype=np.int32)  # heap cell indices
    hn = 0
    st = np.empty(cap, dtype=np.int32)  # plain stack of cells inside a depression
    sn = 0
    dr = np.array([-1, 1, 0, 0, -1, -1, 1, 1], dtype=np.int64)
    dc = np.array([0, 0, -1, 1, -1, 1, -1, 1], dtype=np.int64)
    nnb = 8 if conn8 else 4

    # seed: every border cell at its own (effective) height
    for r in range(ny):
        step = 1 if (r == 0 or r == ny - 1) else max(nx - 1, 1)
        c = 0
        while c < nx:
            i = r * nx + c
            z = hf[i]
            if not np.isfinite(z):
                z = low
            out[i] = z
            hk, hi, hn = _push(hk, hi, hn, z, i)
            c += step

    while hn > 0 or sn > 0:
        if sn > 0:
            sn -= 1
            ci = st[sn]
            lev = out[ci]
        else:
            ci = hi[0]
            lev = hk[0]
            hn = _pop(hk, hi, hn)
        r = ci // nx
        c = ci - r * nx
        for k in range(nnb):
            rr = r + dr[k]
            cc = c + dc[k]
            if rr < 0 or rr >= ny or cc < 0 or cc >= nx:
                continue
            ni = rr * nx + cc
            if out[ni] != inf:
                continue
            z = hf[ni]
            if not np.isfinite(z):
                z = low
            if z <= lev:
                out[ni] = lev
                if sn == st.size:
                    st = _grow(st, sn)
                st[sn] = ni
                sn += 1
            else:
                out[ni] = z
                hk, hi, hn = _push(hk, hi, hn, z, ni)


def priority_flood_fill(h: NDArray[np.float64], low: float, connectivity: int) -> NDArray[np.float64]:
    """Spill level of every cell of ``h`` [float64 (ny, nx)]; non-finite cells count as ``low``.

    Returns a new float64 (ny, nx) array; unmeasured cells get the level water passes through
    them at (the caller puts NaN back).

    Parameters
    ----------
    h : ndarray, shape (ny, nx)
        Heights [m].
    low : float
        Level given to non-finite cells (below every height).
    connectivity : {4, 8}
        Neighbourhood.

    Returns
    -------
    ndarray, shape (ny, nx)
        Spill level of every cell [m].

    References
    ----------
    R. Barnes, C. Lehman, D. Mulla, "Priority-flood: an optimal depression-filling and
    watershed-labeling algorithm for digital elevation models", Computers & Geosciences 62, 117
    (2014), doi:10.1016/j.cageo.2013.04.024.
    """
    h = np.ascontiguousarray(h, dtype=np.float64)
    if h.size >= 2**31 - 1:
        raise ValueError(f"height map too large for the priority-flood ({h.size} points)")
    out = np.empty(h.size, dtype=np.float64)
    _flood(h, float(low), connectivity == 8, out)
    return out.reshape(h.shape)
