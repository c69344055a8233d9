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

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from skimage.registration import phase_cross_correlation

from .errors import InputError
from .heightmap import HeightMap
from .level import polynomial_form
from .windows import tukey   # scipy.signal's, without importing scipy.signal (issue 13)

__all__ = ["StitchResult", "stitch", "read_manifest", "grid_positions"]

MANIFEST_HEADER = ["file", "x_m", "y_m"]


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


def grid_positions(n_rows, n_cols, tile_shape, dx_m, dy_m, overlap_fraction):
    """Nominal positions of a ROWS x COLS grid of tiles, row-major (row 0 first).

    Parameters
    ----------
    n_rows, n_cols : int
    tile_shape : (ny, nx)
        Tile size in samples.
    dx_m, dy_m : float
        Spacing [m].
    overlap_fraction : float
        Nominal fraction of a tile shared with its neighbour, 0 <= f < 1. The step is
        ``(1 - f) * nx * dx`` along x and ``(1 - f) * ny * dy`` along y.

    Returns
    -------
    list of (x_m, y_m)
        Position of each tile's first sample; tile ``r * n_cols + c`` is at row r, column c.
    """
    if n_rows < 1 or n_cols < 1:
        raise ValueError(f"grid must have at least one row and column, got {n_rows}x{n_cols}")
    if not 0 <= overlap_fraction < 1:
        raise ValueError(f"overlap fraction must be in [0, 1), got {overlap_fraction!r}")
    ny, nx = tile_shape
    sx = (1.0 - overlap_fraction) * nx * dx_m
    sy = (1.0 - overlap_fraction) * ny * dy_m
    return [(c * sx, r * sy) for r in range(n_rows) for c in range(n_cols)]


def read_manifest(path):
    """Read a tile manifest: CSV with header exactly ``file,x_m,y_m``.

    Each row names a tile file (relative to the manifest's folder, or absolute) and the
    nominal position [m] of its first sample (row 0, column 0; x along columns, y along rows).

    Returns
    -------
    list of (Path, float, float)

    Raises
    ------
    InputError
        Bad header, malformed row, non-finite position, missing tile file or empty manifest.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InputError(path, "manifest not found") from None
    except (IsADirectoryError, UnicodeDecodeError) as exc:
        raise InputError(path, f"cannot read manifest: {exc}") from None
    rows = [r for r in csv.reader(text.splitlines()) if any(c.strip() for c in r)]
    if not rows:
        raise InputError(path, "empty manifest (expected header file,x_m,y_m)")
    header = [c.strip() for c in rows[0]]
    if header != MANIFEST_HEADER:
        raise InputError(path, f"manifest header must be exactly 'file,x_m,y_m', got {','.join(rows[0])!r}")
    out = []
    for n, row in enumerate(rows[1:], start=2):
        if len(row) != 3:
            raise InputError(path, f"line {n}: expected 3 fields (file,x_m,y_m), got {len(row)}")
        name, xs, ys = (c.strip() for c in row)
        try:
            x, y = float(xs), float(ys)
        except ValueError:
            raise InputError(path, f"line {n}: positions must be numbers, got {xs!r}, {ys!r}") from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise InputError(path, f"line {n}: positions must be finite")
        if not name:
            raise InputError(path, f"line {n}: empty file name")
        f = Path(name)
        if not f.is_absolute():
            f = path.parent / f
        if not f.is_file():
            raise InputError(path, f"line {n}: tile file {name!r} not found (relative to the manifest)")
        out.append((f, x, y))
    if not out:
        raise InputError(path, "manifest lists no tiles")
    return out


# --- helpers ---------------------------------------------------------------------------------

def _tile_label(hm, k):
    src = hm.meta.get("path") or hm.meta.get("source") or hm.name
    return str(src) if src else f"#{k}"


def _plane_removed(z, ok):
    """z minus its least-squares plane over the points ``ok``; unmeasured -> 0."""
    if np.count_nonzero(ok) < 3:
        return np.zeros_like(z)
    return np.where(ok, z - polynomial_form(z, ~ok, degree=1), 0.0)


def _highpass(z, ok, sigma=2.0):
    """z minus its Gaussian-smoothed version (normalised convolution over measured points).

    A plane passes through the smoothing unchanged, so relative tilts vanish and the
    correlation peak of a self-affine surface (otherwise very broad) becomes sharp.
    """
    okf = ok.astype(float)
    num = ndimage.gaussian_filter(np.where(ok, z, 0.0), sigma, mode="constant")
    den = ndimage.gaussian_filter(okf, sigma, mode="constant")
    with np.errstate(invalid="ignore", divide="ignore"):
        smooth = np.where(den > 1e-6, num / den, 0.0)
    return np.where(ok, z - smooth, 0.0)


def _overlap_rect(shape_i, shape_j, t):
    """Overlap of tile i (origin 0) and tile j at integer offset t=(dr, dc), in i's coordinates."""
    r0, c0 = max(0, t[0]), max(0, t[1])
    r1, c1 = min(shape_i[0], t[0] + shape_j[0]), min(shape_i[1], t[1] + shape_j[1])
    return r0, r1, c0, c1


def _register_pair(zi, oki, zj, okj, t0, m, hpi, hpj):
    """Offset T (float row, col) of tile j relative to tile i, starting from integer t0.

    ``zi, zj`` are plane-levelled tiles, ``hpi, hpj`` their high-passed versions (used for
    the integer search). Returns (T, registered).
    """
    r0, r1, c0, c1 = _overlap_rect(zi.shape, zj.shape, t0)
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
    s = phase_cross_correlation(ref, mov, reference_mask=ref_ok, moving_mask=mov_ok,
                                overlap_ratio=0.5)
    s = np.rint(np.asarray(s[0] if isinstance(s, tuple) else s, dtype=float)).astype(int)
    if np.any(np.abs(s) > m):
        return np.asarray(t0, float), False
    t = (int(t0[0] + s[0]), int(t0[1] + s[1]))
    # subpixel refinement on the exactly overlapping windows
    r0, r1, c0, c1 = _overlap_rect(zi.shape, zj.shape, t)
    if r1 - r0 < 4 or c1 - c0 < 4:
        return np.asarray(t, float), True
    a = zi[r0:r1, c0:c1]
    b = zj[r0 - t[0]:r1 - t[0], c0 - t[1]:c1 - t[1]]
    ok = oki[r0:r1, c0:c1] & okj[r0 - t[0]:r1 - t[0], c0 - t[1]:c1 - t[1]]
    if ok.sum() < 16:
        return np.asarray(t, float), True
    w = np.outer(tukey(a.shape[0], 0.5), tukey(a.shape[1], 0.5))
    a = _plane_removed(a, ok) * w
    b = _plane_removed(b, ok) * w
    d = phase_cross_correlation(a, b, upsample_factor=20)[0]
    if np.all(np.abs(d) < 1.0):
        return np.asarray(t, float) + d, True
    return np.asarray(t, float), True


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


def stitch(tiles, nominal_xy_m, max_shift_px=20, blend="feather", min_overlap_px=8, snap_px=0.05):
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
            raise InputError(_tile_label(t, k), f"spacing {t.dx_m:g} x {t.dy_m:g} m differs from "
                             f"the first tile's {dx:g} x {dy:g} m")
    labels = [_tile_label(t, k) for k, t in enumerate(tiles)]
    xy = np.asarray(nominal_xy_m, dtype=float).reshape(n, 2)
    P0 = np.column_stack([xy[:, 1] / dy, xy[:, 0] / dx])        # (row, col) [samples]

    # candidate pairs from nominal footprints
    pairs = []
    for i in range(n):
        for j in range(i + 1, n):
            t0 = tuple(int(v) for v in np.rint(P0[j] - P0[i]))
            r0, r1, c0, c1 = _overlap_rect(tiles[i].shape, tiles[j].shape, t0)
            if r1 - r0 >= min_overlap_px and c1 - c0 >= min_overlap_px:
                pairs.append((i, j, t0))
    if n > 1:
        _check_connected(n, pairs, labels)

    # 1. registration (on plane-levelled tiles)
    ok = [~t.unmeasured for t in tiles]
    lev = [_plane_removed(t.heights_m, o) for t, o in zip(tiles, ok)]
    hp = [_highpass(z, o) for z, o in zip(lev, ok)]
    reg = []
    for i, j, t0 in pairs:
        T, good = _register_pair(lev[i], ok[i], lev[j], ok[j], t0, m, hp[i], hp[j])
        r0, r1, c0, c1 = _overlap_rect(tiles[i].shape, tiles[j].shape, tuple(np.rint(T).astype(int)))
        reg.append((i, j, T, good, max(1, (r1 - r0) * (c1 - c0)), P0[j] - P0[i]))
    if n > 1:   # a nominal overlap whose textures do not match is no overlap
        _check_connected(n, [(i, j, None) for i, j, _, good, *_ in reg if good], labels,
                         how=" whose texture matches (no correlation peak within max_shift_px "
                             "of the nominal position: check the positions)")

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
    sx, sy = shape[1] / 2.0, shape[0] / 2.0          # scaled coordinates for conditioning
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
        X = np.column_stack([np.ones(rr.size), (cc + sl[1].start - sx) / sx,
                             (rr + sl[0].start - sy) / sy])
        d = placed[i][0][si][both] - placed[j][0][sj][both]
        M = X.T @ X
        v = X.T @ d
        I, J = slice(3 * i, 3 * i + 3), slice(3 * j, 3 * j + 3)
        A[I, I] += M
        A[J, J] += M
        A[I, J] -= M
        A[J, I] -= M
        b[I] += v
        b[J] -= v
        ov.append((i, j, sl, si, sj, both, T - Tnom, good))
    u = np.zeros(3 * n)
    if n > 1:
        u[3:], *_ = np.linalg.lstsq(A[3:, 3:], b[3:], rcond=None)
    U = u.reshape(n, 3)
    # corrections in metres of the mosaic frame: a + bx x + by y, x = col dx, y = row dy
    bx = U[:, 1] / (sx * dx)
    by = U[:, 2] / (sy * dy)
    a = U[:, 0] - U[:, 1] - U[:, 2]

    rows, cols = np.mgrid[0:shape[0], 0:shape[1]]
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
    for i, j, sl, si, sj, both, shift, good in ov:
        diff = corrected[i][si][both] - corrected[j][sj][both]
        overlaps.append({"i": i, "j": j, "n_points": int(both.sum()),
                         "rms_mismatch_m": float(np.sqrt(np.mean(diff ** 2))),
                         "shift_px": (float(shift[0]), float(shift[1])), "registered": bool(good)})

    origin_xy = (origin[1] * dx, origin[0] * dy)
    hm = HeightMap(mosaic, dx, dy, name="mosaic",
                   meta={"origin_xy_m": origin_xy, "tiles": labels, "stitch_blend": blend})
    positions = np.column_stack([P[:, 1] * dx, P[:, 0] * dy])
    return StitchResult(heightmap=hm, positions_m=positions, offsets_m=a,
                        tilts=np.column_stack([bx, by]), overlaps=overlaps,
                        meta={"tile_names": labels, "blend": blend, "max_shift_px": m})


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


def _check_connected(n, pairs, labels, how=""):
    """Raise InputError naming a tile cut off from tile 0 in the overlap graph (``how`` is
    appended to the message)."""
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
    raise InputError(labels[k], f"tile {labels[k]} and its neighbours do not overlap the "
                     f"tiles connected to {labels[0]}{how}")
