"""Descriptor families of one block of a scan (the surface level's "held out in space").

A scan is split into equal blocks (tiles of an area: a grid of ``nb x nb``; sections of a profile); each
block, after removing its own mean plane (line), gives one value per entry of five descriptor families:

``spectrum``
    the shape of the spectrum: log10 of the ring-averaged 2D PSD (Persson's normalisation, Tukey window alpha
    = 0.25, :func:`roadscan.spectrum.psd_2d`) in log-spaced rings (``RINGS_PER_DECADE``) from 2 pi / L_block
    to the Nyquist wave vector, *excluding the two lattice axes* (qx = 0 or qy = 0, where seams put their
    power, :func:`near_axes`); averaged into bands of ``RINGS_PER_BAND`` rings, minus the mean over the bands
    (a block's overall level is no diagnostic: the shape is). Profiles: log10 of the 1D PSD C1 of the section
    in the same rings.
``height``
    the L-skewness tau3 and L-kurtosis tau4 of the block's heights (Hosking 1990, J. R. Stat. Soc. B 52, 105:
    ratios of L-moments, linear in the order statistics; robust where the moment skewness and kurtosis of a
    block are dominated by a few deep valleys; Gaussian heights: tau3 = 0, tau4 = 0.1226), and the L-skewness
    of the block's curvature, the Laplacian at a lag of ``CURV_LAG`` points (second difference for a profile).
    Any linear filter of a Gaussian field is Gaussian, so this is 0 for the twin whatever its spectrum,
    direction, smoothing or white noise; a non-Gaussian height law h -> g(h) gives Lap g = g' Lap h +
    g'' |grad h|^2, whose skewness has the sign of g'' (sharp peaks and broad valleys, or worn plateaus). The
    curvature is short-correlated, so unlike the skewness of a block's heights, which a few long waves
    dominate, it is precise on a small block and much the same in every block.
``anisotropy`` (areas)
    the signed components (a, b) = (M_xx - M_yy, 2 M_xy) / (M_xx + M_yy) of the direction tensor M = sum w
    q^ q^T, w = C / (ring mean of C), over the lattice points off the axes (more than ``AXIS_EXCLUDE`` steps
    from them) and from ``ANISO_MIN_K`` lattice steps up, of the prewhitened block (5-point Laplacian before a
    Tukey window, alpha = 0.5): the Laplacian takes the steep self-affine fall-off out of the spectrum, so
    window leakage from the long waves (strong along the axes) cannot fake a direction. Index = hypot(a, b),
    direction = atan2(b, a) / 2 from the x axis. Both are 0 for an isotropic texture (no positive bias, unlike
    the index).
``seams`` (areas)
    straight discontinuities along the lattice axes (stitching seams, steps, tilt residue): the second
    difference across each line of the block (K_j = h_{j+1} - 2 h_j + h_{j-1}, rows and columns in turn) is
    cut into ``SEAM_SEGMENTS`` segments along the line; t = mean / (std / sqrt(n)) of a segment is large where
    the whole segment jumps together, and a line's score is the median over its segments of t^2. The entry is
    log10(max score / median score) over the lines, the larger of rows and columns: about 0.9 for a seamless
    block (the maximum of ~100 scores), 2 to 4 for a step of a fraction of the rms height. Self-normalised per
    segment, it does not move with the texture's direction, height law, smoothing or noise level.
``rain`` (areas)
    the rain-fill response (:func:`roadscan.rain.rain_fill`, 4-connected): the mean log10 wet/dry ring
    spectrum in three equal log-q thirds of the block's band, and the wetted fraction.

The ring-level log10 spectrum is kept too (``spec_rings``): surface effects act on it before it is averaged
into bands (:class:`Geometry.band_matrix`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy import stats

__all__ = ["Geometry", "geometry", "split", "block_descriptors", "FAMILIES"]

RINGS_PER_DECADE = 20
RINGS_PER_BAND = 6
AXIS_EXCLUDE = 3
ANISO_MIN_K = 4
SEAM_SEGMENTS = 4
CURV_LAG = 2
FAMILIES = ("spectrum", "height", "anisotropy", "seams", "rain")


@dataclass(eq=False)
class Geometry:
    """Block layout and ring bookkeeping shared by every block (all blocks have one shape).

    Attributes
    ----------
    is_profile : bool
        True for a line profile (blocks are sections), False for an area scan (blocks are tiles).
    shape : tuple of int
        Shape of every block in points: (ny, nx) tiles, or (n,) sections.
    dx_m, dy_m : float
        Point spacings [m] along x and y (dy_m = dx_m for a profile).
    starts : list of tuple of slice
        Index slices of each block in the scan's height array, one tuple per block.
    rain : bool
        Whether the rain-fill family is described (areas only).
    """

    is_profile: bool
    shape: tuple  # block shape (ny, nx) or (n,)
    dx_m: float
    dy_m: float
    starts: list  # slices of each block
    rain: bool = True

    @cached_property
    def ring_edges(self):
        if self.is_profile:
            L = self.shape[0] * self.dx_m
            q_max = np.pi / self.dx_m
        else:
            L = max(self.shape[0] * self.dy_m, self.shape[1] * self.dx_m)
            q_max = np.pi / max(self.dx_m, self.dy_m)
        q_min = 2 * np.pi / L
        n = max(1, int(np.ceil(RINGS_PER_DECADE * np.log10(q_max / q_min) - 1e-9)))
        return q_min * (q_max / q_min) ** (np.arange(n + 1) / n)

    @cached_property
    def lattice(self):
        """Ring index of each lattice point (-1 outside), axis masks, |q| (areas: full shifted grid)."""
        e = self.ring_edges
        if self.is_profile:
            n = self.shape[0]
            q = 2 * np.pi * np.arange(1, n // 2 + 1) / (n * self.dx_m)
            r = np.searchsorted(e, q, side="right") - 1
            r[(q > e[-1] * (1 + 1e-12))] = -1
            r = np.clip(r, -1, e.size - 2)
            return dict(q=q, ring=r)
        KX, KY, _QX, _QY, Q = _lattice_q(self.shape, self.dx_m, self.dy_m)
        r = np.searchsorted(e, Q.ravel(), side="right").reshape(Q.shape) - 1
        r[(Q > e[-1] * (1 + 1e-12)) | (Q < e[0] * (1 - 1e-12)) | (Q == 0)] = -1
        r = np.clip(r, -1, e.size - 2)
        return dict(q=Q, ring=r, axis=near_axes(KX, KY))

    @cached_property
    def lap_lattice(self):
        """Lattice of the prewhitened (Laplacian) block, (ny - 2) x (nx - 2): the points used by
        the anisotropy components, their ring, and the unit vectors of their physical q."""
        ny, nx = self.shape[0] - 2, self.shape[1] - 2
        KX, KY, QX, QY, Q = _lattice_q((ny, nx), self.dx_m, self.dy_m)
        kr = np.hypot(KX, KY)
        kmax = min(nx, ny) // 2
        sel = (np.minimum(np.abs(KX), np.abs(KY)) > AXIS_EXCLUDE) & (kr >= ANISO_MIN_K) & (kr <= kmax)
        edges = np.geomspace(ANISO_MIN_K, kmax + 1e-9, 13)
        ring = np.clip(np.searchsorted(edges, kr[sel], side="right") - 1, 0, edges.size - 2)
        return dict(
            shape=(ny, nx),
            sel=sel,
            ring=ring,
            n_rings=edges.size - 1,
            ux=QX[sel] / Q[sel],
            uy=QY[sel] / Q[sel],
        )

    @property
    def symmetric(self):
        """Square block of square pixels: the lattice has the symmetry of an isotropic texture, so
        the anisotropy components of a twin have expectation 0 exactly."""
        return (not self.is_profile) and self.shape[0] == self.shape[1] and np.isclose(self.dx_m, self.dy_m)

    @cached_property
    def rings(self):
        """Indices of the rings that hold off-axis lattice points, and their mean |q|."""
        lat = self.lattice
        nr = self.ring_edges.size - 1
        if self.is_profile:
            sel = lat["ring"] >= 0
            cnt = np.bincount(lat["ring"][sel], minlength=nr)
            qs = np.bincount(lat["ring"][sel], lat["q"][sel], minlength=nr)
        else:
            sel = (lat["ring"] >= 0) & ~lat["axis"]
            cnt = np.bincount(lat["ring"][sel], minlength=nr)
            qs = np.bincount(lat["ring"][sel], lat["q"][sel], minlength=nr)
        keep = np.flatnonzero(cnt > 0)
        return keep, qs[keep] / cnt[keep], cnt[keep]

    @cached_property
    def band_matrix(self):
        """(n_bands, n_rings) averaging matrix: bands of RINGS_PER_BAND consecutive kept rings."""
        n = self.rings[0].size
        nb = max(1, int(round(n / RINGS_PER_BAND)))
        idx = np.minimum((np.arange(n) * nb) // n, nb - 1)
        A = np.zeros((nb, n))
        A[idx, np.arange(n)] = 1.0
        return A / A.sum(axis=1, keepdims=True)

    @property
    def band_q(self):
        return 10 ** (self.band_matrix @ np.log10(self.rings[1]))

    def families(self):
        return ("spectrum", "height") if self.is_profile else (FAMILIES if self.rain else FAMILIES[:4])


def _lattice_q(shape, dx_m, dy_m):
    """Integer wave indices (KX, KY) of an fftshifted (ny, nx) lattice and their physical wave
    vectors QX, QY, |Q| [1/m] for spacings dx, dy [m]."""
    ny, nx = shape
    kx = np.fft.fftshift(np.fft.fftfreq(nx) * nx).round().astype(int)
    ky = np.fft.fftshift(np.fft.fftfreq(ny) * ny).round().astype(int)
    KX, KY = np.meshgrid(kx, ky)
    QX = 2 * np.pi * KX / (nx * dx_m)
    QY = 2 * np.pi * KY / (ny * dy_m)
    return KX, KY, QX, QY, np.hypot(QX, QY)


def near_axes(KX, KY):
    """Lattice points (integer indices) on the axes (kx = 0 or ky = 0), where straight steps and seams put
    their power. (Sectors beside the axes, where the window spreads part of it, were tried too: a texture
    stretched by interpolation has no power at high q across its direction, and leaving sectors out then
    bends its ring-averaged spectrum.)"""
    return (KX == 0) | (KY == 0)


def geometry(obj, n_blocks=None, rain=True):
    """Block layout of a levelled HeightMap or Profile (ValueError when a block would be too small).

    Parameters
    ----------
    obj : HeightMap or Profile
        The levelled scan: its shape and spacings [m]; an area needs tiles of 24 points a side or more.
    n_blocks : int, optional
        Tiles a side (None: 2, from 600 points a side 3) or profile sections (None: n // 256 in 2..8).
    rain : bool, optional
        Whether the rain-fill family is described (areas; a profile has none).

    Returns
    -------
    Geometry
    """
    from roadscan.heightmap import Profile

    if isinstance(obj, Profile):
        n = obj.heights_m.size
        k = n_blocks or int(np.clip(n // 256, 2, 8))
        if n // k < 32:
            raise ValueError(f"profile of {n} points is too short to split into sections")
        m = n // k
        return Geometry(True, (m,), obj.dx_m, obj.dx_m, [(slice(i * m, (i + 1) * m),) for i in range(k)])
    ny, nx = obj.shape
    nb = n_blocks or (2 if min(nx, ny) < 600 else 3)
    # equal tiles covering the map (tiles that avoid the simple fractions 1/2, 1/3 where a
    # regular stitching's seams lie were tried: the Tukey taper of a tile's edge attenuates a
    # seam near it anyway, and smaller tiles lose the lowest wave vectors a roll-off needs)
    frac = 1.0 / nb
    by, bx = int(ny * frac), int(nx * frac)
    if min(by, bx) < 24:
        raise ValueError(f"height map of {ny} x {nx} points is too small to split into {nb} x {nb} tiles")
    starts = [
        (slice(j * by, (j + 1) * by), slice(i * bx, (i + 1) * bx)) for j in range(nb) for i in range(nb)
    ]
    return Geometry(False, (by, bx), obj.dx_m, obj.dy_m, starts, rain=rain)


def split(heights, geo):
    """The blocks of a height array in ``geo.starts`` order: (block less its mean plane / line, block as cut).

    Parameters
    ----------
    heights : ndarray
        Heights [m] of the scan the layout was made for (same shape).
    geo : Geometry
        The block layout (:func:`geometry`).

    Returns
    -------
    list of tuple of ndarray
    """
    return [(_detrend(np.array(heights[s], float)), np.array(heights[s], float)) for s in geo.starts]


def _detrend(h):
    """The block less its least-squares mean plane (line for a profile): roadscan's form removal
    (:func:`roadscan.level.polynomial_form`, degree 1)."""
    from roadscan.level import polynomial_form

    return h - polynomial_form(h, np.zeros(h.shape, bool), 1)


def _window(shape, alpha=0.25):
    """The Tukey window of a block and its mean square (roadscan's, :func:`roadscan.spectrum.window_2d`)."""
    from roadscan.spectrum import window_2d

    if len(shape) == 1:
        w, w2 = window_2d(1, shape[0], alpha)
        return w[0], w2
    return window_2d(shape[0], shape[1], alpha)


def _psd_map(h, geo):
    """Persson-normalised PSD on the fftshifted lattice (areas) or C1 at q_k >= 2 pi / L (profiles)."""
    w, w2 = _window(h.shape)
    if geo.is_profile:
        n = h.size
        L = n * geo.dx_m
        F = np.fft.rfft((h - h.mean()) * w)[1 : n // 2 + 1]
        return np.abs(F) ** 2 * geo.dx_m**2 / (2 * np.pi * L * w2)
    ny, nx = h.shape
    area = nx * geo.dx_m * ny * geo.dy_m
    F = np.fft.fftshift(np.fft.fft2(h * w))
    return (F.real**2 + F.imag**2) * (geo.dx_m * geo.dy_m) ** 2 / ((2 * np.pi) ** 2 * area * w2)


def _ring_log(P, geo, exclude_axis=True):
    lat = geo.lattice
    nr = geo.ring_edges.size - 1
    keep = geo.rings[0]
    if geo.is_profile:
        sel = lat["ring"] >= 0
        r, c = lat["ring"][sel], P[sel]
    else:
        sel = (lat["ring"] >= 0) & (~lat["axis"] if exclude_axis else True)
        r, c = lat["ring"][sel], P[sel]
    cnt = np.bincount(r, minlength=nr)[keep]
    s = np.bincount(r, c, minlength=nr)[keep]
    return np.log10(np.maximum(s / np.maximum(cnt, 1), 1e-300))


def _laplacian(h):
    """5-point discrete Laplacian of the interior of a 2D array (no spacing factor: it only prewhitens)."""
    return h[1:-1, 2:] + h[1:-1, :-2] + h[2:, 1:-1] + h[:-2, 1:-1] - 4.0 * h[1:-1, 1:-1]


def anisotropy_components(h, geo):
    """(a, b) of a detrended block (see the module docstring, ``anisotropy``)."""
    lat = geo.lap_lattice
    L = _laplacian(h)
    w, _ = _window(L.shape, 0.5)
    F = np.fft.fftshift(np.fft.fft2((L - L.mean()) * w))
    C = (F.real**2 + F.imag**2)[lat["sel"]]
    r = lat["ring"]
    cnt = np.bincount(r, minlength=lat["n_rings"])
    mean_c = np.bincount(r, C, minlength=lat["n_rings"]) / np.maximum(cnt, 1)
    wt = C / np.where(mean_c[r] > 0, mean_c[r], 1.0)
    s = wt.sum()
    if not s > 0:
        return np.zeros(2)
    wt = wt / s
    ux, uy = lat["ux"], lat["uy"]
    return np.array([float(np.sum(wt * (ux * ux - uy * uy))), float(np.sum(wt * 2.0 * ux * uy))])


def line_score(a):
    """log10(max / median) over the lines (rows) of ``a`` of the line score: the second difference across
    each line, cut into ``SEAM_SEGMENTS`` segments, t = mean / (std / sqrt(n)) per segment, median of t^2
    over the segments (see the module docstring, ``seams``). None when ``a`` is too small."""
    if a.shape[0] < 8:
        return None
    K = a[2:] - 2.0 * a[1:-1] + a[:-2]
    S = K.shape[1] // SEAM_SEGMENTS
    if S < 4:
        return None
    seg = K[:, : SEAM_SEGMENTS * S].reshape(K.shape[0], SEAM_SEGMENTS, S)
    m = seg.mean(axis=-1)
    sd = seg.std(axis=-1, ddof=1)
    t2 = np.where(sd > 0, (m / np.where(sd > 0, sd, 1.0)) ** 2 * S, 0.0)
    score = np.median(t2, axis=1)
    med = float(np.median(score))
    return float(np.log10(score.max() / med)) if med > 0 else None


def seam_score(h):
    """The larger line score (:func:`line_score`) of the rows and of the columns of a detrended block."""
    out = [x for x in (line_score(h), line_score(h.T)) if x is not None]
    return max(out) if out else 0.0


def curvature_l_skewness(h, lag=CURV_LAG):
    """L-skewness tau3 of the lag-``lag`` Laplacian of a block (second difference of a profile):
    0 in expectation for any Gaussian field (see the module docstring, ``height``)."""
    k = lag
    if h.ndim == 1:
        if h.size <= 2 * k + 4:
            return 0.0
        c = h[2 * k :] + h[: -2 * k] - 2.0 * h[k:-k]
    else:
        if min(h.shape) <= 2 * k + 4:
            return 0.0
        c = h[k:-k, 2 * k :] + h[k:-k, : -2 * k] + h[2 * k :, k:-k] + h[: -2 * k, k:-k] - 4.0 * h[k:-k, k:-k]
    return l_moment_ratios(c)[0]


def _rain(h, geo, P=None):
    from roadscan.heightmap import HeightMap
    from roadscan.rain import rain_fill

    hm = HeightMap(h, geo.dx_m, geo.dy_m, name="block")
    rf = rain_fill(hm)
    dry = _ring_log(_psd_map(h, geo) if P is None else P, geo)
    wet = _ring_log(_psd_map(rf.wet.heights_m - rf.wet.heights_m.mean(), geo), geo)
    r = wet - dry
    thirds = np.array_split(np.arange(r.size), 3)
    return np.array([float(np.mean(r[t])) for t in thirds] + [float(rf.wetted_fraction)])


def l_moment_ratios(x):
    """(tau3, tau4) of a sample: L-skewness and L-kurtosis from the unbiased probability-weighted
    moments b_r of the order statistics (Hosking 1990)."""
    x = np.sort(np.asarray(x, float).ravel())
    n = x.size
    i = np.arange(n, dtype=float)
    b0 = x.mean()
    b1 = np.sum(i / (n - 1) * x) / n
    b2 = np.sum(i * (i - 1) / ((n - 1) * (n - 2)) * x) / n
    b3 = np.sum(i * (i - 1) * (i - 2) / ((n - 1) * (n - 2) * (n - 3)) * x) / n
    l2 = 2 * b1 - b0
    l3 = 6 * b2 - 6 * b1 + b0
    l4 = 20 * b3 - 30 * b2 + 12 * b1 - b0
    return (float(l3 / l2), float(l4 / l2)) if l2 > 0 else (0.0, 0.1226)


def spectrum_shape(band_log):
    """The spectrum's shape at its two ends: (lowest band, highest band) minus the mean of the
    bands between them (last axis). A block's overall level is no diagnostic, nor (with a
    fitted power law as the model) its mid-band slope; roll-offs, noise floors and smoothing
    bend the ends, and two entries keep their deviation from being averaged away."""
    b = np.asarray(band_log)
    if b.shape[-1] < 3:
        return b - np.mean(b, axis=-1, keepdims=True)
    mid = np.mean(b[..., 1:-1], axis=-1)
    return np.stack([b[..., 0] - mid, b[..., -1] - mid], axis=-1)


def block_descriptors(h, geo, rain=True, raw=None):
    """The descriptor families of one detrended block ``h`` (see the module docstring).

    Parameters
    ----------
    h : ndarray
        The block's heights [m] less its own mean plane (line), shape ``geo.shape``.
    geo : Geometry
        The layout the block was cut with (its rings, bands and spacings).
    rain : bool, optional
        Also the rain family (areas with ``geo.rain`` only; default True).
    raw : ndarray, optional
        The block as cut, for the height family (None: ``h``): its own plane would hide the long waves.

    Returns
    -------
    dict
        Family -> 1D array, plus ``spec_rings`` (ring-level log10 spectrum), ``bands`` and ``moments``.
    """
    P = _psd_map(h, geo)
    rings = _ring_log(P, geo)
    hv = (h if raw is None else raw).ravel()
    bands = geo.band_matrix @ rings
    out = dict(
        spec_rings=rings,
        bands=bands,
        spectrum=spectrum_shape(bands),
        height=np.array(l_moment_ratios(hv) + (curvature_l_skewness(h),)),
        moments=np.array([float(stats.skew(hv)), float(stats.kurtosis(hv))]),
    )
    if not geo.is_profile:
        out["anisotropy"] = anisotropy_components(h, geo)
        out["seams"] = np.array([seam_score(h)])
        if rain and geo.rain:
            out["rain"] = _rain(h, geo, P)
    return out


def describe(heights, geo, rain=True):
    """Descriptors of every block of ``heights``: dict family -> (n_blocks, n_entries)."""
    per = [block_descriptors(b, geo, rain, raw) for b, raw in split(heights, geo)]
    return {k: np.array([p[k] for p in per]) for k in per[0]}
