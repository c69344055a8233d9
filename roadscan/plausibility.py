"""Are these heights plausible for this scan? A units slip caught before any figure.

A scan written in mm and read as metres is 1000 times too rough and still "valid" numbers:
0.415 m rms on a 12.8 mm scan. The heights are judged against the scan itself (its detrended
rms height ``S_q`` against its lateral size ``L`` and its spacing ``dx``), the range real
textures have, and what an instrument sampling at ``dx`` can resolve:

- **too rough**: ``S_q > L / 2``. A rough surface's rms height grows with the scale it is
  measured over and stays well below it (self-affine textures: ``S_q(L) ~ L^H`` with mean
  slopes of order one at most; road textures and microscope scans give ``S_q / L`` from 1e-6
  to 0.05, the shared samples at most 0.06); a factor 1000 slip gives 30 on a 12.8 mm scan.
- **too smooth**: ``S_q < 1e-5 dx`` (no instrument resolves heights 1e5 times below its
  pixel: interferometers reach ~1e-4 dx), or ``S_q < 10 nm`` at ``dx >= 20 um`` (a texture
  scanner's pixel: laser triangulation and stripe projection resolve about a micrometre);
  ``--units um`` on metres gives 0.4 nm on a 50 um pixel.

``S_q`` is the rms about a least-squares plane (a line for profiles) over a regular subsample of
at most ~65,000 measured points, the lowest and highest 1 % of heights left out (a few spikes
neither tilt the plane nor set the rms; a units slip scales every height alike): ``S_q`` of
ISO 25178-2 after form removal (a plane, not the scan's tilt or the al3d sample's 76 mm offset).

When the heights are implausible, the units that would make them plausible are searched among
m, mm, um and nm (a factor 1000 apart): those passing both checks, the one whose ``S_q / dx``
is closest to 1 (the middle of what texture and microscope scans show) is named in the one-line
refusal, which contains ``units?`` and the flag that fixes it (``--units mm``, with
``--override-calibration`` when the unit came from the file).

Reference: ISO 25178-2:2012 (``S_q``); B. N. J. Persson et al., J. Phys.: Condens. Matter 17
(2005) R1 (self-affine surfaces, rms height against scale).
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

from .errors import InputError
from .order_stats import median, percentiles
from .units import length as _fmt

if TYPE_CHECKING:
    from .heightmap import HeightMap, Profile

__all__ = ["detrended_rms", "check_plausible", "ROUGH_MAX", "SMOOTH_MIN", "UNITS"]

#: largest plausible S_q / L
ROUGH_MAX = 0.5
#: smallest plausible S_q / dx
SMOOTH_MIN = 1e-5
#: a texture scanner's pixel [m] and the smallest S_q it can resolve [m]
COARSE_PIXEL_M, COARSE_FLOOR_M = 20e-6, 10e-9
#: metres per unit of the --units choices
UNITS = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "nm": 1e-9}
_MAX_POINTS = 65_536


def detrended_rms(obj: HeightMap | Profile) -> float:
    """rms height [m] about a least-squares plane (profile: line) of a regular subsample.

    Parameters
    ----------
    obj : HeightMap or Profile

    Returns
    -------
    float
        ``sqrt(mean((h - a - b x - c y)^2))`` over the subsample's measured points.
    """
    h = obj.heights_m
    if h.ndim == 1:
        step = max(1, h.size // _MAX_POINTS)
        z = h[::step]
        x = np.arange(z.size, dtype=np.float64)
        ok = np.isfinite(z)
        cols = [np.ones(int(ok.sum())), x[ok]]
    else:
        step = max(1, int(np.ceil(np.sqrt(h.size / _MAX_POINTS))))
        z = h[::step, ::step]
        grid = np.indices(z.shape, dtype=np.float64)
        yy, xx = grid[0], grid[1]
        ok = np.isfinite(z)
        cols = [np.ones(int(ok.sum())), xx[ok], yy[ok]]
    zo = z[ok]
    scale = _power_of_two_scale(zo)
    zo = zo / scale
    if zo.size < len(cols) + 1:
        if step > 1:  # the subsample missed the measured points: take them all
            return _all_points_rms(h)
        return scale * float(np.std(zo)) if zo.size else float("nan")
    lo, hi = percentiles(zo, [1.0, 99.0])  # np.percentile's values
    keep = (zo >= lo) & (zo <= hi)  # a few spikes neither tilt the plane nor the rms
    if keep.sum() < len(cols) + 1:
        keep[:] = True
    zk = zo[keep]
    zk = zk - median(zk)
    a = np.column_stack([c[keep] for c in cols])
    coef, *_ = np.linalg.lstsq(a, zk, rcond=None)
    r = zk - a @ coef
    return scale * float(np.sqrt(np.mean(r * r)))


def _all_points_rms(h):
    """rms about the mean of every measured point (no plane: too few for one)."""
    v = h[np.isfinite(h)]
    if v.size < 2:
        return float("nan")
    scale = _power_of_two_scale(v)
    return scale * float(np.std(v / scale))


def _power_of_two_scale(z):
    """1.0, or a power of two near max |z| when that exceeds 2^500: heights near the float64
    limit (a units slip in a file) are scaled exactly (a power of two) before they are squared,
    so their rms comes out instead of an overflow; ordinary heights keep every bit."""
    m = float(np.max(np.abs(z))) if z.size else 0.0
    if not (np.isfinite(m) and m > 2.0**500):
        return 1.0
    return float(np.ldexp(1.0, int(np.frexp(m)[1]) - 1))  # 2^(e-1) <= m < 2^e: |z| / scale < 2


def _span(obj):
    h = obj.heights_m
    ok = np.isfinite(h)
    return float(np.max(np.abs(h[ok]))) if ok.any() else 0.0


def _lateral(obj):
    h = obj.heights_m
    if h.ndim == 1:
        return h.size * obj.dx_m, obj.dx_m
    ny, nx = h.shape
    return max(nx * obj.dx_m, ny * obj.dy_m), max(obj.dx_m, obj.dy_m)


def _problem(rms, size, dx):
    """None if plausible, else a short reason."""
    if rms > ROUGH_MAX * size:
        return f"{rms / size:.3g} times its size"
    if rms < SMOOTH_MIN * dx:
        return f"{dx / rms:.3g} times below its spacing" if rms > 0 else "flat"
    if dx >= COARSE_PIXEL_M and rms < COARSE_FLOOR_M:
        return "below what a scanner with that spacing resolves"
    return None


def check_plausible(
    obj: HeightMap | Profile, path: str | os.PathLike[str] | None = None, units: str | None = None
) -> float:
    """Refuse heights implausible for the scan (module notes) in one line with ``units?``.

    Parameters
    ----------
    obj : HeightMap or Profile
        As read; ``obj.meta["height_unit"]`` (set by readers of files that state a unit) tells
        where the unit came from.
    path : str or Path, optional
        For the message.
    units : str, optional
        The ``--units`` given (m, mm, um, nm), used when the file states no unit.

    Returns
    -------
    float
        The detrended rms height [m] (plausible).

    Raises
    ------
    InputError
        ``"... units? ... pass {units} mm"`` (the ``units`` option named by the front end)
        when the heights are implausible.
    """
    rms = detrended_rms(obj)
    if np.isnan(rms):
        return rms  # too few measured points to judge (the caller's checks refuse them)
    size, dx = _lateral(obj)
    why = _problem(rms, size, dx)
    if why is None or (rms <= 1e-9 * _span(obj) and rms <= ROUGH_MAX * size):
        return rms  # plausible, or an exact plane (a synthetic form, not a units question)
    info = obj.meta.get("height_unit") if isinstance(obj.meta, dict) else None
    if info:
        cur_name, cur = str(info["unit"]), float(info["m_per_unit"])
        from_file = info.get("from") == "file"
    else:
        cur_name = units or "m"
        cur = UNITS.get(cur_name, 1.0)
        from_file = False
    best = None
    for name, f in UNITS.items():
        s = f / cur
        if abs(np.log10(s)) < 1 or _problem(rms * s, size, dx) is not None:
            continue
        score = abs(np.log10(rms * s / dx))
        if best is None or score < best[0]:
            best = (score, name)
    where = (
        f"rms height {_fmt(rms)} on a {_fmt(size)} {'profile' if obj.heights_m.ndim == 1 else 'scan'} "
        f"with {_fmt(dx)} spacing ({why})"
    )
    said = f"heights read as {cur_name}" + (" as the file states" if from_file else "")
    if best is None and not np.isfinite(rms):
        return rms  # beyond any unit: the caller's absolute bounds name it (spikes, 1 km)
    if best is None:
        fix = "check the file's units and spacing ({units}, {spacing})"
    elif from_file:
        fix = f"if they are {best[1]}, pass {{units}} {best[1]} {{override_calibration}}"
    else:
        fix = f"if they are {best[1]}, pass {{units}} {best[1]}"
    raise InputError(path, f"units? {where}: {said}; {fix}", ("units", "spacing", "override_calibration"))
