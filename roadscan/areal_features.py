"""Feature parameters of ISO 25178-2:2012 (section 4.6): Spd, Spc, S5p, S5v and S10z.

Segmentation (ISO 25178-2 section 6, ISO 16610-85): the surface is cut into hills, each the
basin of one local maximum (8 neighbours: the watershed of -z), and hills are merged by Wolf
pruning: a hill whose height above its highest saddle to a higher hill is below the threshold
T = 5 % of Sz is merged into that neighbour, until none is left. Merging from the highest
saddle down (the change tree) gives each hill's summit its height above the saddle where it
meets a higher one, its topographic prominence; a peak survives exactly when its prominence
is at least T. This is the same set as the h-maxima transform's (scikit-image ``h_maxima``,
tested against it) and as a union-find over the points from the highest down (tested too).

How it is computed, in numpy alone (the critical points of the discrete surface): heights are
ordered by (z, flattened index); the pattern of each point's higher neighbours is read in a
few passes; a point with none is a maximum, a point whose higher neighbours form two or more
groups (8-adjacency among them) is a possible saddle, the only places where components of
the superlevel set meet. From each group of a saddle a path uphill reaches the maximum of
that component; the saddle heights between maxima then form the hill graph, merged by
vectorised Boruvka rounds (a component whose highest edge leads to a higher one merges there,
as the ordered merging would) and the ordered merging of what is left. Pits likewise, on the
neighbour patterns reversed.

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

import numpy as np

__all__ = ["feature_parameters", "prominences", "PRUNE_FRACTION"]

#: Wolf pruning threshold as a fraction of Sz (ISO 25178-2 default for Spd and S10z)
PRUNE_FRACTION = 0.05


# the 8 neighbours as a ring, clockwise from the upper left: (row offset, column offset)
_RING = ((-1, -1), (-1, 0), (-1, 1), (0, 1), (1, 1), (1, 0), (1, -1), (0, -1))


def _ring_tables():
    """For each of the 256 patterns of higher neighbours on the ring: the number of groups they
    form (8-adjacency among themselves: ring-consecutive cells, and edge cells one corner
    apart), one cell of each group and one higher cell to step to; each the middle of its run
    of consecutive cells (uphill paths then follow roughly the steepest ascent)."""
    adjacent = [(i, (i + 1) % 8) for i in range(8)] + [(1, 3), (3, 5), (5, 7), (7, 1)]
    ngroups = np.zeros(256, np.uint8)
    reps = np.full((256, 4), -1, np.int8)
    step = np.zeros(256, np.int8)
    for code in range(1, 256):
        on = [k for k in range(8) if code >> k & 1]
        root = {k: k for k in on}

        def find(k):
            while root[k] != k:
                k = root[k]
            return k

        for a, b in adjacent:
            if a in root and b in root:
                ra, rb = find(a), find(b)
                root[max(ra, rb)] = min(ra, rb)
        groups = sorted({find(k) for k in on})
        ngroups[code] = len(groups)
        runs = []                                 # (length, middle) of each run of set cells
        for k in on:
            if code == 255 or not code >> ((k - 1) % 8) & 1:
                n = 1
                while n < 8 and code >> ((k + n) % 8) & 1:
                    n += 1
                runs.append((n, (k + (n - 1) // 2) % 8))
        step[code] = max(runs)[1]
        for j, g in enumerate(groups):
            mids = [mid for n, mid in runs if find(mid) == g]
            reps[code, j] = mids[0]
    return ngroups, reps, step


_NGROUPS, _REPS, _STEP = _ring_tables()


def _higher_code(z):
    """8-bit pattern of each point's neighbours that come after it in the order (z, flattened
    index), bit k for ring position k; neighbours outside the field never do."""
    ny, nx = z.shape
    pad = np.full((ny + 2, nx + 2), -np.inf, dtype=z.dtype)
    pad[1:-1, 1:-1] = z
    code = np.zeros((ny, nx), np.uint8)
    above = np.empty((ny, nx), bool)
    for k, (dy, dx) in enumerate(_RING):
        nb = pad[1 + dy:ny + 1 + dy, 1 + dx:nx + 1 + dx]
        # equal heights: the later point in the flattened order is the higher
        (np.greater_equal if dy * nx + dx > 0 else np.greater)(nb, z, out=above)
        code |= above.view(np.uint8) << np.uint8(k)
    return code


def _lower_code(code):
    """The pattern of each point's lower neighbours (the order reversed) from its higher ones."""
    ny, nx = code.shape
    inside = np.full((ny, nx), 255, np.uint8)
    for k, (dy, dx) in enumerate(_RING):
        bit = np.uint8(255 ^ (1 << k))
        if dy:
            inside[0 if dy < 0 else -1, :] &= bit
        if dx:
            inside[:, 0 if dx < 0 else -1] &= bit
    return ~code & inside


def _critical_graph(z, code):
    """(flattened maxima, edges a, b between maxima indices, saddle heights) from the neighbour
    patterns: a point whose higher neighbours form g >= 2 groups may join g components of the
    superlevel set above it; each group is followed uphill (any higher neighbour, heights
    increase, so the path stays above the point) to the maximum it belongs to."""
    ny, nx = code.shape
    flat = code.ravel()
    off = np.array([dy * nx + dx for dy, dx in _RING], dtype=np.int64)
    maxima = np.flatnonzero(flat == 0)
    sad = np.flatnonzero(_NGROUPS[flat] >= 2)
    sc = flat[sad]
    g = _NGROUPS[sc].astype(np.intp)
    first_of = np.repeat(np.cumsum(g) - g, g)     # each saddle's first group
    col = np.arange(first_of.size) - first_of
    cur = np.repeat(sad, g) + off[_REPS[np.repeat(sc, g), col]]
    step = off[_STEP]
    slot = np.flatnonzero(flat[cur] != 0)         # the unfinished paths and where they are
    pos = cur[slot]
    while slot.size:                              # uphill, one step at a time
        pos += step[flat[pos]]
        top = flat[pos] == 0
        cur[slot[top]] = pos[top]
        slot, pos = slot[~top], pos[~top]
    label = np.empty(flat.size, np.int32 if maxima.size < 2 ** 31 else np.int64)
    label[maxima] = np.arange(maxima.size)
    dest = label[cur]
    other = col > 0
    return maxima, dest[first_of[other]], dest[other], np.repeat(z.ravel()[sad], g)[other]


def _change_tree(top, a, b, saddle, rounds=3):
    """Prominence of each maximum (heights ``top``) over the graph of saddle edges: Kruskal's
    merging from the highest saddle down, where the lower component's summit gets its height
    above the saddle. First a few vectorised Boruvka rounds: a component whose highest edge
    leads to a higher component is merged into it at that edge (exactly what the ordered
    merging does, as no other edge of it comes earlier); then the ordered merging of the rest."""
    m = top.size                                  # ``top`` is in flattened-index order:
    prom = np.full(m, np.inf)
    keep = a != b
    a, b, saddle = a[keep], b[keep], saddle[keep]
    root = np.arange(m)
    for _ in range(rounds):
        n = a.size
        if n == 0:
            break
        best = np.full(m, -np.inf)                # the highest saddle of each component
        np.maximum.at(best, a, saddle)
        np.maximum.at(best, b, saddle)
        edge = np.full(m, -1)                     # an edge reaching it (equal saddles: any)
        idx = np.arange(n)
        on = saddle == best[b]
        edge[b[on]] = idx[on]
        on = saddle == best[a]
        edge[a[on]] = idx[on]
        v = np.flatnonzero(edge >= 0)
        e = edge[v]
        o = np.where(a[e] == v, b[e], a[e])
        up = (top[o] > top[v]) | ((top[o] == top[v]) & (o > v))   # equal heights: by index
        v, e, o = v[up], e[up], o[up]
        prom[v] = top[v] - saddle[e]
        root[v] = o
        while True:
            nxt = root[root]
            if np.array_equal(nxt, root):
                break
            root = nxt
        a, b = root[a], root[b]
        keep = a != b
        a, b, saddle = a[keep], b[keep], saddle[keep]
    if a.size:                                    # each pair once, with its highest saddle,
        order = np.argsort(saddle, kind="stable")[::-1]   # from the highest down
        a, b, saddle = a[order], b[order], saddle[order]
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        _, first = np.unique(lo * m + hi, return_index=True)
        first.sort()
        a, b, saddle = a[first], b[first], saddle[first]
    parent = {}
    topl = top.tolist()

    def find(i):
        while True:
            p = parent.get(i, i)
            if p == i:
                return i
            g = parent.get(p, p)
            parent[i] = g                         # path halving
            i = g

    for e, sa, sb in zip(saddle.tolist(), a.tolist(), b.tolist()):
        ra, rb = find(sa), find(sb)               # a component is named by its summit
        if ra == rb:
            continue
        if (topl[ra], ra) < (topl[rb], rb):
            ra, rb = rb, ra
        prom[rb] = topl[rb] - e
        parent[rb] = ra
    return prom


def _prominences_from_code(z, code):
    maxima, a, b, saddle = _critical_graph(z, code)
    return maxima, _change_tree(z.ravel()[maxima], a, b, saddle)


def prominences(z):
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
    return _prominences_from_code(z, _higher_code(_order_copy(z)))


def _order_copy(z):
    """Heights in float32 about their mean, for ordering only (half the memory traffic; a
    resolution of 1e-7 of the range, far below the pruning threshold)."""
    return (z - z.mean()).astype(np.float32)


def _significant(z, code, threshold):
    """(row, column) of the summit of each significant interior peak of ``z`` and its height,
    ``code`` its pattern of higher neighbours."""
    summits, prom = _prominences_from_code(z, code)
    keep = summits[prom >= threshold]
    ny, nx = z.shape
    r, c = keep // nx, keep % nx
    inner = (r > 0) & (r < ny - 1) & (c > 0) & (c < nx - 1)
    pos = np.stack([r[inner], c[inner]], axis=1)
    return pos, z[pos[:, 0], pos[:, 1]]


def feature_parameters(heights_m, dx_m, dy_m, prune_fraction=PRUNE_FRACTION):
    """Spd, Spc, S5p, S5v, S10z of a levelled height map (module docstring).

    Parameters
    ----------
    heights_m : ndarray, shape (ny, nx)
        Heights [m] (mean plane at zero), NaN where unmeasured.
    dx_m, dy_m : float
        Spacings along x (columns) and y (rows) [m].
    prune_fraction : float
        Wolf pruning threshold as a fraction of Sz (0.05).

    Returns
    -------
    dict
        Keys ``Spd_per_m2``, ``Spc_per_m``, ``S10z_m``, ``S5p_m``, ``S5v_m`` and ``features_note``
        (the threshold, the counts and the block size used).
    """
    z = np.asarray(heights_m, dtype=np.float64)
    if np.isnan(z).any():
        z = np.where(np.isfinite(z), z, 0.0)
    ny, nx = z.shape
    sz = float(z.max() - z.min())
    if sz <= 0:
        return {"Spd_per_m2": 0.0, "Spc_per_m": None, "S10z_m": 0.0, "S5p_m": 0.0, "S5v_m": 0.0,
                "features_note": "flat surface: no peak, no pit"}
    T = prune_fraction * sz
    code = _higher_code(_order_copy(z))
    peaks, hp = _significant(z, code, T)
    pits, hv = _significant(-z, _lower_code(code), T)
    area = ny * dy_m * nx * dx_m
    top = np.sort(hp)[::-1][:5]
    deep = np.sort(hv)[::-1][:5]
    s5p = float(top.mean()) if top.size else None
    s5v = float(deep.mean()) if deep.size else None
    spc = None
    if len(peaks):
        r, c = peaks[:, 0], peaks[:, 1]
        zxx = (z[r, c + 1] - 2 * z[r, c] + z[r, c - 1]) / dx_m ** 2
        zyy = (z[r + 1, c] - 2 * z[r, c] + z[r - 1, c]) / dy_m ** 2
        spc = float(-0.5 * np.mean(zxx + zyy))
    from .units import length

    note = (f"watershed segmentation with Wolf pruning at {100 * prune_fraction:g} % of Sz "
            f"({length(T)}): {len(hp)} significant peaks, {len(hv)} pits")
    return {"Spd_per_m2": len(hp) / area, "Spc_per_m": spc,
            "S10z_m": None if s5p is None or s5v is None else s5p + s5v,
            "S5p_m": s5p, "S5v_m": s5v, "features_note": note}
