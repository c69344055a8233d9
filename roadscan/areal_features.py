"""Feature parameters of ISO 25178-2:2012 (section 4.6): Spd, Spc, S5p, S5v and S10z.

Segmentation (ISO 25178-2 section 6, ISO 16610-85): the surface is cut into hills, each the
basin of one local maximum (8 neighbours: the watershed of -z), and hills are merged by Wolf
pruning: a hill whose height above its highest saddle to a higher hill is below the threshold
T = 5 % of Sz is merged into that neighbour, until none is left. Merging from the highest
saddle down (the change tree) gives each hill's summit its height above the saddle where it
meets a higher one, its topographic prominence; a peak survives exactly when its prominence
is at least T. This is the same set as the h-maxima transform's (scikit-image ``h_maxima``,
tested against it) and as a union-find over the points from the highest down (tested too).

How it is computed, in numpy and OpenCV's table look-up (the critical points of the discrete
surface, :mod:`roadscan.areal_critical`): heights are ordered by (z, flattened index); the 8-bit
pattern of each point's higher neighbours comes from four comparisons on the flattened field (each
also gives the opposite neighbour's bit); a point with none is a maximum, a point whose higher
neighbours form two or more groups (8-adjacency among them) is a possible saddle, the only
places where components of the superlevel set meet (looked up in a table only where the ring
holds two runs of higher neighbours or more). From each group of a saddle a path uphill, all
paths in one vectorised walk, reaches the maximum of that component; the saddle heights between
maxima then form the hill graph, merged by vectorised Boruvka rounds (a component whose highest
edge leads to a higher one merges there, as the ordered merging would; the components left are
numbered afresh) and the ordered merging of the few edges left. Pits likewise, on the neighbour
patterns reversed (their critical points come from the same pass). For the parameters only the
significant set is needed: a component standing at least T above its highest saddle has a
prominence of at least T, edges between two such are dropped, and the rounds stop when no other
component is left. When the pits are not counted, S5v needs only the five deepest significant
pits: the lowest minima are decided first, on the critical points near their heights (``_pits``).
An edge at least T below both of its summits is dropped from the start (it changes no answer:
``_needed``; 274k -> 213k edges and half the Boruvka work on a 2048^2 asphalt-like map).

- Spd [1/m^2] = number of significant peaks / projected area;
- Spc [1/m] = -(1/2) mean over significant peaks of (d2z/dx2 + d2z/dy2), second differences
  at the peak's highest point (peaks on the border excluded);
- S5p [m] = mean height of the five highest significant peaks, S5v [m] = mean depth of the
  five deepest significant pits (heights from the mean plane; fewer when fewer exist);
  S10z = S5p + S5v.

A peak or pit whose extreme point lies on the border of the field is not counted (it may
be the flank of a feature cut by the field's edge).

Unmeasured points take the mean height (zero) before segmentation.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .areal_critical import (
    _NGROUPS,
    _REPS,
    _RING,
    _STEP,
    _critical_points,
    _lookup,
    _lower_code,
    _patterns,
)

__all__ = ["feature_parameters", "prominences", "PRUNE_FRACTION"]

#: Wolf pruning threshold as a fraction of Sz (ISO 25178-2 default for Spd and S10z)
PRUNE_FRACTION = 0.05


def _climb(flat, start, step, sparse=0.3):
    """Where the paths from ``start`` end: each point steps to the neighbour ``step[pattern]``
    until the pattern is 0 (an extremum). Ended paths stand still (the step of pattern 0 is
    made 0) until fewer than ``sparse`` of those carried on are still moving. Positions are
    intp (numpy converts any other index type on every gather)."""
    step = step.copy()
    step[0] = 0
    end = start.astype(np.intp)  # (a copy)
    pos, slot = end, None  # slot: which paths pos holds (None: all)
    for _ in range(flat.size + 1):  # (no path is longer: heights increase)
        c = np.take(flat, pos)
        moving = np.count_nonzero(c)
        if moving == 0:
            break
        if moving < sparse * pos.size:
            if slot is not None:
                end[slot] = pos
            keep = np.flatnonzero(c != 0)
            slot = keep if slot is None else np.take(slot, keep)
            pos, c = np.take(pos, keep), np.take(c, keep)
        pos += _lookup(step, c)
    else:
        raise ValueError("the heights are not ordered (infinite values?)")
    if slot is not None:
        end[slot] = pos
    return end


def _critical_graph(flat, nx, extrema, sad, label):
    """(edges a, b between extrema indices, and the saddle of each edge as its index in
    ``sad``) from the patterns ``flat``: a point whose higher neighbours form g >= 2 groups may
    join g components of the superlevel set above it; each group is followed uphill (a higher
    neighbour each step, so the path stays above the point) to the maximum it belongs to, and
    the first group's maximum is joined to each other's. ``label`` is int32 scratch of the
    size of ``flat``."""
    off = np.array([dy * nx + dx for dy, dx in _RING], dtype=np.int64 if flat.size >= 2**31 else np.int32)
    reps = np.where(_REPS >= 0, off[_REPS], 0)  # (256, 4): where each group's path starts
    sad = sad.astype(np.intp, copy=False)
    sc = np.take(flat, sad)
    more = [np.flatnonzero(_lookup(_NGROUPS, sc) > j) for j in (2, 3)]  # a third, a fourth
    start = np.concatenate(
        [sad + _lookup(reps[:, 0].copy(), sc), sad + _lookup(reps[:, 1].copy(), sc)]
        + [np.take(sad, i) + _lookup(reps[:, j + 2].copy(), np.take(sc, i)) for j, i in enumerate(more)]
    )
    end = _climb(flat, start, np.take(off, _STEP))
    label[extrema] = np.arange(extrema.size, dtype=np.int32)
    dest = np.take(label, end)
    n = sad.size
    first = np.concatenate([dest[:n]] + [np.take(dest, i) for i in more])
    return first, dest[n:], np.concatenate([np.arange(n)] + more)


def _needed(top, a, b, saddle, threshold):
    """Which edges (a, b, saddle) between components (summits ``top``) can change an answer:
    those joining two components, and, with a ``threshold``, only those less than it below
    the lower summit. An edge at least the threshold below both summits cannot: whoever
    merges through it into a higher component has a summit at least as high as one of them,
    so a prominence of at least the threshold there; and a path to a higher summit through it
    reaches first one of its ends, higher than its start (a path as good, without the edge)
    or not (then the start stands at least the threshold above the edge too)."""
    if threshold is None:
        return np.flatnonzero(a != b)
    low = np.minimum(np.take(top, a), np.take(top, b))
    low -= saddle
    return np.flatnonzero((low < threshold) & (a != b))


def _change_tree(top, a, b, saddle, threshold=None, few=1000):
    """Prominence of each maximum (heights ``top``, in flattened-index order) over the graph of
    saddle edges: Kruskal's merging from the highest saddle down, where the lower component's
    summit gets its height above the saddle.

    First vectorised Boruvka rounds until at most ``few`` edges are left: a component whose
    highest edge leads to a higher component is merged into it at that edge (exactly what the
    ordered merging does, as no other edge of it comes earlier); the components left are then
    numbered afresh. Then the ordered merging of the rest, each pair of components once with
    its highest saddle. With a ``threshold``, only whether a prominence reaches it is exact: a
    component standing at least that far above its highest saddle has a prominence at least
    that (a later merging saddle is lower) and is left infinite; an edge between two such is
    dropped (a path through such a component, lower than where it starts, dips at least that
    far); the rounds stop when none other is left."""
    prom = np.full(top.size, np.inf)
    ids = np.arange(top.size)  # the summit of each component left
    keep = _needed(top, a, b, saddle, threshold)
    a, b = np.take(a, keep).astype(np.intp), np.take(b, keep).astype(np.intp)  # (indices)
    saddle = np.take(saddle, keep)
    while a.size > few:
        m = top.size
        best = np.full(m, -np.inf)  # the highest saddle of each component
        np.maximum.at(best, a, saddle)
        np.maximum.at(best, b, saddle)
        if threshold is not None:
            low = top - best < threshold
            low[m - 1 - np.argmax(top[::-1])] = False  # the highest summit
            nlow = np.count_nonzero(low)
            if nlow == 0:
                return prom
            if nlow < m // 2:  # an edge between two such is no longer needed
                keep = np.flatnonzero(np.take(low, a) | np.take(low, b))
                a, b, saddle = np.take(a, keep), np.take(b, keep), np.take(saddle, keep)
        edge = np.full(m, -1)  # an edge reaching it (equal saddles: any)
        on = np.flatnonzero(saddle == np.take(best, b))
        edge[np.take(b, on)] = on
        on = np.flatnonzero(saddle == np.take(best, a))
        edge[np.take(a, on)] = on
        v = np.flatnonzero(edge >= 0)
        e = np.take(edge, v)
        ea, eb = np.take(a, e), np.take(b, e)
        o = np.where(ea == v, eb, ea)
        tv, to = np.take(top, v), np.take(top, o)
        up = np.flatnonzero((to > tv) | ((to == tv) & (o > v)))  # equal heights: by index
        if not up.size:
            break
        v, o = np.take(v, up), np.take(o, up)
        prom[np.take(ids, v)] = np.take(tv, up) - np.take(saddle, np.take(e, up))
        root = np.arange(m)
        root[v] = o
        while True:  # to the final component, by pointer jumping
            nxt = np.take(root, o)
            if np.array_equal(nxt, o):
                break
            o = nxt
            root[v] = o
        left = np.ones(m, bool)
        left[v] = False
        renumber = np.cumsum(left) - 1
        ids, top = ids[left], top[left]
        root = np.take(renumber, root)
        a, b = np.take(root, a), np.take(root, b)
        keep = _needed(top, a, b, saddle, threshold)
        a, b, saddle = np.take(a, keep), np.take(b, keep), np.take(saddle, keep)
    if a.size:  # each pair once, with its highest saddle,
        order = np.argsort(saddle, kind="stable")[::-1]  # from the highest down
        a, b, saddle = a[order], b[order], saddle[order]
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        _, first = np.unique(lo.astype(np.int64) * top.size + hi, return_index=True)
        first.sort()
        a, b, saddle = a[first], b[first], saddle[first]
    parent = {}
    topl, idl = top.tolist(), ids.tolist()

    def find(i):
        while True:
            p = parent.get(i, i)
            if p == i:
                return i
            g = parent.get(p, p)
            parent[i] = g  # path halving
            i = g

    for e, sa, sb in zip(saddle.tolist(), a.tolist(), b.tolist()):
        ra, rb = find(sa), find(sb)  # a component is named by its summit
        if ra == rb:
            continue
        if (topl[ra], ra) < (topl[rb], rb):
            ra, rb = rb, ra
        prom[idl[rb]] = topl[rb] - e
        parent[rb] = ra
    return prom


def _extremum_prominences(flat, nx, extrema, sad, label, top, sh, threshold=None):
    """Prominence of each extremum (flattened indices ``extrema``, heights ``top``), ``flat``
    the patterns of higher neighbours, ``sad`` the possible saddles (heights ``sh``); for pits
    all heights negated."""
    a, b, s = _critical_graph(flat, nx, extrema, sad, label)
    return _change_tree(top, a, b, np.take(sh, s), threshold)


def prominences(z: NDArray[np.float64]) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """(flattened summit indices, their prominence [m]) of every local maximum of ``z``: the
    height of the summit above the highest saddle through which a higher summit is reached
    (infinite for the highest). Equal heights are ordered by flattened index.

    Parameters
    ----------
    z : ndarray, shape (ny, nx)
        Heights [m].

    Returns
    -------
    summits : ndarray of int
        Flattened indices of the local maxima.
    prominence : ndarray
        Their prominence [m].

    References
    ----------
    ISO 25178-2:2021, 5.4 (feature parameters, Wolf pruning by prominence); the change tree
    of the critical points: Wolf, G. W. (1991), A Fortran subroutine for cartographic
    generalization, Computers & Geosciences 17, 1359-1381.
    """
    z = np.asarray(z, dtype=np.float64)
    order, code, cand = _patterns(z, z.mean())
    (maxima, sad, _, _), (top, sh, _, _) = _critical_points(code, _lower_code(code), cand, z)
    label = order.view(np.int32).ravel()  # scratch now
    return maxima, _extremum_prominences(code.ravel(), z.shape[1], maxima, sad, label, top, sh)


def _significant(z, extrema, prom, threshold, sign, shift=0.0):
    """(row, column) of each significant interior extremum of ``z`` and its height less
    ``shift`` (times ``sign``)."""
    keep = extrema[prom >= threshold]
    ny, nx = z.shape
    r, c = keep // nx, keep % nx
    inner = (r > 0) & (r < ny - 1) & (c > 0) & (c < nx - 1)
    pos = np.stack([r[inner], c[inner]], axis=1)
    return pos, sign * (z[pos[:, 0], pos[:, 1]] - shift)


def _pits(z, low, minima, vsad, zmin, zvs, label, T, shift, deepest=None):
    """:func:`_significant` pits of ``z``: all of them, or at least the ``deepest`` (n) deepest.

    With ``deepest``, only the k lowest minima (k = 64, 256, ...) are decided, on the minima
    and saddles of the pits below the k-th lowest minimum plus 2T: a minimum's significance
    depends only on the saddles less than T above it (the ordered merging takes the saddles
    from the lowest up: it runs the same on these until then). The first k giving n
    significant interior pits gives the n deepest of all."""
    k, nx = 64, z.shape[1]
    while deepest is not None and k < minima.size:
        zk = np.partition(zmin, k - 1)[k - 1]
        mi, si = np.flatnonzero(zmin < zk + 2 * T), np.flatnonzero(zvs < zk + 2 * T)
        prom = _extremum_prominences(low.ravel(), nx, minima[mi], vsad[si], label, -zmin[mi], -zvs[si], T)
        sure = zmin[mi] <= zk
        pos, hv = _significant(z, minima[mi][sure], prom[sure], T, -1.0, shift)
        if hv.size >= deepest:
            return pos, hv
        k *= 4
    prom = _extremum_prominences(low.ravel(), nx, minima, vsad, label, -zmin, -zvs, T)
    return _significant(z, minima, prom, T, -1.0, shift)


def feature_parameters(
    heights_m: NDArray[np.float64],
    dx_m: float,
    dy_m: float,
    prune_fraction: float = PRUNE_FRACTION,
    *,
    mean: float | None = None,
    z_min: float | None = None,
    z_max: float | None = None,
    count_pits: bool = True,
) -> dict[str, Any]:
    """Spd, Spc, S5p, S5v, S10z of a levelled height map (module docstring).

    Parameters
    ----------
    heights_m : ndarray, shape (ny, nx)
        Heights [m] (mean plane at zero, or at ``mean``), NaN where unmeasured.
    dx_m, dy_m : float
        Spacings along x (columns) and y (rows) [m].
    prune_fraction : float
        Wolf pruning threshold as a fraction of Sz (0.05).
    mean : float, optional
        When given, ``heights_m`` are all finite and the figures are those of ``heights_m -
        mean`` (the same values, without that full-size copy: only the heights used are
        shifted).
    z_min, z_max : float, optional
        The lowest and highest of ``heights_m`` when already known (all finite) [m].
    count_pits : bool
        False: the pits are not counted, only the five deepest significant ones are found
        (S5v; far fewer critical points to merge). The figures are the same.

    Returns
    -------
    dict
        Keys ``Spd_per_m2``, ``Spc_per_m``, ``S10z_m``, ``S5p_m``, ``S5v_m`` and ``features_note``
        (the threshold, the number of significant peaks and of pits, unless not counted).
    """
    z = np.asarray(heights_m, dtype=np.float64)
    shift = 0.0 if mean is None else float(mean)  # the heights are z - shift
    if mean is None:
        mean = z.mean()
        if np.isnan(mean) and np.isnan(z).any():  # (NaN anywhere makes the mean NaN)
            z = np.where(np.isfinite(z), z, 0.0)
            mean = z.mean()
    lo = z.min() if z_min is None else z_min
    hi = z.max() if z_max is None else z_max
    ny, nx = z.shape
    sz = float((hi - shift) - (lo - shift))  # max and min of z - shift
    if sz <= 0:
        return {
            "Spd_per_m2": 0.0,
            "Spc_per_m": None,
            "S10z_m": 0.0,
            "S5p_m": 0.0,
            "S5v_m": 0.0,
            "features_note": "flat surface: no peak, no pit",
        }
    T = prune_fraction * sz
    order, code, cand = _patterns(z, mean)
    low = _lower_code(code)
    (maxima, psad, minima, vsad), (zmax, zps, zmin, zvs) = _critical_points(code, low, cand, z, shift)
    label = order.view(np.int32).ravel()  # scratch now
    prom = _extremum_prominences(code.ravel(), nx, maxima, psad, label, zmax, zps, T)
    peaks, hp = _significant(z, maxima, prom, T, 1.0, shift)
    _, hv = _pits(z, low, minima, vsad, zmin, zvs, label, T, shift, None if count_pits else 5)
    area = ny * dy_m * nx * dx_m
    top = np.sort(hp)[::-1][:5]
    deep = np.sort(hv)[::-1][:5]
    s5p = float(top.mean()) if top.size else None
    s5v = float(deep.mean()) if deep.size else None
    spc = None
    if len(peaks):
        r, c = peaks[:, 0], peaks[:, 1]
        h = z[r, c] - shift  # (the heights z - shift, as in S5p)
        zxx = ((z[r, c + 1] - shift) - 2 * h + (z[r, c - 1] - shift)) / dx_m**2
        zyy = ((z[r + 1, c] - shift) - 2 * h + (z[r - 1, c] - shift)) / dy_m**2
        spc = float(-0.5 * np.mean(zxx + zyy))
    from .units import length

    note = (
        f"watershed segmentation with Wolf pruning at {100 * prune_fraction:g} % of Sz "
        f"({length(T)}): {len(hp)} significant peaks, "
        + (
            f"{len(hv)} pits"
            if count_pits
            else "the five deepest significant pits for S5v (pits not counted further)"
        )
    )
    return {
        "Spd_per_m2": len(hp) / area,
        "Spc_per_m": spc,
        "S10z_m": None if s5p is None or s5v is None else s5p + s5v,
        "S5p_m": s5p,
        "S5v_m": s5v,
        "features_note": note,
    }
