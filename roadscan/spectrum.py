"""Power spectral densities of height maps and line profiles (Persson's normalisation).

2D (DESIGN.md section 2). With the window w, H_m = FFT2(w h) and A = L_x L_y = n_x dx n_y dy,

    C(q_m) = (dx dy)^2 |H_m|^2 / ((2 pi)^2 A <w^2>)          [m^4]

on the FFT lattice q = 2 pi (k_x / L_x, k_y / L_y); <h^2> = sum_m C(q_m) (2 pi)^2 / A
(Parseval, for the windowed heights divided by <w^2>), and for an isotropic surface
<h^2> = 2 pi int q C(q) dq. Dividing by <w^2> (the mean of w^2 over the grid, 0.7105 for the
2D Tukey window with alpha = 0.25) restores the power the window removes. The window is the
outer product of two 1D Tukey windows (``roadscan.windows.tukey``, equal to
``scipy.signal.windows.tukey``) (alpha = 0: rectangular,
alpha = 1: Hann). SurfaceTopography's C is (2 pi)^2 times this one.

1D (line profiles), with L = n dx:

    C1(q_k) = dx^2 |FFT(w h)_k|^2 / (2 pi L <w^2>)            [m^3],  <h^2> = 2 int_0^inf C1 dq.

For an isotropic surface C1(q_x) = int dq_y C(sqrt(q_x^2 + q_y^2)) (an Abel transform). For a
power law C ~ q^(-2(1+H)) it inverts to the conversion used here, named
``"power-law Abel inversion"`` in ``meta['conversion']``:

    C(q) = C1(q) / q * Gamma(1 + H) / (sqrt(pi) Gamma(H + 1/2)),

with H estimated from the slope of C1 (C1 ~ q^-(1 + 2H)) over its self-affine band unless given.

Angular averages use log-spaced rings from q_min = 2 pi / L (the longer side) to the Nyquist
wave vector q_max = pi / max(dx, dy); each ring reports the mean |q| and the mean C of the
lattice points inside it, and the number of points; empty rings are dropped.

Reference: Persson et al., J. Phys.: Condens. Matter 17, R1 (2005); Jacobs, Junge, Pastewka,
Surf. Topogr.: Metrol. Prop. 5, 013001 (2017).
"""
from __future__ import annotations

from functools import lru_cache

import math

import numpy as np

from .heightmap import HeightMap, Profile
from .level import row_chunks
from .spectrum_types import HalfLattice, Spectrum, Spectrum2D, _full_from_half  # noqa: F401
from .windows import tukey

__all__ = ["psd_2d", "angular_average", "psd_area", "psd_profile", "anisotropy",
           "window_2d", "profile_to_area_factor", "NORMALISATION_2D", "NORMALISATION_1D"]

NORMALISATION_2D = "C = (dx dy)^2 |FFT2(w h)|^2 / ((2 pi)^2 A <w^2>) [m^4] (Persson; DESIGN.md sec 2)"
NORMALISATION_1D = "C1 = dx^2 |FFT(w h)|^2 / (2 pi L <w^2>) [m^3]; <h^2> = 2 int_0^inf C1 dq"
_WORKERS = -1
#: maps of up to this many points are transformed with numpy's FFT (pocketfft, one thread):
#: importing ``scipy.fft`` took 0.28 s (scipy 1.17), more than the whole FFT of such a map;
#: larger maps use ``scipy.fft`` (the same pocketfft) on every core
NUMPY_FFT_MAX_POINTS = 1 << 22


class _NumpyFFT:
    """numpy.fft for small maps (no scipy import)."""

    name = "numpy.fft"

    @staticmethod
    def rfft(x, axis=-1):
        return np.fft.rfft(x, axis=axis)

    @staticmethod
    def fft(F, axis):
        return np.fft.fft(F, axis=axis)

    @staticmethod
    def rfft2(x):
        return np.fft.rfft2(x)


class _ScipyFFT:
    """scipy.fft with every core (``workers=-1``) for large maps."""

    name = f"scipy.fft (workers={_WORKERS})"

    @staticmethod
    def rfft(x, axis=-1):
        import scipy.fft as sfft

        return sfft.rfft(x, axis=axis, workers=_WORKERS)

    @staticmethod
    def fft(F, axis):
        import scipy.fft as sfft

        return sfft.fft(F, axis=axis, overwrite_x=True, workers=_WORKERS)   # in place

    @staticmethod
    def rfft2(x):
        import scipy.fft as sfft

        return sfft.rfft2(x, workers=_WORKERS)


def fft_backend(npoints):
    """The FFT used for ``npoints`` samples: numpy's up to :data:`NUMPY_FFT_MAX_POINTS`,
    scipy's with every core above (``.rfft(x, axis)``, ``.rfft2(x)``, ``.fft(F, axis)``, in place
    for scipy);
    :mod:`benchmarks.bench_psd` takes its floor from the same one."""
    return _NumpyFFT if npoints <= NUMPY_FFT_MAX_POINTS else _ScipyFFT


@lru_cache(maxsize=16)
def _tukey(n, alpha):
    w = tukey(n, alpha) if alpha > 0 else np.ones(n)
    w.setflags(write=False)
    return w


def window_2d(ny, nx, alpha=0.25):
    """The 2D Tukey window (outer product of two 1D Tukey windows) and its mean square <w^2>."""
    wy, wx = _tukey(ny, float(alpha)), _tukey(nx, float(alpha))
    return np.outer(wy, wx), _window_mean_square(ny, nx, alpha)


def _window_mean_square(ny, nx, alpha):
    """<w^2> of :func:`window_2d` without building the window."""
    wy, wx = _tukey(ny, float(alpha)), _tukey(nx, float(alpha))
    return float(np.mean(wy**2) * np.mean(wx**2))


def _require_filled(obj, fill_values=None):
    if fill_values is not None:
        n = int(np.count_nonzero(obj.unmeasured))
        if np.shape(fill_values) != (n,) or not np.isfinite(fill_values).all():
            raise ValueError(f"fill_values must be {n} finite heights (one per unmeasured point)")
        return
    if obj.unmeasured.any():
        raise ValueError(f"{obj.name or type(obj).__name__}: {int(obj.unmeasured.sum())} unmeasured "
                         "points; fill them first (roadscan.inpaint.fill_unmeasured)")


def _ring_edges(q_min, q_max, rings_per_decade):
    if not (0 < q_min < q_max):
        raise ValueError(f"need 0 < q_min < q_max, got {q_min}, {q_max}")
    n = max(1, int(np.ceil(rings_per_decade * np.log10(q_max / q_min) - 1e-9)))
    return q_min * (q_max / q_min) ** (np.arange(n + 1) / n)


def _ring_index(q, q_min, q_max, n_rings):
    """Ring number of each |q| (-1 outside [q_min, q_max]); rings log-spaced."""
    qc = np.maximum(q, q_min * 1e-3)
    r = np.floor(np.log(qc / q_min) / np.log(q_max / q_min) * n_rings).astype(np.int64)
    r = np.clip(r, 0, n_rings - 1)                      # |q| == q_min or q_max up to round-off
    r[(q < q_min * (1 - 1e-12)) | (q > q_max * (1 + 1e-12)) | (q <= 0)] = -1
    return r


def _half_qx(nx, dx):
    """qx [1/m] of the rfft half lattice's columns as they sit on the full lattice: the
    Nyquist column of an even nx is q_x = -pi/dx there (numpy's fftfreq), the others >= 0."""
    return 2 * np.pi * np.fft.fftfreq(nx, dx)[: nx // 2 + 1]


def _mirror_columns(nx):
    """Columns of the rfft half lattice stored once on the full lattice (q_x = 0 and, for an
    even nx, the Nyquist column); every other column stands for itself and its mirror -q."""
    return (0, nx // 2) if nx % 2 == 0 and nx > 1 else (0,)


@lru_cache(maxsize=8)
def _ring_runs(ny, nx, dx, dy, q_min, q_max, n_rings):
    """Ring bookkeeping on the rfft2 half lattice (cached per grid; a few MB whatever the size).

    Along a row of the half lattice |q| grows with q_x, so the ring number is constant on
    runs of consecutive points: ``starts`` are the flat indices where a run begins and
    ``ring`` its ring (-1 outside [q_min, q_max]), so that ring sums are one
    ``np.add.reduceat`` pass. ``edges`` are (column, rings of its points) of the columns
    stored once (:func:`_mirror_columns`); ``count`` and ``qsum`` are the number of full-
    lattice points per ring and the sum of their |q|.
    """
    qx = 2 * np.pi * np.fft.rfftfreq(nx, dx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, dy)
    nxr = qx.size
    wcol = np.full(nxr, 2.0)
    wcol[list(_mirror_columns(nx))] = 1.0
    starts, rings = [], []
    count = np.zeros(n_rings)
    qsum = np.zeros(n_rings)
    edge_rings = {c: np.empty(ny, dtype=np.int64) for c in _mirror_columns(nx)}
    for sl in row_chunks(ny, nxr):
        q = np.hypot(qx[None, :], qy[sl, None])
        ring = _ring_index(q.ravel(), q_min, q_max, n_rings).reshape(q.shape)
        for c, er in edge_rings.items():
            er[sl] = ring[:, c]
        flat = ring.ravel()
        st = np.flatnonzero(np.concatenate([[True], flat[1:] != flat[:-1]]))
        starts.append(st + sl.start * nxr)
        rings.append(flat[st])
        ok = ring >= 0
        wt = np.broadcast_to(wcol, ring.shape)[ok]
        count += np.bincount(ring[ok], weights=wt, minlength=n_rings)
        qsum += np.bincount(ring[ok], weights=wt * q[ok], minlength=n_rings)
    out = (np.concatenate(starts), np.concatenate(rings), tuple(edge_rings.items()), count, qsum)
    for a in (out[0], out[1], out[3], out[4], *edge_rings.values()):
        a.setflags(write=False)
    return out


def _ring_sums(P, runs, n_rings):
    """Sum over the full lattice of P in each ring, from the rfft half lattice ``P``."""
    starts, ring, edges = runs[0], runs[1], runs[2]
    part = np.add.reduceat(P.ravel(), starts)
    ok = ring >= 0
    csum = 2.0 * np.bincount(ring[ok], weights=part[ok], minlength=n_rings)
    for c, er in edges:
        sel = er >= 0
        csum -= np.bincount(er[sel], weights=P[:, c][sel], minlength=n_rings)
    return csum


def _taper_ranges(w):
    """(k0, k1) with w == 1 exactly on [k0, k1) and nowhere else, or None."""
    one = np.flatnonzero(w == 1.0)
    if one.size == 0 or one[-1] - one[0] + 1 != one.size:
        return None
    return int(one[0]), int(one[-1]) + 1


#: bands of rows of the FFT step (a map up to this size is transformed in one rfft2 call)
_FFT_BAND_BYTES = 1 << 20


def _half_psd(hm, window_alpha, fill_values=None):
    """|FFT2(w h)|^2 on the rfft2 half lattice (unscaled), the factor that makes it C [m^4]
    and <w^2>.

    The heights are read band by band of rows (about 1 MiB each): a band is copied, its
    unmeasured points set from ``fill_values`` (raster order) when given, multiplied by the
    window where the window is not 1 (its tapered margins; each point by its row's and its
    column's weight, which equals h w to float64 round-off) and transformed along x (rfft);
    then one in-place complex FFT along y (a map of one band: ``rfft2`` of it). The same
    transform as ``rfft2`` of :func:`fft_backend` (numpy's, or scipy's on every core for
    large maps), without a windowed copy of the whole map: the work memory is
    the complex half spectrum plus a band, then |F|^2 (float64, half the heights' size).
    """
    ny, nx = hm.shape
    w2 = _window_mean_square(ny, nx, window_alpha)
    wy, wx = _tukey(ny, float(window_alpha)), _tukey(nx, float(window_alpha))
    ry, rx = _taper_ranges(wy), _taper_ranges(wx)
    h, bad = hm.heights_m, hm.unmeasured
    fft = fft_backend(ny * nx)
    # maps on numpy's FFT (up to 4 Mpx, 32 MiB) are done in one band: one rfft2, no copies
    # of band spectra; larger maps band by band (the memory of issue 14)
    bands = [slice(0, ny)] if fft is _NumpyFFT else row_chunks(ny, nx, _FFT_BAND_BYTES)
    F = np.empty((ny, nx // 2 + 1), dtype=np.complex128) if len(bands) > 1 else None
    k = 0
    for sl in bands:
        rows_tapered = ry is None or rx is None or sl.start < ry[0] or sl.stop > ry[1]
        filled = fill_values is not None and bool(np.any(bad[sl]))
        # the band's copy, times its rows' weights in the same pass when it can be
        x = h[sl] * wy[sl, None] if rows_tapered and not filled else h[sl].copy()
        if filled:
            b = bad[sl]
            m = int(np.count_nonzero(b))
            x[b] = fill_values[k:k + m]
            k += m
            if rows_tapered:
                x *= wy[sl, None]
        if ry is None or rx is None:                   # e.g. the Hann window: every point
            x *= wx
        else:
            if rx[0] > 0:
                x[:, : rx[0]] *= wx[: rx[0]]
            if rx[1] < nx:
                x[:, rx[1]:] *= wx[rx[1]:]
        if F is None:                                  # one band: the map itself
            F = fft.rfft2(x)
        else:
            F[sl] = fft.rfft(x, axis=1)
    del x
    if len(bands) > 1:
        F = fft.fft(F, axis=0)
    P = np.empty(F.shape)
    for sl in row_chunks(*F.shape):
        f = F[sl]
        np.multiply(f.real, f.real, out=P[sl])
        P[sl] += f.imag * f.imag
    del F
    area = nx * hm.dx_m * ny * hm.dy_m
    scale = (hm.dx_m * hm.dy_m) ** 2 / ((2 * np.pi) ** 2 * area * w2)
    return P, scale, w2


def _meta_2d(hm, alpha, w2):
    return {"window": "tukey2d", "window_alpha": float(alpha), "window_mean_square": w2,
            "dx_m": hm.dx_m, "dy_m": hm.dy_m, "nx": hm.nx, "ny": hm.ny,
            "normalisation": NORMALISATION_2D, "name": hm.name}


def _spectrum2d(hm, P, scale, window_alpha, w2):
    qx = np.fft.fftshift(2 * np.pi * np.fft.fftfreq(hm.nx, hm.dx_m))
    qy = np.fft.fftshift(2 * np.pi * np.fft.fftfreq(hm.ny, hm.dy_m))
    return Spectrum2D(qx, qy, meta=_meta_2d(hm, window_alpha, w2),
                      half=HalfLattice(P, scale, hm.nx))


def psd_2d(hm, window_alpha=0.25):
    """Full 2D PSD map of a filled height map.

    C(q_m) = (dx dy)^2 |FFT2(w h)|^2 / ((2 pi)^2 A <w^2>) [m^4], w the 2D Tukey window
    (``window_alpha``), power loss corrected by <w^2>. The caller levels (and fills) first:
    the map must have no unmeasured points; no mean or tilt is removed here.

    Returns
    -------
    Spectrum2D
        fftshifted lattice wave vectors ``qx_per_m`` (nx,), ``qy_per_m`` (ny,) [1/m] and the
        map ``C_m4`` (ny, nx), built from the rfft2 half lattice when first read;
        ``meta`` holds the window, <w^2> and the normalisation.
    """
    _require_filled(hm)
    P, scale, w2 = _half_psd(hm, window_alpha)
    return _spectrum2d(hm, P, scale, window_alpha, w2)


def _default_range(Lx, Ly, dx, dy, q_min, q_max):
    q_min = 2 * np.pi / max(Lx, Ly) if q_min is None else float(q_min)
    q_max = np.pi / max(dx, dy) if q_max is None else float(q_max)
    return q_min, q_max


def _grid_of(spec2d):
    """(Lx, Ly, dx, dy) of a 2D map: from its meta when present (exact), else its lattice."""
    qx, qy = np.asarray(spec2d.qx_per_m), np.asarray(spec2d.qy_per_m)
    m = spec2d.meta
    if all(k in m for k in ("dx_m", "dy_m", "nx", "ny")) and (m["nx"], m["ny"]) == (qx.size, qy.size):
        dx, dy = float(m["dx_m"]), float(m["dy_m"])
        return qx.size * dx, qy.size * dy, dx, dy
    Lx, Ly = 2 * np.pi / abs(qx[1] - qx[0]), 2 * np.pi / abs(qy[1] - qy[0])
    return Lx, Ly, Lx / qx.size, Ly / qy.size


def _spectrum_from_rings(csum, count, qsum, edges, meta):
    keep = count > 0
    c = count[keep]
    return Spectrum(qsum[keep] / c, csum[keep] / c, count=np.rint(c).astype(np.int64),
                    kind="area", meta=meta)


def angular_average(spec2d, rings_per_decade=20, q_min=None, q_max=None):
    """Average a 2D PSD map over log-spaced rings of |q|.

    Rings: ``rings_per_decade`` per decade (rounded so that they tile [q_min, q_max]
    exactly) from q_min = 2 pi / L (longer side; default) to q_max = pi / max(dx, dy)
    (Nyquist; default). Each ring reports the mean |q| and the mean C of the lattice points
    with q_min <= |q| <= q_max inside it; ``count`` is the number of points; empty rings are
    dropped.

    Returns
    -------
    Spectrum
        kind ``"area"``; ``meta`` carries the ring edges and the 2D map's meta.
    """
    qx, qy = np.asarray(spec2d.qx_per_m), np.asarray(spec2d.qy_per_m)
    Lx, Ly, dx, dy = _grid_of(spec2d)
    q_min, q_max = _default_range(Lx, Ly, dx, dy, q_min, q_max)
    edges = _ring_edges(q_min, q_max, rings_per_decade)
    n = edges.size - 1
    q = np.hypot(qx[None, :], qy[:, None]).ravel()
    ring = _ring_index(q, q_min, q_max, n)
    sel = ring >= 0
    r = ring[sel]
    count = np.bincount(r, minlength=n).astype(np.float64)
    csum = np.bincount(r, weights=np.asarray(spec2d.C_m4).ravel()[sel], minlength=n)
    qsum = np.bincount(r, weights=q[sel], minlength=n)
    meta = dict(spec2d.meta)
    meta.update(rings_per_decade=rings_per_decade, ring_edges_per_m=edges.tolist(),
                q_range_per_m=(q_min, q_max))
    return _spectrum_from_rings(csum, count, qsum, edges, meta)


def psd_area(hm, window_alpha=0.25, rings_per_decade=20, q_min=None, q_max=None,
             fill_values=None):
    """The whole spectrum step of a levelled, filled height map: window, FFT, angular average.

    Same normalisation and rings as :func:`psd_2d` and :func:`angular_average` (the ring
    average is taken on the rfft half lattice, each point whose mirror image is not stored
    counted twice, which equals the average over the full lattice).

    ``fill_values``: values for the unmeasured points of ``hm`` in raster order (as
    :func:`roadscan.inpaint.unmeasured_fill` gives them); the map is then transformed as if
    filled, without a filled copy of it.

    Precision and memory: float64 throughout (heights, window, FFT, |F|^2, ring sums). The
    work memory is the complex half spectrum (the size of the heights) plus a band of rows,
    then |F|^2 on the half lattice (half the heights' size), which the returned Spectrum2D
    keeps; its fftshifted full map is only built when ``C_m4`` is read
    (:meth:`Spectrum2D.central` gives a part without it). The ring sums are one pass over
    |F|^2 along runs of equal ring (cached per grid).

    Returns
    -------
    (Spectrum, Spectrum2D)
    """
    _require_filled(hm, fill_values)
    ny, nx = hm.shape
    P, scale, w2 = _half_psd(hm, window_alpha, fill_values)
    q_min, q_max = _default_range(nx * hm.dx_m, ny * hm.dy_m, hm.dx_m, hm.dy_m, q_min, q_max)
    edges = _ring_edges(q_min, q_max, rings_per_decade)
    n = edges.size - 1
    runs = _ring_runs(ny, nx, hm.dx_m, hm.dy_m, q_min, q_max, n)
    csum = _ring_sums(P, runs, n) * scale
    spec2d = _spectrum2d(hm, P, scale, window_alpha, w2)
    meta = dict(spec2d.meta)
    meta.update(rings_per_decade=rings_per_decade, ring_edges_per_m=edges.tolist(),
                q_range_per_m=(q_min, q_max))
    return _spectrum_from_rings(csum, runs[3].copy(), runs[4].copy(), edges, meta), spec2d


# ----------------------------------------------------------------------------- profiles

_lgamma = np.vectorize(math.lgamma, otypes=[float])


def profile_to_area_factor(hurst):
    """Gamma(1 + H) / (sqrt(pi) Gamma(H + 1/2)): C(q) = C1(q) / q times this (power law)."""
    h = np.asarray(hurst, dtype=float)
    out = np.exp(_lgamma(1.0 + h) - _lgamma(h + 0.5)) / np.sqrt(np.pi)
    return float(out) if out.ndim == 0 else out


def _profiles_array(profiles):
    if isinstance(profiles, HeightMap):
        _require_filled(profiles)
        return profiles.heights_m, profiles.dx_m
    if isinstance(profiles, Profile):
        profiles = [profiles]
    profiles = list(profiles)
    if not profiles or not all(isinstance(p, Profile) for p in profiles):
        raise TypeError("expected a Profile, a list of Profiles or a HeightMap (rows along x)")
    n, dx = profiles[0].n, profiles[0].dx_m
    for p in profiles:
        _require_filled(p)
        if p.n != n or not np.isclose(p.dx_m, dx, rtol=1e-9):
            raise ValueError("profiles must share length and spacing")
    return np.stack([p.heights_m for p in profiles]), dx


def psd_profile(profiles, window_alpha=0.25, hurst=None, rings_per_decade=20, detrend="mean"):
    """1D PSD of line profiles and its isotropic 2D estimate.

    C1(q_k) = dx^2 |FFT(w h)_k|^2 / (2 pi L <w^2>) [m^3] at q_k = 2 pi k / L, k = 1 .. n/2,
    averaged over the profiles (1D Tukey window, power loss corrected). The 2D estimate uses
    the power-law Abel inversion C(q) = C1(q) / q * Gamma(1 + H) / (sqrt(pi) Gamma(H + 1/2))
    on C1 averaged in log-spaced bins (2 pi / L to pi / dx, ``rings_per_decade``).

    Parameters
    ----------
    profiles : Profile, sequence of Profile, or HeightMap
        Filled profiles of equal length and spacing; a HeightMap contributes its rows (x).
    window_alpha : float
        Tukey alpha (0.25 default).
    hurst : float, optional
        H for the conversion; by default fitted to C1 (slope -(1 + 2H)) over the band found
        by :func:`roadscan.fit.detect_band`.
    detrend : {"mean", "linear", None}
        Removed from each profile before windowing.

    Returns
    -------
    q_per_m : (n/2,) array
    C1_m3 : (n/2,) array
    Spectrum
        kind ``"profile"``; ``meta['conversion']`` names the conversion and the H used.
    """
    from .fit import detect_band, _loglog_fit  # fit does not import spectrum

    h, dx = _profiles_array(profiles)
    h = np.array(h, dtype=np.float64)
    n = h.shape[1]
    if detrend == "linear":
        x = np.linspace(-1, 1, n)
        h = h - h.mean(axis=1, keepdims=True)
        h = h - np.outer(h @ x / (x @ x), x)
    elif detrend == "mean":
        h = h - h.mean(axis=1, keepdims=True)
    elif detrend is not None:
        raise ValueError(f"detrend must be 'mean', 'linear' or None, got {detrend!r}")
    w = _tukey(n, float(window_alpha))
    w2 = float(np.mean(w**2))
    L = n * dx
    F = fft_backend(h.size).rfft(h * w[None, :], axis=1)[:, 1:]
    C1 = (np.abs(F) ** 2).mean(axis=0) * dx**2 / (2 * np.pi * L * w2)
    q = 2 * np.pi * np.arange(1, C1.size + 1) / L
    q_min, q_max = 2 * np.pi / L, np.pi / dx
    edges = _ring_edges(q_min, q_max, rings_per_decade)
    nb = edges.size - 1
    b = _ring_index(q, q_min, q_max, nb)
    s = b >= 0
    cnt = np.bincount(b[s], minlength=nb).astype(np.float64)
    keep = cnt > 0
    qb = np.bincount(b[s], weights=q[s], minlength=nb)[keep] / cnt[keep]
    c1b = np.bincount(b[s], weights=C1[s], minlength=nb)[keep] / cnt[keep]
    counts = np.rint(cnt[keep] * h.shape[0]).astype(np.int64)
    source = "given"
    if hurst is None:
        tmp = Spectrum(qb, c1b, count=counts, kind="profile")
        lo, hi = detect_band(tmp)
        slope, _, _, _ = _loglog_fit(qb, c1b, lo, hi)
        hurst = float(np.clip((-slope - 1.0) / 2.0, 0.01, 1.0))
        source = f"fitted to C1 on [{lo:.4g}, {hi:.4g}] 1/m"
    factor = profile_to_area_factor(hurst)
    meta = {"conversion": "power-law Abel inversion: C(q) = C1(q)/q * Gamma(1+H)/(sqrt(pi) Gamma(H+1/2))",
            "conversion_hurst": float(hurst), "conversion_hurst_source": source,
            "window": "tukey", "window_alpha": float(window_alpha), "window_mean_square": w2,
            "dx_m": dx, "n_profiles": int(h.shape[0]), "profile_length_m": L,
            "normalisation_1d": NORMALISATION_1D, "normalisation": NORMALISATION_2D,
            "rings_per_decade": rings_per_decade, "q_range_per_m": (q_min, q_max),
            "C1_binned_m3": c1b.tolist()}
    spec = Spectrum(qb, c1b / qb * factor, count=counts, kind="profile", meta=meta)
    return q, C1, spec


# ----------------------------------------------------------------------------- anisotropy

def anisotropy(spec2d, q_min=None, q_max=None, rings_per_decade=10, n_sectors=36):
    """Directional distribution of a 2D PSD map (for a figure and the summary).

    Each lattice point in [q_min, q_max] (defaults as :func:`angular_average`) is weighted by
    C / (mean C of its ring), so the steep fall of C with q does not let the few lowest rings
    dominate (every lattice point counts alike; weights normalised to sum 1). From these:
    the tensor M = sum w q^ q^T (q^ = q / |q|, trace 1).

    Returns
    -------
    dict
        ``power_ratio_x_to_y`` = M_xx / M_yy (> 1: heights vary more along x, i.e. texture
        ridges run along y); ``dominant_direction_deg``: direction of the principal axis of M
        (the wave-vector direction with most power, degrees from +x in [0, 180));
        ``anisotropy_index`` = (l1 - l2) / (l1 + l2) of M's eigenvalues (0 isotropic, 1 fully
        one-directional); ``sector_angle_deg`` and ``sector_power_fraction``: weights summed
        in ``n_sectors`` sectors of wave-vector direction over [0, 180) (centres, fractions).
    """
    qx, qy = np.asarray(spec2d.qx_per_m), np.asarray(spec2d.qy_per_m)
    Lx, Ly, dx, dy = _grid_of(spec2d)
    q_min, q_max = _default_range(Lx, Ly, dx, dy, q_min, q_max)
    half = getattr(spec2d, "half", None)
    if half is not None and getattr(spec2d, "_C", None) is None:
        return _anisotropy_half(half, qy.size, dx, dy, q_min, q_max, rings_per_decade, n_sectors)
    QX, QY = np.meshgrid(qx, qy)
    q = np.hypot(QX, QY).ravel()
    n = _ring_edges(q_min, q_max, rings_per_decade).size - 1
    ring = _ring_index(q, q_min, q_max, n)
    sel = ring >= 0
    r = ring[sel]
    C = np.asarray(spec2d.C_m4).ravel()[sel]
    cnt = np.bincount(r, minlength=n)
    csum = np.bincount(r, weights=C, minlength=n)
    ok = (cnt > 0) & (csum > 0)
    mean_c = np.where(ok, csum / np.maximum(cnt, 1), 1.0)
    w = np.where(ok[r], C / mean_c[r], 0.0)
    w /= w.sum()
    ux, uy = QX.ravel()[sel] / q[sel], QY.ravel()[sel] / q[sel]
    M = np.array([[np.sum(w * ux * ux), np.sum(w * ux * uy)],
                  [np.sum(w * ux * uy), np.sum(w * uy * uy)]])
    evals, evecs = np.linalg.eigh(M)
    v = evecs[:, 1]
    theta = np.degrees(np.arctan2(v[1], v[0])) % 180.0
    ang = np.degrees(np.arctan2(uy, ux)) % 180.0
    sec = np.minimum((ang / 180.0 * n_sectors).astype(int), n_sectors - 1)
    sp = np.bincount(sec, weights=w, minlength=n_sectors)
    return {"power_ratio_x_to_y": float(M[0, 0] / M[1, 1]),
            "dominant_direction_deg": float(theta),
            "anisotropy_index": float((evals[1] - evals[0]) / (evals[1] + evals[0])),
            "sector_angle_deg": ((np.arange(n_sectors) + 0.5) * 180.0 / n_sectors).tolist(),
            "sector_power_fraction": (sp / sp.sum()).tolist(),
            "q_range_per_m": (q_min, q_max)}


@lru_cache(maxsize=4)
def _sector_runs(ny, nx, dx, dy, q_min, q_max, n_rings, n_sectors):
    """Runs of equal (ring, sector) along the rows of the rfft half lattice, per band of rows
    (cached per grid): ring of 10-per-decade rings as in :func:`anisotropy`, sector of the
    wave-vector direction in [0, 180) degrees; key = ring * n_sectors + sector, -1 outside
    [q_min, q_max]. Also the number of full-lattice points per key."""
    qx, qy = _half_qx(nx, dx), 2 * np.pi * np.fft.fftfreq(ny, dy)
    nxr = qx.size
    wcol = np.full(nxr, 2.0)
    wcol[list(_mirror_columns(nx))] = 1.0
    bands, count = [], np.zeros(n_rings * n_sectors)
    for sl in row_chunks(ny, nxr):
        QX, QY = np.broadcast_arrays(qx[None, :], qy[sl, None])
        q = np.hypot(QX, QY)
        ring = _ring_index(q.ravel(), q_min, q_max, n_rings).reshape(q.shape)
        with np.errstate(invalid="ignore", divide="ignore"):
            ang = np.degrees(np.arctan2(QY / q, QX / q)) % 180.0
        sec = np.minimum(np.nan_to_num(ang / 180.0 * n_sectors).astype(np.int64), n_sectors - 1)
        key = np.where(ring >= 0, ring * n_sectors + sec, -1)
        flat = key.ravel()
        st = np.flatnonzero(np.concatenate([[True], flat[1:] != flat[:-1]]))
        ok = key >= 0
        count += np.bincount(key[ok], weights=np.broadcast_to(wcol, key.shape)[ok],
                             minlength=count.size)
        edges = tuple((c, key[:, c].copy()) for c in _mirror_columns(nx))
        bands.append((sl, st, flat[st], edges))
    return bands, count


def _anisotropy_half(half, ny, dx, dy, q_min, q_max, rings_per_decade, n_sectors):
    """:func:`anisotropy` on the rfft half lattice (each stored point and its mirror -q have
    the same |q|, ring, direction modulo 180 degrees and q^ q^T): sums of C, C qx^2/q^2,
    C qy^2/q^2 and C qx qy/q^2 per (ring, sector), read band by band; float64."""
    nx = half.nx
    n = _ring_edges(q_min, q_max, rings_per_decade).size - 1
    bands, cnt = _sector_runs(ny, nx, dx, dy, q_min, q_max, n, n_sectors)
    qx, qy = _half_qx(nx, dx), 2 * np.pi * np.fft.fftfreq(ny, dy)
    nk = n * n_sectors
    sums = np.zeros((4, nk))
    P = half.P
    for sl, st, key, edges in bands:
        p = P[sl]
        q = np.hypot(qx[None, :], qy[sl, None])
        q[q == 0] = np.inf
        ux, uy = qx[None, :] / q, qy[sl, None] / q
        ok = key >= 0
        for i, a in enumerate((p, p * ux * ux, p * uy * uy, p * ux * uy)):
            part = np.add.reduceat(a.ravel(), st)[ok]
            sums[i] += 2.0 * np.bincount(key[ok], weights=part, minlength=nk)
            for c, kc in edges:                       # columns stored once count once
                sel = kc >= 0
                sums[i] -= np.bincount(kc[sel], weights=a[:, c][sel], minlength=nk)
    cnt_r = cnt.reshape(n, n_sectors).sum(axis=1)
    csum_r = sums[0].reshape(n, n_sectors).sum(axis=1)
    ok = (cnt_r > 0) & (csum_r > 0)
    inv = np.where(ok, cnt_r / np.where(ok, csum_r, 1.0), 0.0)      # 1 / mean C of the ring
    wk = sums * np.repeat(inv, n_sectors)[None, :]                  # weights C / mean C
    total = wk[0].sum()
    Mxx, Myy, Mxy = wk[1].sum() / total, wk[2].sum() / total, wk[3].sum() / total
    M = np.array([[Mxx, Mxy], [Mxy, Myy]])
    evals, evecs = np.linalg.eigh(M)
    v = evecs[:, 1]
    theta = np.degrees(np.arctan2(v[1], v[0])) % 180.0
    sp = wk[0].reshape(n, n_sectors).sum(axis=0)
    return {"power_ratio_x_to_y": float(M[0, 0] / M[1, 1]),
            "dominant_direction_deg": float(theta),
            "anisotropy_index": float((evals[1] - evals[0]) / (evals[1] + evals[0])),
            "sector_angle_deg": ((np.arange(n_sectors) + 0.5) * 180.0 / n_sectors).tolist(),
            "sector_power_fraction": (sp / sp.sum()).tolist(),
            "q_range_per_m": (q_min, q_max)}
