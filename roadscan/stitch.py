"""Stitching: overlapping height-map tiles into one height map (thesis section 4.1).

A profiler sees a few millimetres at a time, so a sample is scanned as overlapping tiles with
nominal positions (stage coordinates). :func:`stitch` puts them together in four steps:

1. **Registration.** Every pair of tiles whose nominal footprints overlap is registered by
   masked normalised cross-correlation computed by FFT (Padfield 2012, as implemented by
   :func:`skimage.registration.phase_cross_correlation` with masks), on the overlap window
   enlarged by ``max_shift_px`` on every side, unmeasured points masked out. It runs on
   high-passed tiles (each minus its Gaussian smoothing, sigma = 2 samples): a plane passes
   through the smoothing unchanged, so the tiles' different tilts cannot bias the peak, and the
   otherwise very broad correlation peak of a self-affine surface becomes sharp. The
   integer shift is then refined to a subpixel one by upsampled phase correlation
   (Guizar-Sicairos et al. 2008, ``upsample_factor``) on the exactly overlapping windows
   (plane removed, Tukey-windowed).
2. **Positions.** The pairwise offsets are reconciled by one weighted least-squares solve for
   all tile positions (weights sqrt(number of overlapping points)); tile 0 keeps its nominal
   position (gauge).
3. **Heights.** Each tile k gets a plane correction ``a_k + b_k x + c_k y`` (x, y [m] in the
   mosaic frame, origin at mosaic sample (0, 0); x along columns, y along rows). All
   corrections are found together by one linear least-squares fit of the height differences over
   every overlap point of every pair (not pairwise drift), gauge: tile 0's correction is zero,
   so the mosaic keeps tile 0's height datum and tilt.
4. **Blending.** Corrected tiles are averaged with feathered weights: each point's weight is
   its Euclidean distance (in samples) to the nearest edge or unmeasured point of its tile,
   so every tile fades out towards its edges and no seam is left. A point is unmeasured (NaN)
   in the mosaic only if no tile measured it. Tiles whose refined position is off the grid by
   more than ``snap_px`` are resampled (cubic spline) onto the mosaic grid; otherwise they are
   placed without interpolation (no smoothing of the high-q spectrum).

Each overlap's residual rms height mismatch after correction is reported. Tiles that overlap no
other tile (a disconnected overlap graph) are refused with :class:`roadscan.errors.InputError`.

Conventions: a tile's nominal position is the (x, y) [m] of its first sample (row 0, column 0);
x runs along columns (dx), y along rows (dy). All tiles must share the same spacing.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from scipy import ndimage

from .errors import InputError
from .heightmap import HeightMap
from .tile_layout import MANIFEST_HEADER, grid_positions, read_manifest  # noqa: F401 (re-exported)
from .tile_registration import check_connected, highpass, overlap_rect, plane_removed, register_pair

__all__ = ["StitchResult", "stitch", "read_manifest", "grid_positions"]


@dataclass(frozen=True, eq=False)
class StitchResult:
    """Result of :func:`stitch`.

    Attributes
    ----------
    heightmap : HeightMap
        The mosaic [m]; NaN where no tile measured. ``meta["origin_xy_m"]`` is the (x, y) [m]
        of its sample (0, 0) in the frame of the nominal positions.
    positions_m : (n, 2) array
        Refined (x, y) [m] of each tile's first sample, in the frame of the nominal positions.
    offsets_m : (n,) array
        Height offset a_k [m] subtracted from tile k.
    tilts : (n, 2) array
        Slopes (b_k, c_k) [m/m] of the plane subtracted from tile k: the correction is
        ``a_k + b_k x + c_k y`` with (x, y) [m] measured from the mosaic's sample (0, 0).
    overlaps : list of dict
        One per registered pair: ``i``, ``j`` (tile indices), ``n_points`` (overlapping
        measured points), ``rms_mismatch_m`` (rms of the corrected height difference),
        ``shift_px`` ((row, col) correction of j's position relative to i found by registration,
        against the nominal relative position), ``registered`` (False if the correlation peak
        fell outside ``max_shift_px`` and the nominal offset was kept).
    meta : dict
        ``tile_names``, ``blend``, ``max_shift_px``.
    """

    heightmap: HeightMap
    positions_m: np.ndarray
    offsets_m: np.ndarray
    tilts: np.ndarray
    overlaps: list
    meta: dict = field(default_factory=dict)


# --- helpers ---------------------------------------------------------------------------------


def _tile_label(hm, k):
    src = hm.meta.get("path") or hm.meta.get("source") or hm.name
    return str(src) if src else f"#{k}"


def _place(z, ok, frac, snap_px):
    """Resample a tile by a fractional shift ``frac`` (rows, cols) if it exceeds snap_px."""
    if np.all(np.abs(frac) <= snap_px):
        return z, ok
    filled = z
    if not ok.all():
        idx = ndimage.distance_transform_edt(~ok, return_distances=False, return_indices=True)
        filled = z[tuple(idx)]
    zs = ndimage.shift(filled, frac, order=3, mode="nearest")
    bad = ndimage.shift((~ok).astype(float), frac, order=1, mode="constant", cval=1.0) > 1e-6
    return np.where(bad, np.nan, zs), ~bad


def stitch(
    tiles: Sequence[HeightMap],
    nominal_xy_m: Sequence[tuple[float, float]],
    max_shift_px: int = 20,
    blend: Literal["feather", "average"] = "feather",
    min_overlap_px: int = 8,
    snap_px: float = 0.05,
) -> StitchResult:
    """Stitch overlapping tiles into one height map.

    Parameters
    ----------
    tiles : list of HeightMap
        Tiles with a common spacing (dx, dy) [m]. Their ``name`` (or ``meta["path"]``) is used
        in error messages.
    nominal_xy_m : list of (x_m, y_m)
        Nominal position [m] of each tile's first sample (row 0, column 0); x along columns,
        y along rows. May be wrong by up to ``max_shift_px`` samples.
    max_shift_px : int
        Largest position error searched by registration, per pair [samples].
    blend : {"feather", "average"}
        Feathered weights (distance to the tile's edge or dropouts) or a plain average.
    min_overlap_px : int
        Nominal overlaps narrower than this (in either direction) do not count as overlaps.
    snap_px : float
        Tiles whose refined position is within this of the grid are placed without
        interpolation [samples].

    Returns
    -------
    StitchResult

    Raises
    ------
    InputError
        Mismatched spacings, or a tile that overlaps no other tile ("tile X does not overlap
        any other tile"; for a group of tiles cut off from tile 0, the message names one of
        them and says so).
    """
    tiles = list(tiles)
    n = len(tiles)
    if n == 0:
        raise ValueError("no tiles to stitch")
    if len(nominal_xy_m) != n:
        raise ValueError(f"{n} tiles but {len(nominal_xy_m)} positions")
    if blend not in ("feather", "average"):
        raise ValueError(f"blend must be 'feather' or 'average', got {blend!r}")
    m = int(max_shift_px)
    dx, dy = tiles[0].dx_m, tiles[0].dy_m
    for k, t in enumerate(tiles):
        if not (math.isclose(t.dx_m, dx, rel_tol=1e-6) and math.isclose(t.dy_m, dy, rel_tol=1e-6)):
            raise InputError(
                _tile_label(t, k),
                f"spacing {t.dx_m:g} x {t.dy_m:g} m differs from the first tile's {dx:g} x {dy:g} m",
            )
    labels = [_tile_label(t, k) for k, t in enumerate(tiles)]
    xy = np.asarray(nominal_xy_m, dtype=float).reshape(n, 2)
    P0 = np.column_stack([xy[:, 1] / dy, xy[:, 0] / dx])  # (row, col) [samples]

    # candidate pairs from nominal footprints
    pairs = []
    for i in range(n):
        for j in range(i + 1, n):
            t0 = tuple(int(v) for v in np.rint(P0[j] - P0[i]))
            r0, r1, c0, c1 = overlap_rect(tiles[i].shape, tiles[j].shape, t0)
            if r1 - r0 >= min_overlap_px and c1 - c0 >= min_overlap_px:
                pairs.append((i, j, t0))
    if n > 1:
        check_connected(n, pairs, labels)

    # 1. registration (on plane-levelled tiles)
    ok = [~t.unmeasured for t in tiles]
    lev = [plane_removed(t.heights_m, o) for t, o in zip(tiles, ok)]
    hp = [highpass(z, o) for z, o in zip(lev, ok)]
    reg = []
    for i, j, t0 in pairs:
        T, good = register_pair(lev[i], ok[i], lev[j], ok[j], t0, m, hp[i], hp[j])
        r0, r1, c0, c1 = overlap_rect(tiles[i].shape, tiles[j].shape, tuple(np.rint(T).astype(int)))
        reg.append((i, j, T, good, max(1, (r1 - r0) * (c1 - c0)), P0[j] - P0[i]))
    if n > 1:  # a nominal overlap whose textures do not match is no overlap
        check_connected(
            n,
            [(i, j, None) for i, j, _, good, *_ in reg if good],
            labels,
            how=" whose texture matches (no correlation peak within max_shift_px "
            "of the nominal position: check the positions)",
        )

    # 2. one weighted least-squares solve for all positions (gauge: tile 0 nominal)
    P = P0.copy()
    if reg:
        D = np.zeros((len(reg) + 1, n))
        rhs = np.zeros((len(reg) + 1, 2))
        for e, (i, j, T, good, npts, _) in enumerate(reg):
            w = math.sqrt(npts) * (1.0 if good else 1e-3)
            D[e, i], D[e, j], rhs[e] = -w, w, w * T
        D[-1, 0], rhs[-1] = 1e6, 1e6 * P0[0]
        P, *_ = np.linalg.lstsq(D, rhs, rcond=None)

    # placement on the mosaic grid
    # mosaic grid aligned with tile 0's samples (tile 0 is never resampled)
    origin = P[0] - np.ceil(P[0] - P.min(axis=0) - 1e-9)
    Q = P - origin
    N = np.rint(Q).astype(int)
    frac = Q - N
    shape = tuple(int(v) for v in np.max(N + np.array([t.shape for t in tiles]), axis=0))
    placed = [_place(t.heights_m, o, f, snap_px) for t, o, f in zip(tiles, ok, frac)]

    # 3. one global least-squares solve for the plane corrections (gauge: tile 0 = 0)
    sx, sy = shape[1] / 2.0, shape[0] / 2.0  # scaled coordinates for conditioning
    A = np.zeros((3 * n, 3 * n))
    b = np.zeros(3 * n)
    ov = []
    for i, j, T, good, _, Tnom in reg:
        sl, si, sj = _common(N[i], placed[i][0].shape, N[j], placed[j][0].shape)
        if sl is None:
            continue
        both = placed[i][1][si] & placed[j][1][sj]
        rr, cc = np.nonzero(both)
        if rr.size < 3:
            continue
        X = np.column_stack([np.ones(rr.size), (cc + sl[1].start - sx) / sx, (rr + sl[0].start - sy) / sy])
        d = placed[i][0][si][both] - placed[j][0][sj][both]
        M = X.T @ X
        v = X.T @ d
        Ii, Jj = slice(3 * i, 3 * i + 3), slice(3 * j, 3 * j + 3)
        A[Ii, Ii] += M
        A[Jj, Jj] += M
        A[Ii, Jj] -= M
        A[Jj, Ii] -= M
        b[Ii] += v
        b[Jj] -= v
        ov.append((i, j, sl, si, sj, both, T - Tnom, good))
    u = np.zeros(3 * n)
    if n > 1:
        u[3:], *_ = np.linalg.lstsq(A[3:, 3:], b[3:], rcond=None)
    U = u.reshape(n, 3)
    # corrections in metres of the mosaic frame: a + bx x + by y, x = col dx, y = row dy
    bx = U[:, 1] / (sx * dx)
    by = U[:, 2] / (sy * dy)
    a = U[:, 0] - U[:, 1] - U[:, 2]

    rows, cols = np.mgrid[0 : shape[0], 0 : shape[1]]
    acc = np.zeros(shape)
    wsum = np.zeros(shape)
    corrected = []
    for k, (z, o) in enumerate(placed):
        sl = (slice(N[k][0], N[k][0] + z.shape[0]), slice(N[k][1], N[k][1] + z.shape[1]))
        plane = a[k] + bx[k] * cols[sl] * dx + by[k] * rows[sl] * dy
        zc = z - plane
        corrected.append(zc)
        if blend == "feather":
            w = ndimage.distance_transform_edt(np.pad(o, 1))[1:-1, 1:-1]
        else:
            w = o.astype(float)
        acc[sl] += np.where(o, zc, 0.0) * w
        wsum[sl] += w
    with np.errstate(invalid="ignore", divide="ignore"):
        mosaic = np.where(wsum > 0, acc / wsum, np.nan)

    overlaps = []
    for i, j, _, si, sj, both, shift, good in ov:
        diff = corrected[i][si][both] - corrected[j][sj][both]
        overlaps.append(
            {
                "i": i,
                "j": j,
                "n_points": int(both.sum()),
                "rms_mismatch_m": float(np.sqrt(np.mean(diff**2))),
                "shift_px": (float(shift[0]), float(shift[1])),
                "registered": bool(good),
            }
        )

    origin_xy = (origin[1] * dx, origin[0] * dy)
    hm = HeightMap(
        mosaic, dx, dy, name="mosaic", meta={"origin_xy_m": origin_xy, "tiles": labels, "stitch_blend": blend}
    )
    positions = np.column_stack([P[:, 1] * dx, P[:, 0] * dy])
    return StitchResult(
        heightmap=hm,
        positions_m=positions,
        offsets_m=a,
        tilts=np.column_stack([bx, by]),
        overlaps=overlaps,
        meta={"tile_names": labels, "blend": blend, "max_shift_px": m},
    )


def _common(Ni, shape_i, Nj, shape_j):
    """Common rectangle of two placed tiles: mosaic slices and the slices into each tile."""
    r0, c0 = max(Ni[0], Nj[0]), max(Ni[1], Nj[1])
    r1 = min(Ni[0] + shape_i[0], Nj[0] + shape_j[0])
    c1 = min(Ni[1] + shape_i[1], Nj[1] + shape_j[1])
    if r1 <= r0 or c1 <= c0:
        return None, None, None
    sl = (slice(r0, r1), slice(c0, c1))
    si = (slice(r0 - Ni[0], r1 - Ni[0]), slice(c0 - Ni[1], c1 - Ni[1]))
    sj = (slice(r0 - Nj[0], r1 - Nj[0]), slice(c0 - Nj[1], c1 - Nj[1]))
    return sl, si, sj
