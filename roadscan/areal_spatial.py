"""Spatial parameters of ISO 25178-2:2012 (section 4.2): Sal, Str and Std.

The autocorrelation function of the levelled heights z (mean zero) over the definition area A,

    f_ACF(tx, ty) = integral_A z(x, y) z(x - tx, y - ty) dx dy / integral_A z^2 dx dy,

is computed by FFT on a grid zero-padded to twice the field (a linear, not circular,
correlation; the integrals run over the overlap, each divided by the same full-field
integral), on lags |tx| <= Lx / 2, |ty| <= Ly / 2.

- Sal [m], autocorrelation length: the shortest lag distance at which f_ACF has decayed to
  s = 0.2 (ISO 25178-3 default);
- Str, texture aspect ratio: Sal divided by the longest lag distance at which f_ACF (its
  central region above s) has decayed to s; 1 for an isotropic surface, towards 0 for a
  strongly directional one;
- Std [deg], texture direction: the lay, i.e. the direction of the ridges, perpendicular to the
  absolute maximum of the angular power spectrum f_APS(theta) = integral |Z(r cos theta,
  r sin theta)|^2 r dr (rays every 0.25 degree, peak refined by a parabola); measured from the
  +x axis (columns) towards +y (rows), in [0, 180). On an isotropic surface (Str > 0.5) it is
  the direction of a random fluctuation, and the note says so.

Decay distances are refined to a fraction of a pixel by linear interpolation of f_ACF along
the ray through the boundary point. Unmeasured points are set to the mean (zero) and do not
count in the normalisation's area.

Large maps: the ACF of a map of more than :data:`MAX_POINTS` points is computed on every k-th
point along each axis (k the smallest integer bringing it under MAX_POINTS): the lags stay exact
multiples of k pixels, only the number of products averaged falls. When that leaves Sal
shorter than 10 k pixels, the ACF is recomputed at full resolution on the central
MAX_SIDE x MAX_SIDE window.
"""
from __future__ import annotations

import numpy as np

__all__ = ["spatial_parameters", "autocorrelation", "MAX_SIDE", "MAX_POINTS", "S_THRESHOLD"]

MAX_SIDE = 1024
#: largest map whose ACF is computed from every point
MAX_POINTS = 1 << 21
S_THRESHOLD = 0.2
#: Str below which a surface is called strongly anisotropic (ISO 25178-2 note: < 0.3)
STR_ANISOTROPIC = 0.3


def autocorrelation(z):
    """(f_ACF on lags |t| <= L/2, centred; |Z(q)|^2 of the padded field) of a 2D field with
    NaN where unmeasured. f_ACF[cy, cx] = 1 at the centre (cy, cx) = (ny // 2, nx // 2).

    Parameters
    ----------
    z : ndarray, shape (ny, nx)
        Levelled heights [m], NaN where unmeasured.

    Returns
    -------
    acf : ndarray
        Normalised autocorrelation on lags up to half the size, centred.
    P : ndarray
        |Z(q)|^2 of the zero-padded field.
    shape : tuple of int
        Shape of the padded field.
    """
    from scipy import fft

    z = np.asarray(z, dtype=np.float64)
    bad = ~np.isfinite(z)
    zz = np.where(bad, 0.0, z - np.nanmean(z) if bad.any() else z - z.mean())
    ny, nx = zz.shape
    shape = (fft.next_fast_len(2 * ny, real=True), fft.next_fast_len(2 * nx, real=True))
    F = fft.rfft2(zz, shape, workers=-1)
    P = F.real ** 2 + F.imag ** 2
    R = fft.irfft2(P, shape, workers=-1)
    R /= R[0, 0]
    hy, hx = ny // 2, nx // 2
    acf = np.concatenate([R[-hy:], R[: hy + 1]], axis=0)
    acf = np.concatenate([acf[:, -hx:], acf[:, : hx + 1]], axis=1)
    return acf, P, shape


def _crossing(acf, iy, ix, s, step=0.05):
    """Distance [pixels] from the centre along the ray through pixel (iy, ix) at which the
    bilinear f_ACF first falls below s (outward from the centre)."""
    from scipy.ndimage import map_coordinates

    cy, cx = (acf.shape[0] - 1) // 2, (acf.shape[1] - 1) // 2
    r_end = np.hypot(iy - cy, ix - cx)
    if r_end == 0:
        return 0.0
    t = np.arange(0.0, r_end + step / 2, step) / r_end
    vals = map_coordinates(acf, [cy + t * (iy - cy), cx + t * (ix - cx)], order=1)
    below = np.flatnonzero(vals < s)
    if below.size == 0:
        return float(r_end)
    k = below[0]
    if k == 0:
        return 0.0
    f = (vals[k - 1] - s) / (vals[k - 1] - vals[k])
    return float((t[k - 1] + f * (t[k] - t[k - 1])) * r_end)


def _decay_lengths(acf, dy, dx, s):
    """(Sal, longest decay, touches_edge) [m] of a centred f_ACF with pixel spacings dy, dx."""
    from scipy import ndimage as ndi

    ny, nx = acf.shape
    cy, cx = (ny - 1) // 2, (nx - 1) // 2
    lab, _ = ndi.label(acf >= s)
    centre = lab == lab[cy, cx]
    yy, xx = np.mgrid[0:ny, 0:nx]
    dist = np.hypot((yy - cy) * dy, (xx - cx) * dx)
    out = ~centre
    if not out.any():
        return None, None, True
    # nearest points outside the central region: refine along a few rays
    d_out = np.where(out, dist, np.inf).ravel()
    near = np.argsort(d_out)[:16]
    sal = min(_ray(acf, i // nx, i % nx, dy, dx, s) for i in near)
    edge = centre[0].any() or centre[-1].any() or centre[:, 0].any() or centre[:, -1].any()
    d_in = np.where(centre, dist, -np.inf).ravel()
    far = np.argsort(d_in)[::-1][:16]
    longest = max(_ray(acf, i // nx, i % nx, dy, dx, s) for i in far)
    return sal, longest, bool(edge)


def _ray(acf, iy, ix, dy, dx, s):
    """:func:`_crossing` in metres (the ray's pixel length converted with its direction)."""
    cy, cx = (acf.shape[0] - 1) // 2, (acf.shape[1] - 1) // 2
    r_px = np.hypot(iy - cy, ix - cx)
    if r_px == 0:
        return 0.0
    r_m = np.hypot((iy - cy) * dy, (ix - cx) * dx)
    return _crossing(acf, iy, ix, s) * r_m / r_px


def _texture_direction(P, shape, dy, dx, step_deg=0.25):
    """Std [deg] from |Z(q)|^2 on the rfft2 grid of ``shape``: the lay is perpendicular to the
    maximum of the angular power spectrum f_APS(theta) = integral P(r cos theta, r sin theta)
    r dr, sampled along each ray by bilinear interpolation (rays, not lattice sectors: a
    sector of 1 degree holds lattice points unevenly at small |q|, which would favour the
    axes and diagonals)."""
    from scipy.ndimage import map_coordinates

    ny = shape[0]
    Ps = np.fft.fftshift(P, axes=0)                       # rows: ky from -ny/2
    dqy, dqx = 1.0 / (shape[0] * dy), 1.0 / (shape[1] * dx)
    q_top = min(0.5 / dx, 0.5 / dy)
    dq = min(dqx, dqy)
    r = np.arange(1.0, q_top / dq) * dq                   # [1/m], from the first ring outwards
    theta = np.radians(np.arange(0.0, 180.0, step_deg))
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    sign = np.where(c < 0, -1.0, 1.0)                     # P(q) = P(-q): keep qx >= 0
    kx = sign * c * r[None, :] / dqx
    ky = sign * s * r[None, :] / dqy + ny // 2
    vals = map_coordinates(Ps, [ky.ravel(), kx.ravel()], order=1, mode="nearest").reshape(kx.shape)
    aps = (vals * r[None, :]).sum(axis=1)
    k = int(np.argmax(aps))
    n = aps.size
    a, b, cc = aps[(k - 1) % n], aps[k], aps[(k + 1) % n]
    den = a - 2 * b + cc
    off = 0.5 * (a - cc) / den if den != 0 else 0.0
    theta_q = (k + off) * step_deg
    return float((theta_q + 90.0) % 180.0)


def spatial_parameters(heights_m, dx_m, dy_m, s=S_THRESHOLD):
    """Sal, Str and Std of a levelled height map (module docstring for the definitions).

    Parameters
    ----------
    heights_m : (ny, nx) array [m], NaN where unmeasured
    dx_m, dy_m : float
        Spacings along x (columns) and y (rows) [m].
    s : float
        Decay threshold of the autocorrelation (0.2, ISO 25178-3).

    Returns
    -------
    dict with keys ``Sal_m``, ``Str``, ``Std_deg`` and ``spatial_note`` (what was decided
    and why a figure is null): ``Sal_m`` and ``Str`` are None when f_ACF does not decay to s
    within half the field; ``Str`` is None when its central region reaches the edge of the lag
    window and the ratio it allows is not below 0.3 (the field is too small to decide whether
    the surface is isotropic), and is an upper bound, said in the note, when it is below 0.3.
    """
    z = np.asarray(heights_m, dtype=np.float64)
    ny, nx = z.shape
    k = 1
    while -(-ny // k) * -(-nx // k) > MAX_POINTS:
        k += 1
    how = "whole field"
    acf, P, shape = autocorrelation(z[::k, ::k])
    sal, longest, edge = _decay_lengths(acf, dy_m * k, dx_m * k, s)
    std = _texture_direction(P, shape, dy_m * k, dx_m * k)
    if k > 1:
        how = f"points of one row and column in {k}"
        if sal is not None and sal < 10 * k * min(dx_m, dy_m):
            y0, x0 = max(0, (ny - MAX_SIDE) // 2), max(0, (nx - MAX_SIDE) // 2)
            acf, _, _ = autocorrelation(z[y0:y0 + MAX_SIDE, x0:x0 + MAX_SIDE])
            sal, longest, edge = _decay_lengths(acf, dy_m, dx_m, s)
            how = f"central {min(ny, MAX_SIDE)} x {min(nx, MAX_SIDE)} points at full resolution"
    note = f"autocorrelation (s = {s:g}) over the {how}"
    if sal is None:
        return {"Sal_m": None, "Str": None, "Std_deg": std,
                "spatial_note": note + "; it does not decay to s within half the field: "
                                       "Sal and Str undefined (field too small)"}
    ratio = sal / longest if longest > 0 else None
    if edge:
        if ratio is not None and ratio < STR_ANISOTROPIC:
            note += (f"; along the lay it has not decayed to s within half the field: Str is an "
                     f"upper bound (strongly anisotropic)")
        else:
            note += ("; along its slowest direction it has not decayed to s within half the "
                     "field: too small to decide the texture aspect ratio, Str null")
            ratio = None
    if ratio is not None and ratio > 0.5:
        note += "; isotropic (Str > 0.5): Std is the direction of a random fluctuation"
    return {"Sal_m": float(sal), "Str": None if ratio is None else float(min(ratio, 1.0)),
            "Std_deg": std, "spatial_note": note}
