"""Power spectral densities of height maps (Persson's normalisation): the public entry.

2D (docs: Theory). With the window w, H_m = FFT2(w h) and A = L_x L_y = n_x dx n_y dy,

    C(q_m) = (dx dy)^2 |H_m|^2 / ((2 pi)^2 A <w^2>)          [m^4]

on the FFT lattice q = 2 pi (k_x / L_x, k_y / L_y); <h^2> = sum_m C(q_m) (2 pi)^2 / A
(Parseval, for the windowed heights divided by <w^2>), and for an isotropic surface
<h^2> = 2 pi int q C(q) dq. Dividing by <w^2> (the mean of w^2 over the grid, 0.7105 for the
2D Tukey window with alpha = 0.25) restores the power the window removes. The window is the
outer product of two 1D Tukey windows (``roadscan.windows.tukey``, equal to
``scipy.signal.windows.tukey``) (alpha = 0: rectangular,
alpha = 1: Hann). SurfaceTopography's C is (2 pi)^2 times this one.

Angular averages use the log-spaced rings of :mod:`roadscan.rings`; each ring reports the
mean |q| and the mean C of the lattice points inside it, and the number of points; empty
rings are dropped.

The rest of the spectrum step lives beside it and is re-exported here: the FFT backend
(:mod:`roadscan.fft_backends`), the 1D profile spectrum (:mod:`roadscan.profile_spectrum`) and
the anisotropy (:mod:`roadscan.anisotropy`).

Reference: Persson et al., J. Phys.: Condens. Matter 17, R1 (2005); Jacobs, Junge, Pastewka,
Surf. Topogr.: Metrol. Prop. 5, 013001 (2017).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .anisotropy import anisotropy
from .bands import row_chunks
from .fft_backends import _WORKERS, NUMPY_FFT_MAX_POINTS, _NumpyFFT, fft_backend  # noqa: F401
from .heightmap import HeightMap
from .heightmap import require_filled as _require_filled
from .profile_spectrum import profile_to_area_factor, psd_profile
from .rings import _default_range, _grid_of, _ring_edges, _ring_index, _ring_runs, _ring_sums
from .spectrum_types import (
    NORMALISATION_1D,
    NORMALISATION_2D,
    HalfLattice,
    Spectrum,
    Spectrum2D,
)
from .windows import tukey_cached as _tukey

__all__ = [
    "psd_2d",
    "angular_average",
    "psd_area",
    "psd_profile",
    "anisotropy",
    "window_2d",
    "profile_to_area_factor",
    "NORMALISATION_2D",
    "NORMALISATION_1D",
    "fft_backend",
    "prepare_lattice",
]


def prepare_lattice(
    ny: int,
    nx: int,
    dx_m: float,
    dy_m: float,
    rings_per_decade: int = 20,
    anisotropy_rings: int = 10,
    n_sectors: int = 36,
) -> None:
    """Compute (and cache) the lattice bookkeeping that :func:`psd_area` and :func:`anisotropy`
    use on an (ny, nx) grid with their default |q| range: the runs of equal ring of the rfft2
    half lattice and its (ring, direction sector) runs. They depend on the grid alone, so a
    caller may compute them ahead, e.g. on an idle core while the scan is still being checked;
    the spectrum then finds them cached (the same arrays it would compute).

    Parameters
    ----------
    ny, nx : int
        Rows and columns of the map.
    dx_m, dy_m : float
        Spacings [m].
    rings_per_decade : int, optional
        Rings of :func:`psd_area`.
    anisotropy_rings, n_sectors : int, optional
        Rings and direction sectors of :func:`anisotropy`.

    Returns
    -------
    None
    """
    from .anisotropy import _sector_runs

    q_min, q_max = _default_range(nx * dx_m, ny * dy_m, dx_m, dy_m, None, None)
    n = _ring_edges(q_min, q_max, rings_per_decade).size - 1
    _ring_runs(ny, nx, dx_m, dy_m, q_min, q_max, n)
    n = _ring_edges(q_min, q_max, anisotropy_rings).size - 1
    _sector_runs(ny, nx, dx_m, dy_m, q_min, q_max, n, n_sectors)


def window_2d(ny: int, nx: int, alpha: float = 0.25) -> tuple[NDArray[np.float64], float]:
    """The 2D Tukey window (outer product of two 1D Tukey windows) and its mean square <w^2>.

    Parameters
    ----------
    ny, nx : int
        Rows and columns of the map.
    alpha : float, optional
        Tukey taper fraction (0 rectangular, 1 Hann).

    Returns
    -------
    w : ndarray, shape (ny, nx)
        The window.
    w2 : float
        Its mean square <w^2>.
    """
    wy, wx = _tukey(ny, float(alpha)), _tukey(nx, float(alpha))
    return np.outer(wy, wx), _window_mean_square(ny, nx, alpha)


def _window_mean_square(ny, nx, alpha):
    """<w^2> of :func:`window_2d` without building the window."""
    wy, wx = _tukey(ny, float(alpha)), _tukey(nx, float(alpha))
    return float(np.mean(wy**2) * np.mean(wx**2))


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
    # of band spectra; larger maps band by band (bounded memory)
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
            x[b] = fill_values[k : k + m]
            k += m
            if rows_tapered:
                x *= wy[sl, None]
        if ry is None or rx is None:  # e.g. the Hann window: every point
            x *= wx
        else:
            if rx[0] > 0:
                x[:, : rx[0]] *= wx[: rx[0]]
            if rx[1] < nx:
                x[:, rx[1] :] *= wx[rx[1] :]
        if F is None:  # one band: the map itself
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
    return {
        "window": "tukey2d",
        "window_alpha": float(alpha),
        "window_mean_square": w2,
        "dx_m": hm.dx_m,
        "dy_m": hm.dy_m,
        "nx": hm.nx,
        "ny": hm.ny,
        "normalisation": NORMALISATION_2D,
        "name": hm.name,
    }


def _spectrum2d(hm, P, scale, window_alpha, w2):
    qx = np.fft.fftshift(2 * np.pi * np.fft.fftfreq(hm.nx, hm.dx_m))
    qy = np.fft.fftshift(2 * np.pi * np.fft.fftfreq(hm.ny, hm.dy_m))
    return Spectrum2D(qx, qy, meta=_meta_2d(hm, window_alpha, w2), half=HalfLattice(P, scale, hm.nx))


def psd_2d(hm: HeightMap, window_alpha: float = 0.25) -> Spectrum2D:
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

    Parameters
    ----------
    hm : HeightMap
        Levelled height map without unmeasured points [m].
    window_alpha : float, optional
        Tukey taper fraction.

    References
    ----------
    B.N.J. Persson et al., J. Phys.: Condens. Matter 17, R1 (2005), doi:10.1088/0953-8984/17/1/R01.
    """
    _require_filled(hm)
    P, scale, w2 = _half_psd(hm, window_alpha)
    return _spectrum2d(hm, P, scale, window_alpha, w2)


def _spectrum_from_rings(csum, count, qsum, edges, meta):
    keep = count > 0
    c = count[keep]
    return Spectrum(qsum[keep] / c, csum[keep] / c, count=np.rint(c).astype(np.int64), kind="area", meta=meta)


def angular_average(
    spec2d: Spectrum2D, rings_per_decade: int = 20, q_min: float | None = None, q_max: float | None = None
) -> Spectrum:
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

    Parameters
    ----------
    spec2d : Spectrum2D
        The 2D spectrum map.
    rings_per_decade : int, optional
        Log-spaced rings per decade of |q|.
    q_min, q_max : float, optional
        Range of |q| [1/m] (defaults 2 pi / L and pi / a).
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
    meta.update(
        rings_per_decade=rings_per_decade, ring_edges_per_m=edges.tolist(), q_range_per_m=(q_min, q_max)
    )
    return _spectrum_from_rings(csum, count, qsum, edges, meta)


def psd_area(
    hm: HeightMap,
    window_alpha: float = 0.25,
    rings_per_decade: int = 20,
    q_min: float | None = None,
    q_max: float | None = None,
    fill_values: ArrayLike | None = None,
) -> tuple[Spectrum, Spectrum2D]:
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

    Parameters
    ----------
    hm : HeightMap
        Levelled height map [m], filled or with ``fill_values`` for its unmeasured points.
    window_alpha : float, optional
        Tukey taper fraction of the 2D window (0.25).
    rings_per_decade : int, optional
        Log-spaced rings per decade of |q|.
    q_min, q_max : float, optional
        Range of |q| [1/m] (defaults 2 pi / L and pi / a).
    fill_values : ndarray, optional
        Heights for the unmeasured points in raster order.

    References
    ----------
    B.N.J. Persson et al., "On the nature of surface roughness with application to contact
    mechanics, sealing, rubber friction and adhesion", J. Phys.: Condens. Matter 17, R1 (2005),
    doi:10.1088/0953-8984/17/1/R01 (the normalisation <h^2> = 2 pi int q C dq).

    Examples
    --------
    >>> from roadscan.io import read
    >>> from roadscan.level import level
    >>> from roadscan.inpaint import fill_unmeasured
    >>> from roadscan import psd_area
    >>> flat, _ = fill_unmeasured(level(read("sample_scans/asphalt.x3p")))  # doctest: +SKIP
    >>> spectrum, spectrum_2d = psd_area(flat)                              # doctest: +SKIP
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
    meta.update(
        rings_per_decade=rings_per_decade, ring_edges_per_m=edges.tolist(), q_range_per_m=(q_min, q_max)
    )
    return _spectrum_from_rings(csum, runs[3].copy(), runs[4].copy(), edges, meta), spec2d
