"""Feature parameters of ISO 25178-2:2012 (section 4.6): Spd, Spc, S5p, S5v and S10z.

Segmentation (ISO 25178-2 section 6, ISO 16610-85): the surface is cut into hills, each the
basin of steepest ascent of one local maximum (8 neighbours: the watershed of -z), and hills
are merged by Wolf pruning: a hill whose height above its highest saddle to a higher hill is
below the threshold T = 5 % of Sz is merged into that neighbour, until none is left. The saddle
between two adjacent hills is the highest min(z_p, z_q) over neighbouring points p, q on either
side of their boundary, and the merging runs over the hill graph from the highest saddle down
(the change tree: each merge gives the lower hill's height above the saddle, its topographic
prominence); a peak survives exactly when its prominence is at least T. This is the same set
as the h-maxima transform's (scikit-image ``h_maxima``, tested against it), in numpy alone: a
few passes over the map plus one pass over the hills. Pits likewise on -z.

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


def _steepest_ascent(z):
    """Index of the highest of each point's 8 neighbours when higher than the point, else the
    point's own index (flattened, int32 below 2^31 points); heights compared as (z, index)."""
    ny, nx = z.shape
    pad = np.full((ny + 2, nx + 2), -np.inf)
    pad[1:-1, 1:-1] = z
    best = z.copy()
    code = np.zeros((ny, nx), dtype=np.int8)      # which neighbour is the highest (0: none)
    offsets = [0]
    up = np.empty((ny, nx), dtype=bool)
    tie = np.empty((ny, nx), dtype=bool)
    # equal heights are ordered by their flattened index (a flat plateau drains to one point):
    # neighbours come in increasing offset, so a later one wins a tie, except against the
    # point itself when it lies before it
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dy or dx:
                nb = pad[1 + dy:ny + 1 + dy, 1 + dx:nx + 1 + dx]
                np.greater(nb, best, out=up)
                np.equal(nb, best, out=tie)
                if dy * nx + dx < 0:
                    tie &= code != 0
                up |= tie
                np.copyto(best, nb, where=up)
                np.copyto(code, len(offsets), where=up)
                offsets.append(dy * nx + dx)
    itype = np.int32 if ny * nx < 2 ** 31 else np.int64
    ptr = np.arange(ny * nx, dtype=itype)
    ptr += np.asarray(offsets, dtype=itype)[code.ravel()]
    return ptr


def _hill_labels(z):
    """(hill label of each point, flattened index of each hill's summit)."""
    ptr = _steepest_ascent(z)
    active = np.flatnonzero(ptr[ptr] != ptr)      # points not yet pointing at their summit
    while active.size:                            # pointer jumping on those only
        ptr[active] = ptr[ptr[active]]
        active = active[ptr[ptr[active]] != ptr[active]]
    summits = np.flatnonzero(ptr == np.arange(ptr.size, dtype=ptr.dtype))
    lut = np.empty(ptr.size, dtype=np.int32 if summits.size < 2 ** 31 else np.int64)
    lut[summits] = np.arange(summits.size)
    return lut[ptr].reshape(z.shape), summits


def _saddles(z, lab, m):
    """(hill a, hill b, saddle height) of every pair of adjacent hills, each pair once with its
    highest saddle.

    One sort of 64-bit words: the pair (a, b) in the high bits, the saddle height quantised to
    2^20 levels between the lowest and the highest height in the low bits (a resolution of
    Sz / 10^6, far below the pruning threshold); the exact height is then read back."""
    ny, nx = z.shape
    lo = float(z.min())
    scale = ((1 << 20) - 1) / max(float(z.max()) - lo, 1e-300)
    words, exact = [], []
    for dy, dx in ((0, 1), (1, 0), (1, 1), (1, -1)):
        j0, j1 = max(0, -dx), nx - max(0, dx)
        a, b = lab[:ny - dy, j0:j1], lab[dy:, j0 + dx:j1 + dx]
        cross = a != b
        if not cross.any():
            continue
        la, lb = a[cross].astype(np.int64), b[cross].astype(np.int64)
        sad = np.minimum(z[:ny - dy, j0:j1][cross], z[dy:, j0 + dx:j1 + dx][cross])
        q = ((sad - lo) * scale).astype(np.int64)
        words.append(((np.minimum(la, lb) * m + np.maximum(la, lb)) << 20) | q)
    if not words:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0)
    w = np.sort(np.concatenate(words))
    pair = w >> 20
    last = np.r_[pair[1:] != pair[:-1], True]     # each pair's highest saddle sorts last
    pair, q = pair[last], w[last] & ((1 << 20) - 1)
    return pair // m, pair % m, lo + q / scale


def prominences(z):
    """(flattened summit indices, their prominence [m]) of every local maximum of ``z``: the
    height of the summit above the highest saddle through which a higher summit is reached
    (infinite for the highest). Module docstring: the change tree over the hill graph.

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
    ISO 25178-2:2021, 5.4 (feature parameters, Wolf pruning by prominence).
    """
    lab, summits = _hill_labels(z)
    m = summits.size
    top = z.ravel()[summits]
    prom = np.full(m, np.inf)
    a, b, sad = _saddles(z, lab, m)
    order = np.argsort(sad)[::-1]
    parent = list(range(m))
    high = list(range(m))                         # each component's highest hill
    topl = top.tolist()

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for e, sa, sb in zip(sad[order].tolist(), a[order].tolist(), b[order].tolist()):
        ra, rb = find(sa), find(sb)
        if ra == rb:
            continue
        ha, hb = high[ra], high[rb]
        if topl[ha] < topl[hb]:
            ra, rb, ha, hb = rb, ra, hb, ha
        prom[hb] = topl[hb] - e                   # the lower component's summit ends here
        parent[rb] = ra
    return summits, prom


def _significant(z, threshold):
    """(row, column) of the summit of each significant interior peak of ``z`` and its height."""
    summits, prom = prominences(z)
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
    peaks, hp = _significant(z, T)
    pits, hv = _significant(-z, T)
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
