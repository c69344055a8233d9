"""Spatial parameters of ISO 25178-2:2012 (section 4.2): Sal, Str and Std.

The autocorrelation function of the levelled heights z (mean zero) over the definition area A,

    f_ACF(tx, ty) = integral_A z(x, y) z(x - tx, y - ty) dx dy / integral_A z^2 dx dy,

is computed by FFT on a grid zero-padded to at least 1.5 times the field (a linear, not
circular, correlation on the lags used: the wrapped-around products start beyond half the
field; the integrals run over the overlap, each divided by the same full-field
integral), on lags |tx| <= Lx / 2, |ty| <= Ly / 2.

- Sal [m], autocorrelation length: the shortest lag distance at which f_ACF has decayed to
  s = 0.2 (ISO 25178-3 default);
- Str, texture aspect ratio: Sal divided by the longest lag distance at which f_ACF has
  decayed to s (over all directions); 1 for an isotropic surface, towards 0 for a
  strongly directional one;
- Std [deg], texture direction: the lay, i.e. the direction of the ridges, perpendicular to the
  absolute maximum of the angular power spectrum f_APS(theta) = integral |Z(r cos theta,
  r sin theta)|^2 r dr (rays every 0.25 degree, peak refined by a parabola); measured from the
  +x axis (columns) towards +y (rows), in [0, 180). On an isotropic surface (Str > 0.5) it is
  the direction of a random fluctuation, and the note says so.

Decay distances are taken along rays from the origin every 0.5 degree (the first lag at which
the bilinearly interpolated f_ACF falls below s, refined linearly between samples a quarter
pixel apart). Numpy only (its FFT). Unmeasured points are set to the mean (zero) and do not
count in the normalisation's area.

Large maps (more than :data:`MAX_POINTS` points): the ACF is first computed at full
resolution on the central MAX_SIDE x MAX_SIDE window; when Sal there is shorter than 10 k
pixels (k the smallest integer bringing the map under MAX_POINTS when taking every k-th point
along each axis), the window gives Sal, Str and Std; otherwise they are computed on every k-th
point of the whole field (the lags stay exact multiples of k pixels, only the number of
products averaged falls). The FFTs run in double precision (numpy's pocketfft is faster there
than in single), but the last one, back along x, in single (relative error near 1e-7 of the
zero lag, far below s).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["spatial_parameters", "autocorrelation", "MAX_SIDE", "MAX_POINTS", "S_THRESHOLD"]

MAX_SIDE = 1024
#: largest map whose ACF is computed from every point
MAX_POINTS = 1 << 21
S_THRESHOLD = 0.2
#: Str below which a surface is called strongly anisotropic (ISO 25178-2 note: < 0.3)
STR_ANISOTROPIC = 0.3


def autocorrelation(
    z: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], tuple[int, int]]:
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
    P : ndarray, shape (shape[0], shape[1] // 2 + 1)
        |Z(q)|^2 of the zero-padded field on the rfft2 grid (rows qy, columns qx >= 0; the
        transposed view of a contiguous array).
    shape : tuple of int
        Shape of the padded field.
    """
    z = np.asarray(z, dtype=np.float64)
    good = np.isfinite(z)
    n = int(np.count_nonzero(good))
    ny, nx = z.shape
    hy, hx = ny // 2, nx // 2
    shape = (_fast_len(ny + hy + 1), _fast_len(nx + hx + 1))  # no wrap-around up to L/2
    zz = z - (z.mean() if n == z.size else np.add.reduce(z, axis=None, where=good) / n)
    if n < z.size:
        np.copyto(zz, 0.0, where=~good)
    # the padding rows are zero, so the row transforms run over the field's rows only; their
    # half spectrum is written transposed, so that every later transform runs along
    # contiguous memory (pocketfft runs about half as fast along a strided axis)
    F = np.fft.fft(_rfft_transposed(zz, shape[1]), shape[0], axis=1)
    Fv = F.view(F.real.dtype)  # (re, im) pairs
    np.square(Fv, out=Fv)
    PT = np.add(Fv[:, 0::2], Fv[:, 1::2])  # |Z|^2, rows kx, columns ky
    del F, Fv
    # P is real: its inverse transform along ky is G[-k] = H[k] / n (and G[k] = conj(H[k]) / n)
    # with H = rfft(P) (half the work of a complex transform; the 1/n goes with the
    # normalisation). Row k >= 0 of H, transformed back along x, is the ACF at the lags
    # (-k, tx); the lags (k, tx) are those of (-k, -tx) (the ACF of a real field is even).
    H = _rfft_transposed(PT)
    R = np.fft.irfft(H[: hy + 1].astype(np.complex64), shape[1], axis=1)  # row k: ty = -k
    del H
    acf = np.empty((2 * hy + 1, 2 * hx + 1))
    neg = acf[hy::-1]  # ty = 0, -1, ..., -hy
    np.divide(R[:, -hx:], R[0, 0], out=neg[:, :hx])
    np.divide(R[:, : hx + 1], R[0, 0], out=neg[:, hx:])
    acf[hy + 1 :] = acf[hy - 1 :: -1, ::-1]  # f(ty, tx) = f(-ty, -tx)
    return acf, PT.T, shape


def _rfft_transposed(x, n=None):
    """rfft of the rows of the 2D float array ``x`` (zero-padded to ``n``), returned
    transposed: shape (n // 2 + 1, rows), complex128, each row contiguous. Written in place by
    pocketfft (numpy >= 2; numpy 1, without ``out``, transposes a copy) into rows 8 elements
    longer than needed: a power-of-two row length would send the transposed writes to a few
    cache sets (twice slower on 1024 rows)."""
    m = (x.shape[1] if n is None else n) // 2 + 1
    out = np.empty((m, x.shape[0] + 8), np.complex128)[:, : x.shape[0]]
    try:
        np.fft.rfft(x, n, axis=1, out=out.T)
    except TypeError:  # numpy < 2
        out.T[...] = np.fft.rfft(x, n, axis=1)
    return out


def _fast_len(n):
    """Smallest 2^a 3^b 5^c >= n (a fast FFT length)."""
    best = 1 << int(np.ceil(np.log2(n)))
    p5 = 1
    while p5 < best:
        p35 = p5
        while p35 < best:
            p = p35
            while p < n:
                p *= 2
            best = min(best, p)
            p35 *= 3
        p5 *= 5
    return best


def _bilinear(img, y, x):
    """Bilinear interpolation of ``img`` at fractional (row, column) positions inside it."""
    ny, nx = img.shape
    y0 = np.clip(np.floor(y), 0, ny - 2)
    x0 = np.clip(np.floor(x), 0, nx - 2)
    fy, fx = y - y0, x - x0
    i = y0.astype(np.intp) * nx + x0.astype(np.intp)  # flattened upper-left corner
    f = img.ravel()
    a, b = f[i], f[i + 1]
    top = a + fx * (b - a)
    a, b = f[i + nx], f[i + nx + 1]
    top += fy * (a + fx * (b - a) - top)
    return top


def _decay_lengths(acf, dy, dx, s, step_deg=0.5):
    """Along rays from the origin every ``step_deg`` (the ACF is even: 0 to 180 degrees), the
    first lag distance [m] at which the bilinear f_ACF falls below s.

    Returns
    -------
    (Sal or None, longest decay among the rays that decay, longest lag reached by a ray that
    does not decay or None)
    """
    hy, hx = (acf.shape[0] - 1) // 2, (acf.shape[1] - 1) // 2
    theta = np.radians(np.arange(0.0, 180.0, step_deg))
    c, sn = np.cos(theta), np.sin(theta)
    with np.errstate(divide="ignore"):
        r_max = np.minimum(
            np.where(c != 0, hx * dx / np.abs(c), np.inf), np.where(sn != 0, hy * dy / np.abs(sn), np.inf)
        )  # [m]
    dr = 0.25 * min(dx, dy)
    r_all = np.arange(0.0, r_max.max() + dr, dr)
    hit = np.zeros(theta.size, bool)
    k = np.ones(theta.size, np.int64)
    v0, v1 = np.ones(theta.size), np.ones(theta.size)
    todo = np.arange(theta.size)
    for n in (min(256, r_all.size), r_all.size):  # most rays decay within the first 64 pixels
        r = r_all[:n]
        rm = r_max[todo, None]
        inside = r[None, :] <= rm * (1 + 1e-12)
        rr = np.minimum(r[None, :], rm)
        vals = _bilinear(acf, hy + rr * sn[todo, None] / dy, hx + rr * c[todo, None] / dx)
        below = (vals < s) & inside
        got = below.any(axis=1)
        kk = np.maximum(np.argmax(below, axis=1), 1)
        rows = np.arange(todo.size)
        done = got | (n == r_all.size)
        hit[todo[done]] = got[done]
        k[todo[done]] = kk[done]
        v0[todo[done]], v1[todo[done]] = vals[rows, kk - 1][done], vals[rows, kk][done]
        todo = todo[~done]
        if not todo.size:
            break
    r = r_all
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.clip((v0 - s) / (v0 - v1), 0.0, 1.0)
    d = r[k - 1] + f * dr
    if not hit.any():
        return None, None, float(r_max.max())
    open_ = float(r_max[~hit].max()) if (~hit).any() else None
    return float(d[hit].min()), float(d[hit].max()), open_


def _texture_direction(P, shape, dy, dx, step_deg=0.25):
    """Std [deg] from |Z(q)|^2 on the rfft2 grid of ``shape``: the lay is perpendicular to the
    maximum of the angular power spectrum f_APS(theta) = integral P(r cos theta, r sin theta)
    r dr, sampled along each ray by bilinear interpolation (rays, not lattice sectors: a
    sector of 1 degree holds lattice points unevenly at small |q|, which would favour the
    axes and diagonals). The rays are sampled 32 at a time, so that the sample positions,
    their integer and fractional parts and the gathered corners stay in cache."""
    ny = shape[0]
    # rows kx, columns ky from -ny/2 (fftshift), in single precision (half the memory traffic
    # of the gathers below; a relative error near 1e-8 of P)
    PT = np.asarray(P).T
    nk, nc = PT.shape
    Pt = np.empty((nk, nc), np.float32)
    h = nc // 2
    Pt[:, h:] = PT[:, : nc - h]
    Pt[:, :h] = PT[:, nc - h :]
    dqy, dqx = 1.0 / (shape[0] * dy), 1.0 / (shape[1] * dx)
    q_top = min(0.5 / dx, 0.5 / dy)
    dq = min(dqx, dqy)
    r = np.arange(1.0, q_top / dq) * dq  # [1/m], from the first ring outwards
    theta = np.radians(np.arange(0.0, 180.0, step_deg))
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    sign = np.where(c < 0, -1.0, 1.0)  # P(q) = P(-q): keep qx >= 0
    sc, ss = sign * c, sign * s
    f = Pt.ravel()
    f1, fn, fn1 = f[1:], f[nc:], f[nc + 1 :]  # the corners right, below, diagonal
    aps = np.empty(theta.size)
    for t0 in range(0, theta.size, 32):  # 32 rays at a time: cache-sized
        rows = slice(t0, t0 + 32)
        kx = sc[rows] * r
        kx /= dqx
        ky = ss[rows] * r
        ky /= dqy
        ky += ny // 2
        i = kx.astype(np.intp)  # floor: kx, ky >= 0
        np.minimum(i, nk - 2, out=i)
        kx -= i  # fraction along kx
        i *= nc
        j = ky.astype(np.intp)
        np.minimum(j, nc - 2, out=j)
        ky -= j  # fraction along ky
        i += j  # flattened corner (kx0, ky0)
        a = f[i]
        lo = f1[i] - a
        lo = lo * ky
        lo += a  # at kx0
        a = fn[i]
        hi = fn1[i] - a
        hi = hi * ky
        hi += a  # at kx0 + 1
        hi -= lo
        hi *= kx
        hi += lo
        aps[rows] = hi @ r
    k = int(np.argmax(aps))
    n = aps.size
    a, b, cc = aps[(k - 1) % n], aps[k], aps[(k + 1) % n]
    den = a - 2 * b + cc
    off = 0.5 * (a - cc) / den if den != 0 else 0.0
    theta_q = (k + off) * step_deg
    return float((theta_q + 90.0) % 180.0)


def _varies(z):
    """True when the 2D array ``z`` holds at least 4 finite values, not all equal (decided on
    its first row when it can be, as on a measured surface)."""
    row = z[0][np.isfinite(z[0])]
    if row.size >= 4 and row.max() > row.min():
        return True
    good = z[np.isfinite(z)]
    return good.size >= 4 and bool(good.max() > good.min())


def spatial_parameters(
    heights_m: NDArray[np.float64], dx_m: float, dy_m: float, s: float = S_THRESHOLD
) -> dict[str, Any]:
    """Sal, Str and Std of a levelled height map (module docstring for the definitions).

    Parameters
    ----------
    heights_m : ndarray, shape (ny, nx)
        Heights [m], NaN where unmeasured.
    dx_m, dy_m : float
        Spacings along x (columns) and y (rows) [m].
    s : float
        Decay threshold of the autocorrelation (0.2, ISO 25178-3).

    Returns
    -------
    dict
        Keys ``Sal_m``, ``Str``, ``Std_deg`` and ``spatial_note`` (what was decided and why a
        figure is null): ``Sal_m`` and ``Str`` are None when f_ACF does not decay to s within half
        the field; ``Str`` is None when its central region reaches the edge of the lag window and
        the ratio it allows is not below 0.3 (the field is too small to decide whether the surface
        is isotropic), and is an upper bound, said in the note, when it is below 0.3.
    """
    z = np.asarray(heights_m, dtype=np.float64)
    ny, nx = z.shape
    if min(ny, nx) < 4 or not _varies(z):
        return {
            "Sal_m": None,
            "Str": None,
            "Std_deg": None,
            "spatial_note": "no autocorrelation: the field is flat or smaller than 4 x 4 measured points",
        }
    k = 1
    while -(-ny // k) * -(-nx // k) > MAX_POINTS:
        k += 1
    how, sal = "whole field", None
    if k > 1:  # the central window first: enough when
        y0, x0 = max(0, (ny - MAX_SIDE) // 2), max(0, (nx - MAX_SIDE) // 2)  # Sal is short
        acf, P, shape = autocorrelation(z[y0 : y0 + MAX_SIDE, x0 : x0 + MAX_SIDE])
        sal, longest, open_ = _decay_lengths(acf, dy_m, dx_m, s)
        if sal is not None and sal < 10 * k * min(dx_m, dy_m):
            std = _texture_direction(P, shape, dy_m, dx_m)
            how = f"central {min(ny, MAX_SIDE)} x {min(nx, MAX_SIDE)} points at full resolution"
        else:
            sal = None
            how = f"points of one row and column in {k}"
    if sal is None:
        acf, P, shape = autocorrelation(z[::k, ::k])
        sal, longest, open_ = _decay_lengths(acf, dy_m * k, dx_m * k, s)
        std = _texture_direction(P, shape, dy_m * k, dx_m * k)
    note = f"autocorrelation (s = {s:g}) over the {how}"
    if sal is None:
        return {
            "Sal_m": None,
            "Str": None,
            "Std_deg": std,
            "spatial_note": note + "; it does not decay to s within half the field: "
            "Sal and Str undefined (field too small)",
        }
    ratio = sal / longest if longest > 0 else None
    if open_ is not None:
        bound = sal / open_
        if bound < STR_ANISOTROPIC:
            ratio = bound
            note += (
                "; along the lay it has not decayed to s within half the field: Str is an "
                "upper bound (strongly anisotropic)"
            )
        else:
            note += (
                "; along its slowest direction it has not decayed to s within half the "
                "field: too small to decide the texture aspect ratio, Str null"
            )
            ratio = None
    if ratio is not None and ratio > 0.5:
        note += "; isotropic (Str > 0.5): Std is the direction of a random fluctuation"
    return {
        "Sal_m": float(sal),
        "Str": None if ratio is None else float(min(ratio, 1.0)),
        "Std_deg": std,
        "spatial_note": note,
    }
