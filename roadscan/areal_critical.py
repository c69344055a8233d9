"""Critical points of the discrete surface of a height map, for the feature segmentation of
:mod:`roadscan.areal_features` (ISO 25178-2:2012 section 6, ISO 16610-85).

Heights are ordered by (z, flattened index); each point gets the 8-bit pattern of its
neighbours that come after it in that order (its higher neighbours, ring positions clockwise
from the upper left). A point with none is a maximum, with all a minimum; a point whose higher
neighbours form two or more groups (8-adjacency among them) is a possible saddle of the peaks,
one whose lower neighbours do a possible saddle of the pits: the only places where components
of the superlevel (sublevel) sets meet. Numpy only; the patterns are made a band of rows at a
time, so that the passes over them run in cache.

References
----------
Wolf, G. W. (1991), A Fortran subroutine for cartographic generalization, Computers &
Geosciences 17, 1359-1381.
"""

from __future__ import annotations

import numpy as np

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

        def find(k, root=root):
            while root[k] != k:
                k = root[k]
            return k

        for a, b in adjacent:
            if a in root and b in root:
                ra, rb = find(a), find(b)
                root[max(ra, rb)] = min(ra, rb)
        groups = sorted({find(k) for k in on})
        ngroups[code] = len(groups)
        runs = []  # (length, middle) of each run of set cells
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


def _kind_table():
    """For each pattern of higher neighbours of an inner point: bit 0 a possible saddle of the
    peaks (two or more groups of higher neighbours), bit 1 of the pits (of lower ones), bit 2
    a maximum, bit 3 a minimum."""
    codes = np.arange(256)
    return (
        (_NGROUPS >= 2) | (_NGROUPS[255 - codes] >= 2) << 1 | (codes == 0) << 2 | (codes == 255) << 3
    ).astype(np.uint8)


_KIND = _kind_table()


def _lookup(table, codes):
    """``table[codes]`` for uint8 ``codes`` and a table of 256 int32 or narrower, by OpenCV's
    LUT (about five times faster than ``np.take``, which first converts every index to
    intp)."""
    if codes.size == 0 or table.dtype.itemsize > 4:
        return np.take(table, codes)
    import cv2

    return cv2.LUT(codes, table.reshape(1, 256)).reshape(-1)


def _higher_code(z):
    """8-bit pattern of each point's neighbours that come after it in the order (z, flattened
    index), bit k for ring position k; neighbours outside the field never do. Four comparisons,
    one per earlier neighbour, on the flattened field (contiguous; the pairs that wrap around
    a row end are cleared after): a neighbour comes after a point exactly when the point does
    not come after it."""
    ny, nx = z.shape
    flat = z.ravel()
    code = np.zeros(ny * nx, np.uint8)
    for k in (0, 1, 2, 7):  # offsets (-1, -1), (-1, 0), (-1, 1), (0, -1)
        dy, dx = _RING[k]
        o = -(dy * nx + dx)
        if not 0 < o < flat.size:  # (a single column has no (-1, 1))
            continue
        t = np.greater(flat[:-o], flat[o:]).view(np.uint8)  # equal: the earlier is the lower
        bit = np.multiply(t, np.uint8(1 << k))  # (a multiplication: faster than a shift)
        code[o:] |= bit
        t ^= np.uint8(1)  # the point seen from that neighbour
        np.multiply(t, np.uint8(1 << (k + 4) % 8), out=bit)
        code[:-o] |= bit
    code = code.reshape(ny, nx)
    code[:, 0] &= np.uint8(sum(1 << k for k, (dy, dx) in enumerate(_RING) if dx >= 0))
    code[:, -1] &= np.uint8(sum(1 << k for k, (dy, dx) in enumerate(_RING) if dx <= 0))
    return code


def _lower_code(code):
    """The pattern of each point's lower neighbours (the order reversed) from its higher ones."""
    low = ~code
    for k, (dy, dx) in enumerate(_RING):
        bit = np.uint8(255 ^ (1 << k))
        if dy:
            low[0 if dy < 0 else -1, :] &= bit
        if dx:
            low[:, 0 if dx < 0 else -1] &= bit
    return low


def _look(code, first, last):
    """Where to look the kind of a point up (:func:`_critical_points`) in the rows ``code`` of
    the patterns of higher neighbours: no higher neighbour, all, or two runs of them on the
    ring or more (two groups need two runs, of the higher and so of the lower ones); the
    border columns, and the first and last rows when they are the field's (``first``,
    ``last``)."""
    run = code * np.uint8(2)  # bit k: bit k - 1 of the pattern
    run |= (code >= 128).view(np.uint8)
    np.invert(run, out=run)
    run &= code  # the first cell of each run
    more = run - 1
    more &= run  # nonzero: two runs or more
    ends = code + 1
    ends &= 254  # zero: no higher neighbour, or all
    look = more != 0
    look |= ends == 0
    look[:, 0] = look[:, -1] = True
    if first:
        look[0, :] = True
    if last:
        look[-1, :] = True
    return look


def _critical_points(code, low, cand, z, shift=0.0):
    """(maxima, saddles of the peaks, minima, saddles of the pits), flattened indices in
    increasing order, and their heights in ``z`` less ``shift``, from the patterns of higher
    and lower neighbours at the points ``cand`` (:func:`_look`, the border from both)."""
    ny, nx = code.shape
    k = _lookup(_KIND, np.take(code.ravel(), cand))
    # the border (all of it in cand), where the lower pattern is not the higher one inverted
    rows = np.arange(1, ny - 1) * nx
    side = np.concatenate(
        [
            np.arange(nx),
            np.arange(cand.size - nx, cand.size),
            np.searchsorted(cand, rows),
            np.searchsorted(cand, rows + nx - 1),
        ]
    )
    c, lo = np.take(code.ravel(), cand[side]), np.take(low.ravel(), cand[side])
    k[side] = (_NGROUPS[c] >= 2) | (_NGROUPS[lo] >= 2) << 1 | (c == 0) << 2 | (lo == 0) << 3
    zc = np.take(z.ravel(), cand)
    if shift:
        zc -= shift
    kinds = [np.flatnonzero((k & np.uint8(bit)) != 0) for bit in (4, 1, 8, 2)]
    return [np.take(cand, i) for i in kinds], [np.take(zc, i) for i in kinds]


def _patterns(z, mean, band=64):
    """(order copy, patterns of higher neighbours, :func:`_look`'s points as flattened
    indices) of ``z``. The order copy holds the heights in float32 about their ``mean``, for
    ordering only (half the memory traffic; a resolution of 1e-7 of the range, far below the
    pruning threshold). All made ``band`` rows at a time (and a row either side for the
    comparisons), so that each pass reads the previous one's output from cache."""
    ny, nx = z.shape
    order, code, cand = np.empty(z.shape, np.float32), np.empty(z.shape, np.uint8), []
    for r0 in range(0, ny, band):
        r1, a, b = min(r0 + band, ny), max(r0 - 1, 0), min(r0 + band + 1, ny)
        done = r0 + (r0 > 0)  # rows before it are in the copy already
        np.subtract(z[done:b], mean, out=order[done:b], casting="unsafe")
        code[r0:r1] = _higher_code(order[a:b])[r0 - a : r1 - a]
        cand.append(np.flatnonzero(_look(code[r0:r1], r0 == 0, r1 == ny)) + r0 * nx)
    return order, code, np.concatenate(cand)
