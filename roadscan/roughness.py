"""Roughness figures: ISO 25178-2 areal parameters, ISO 4287 profile parameters and the
mean profile depth (MPD) of ISO 13473-1.

Heights in metres; parameters with a length carry ``_m`` in their key, dimensionless ones are
bare (``Ssk``, ``Sku``, ``Sdq``; ``Sdr`` is a fraction, not a percentage).

The MPD functions live in ``roadscan._mean_profile_depth`` and are re-exported here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._mean_profile_depth import MPD_SETTINGS, mean_profile_depth, mean_profile_depth_area, segment_depths
from .bands import row_chunks
from .heightmap import HeightMap, Profile
from .level import fit_polynomial, level

__all__ = [
    "area_parameters",
    "profile_parameters",
    "mean_profile_depth",
    "mean_profile_depth_area",
    "segment_depths",
    "MPD_SETTINGS",
]


def _moments(z):
    sq = float(np.sqrt(np.mean(z**2)))
    return {
        "a": float(np.mean(np.abs(z))),
        "q": sq,
        "sk": float(np.mean(z**3) / sq**3) if sq > 0 else 0.0,
        "ku": float(np.mean(z**4) / sq**4) if sq > 0 else 0.0,
        "p": float(z.max()),
        "v": float(-z.min()),
    }


def area_parameters(hm: HeightMap, level_degree: int | None = 1) -> dict[str, Any]:
    """ISO 25178-2 height and hybrid parameters of the levelled, measured heights.

    z = h minus the least-squares plane (``level_degree``; None to skip) over measured points.
    Sa = <|z|>, Sq = <z^2>^(1/2), Ssk = <z^3>/Sq^3, Sku = <z^4>/Sq^4, Sp = max z,
    Sv = -min z, Sz = Sp + Sv (over the whole map).

    Slopes, ISO 25178-2:2021 (4.3.1, 4.3.2) discretised as follows.
    Sdq = (<(dz/dx)^2> + <(dz/dy)^2>)^(1/2) with forward differences
    dz/dx = (z[i, j+1] - z[i, j]) / dx and dz/dy = (z[i+1, j] - z[i, j]) / dy, each mean taken
    over the pairs of measured neighbours. Sdr (developed interfacial area ratio, as a
    fraction, not in %) = <A_cell> / (dx dy) - 1 over the grid cells whose four corners are
    measured, A_cell being the mean of the cell's two triangulations (split along either
    diagonal: four triangles, each of area (dx dy / 2) sqrt(1 + gx^2 + gy^2) with gx, gy the
    edge differences of its two legs). Sdq and Sdr are None (undefined, not NaN) when no such
    neighbours or cells exist (e.g. every other row and column missing).

    The map is read band by band of rows (z evaluated on the fly, plane included), with the
    sums accumulated in float64: the memory used is a few rows whatever the map's size, and
    the result equals the whole-map formulas to float64 round-off.

    Returns
    -------
    dict
        Keys ``Sa_m``, ``Sq_m``, ``Ssk``, ``Sku``, ``Sp_m``, ``Sv_m``, ``Sz_m``, ``Sdq``, ``Sdr``.

    Parameters
    ----------
    hm : HeightMap
        Height map [m].
    level_degree : int or None, optional
        Degree of the least-squares form removed first (None: none).

    References
    ----------
    ISO 25178-2:2021, Geometrical product specifications (GPS) -- Surface texture: Areal -- Part 2:
    Terms, definitions and surface texture parameters.
    """
    h, bad = hm.heights_m, hm.unmeasured
    ny, nx = h.shape
    form = fit_polynomial(h, bad, level_degree) if level_degree is not None else None
    acc = np.zeros(9)  # n, sum|z|, sum z^2, z^3, z^4, n_gx, sum gx^2, n_gy, sum gy^2
    sdr_sum, n_cells = 0.0, 0
    zmax, zmin = -np.inf, np.inf
    for sl in row_chunks(ny, nx):
        ext = slice(sl.start, min(sl.stop + 1, ny))  # one more row for the gradients
        z = form.rows(ext, minus=h[ext]) if form is not None else h[ext]
        zb = z[: sl.stop - sl.start]
        zm = zb[~bad[sl]]
        if zm.size:
            z2 = zm * zm
            acc[:5] += (zm.size, np.abs(zm).sum(), z2.sum(), (z2 * zm).sum(), (z2 * z2).sum())
            zmax, zmin = max(zmax, zm.max()), min(zmin, zm.min())
        if z.shape[0] < 2:
            continue
        d_x = np.diff(z, axis=1) / hm.dx_m  # NaN where a point is missing
        d_y = np.diff(z, axis=0) / hm.dy_m
        gx2, gy2 = d_x[:-1] ** 2, d_y**2  # forward differences of this band's rows
        okx, oky = np.isfinite(gx2), np.isfinite(gy2)
        acc[5:] += (okx.sum(), gx2[okx].sum(), oky.sum(), gy2[oky].sum())
        top, bot = gx2, d_x[1:] ** 2  # cell edges: along x (top, bottom) ...
        left, right = gy2[:, :-1], gy2[:, 1:]  # ... and along y (left, right)
        cell = (
            np.sqrt(1 + top + right)
            + np.sqrt(1 + bot + left)
            + np.sqrt(1 + top + left)
            + np.sqrt(1 + bot + right)
        )
        cell = cell[np.isfinite(cell)]
        n_cells += cell.size
        sdr_sum += 0.25 * cell.sum()
    n, sa, s2, s3, s4, ngx, sgx2, ngy, sgy2 = acc
    sq = float(np.sqrt(s2 / n))
    m = {
        "a": float(sa / n),
        "q": sq,
        "sk": float(s3 / n / sq**3) if sq > 0 else 0.0,
        "ku": float(s4 / n / sq**4) if sq > 0 else 0.0,
        "p": float(zmax),
        "v": float(-zmin),
    }
    sdq = float(np.sqrt(sgx2 / ngx + sgy2 / ngy)) if ngx and ngy else None
    sdr = float(sdr_sum / n_cells - 1.0) if n_cells else None
    return {
        "Sa_m": m["a"],
        "Sq_m": m["q"],
        "Ssk": m["sk"],
        "Sku": m["ku"],
        "Sp_m": m["p"],
        "Sv_m": m["v"],
        "Sz_m": m["p"] + m["v"],
        "Sdq": sdq,
        "Sdr": sdr,
    }


def profile_parameters(profile: Profile, level_degree: int | None = 1) -> dict[str, Any]:
    """ISO 4287-style parameters of a profile's levelled, measured heights (no filtering:
    over the whole evaluation length). Ra, Rq, Rsk, Rku, Rp, Rv, Rt = Rp + Rv and
    Rdq = rms slope (finite differences between measured neighbours; None, undefined, when no
    two neighbours are measured).

    Returns
    -------
    dict
        Keys ``Ra_m``, ``Rq_m``, ``Rsk``, ``Rku``, ``Rp_m``, ``Rv_m``, ``Rt_m``, ``Rdq``.

    Parameters
    ----------
    profile : Profile
        Line profile [m].
    level_degree : int or None, optional
        Degree of the least-squares line or polynomial removed first.

    References
    ----------
    ISO 4287:1997 (ISO 21920-2:2021), profile surface texture parameters.
    """
    if level_degree is not None:
        profile = level(profile, level_degree)
    z = profile.heights_m
    m = _moments(z[~profile.unmeasured])
    s = np.diff(z) / profile.dx_m
    s = s[np.isfinite(s)]
    return {
        "Ra_m": m["a"],
        "Rq_m": m["q"],
        "Rsk": m["sk"],
        "Rku": m["ku"],
        "Rp_m": m["p"],
        "Rv_m": m["v"],
        "Rt_m": m["p"] + m["v"],
        "Rdq": float(np.sqrt(np.mean(s**2))) if s.size else None,
    }
