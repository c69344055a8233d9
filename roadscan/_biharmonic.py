"""Biharmonic inpainting of unmeasured points with numpy only.

The same linear system as scikit-image's ``inpaint_biharmonic`` (Damelin & Hoang 2018; one
global solve, ``split_into_regions=False``): for every unmeasured point p,

    sum_k c_k u(p + k) = 0,

with the 13-point stencil of the squared 5-point Laplacian (c = 20 at p, -8 at its four
neighbours, 2 at the diagonals, 1 two points away along the axes); near the map's edges the
stencil is ``laplace(laplace(delta))`` on the window cut by the edge, with scipy.ndimage's
``reflect`` boundary, as scikit-image builds it. Measured heights move to the right-hand
side. The solution is clipped to the range of the measured heights, as scikit-image does.

The system is block-diagonal over clusters of unmeasured points that the stencil couples
(|dx| + |dy| <= 2): clusters are the 8-connected components of the mask dilated by its
4-neighbourhood (run-length labelling). Clusters of up to :data:`SMALL` points are solved
together as one batched dense solve (by size, 32 MiB at a time); a larger cluster is solved by
block elimination over pairs of its lines (the stencil reaches two lines, so the pairs form a
block-tridiagonal system), with dense LU on each block; the lines are rows, columns, diagonals
or antidiagonals, whichever gives the cluster the least LU work. Agreement with scikit-image's
sparse LU: 1e-13 of the height range on the shipped sample, 1e-15 on random maps with
clusters at every edge (tests).

Why not scikit-image: its sparse solve needs ``scipy.sparse.linalg``, and importing scipy
(1.17, with its array-API layer) took 0.3 s of the 0.9 s ``roadscan analyse`` of the sample;
this module is as fast as the sparse solve on such maps and needs no scipy.
"""

from __future__ import annotations

import contextlib
import importlib
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .bands import measured_mean_range
from .blas_threads import single_threaded_blas

try:  # numpy.linalg.solve's own gufunc: the same LAPACK gesv, 8 us less per call
    _gesv: Any = importlib.import_module("numpy.linalg._umath_linalg").solve
except (ImportError, AttributeError):  # pragma: no cover
    _gesv = None

__all__ = ["biharmonic_fill_values", "SMALL"]

#: clusters of at most this many unknowns go to the batched dense solve
SMALL = 128

_OFFSETS = np.array(
    [
        (0, 0),
        (-1, 0),
        (1, 0),
        (0, -1),
        (0, 1),
        (-1, -1),
        (-1, 1),
        (1, -1),
        (1, 1),
        (-2, 0),
        (2, 0),
        (0, -2),
        (0, 2),
    ]
)
_COEFS = np.array([20.0, -8, -8, -8, -8, 2, 2, 2, 2, 1, 1, 1, 1])
_edge_cache: dict = {}


def _laplace_reflect(a):
    """scipy.ndimage.laplace(a, mode="reflect") (d c b a | a b c d at the edges)."""
    p = np.pad(a, 1, mode="symmetric")
    return (p[:-2, 1:-1] + p[2:, 1:-1] - 2 * a) + (p[1:-1, :-2] + p[1:-1, 2:] - 2 * a)


def _edge_stencil(shape, center):
    """Offsets and coefficients of the stencil on a window cut by the map's edge."""
    key = (shape, center)
    if key not in _edge_cache:
        d = np.zeros(shape)
        d[center] = 1.0
        c = _laplace_reflect(_laplace_reflect(d))
        idx = np.nonzero(c)
        _edge_cache[key] = (np.stack(idx, 1) - np.array(center), c[idx])
    return _edge_cache[key]


def grow4(bad: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """``bad`` dilated by its 4-neighbourhood: two unmeasured points coupled by the stencil
    (|dx| + |dy| <= 2) are then 8-connected (scikit-image's ``split_into_regions`` grouping)."""
    grown = bad.copy()
    grown[1:] |= bad[:-1]
    grown[:-1] |= bad[1:]
    grown[:, 1:] |= bad[:, :-1]
    grown[:, :-1] |= bad[:, 1:]
    return grown


def _clusters(bad):
    """Cluster label (1..n, in raster order of each cluster's first point of the grown mask)
    of every unmeasured point, raster order.

    Run-length labelling: the runs of the grown mask along rows, two runs of adjacent rows
    joined when they touch diagonally or overlap (8-connectivity), their components found by
    hooking roots onto the smaller root and pointer jumping (Shiloach & Vishkin 1982).
    """
    ny, nx = bad.shape
    w = nx + 1
    e = np.zeros((ny, w + 1), np.int8)
    e[:, 1:-1] = grow4(bad)
    d = np.diff(e, axis=1)
    st = np.flatnonzero(d)  # row * w + column: start, end, ...
    st, en = st[0::2], st[1::2]
    del e, d
    nxt = st - st % w + w  # start of the next row
    lo = np.searchsorted(en, nxt + st % w)  # runs below ending at or after the
    hi = np.searchsorted(st, nxt + en % w, side="right")  # start, starting at or before the end
    cnt = np.maximum(hi - lo, 0)
    u = np.repeat(np.arange(st.size), cnt)
    v = np.arange(int(cnt.sum())) + np.repeat(lo - (np.cumsum(cnt) - cnt), cnt)
    p = np.arange(st.size)
    while u.size:
        pu, pv = p[u], p[v]
        keep = pu != pv
        if not keep.any():
            break
        u, v, pu, pv = u[keep], v[keep], pu[keep], pv[keep]
        np.minimum.at(p, np.maximum(pu, pv), np.minimum(pu, pv))
        while True:
            q = p[p]
            if np.array_equal(q, p):
                break
            p = q
    lab = np.cumsum(p == np.arange(st.size), dtype=np.int32)[p]
    pts = np.flatnonzero(bad)
    r, c = np.divmod(pts, nx)
    return lab[np.searchsorted(st, r * w + c, side="right") - 1]


#: unknowns per chunk of the system's assembly (bounds its (chunk, 13) work arrays)
_CHUNK = 1 << 13


def _stencil_groups(ps, ny, nx):
    """(unknowns, flat offsets, coefficients) of the interior stencil and of each cut window
    at the map's edge (at most 24 kinds: the window's shape and the point's place in it)."""
    r, c = np.divmod(ps, nx)
    inner = (r >= 2) & (r < ny - 2) & (c >= 2) & (c < nx - 2)
    flat = _OFFSETS[:, 0] * nx + _OFFSETS[:, 1]
    groups = [(np.flatnonzero(inner), flat, _COEFS)]
    e = np.flatnonzero(~inner)
    if e.size:
        re, ce = r[e], c[e]
        r0, c0 = np.maximum(re - 2, 0), np.maximum(ce - 2, 0)
        kind = np.stack([np.minimum(re + 3, ny) - r0, re - r0, np.minimum(ce + 3, nx) - c0, ce - c0])
        code = ((kind[0] * 5 + kind[1]) * 6 + kind[2]) * 5 + kind[3]
        for g in np.flatnonzero(np.bincount(code)):  # (np.unique would import numpy.ma)
            sel = np.flatnonzero(code == g)
            k = kind[:, sel[0]]
            offs, cf = _edge_stencil((int(k[0]), int(k[2])), (int(k[1]), int(k[3])))
            groups.append((e[sel], offs[:, 0] * nx + offs[:, 1], cf))
    return groups


def _system(h, ref, ps, where):
    """The system for z = h - ref in compressed rows: (rows, cols, vals), row pointers and
    right-hand side; unknowns numbered as ``ps`` (their flat positions, solve order) and
    ``where`` (solve index of every map point, -1 if measured). The heights read at unknowns
    are not used."""
    ny, nx = h.shape
    n = ps.size
    zf = h.ravel()
    rhs = np.zeros(n)
    cnt = np.zeros(n, np.intp)
    parts = []
    for sel, off, cf in _stencil_groups(ps, ny, nx):
        for i0 in range(0, sel.size, _CHUNK):
            s = sel[i0 : i0 + _CHUNK]
            nb = ps[s, None] + off
            j = where[nb]
            unk = j >= 0
            rhs[s] -= (np.where(unk, ref, zf[nb]) - ref) @ cf
            f = np.flatnonzero(unk)  # entries by row, then offset
            c = np.bincount(f // off.size, minlength=s.size)
            cnt[s] = c
            parts.append((s, c, j.ravel()[f], cf[f % off.size]))
    rowptr = np.zeros(n + 1, np.intp)
    np.cumsum(cnt, out=rowptr[1:])
    cols = np.empty(int(rowptr[-1]), np.intp)
    vals = np.empty(int(rowptr[-1]))
    for s, c, j, v in parts:
        dest = np.arange(j.size) + np.repeat(rowptr[s] - (np.cumsum(c) - c), c)
        cols[dest] = j
        vals[dest] = v
    rows = np.repeat(np.arange(n), cnt)
    return (rows, cols, vals), rowptr, rhs


#: matrix entries of one batched dense solve (32 MiB of float64)
_BATCH_ENTRIES = 1 << 22


def _solve_small(coo, rowptr, rhs, start, sizes, x):
    """All clusters of ``sizes`` (each <= SMALL) as batched dense solves, by size, at most
    :data:`_BATCH_ENTRIES` matrix entries at a time."""
    for m in np.flatnonzero(np.bincount(sizes)):
        same = start[sizes == m]  # solve-order start of each such cluster
        step = max(1, _BATCH_ENTRIES // int(m * m))
        for i0 in range(0, same.size, step):
            _solve_batch(coo, rowptr, rhs, same[i0 : i0 + step], int(m), x)


def _gather(lo, hi):
    """Concatenated ranges [lo_i, hi_i)."""
    lens = hi - lo
    return np.arange(int(lens.sum())) + np.repeat(lo - (np.cumsum(lens) - lens), lens)


def _solve_batch(coo, rowptr, rhs, first, m, x):
    """Clusters of m unknowns starting at ``first`` (solve order): one stacked dense solve."""
    rows, cols, vals = coo
    k = first.size
    lo, hi = rowptr[first], rowptr[first + m]  # each cluster's entries (rows sorted)
    e = _gather(lo, hi)
    ci = np.repeat(np.arange(k), hi - lo)
    base = first[ci]
    A = np.zeros((k, m, m))
    A[ci, rows[e] - base, cols[e] - base] = vals[e]
    at = first[:, None] + np.arange(m)[None, :]
    x[at] = np.linalg.solve(A, rhs[at][..., None])[..., 0]


#: matrix entries of the elimination's buffer (1 MiB: cached, and reused by the allocator)
_BUFFER_ENTRIES = 1 << 17

#: the fixed cost of one block in the elimination (Python and LAPACK call), in units of the
#: cubed block size
_BLOCK_COST = 1e4


def _blocks(start, sizes, pr, pc):
    """Unknowns of the large clusters (solve order) sorted by block, and each one's block.

    A block is two adjacent lines of a cluster (rows, columns, diagonals r + c or
    antidiagonals r - c, and either parity): the stencil reaches two lines, so the blocks form
    a block-tridiagonal system. Each cluster takes the kind of line with the least work: the
    sum of the cubed block sizes (LU) and :data:`_BLOCK_COST` per block."""
    idx = _gather(start, start + sizes)
    cl = np.repeat(np.arange(sizes.size), sizes)
    first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    r, c = pr[idx], pc[idx]
    best, blk = np.full(sizes.size, np.inf), np.zeros(idx.size, np.intp)
    for line in (r, c, r + c, r - c):
        line = line - np.minimum.reduceat(line, first)[cl]
        span = int(line.max()) // 2 + 2
        for parity in (0, 1):
            b = (line + parity) // 2
            nk = np.bincount(cl * span + b, minlength=sizes.size * span).astype(float)
            work = (nk**3 + _BLOCK_COST * (nk > 0)).reshape(sizes.size, span).sum(1)
            take = work < best
            best[take] = work[take]
            sel = take[cl]
            blk[sel] = b[sel]
    o = np.lexsort((blk, cl))  # by cluster, block; raster inside
    key = cl[o] * (int(blk.max()) + 1) + blk[o]
    return idx[o], cl[o], np.cumsum(np.r_[True, key[1:] != key[:-1]]) - 1


def _solve_large(coo, rowptr, rhs, start, sizes, pr, pc, x):
    """Clusters of more than SMALL unknowns (solve-order starts ``start``), by block
    elimination over the blocks of :func:`_blocks`: D_k = A_kk - A_k,k-1 D_k-1^-1 A_k-1,k,
    [G_k | g_k] = D_k^-1 [A_k,k+1 | y_k] (block-tridiagonal LU), then back substitution
    x_k = g_k - G_k x_k+1."""
    u, cl, gb = _blocks(start, sizes, pr, pc)
    nbk = int(gb[-1]) + 1
    bs = np.bincount(gb, minlength=nbk)  # block sizes
    b0 = np.concatenate([[0], np.cumsum(bs)[:-1]])
    bcl = cl[b0]  # cluster of each block
    sp = np.where(np.r_[False, bcl[1:] == bcl[:-1]], np.r_[0, bs[:-1]], 0)  # previous block
    sn = np.where(np.r_[bcl[:-1] == bcl[1:], False], np.r_[bs[1:], 0], 0)  # next block
    w = sp + bs + sn + 1  # [A_k,k-1 | A_kk | A_k,k+1 | y]
    off = np.concatenate([[0], np.cumsum(bs * w)])
    loc = np.empty(x.size, np.intp)  # unknown -> position in sorted order
    loc[u] = np.arange(u.size)
    X = [None] * nbk
    k0 = 0
    while k0 < nbk:  # blocks of at most _BUFFER_ENTRIES
        k1 = int(np.searchsorted(off, off[k0] + _BUFFER_ENTRIES, side="right")) - 1
        k1 = min(max(k0 + 1, k1), nbk)
        _eliminate(coo, rowptr, rhs, u, loc, gb, (bs, sp, w, off, b0), k0, k1, X)
        k0 = k1
    v = np.ones(u.size + nbk)  # x_k of each block, then a 1
    at = b0 + np.arange(nbk)
    nxt = at + bs + (sn > 0)  # [x_k+1 | 1], or the block's own 1
    for k, a, s, b, c in zip(
        range(nbk - 1, -1, -1),
        at[::-1].tolist(),
        bs[::-1].tolist(),
        nxt[::-1].tolist(),
        (nxt + sn + 1)[::-1].tolist(),
    ):
        np.matmul(X[k], v[b:c], out=v[a : a + s])  # x_k = g_k - G_k x_k+1
    x[u] = v[np.arange(u.size) + gb]


def _singular(err, flag):
    """numpy's error callback while :func:`_solve_gufunc` runs: LAPACK found a zero pivot."""
    raise np.linalg.LinAlgError("Singular matrix")


def _solve_gufunc(a, b):
    """``np.linalg.solve(a, b)`` for float64 (a, b) without its argument checks."""
    return _gesv(a, b, signature="dd->d")


def _eliminate(coo, rowptr, rhs, u, loc, gb, meta, k0, k1, X):
    """Forward elimination of blocks k0..k1-1 (their matrices built in one buffer)."""
    bs, sp, w, off, b0 = meta
    a, b = int(b0[k0]), int(b0[k1 - 1] + bs[k1 - 1])  # their unknowns (sorted order)
    g = gb[a:b]
    o0 = off[k0]
    row = off[g] - o0 + (np.arange(a, b) - b0[g]) * w[g]  # each row's place in the buffer
    cnt = rowptr[u[a:b] + 1] - rowptr[u[a:b]]
    e = _gather(rowptr[u[a:b]], rowptr[u[a:b] + 1])
    j = loc[coo[1][e]]
    v = coo[2][e]
    right = j >= np.repeat(b0[g] + bs[g], cnt)  # in the next block: -A_k,k+1
    v[right] *= -1
    buf = np.zeros(int(off[k1] - o0))
    buf[np.repeat(row - (b0[g] - sp[g]), cnt) + j] = v
    buf[row + w[g] - 1] = rhs[u[a:b]]
    del e, j, v, right
    if _gesv is None:
        solve, guard = np.linalg.solve, contextlib.nullcontext()
    else:  # a singular block raises LinAlgError, as np.linalg.solve does
        solve = _solve_gufunc
        guard = np.errstate(call=_singular, invalid="call", over="ignore", divide="ignore", under="ignore")
    with guard:
        _forward(buf, (bs, sp, w, off - o0), k0, k1, X, solve)


def _forward(buf, meta, k0, k1, X, solve):
    """Block-tridiagonal LU of blocks k0..k1-1 in ``buf``: X_k = [-G_k | g_k]."""
    bs, sp, w, off = meta
    prev = X[k0 - 1] if k0 else None
    for k, s, p, q, o in zip(
        range(k0, k1), bs[k0:k1].tolist(), sp[k0:k1].tolist(), w[k0:k1].tolist(), off[k0:k1].tolist()
    ):
        R = buf[o : o + s * q].reshape(s, q)
        D = R[:, p : p + s]
        if p:
            upd = R[:, :p] @ prev  # A_k,k-1 [-G | g]
            D += upd[:, :s]
            y = R[:, -1]
            y -= upd[:, s]
        X[k] = prev = solve(D, R[:, p + s :])


def biharmonic_fill_values(
    h: NDArray[np.float64], bad: NDArray[np.bool_], stats: tuple[float, float, float] | None = None
) -> NDArray[np.float64]:
    """Biharmonic heights for the unmeasured points of a map (see the module docstring).

    Parameters
    ----------
    h : (ny, nx) float64 array
        Heights [m]; values at ``bad`` are ignored (NaN is fine there).
    bad : (ny, nx) bool array
        Unmeasured points (at least one measured point).
    stats : tuple of float, optional
        (mean, min, max) of the measured heights: the system is solved for h - mean (as
        scikit-image is called by :mod:`roadscan.inpaint`) and clipped to [min, max]; computed
        here when not given.

    Returns
    -------
    ndarray, shape (n_unmeasured,)
        float64, raster (C) order: ``h[bad] = values`` fills the map. Memory: an index map
        (int32) and the grown mask (bytes), a few arrays per unmeasured point and the
        [G_k | g_k] blocks of the large clusters; no copy of the map.
    """
    h = np.ascontiguousarray(h, dtype=np.float64)
    bad = np.ascontiguousarray(bad, dtype=bool)
    pts = np.flatnonzero(bad)
    if pts.size == 0:
        return np.empty(0)
    if stats is None:
        stats = measured_mean_range(h, bad)
    ref = float(stats[0])
    lo, hi = float(stats[1]) - ref, float(stats[2]) - ref
    lab = _clusters(bad)
    order_sorted = np.argsort(lab, kind="stable")  # unknowns by cluster, raster inside
    ps = pts[order_sorted]  # flat position of each, solve order
    where = np.full(h.size, -1, np.int32 if pts.size < 2**31 else np.intp)
    where[ps] = np.arange(pts.size)
    counts = np.bincount(lab)[1:]
    counts = counts[counts > 0]
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    x = np.empty(pts.size)
    small = counts <= SMALL
    with single_threaded_blas():  # many small products: no thread pool
        coo, rowptr, rhs = _system(h, ref, ps, where)
        del where
        if small.any():
            _solve_small(coo, rowptr, rhs, start[small], counts[small], x)
        if not small.all():
            pr, pc = np.divmod(ps, bad.shape[1])
            _solve_large(coo, rowptr, rhs, start[~small], counts[~small], pr, pc, x)
    np.clip(x, lo, hi, out=x)
    out = np.empty(pts.size)
    out[order_sorted] = x + ref
    return out
