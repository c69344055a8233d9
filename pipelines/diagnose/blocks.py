"""Descriptor families of one block of a scan (the surface level's "held out in space").

A scan is split into equal blocks (tiles of an area: a grid of ``nb x nb``; sections of a
profile); each block, after removing its own mean plane (line), gives one value per entry of
five descriptor families:

``spectrum``
    the shape of the spectrum: log10 of the ring-averaged 2D PSD (Persson's normalisation, Tukey window alpha = 0.25,
    :func:`roadscan.spectrum.psd_2d`) in log-spaced rings (``RINGS_PER_DECADE``) from
    2 pi / L_block to the Nyquist wave vector, *excluding the two lattice axes* (qx = 0 or
    qy = 0, where seams put their power); averaged into bands of ``RINGS_PER_BAND`` rings, minus
    the mean over the bands (a block's overall level is no diagnostic: the shape is).
    Profiles: log10 of the 1D PSD C1 of the section in the same rings.
``height``
    the L-skewness tau3 and L-kurtosis tau4 of the block's heights (Hosking 1990, J. R. Stat.
    Soc. B 52, 105: ratios of L-moments, linear in the order statistics; robust where the
    moment skewness and kurtosis of a block are dominated by a few deep valleys; Gaussian
    heights: tau3 = 0, tau4 = 0.1226).
``anisotropy`` (areas)
    the index (l1 - l2) / (l1 + l2) of the direction tensor M = sum w q^ q^T, w = C / (ring mean
    of C), over the off-axis lattice points (as :func:`roadscan.spectrum.anisotropy`, axes left out).
``seams`` (areas)
    the lattice-axis excess: the mean over rings (radius >= ``AXIS_MIN_K`` lattice steps) of
    log10( mean C on the axes / mean C on the lattice lines one and two steps beside them ).
    About 0 for a seamless surface, directional or not (C is smooth across the axis), > 0 when
    steps, seams or stitching residue put power exactly on the axes.
``rain`` (areas)
    the rain-fill response (:func:`roadscan.rain.rain_fill`, 4-connected): the mean log10
    wet/dry ring spectrum in three equal log-q thirds of the block's band, and the wetted
    fraction.

The ring-level log10 spectrum is kept too (``spec_rings``): surface effects act on it before
it is averaged into bands (:class:`Geometry.band_matrix`).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy import stats

__all__ = ["Geometry", "geometry", "split", "block_descriptors", "FAMILIES"]

RINGS_PER_DECADE = 20
RINGS_PER_BAND = 6
AXIS_MIN_K = 8
FAMILIES = ("spectrum", "height", "anisotropy", "seams", "rain")


@dataclass(eq=False)
class Geometry:
    """Block layout and ring bookkeeping shared by every block (all blocks have one shape)."""

    is_profile: bool
    shape: tuple          # block shape (ny, nx) or (n,)
    dx_m: float
    dy_m: float
    starts: list          # slices of each block
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
        ny, nx = self.shape
        kx = np.fft.fftshift(np.fft.fftfreq(nx) * nx).round().astype(int)
        ky = np.fft.fftshift(np.fft.fftfreq(ny) * ny).round().astype(int)
        KX, KY = np.meshgrid(kx, ky)
        QX = 2 * np.pi * KX / (nx * self.dx_m)
        QY = 2 * np.pi * KY / (ny * self.dy_m)
        Q = np.hypot(QX, QY)
        r = np.searchsorted(e, Q.ravel(), side="right").reshape(Q.shape) - 1
        r[(Q > e[-1] * (1 + 1e-12)) | (Q < e[0] * (1 - 1e-12)) | (Q == 0)] = -1
        r = np.clip(r, -1, e.size - 2)
        m = np.minimum(np.abs(KX), np.abs(KY))
        kr = np.hypot(KX, KY)
        return dict(q=Q, ring=r, axis=(m == 0), beside=(m >= 1) & (m <= 2), kr=kr,
                    ux=np.where(Q > 0, QX / np.where(Q > 0, Q, 1), 0), uy=np.where(Q > 0, QY / np.where(Q > 0, Q, 1), 0))

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


def geometry(obj, n_blocks=None, rain=True):
    """Block layout of a levelled HeightMap or Profile.

    Areas: ``nb x nb`` equal tiles, nb = 2 below 600 points a side, else 3. Profiles: sections of at least 256 points, 4 to 8 of them.
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
    starts = [(slice(j * by, (j + 1) * by), slice(i * bx, (i + 1) * bx)) for j in range(nb) for i in range(nb)]
    return Geometry(False, (by, bx), obj.dx_m, obj.dy_m, starts, rain=rain)


def split(heights, geo):
    """The blocks of a height array: (block with its own mean plane / line removed, block as cut)."""
    return [(_detrend(np.array(heights[s], float)), np.array(heights[s], float)) for s in geo.starts]


def _detrend(h):
    if h.ndim == 1:
        x = np.linspace(-1, 1, h.size)
        A = np.column_stack([np.ones_like(x), x])
    else:
        ny, nx = h.shape
        Y, X = np.meshgrid(np.linspace(-1, 1, ny), np.linspace(-1, 1, nx), indexing="ij")
        A = np.column_stack([np.ones(h.size), X.ravel(), Y.ravel()])
    c, *_ = np.linalg.lstsq(A, h.ravel(), rcond=None)
    return h - (A @ c).reshape(h.shape)


def _window(shape, alpha=0.25):
    from scipy.signal.windows import tukey

    w = tukey(shape[0], alpha)
    if len(shape) == 2:
        w = np.outer(w, tukey(shape[1], alpha))
    return w, float(np.mean(w ** 2))


def _psd_map(h, geo):
    """Persson-normalised PSD on the fftshifted lattice (areas) or C1 at q_k >= 2 pi / L (profiles)."""
    w, w2 = _window(h.shape)
    if geo.is_profile:
        n = h.size
        L = n * geo.dx_m
        F = np.fft.rfft((h - h.mean()) * w)[1:n // 2 + 1]
        return np.abs(F) ** 2 * geo.dx_m ** 2 / (2 * np.pi * L * w2)
    ny, nx = h.shape
    area = nx * geo.dx_m * ny * geo.dy_m
    F = np.fft.fftshift(np.fft.fft2(h * w))
    return (F.real ** 2 + F.imag ** 2) * (geo.dx_m * geo.dy_m) ** 2 / ((2 * np.pi) ** 2 * area * w2)


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


def _anisotropy_index(P, geo):
    lat = geo.lattice
    sel = (lat["ring"] >= 0) & ~lat["axis"]
    r = lat["ring"][sel]
    C = P[sel]
    nr = geo.ring_edges.size - 1
    cnt = np.bincount(r, minlength=nr)
    mean_c = np.bincount(r, C, minlength=nr) / np.maximum(cnt, 1)
    w = C / np.where(mean_c[r] > 0, mean_c[r], 1.0)
    w = w / w.sum()
    ux, uy = lat["ux"][sel], lat["uy"][sel]
    M = np.array([[np.sum(w * ux * ux), np.sum(w * ux * uy)], [np.sum(w * ux * uy), np.sum(w * uy * uy)]])
    ev = np.linalg.eigvalsh(M)
    return float((ev[1] - ev[0]) / (ev[1] + ev[0]))


def _axis_excess(P, geo):
    lat = geo.lattice
    nr = geo.ring_edges.size - 1
    ok = (lat["ring"] >= 0) & (lat["kr"] >= AXIS_MIN_K)
    on, bes = ok & lat["axis"], ok & lat["beside"]
    c_on = np.bincount(lat["ring"][on], P[on], minlength=nr)
    n_on = np.bincount(lat["ring"][on], minlength=nr)
    c_b = np.bincount(lat["ring"][bes], P[bes], minlength=nr)
    n_b = np.bincount(lat["ring"][bes], minlength=nr)
    m = (n_on > 0) & (n_b > 0) & (c_b > 0)
    if not m.any():
        return 0.0
    return float(np.mean(np.log10((c_on[m] / n_on[m]) / (c_b[m] / n_b[m]))))


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
    """The descriptor families of one detrended block ``h`` -> dict family -> 1D array, plus
    ``spec_rings`` (the ring-level log10 spectrum the spectrum family averages). The height
    family uses ``raw`` (the block as cut from the levelled scan, default ``h``): removing each
    block's own plane would remove much of the long-wavelength height distribution."""
    P = _psd_map(h, geo)
    rings = _ring_log(P, geo)
    hv = (h if raw is None else raw).ravel()
    bands = geo.band_matrix @ rings
    out = dict(spec_rings=rings, bands=bands, spectrum=spectrum_shape(bands),
               height=np.array(l_moment_ratios(hv)),
               moments=np.array([float(stats.skew(hv)), float(stats.kurtosis(hv))]))
    if not geo.is_profile:
        out["anisotropy"] = np.array([_anisotropy_index(P, geo)])
        out["seams"] = np.array([_axis_excess(P, geo)])
        if rain and geo.rain:
            out["rain"] = _rain(h, geo, P)
    return out


def describe(heights, geo, rain=True):
    """Descriptors of every block of ``heights``: dict family -> (n_blocks, n_entries)."""
    per = [block_descriptors(b, geo, rain, raw) for b, raw in split(heights, geo)]
    return {k: np.array([p[k] for p in per]) for k in per[0]}
