"""The unit of a text file's coordinate columns when no title line states it.

An x,z profile (or x,y,z point list) exported in millimetres with no unit line carries its
spacing in millimetres: read as metres, a 150 mm CAPTIF-like profile at 0.0375 mm becomes a
150 m profile at 3.75 cm with 0.73 m rms heights, and every number after it is wrong. The
coordinates are therefore read in the unit of the heights (``units``, default m) and that
reading is checked against what a road or microscope profiler can give; when it is
implausible and another unit (the same for coordinates and heights) is plausible, the file is
refused in one line naming that unit and the flag (``--units mm``). Plausible means

- spacing ``dx`` in [1 nm, 1 cm] (microscopes to road texture profilers; ISO 13473-1 asks for
  at most 1 mm for texture, unevenness profilers sample at 25 mm and more but are not texture),
- detrended rms height ``Sq`` at most 50 mm (road textures reach a few mm: ISO 13473-1 MPD
  0.2..3 mm; a microscope field far less),
- ``Sq`` at most half the length and at least 1e-5 of the spacing (the scan-against-itself
  bounds of :mod:`roadscan.plausibility`).

A file whose coordinates really are metres and heights metres with a large rms (a long
unevenness profile) is read with ``--units m`` given explicitly: the unit is then stated.
When heights are given in ``units`` and the coordinates read in ``units`` are impossible, the
other units are tried for the coordinates alone: metres as the one plausible reading (the older
convention of unitless coordinates in metres) is taken with a warning naming ``--x-units m``;
any other plausible unit is refused, naming ``--x-units`` and the title line that states each
column's unit (``x (um), z (mm)``).

Reference: ISO 13473-1:2019 (texture profile sampling and MPD); ISO 25178-2:2012 (``Sq``).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, OptionNote
from ..units import length as _len

__all__ = ["UNITS", "check_coordinate_units", "plausible_reading", "line_rms"]

#: candidate units, metres per unit
UNITS = {"m": 1.0, "mm": 1e-3, "um": 1e-6}
DX_RANGE_M = (1e-9, 1e-2)
SQ_MAX_M = 0.05
ROUGH_MAX = 0.5
SMOOTH_MIN = 1e-5
_MAX_POINTS = 250_000


def line_rms(z):
    """rms about a least-squares line (2D ``z``: plane) of the finite values of ``z`` (in its
    own unit), the lowest and highest 1 % left out (spikes do not decide a unit), over a regular
    subsample of at most about 250,000 points.

    Parameters
    ----------
    z : ndarray
        Heights (1D or 2D) in their own unit.

    Returns
    -------
    float
    """
    z = np.asarray(z, float)
    step = max(1, int(np.ceil((z.size / _MAX_POINTS) ** (1 / max(z.ndim, 1)))))
    if step > 1:  # a regular subsample: a unit is not decided by detail
        z = z[(slice(None, None, step),) * z.ndim]
    flat = z.ravel()
    pos = np.flatnonzero(np.isfinite(flat))
    zv = flat[pos]
    ncoef = 1 + z.ndim
    if zv.size < ncoef + 1:
        return float(np.std(zv)) if zv.size else float("nan")
    lo, hi = np.percentile(zv, [1.0, 99.0])
    keep = (zv >= lo) & (zv <= hi)
    if keep.sum() < ncoef + 1:
        keep[:] = True
    pos, zk = pos[keep], zv[keep]
    coords = [pos] if z.ndim == 1 else list(np.divmod(pos, z.shape[-1]))
    a = np.column_stack([np.ones(zk.size)] + [c - c.mean() for c in coords])  # centred
    zk = zk - zk.mean()
    coef = np.linalg.lstsq(a.T @ a, a.T @ zk, rcond=None)[0]  # normal equations (a 2 x 2 or
    # 3 x 3 system; lstsq: a single measured row or column leaves it singular)
    r = zk - a @ coef
    return float(np.sqrt(np.mean(r * r)))


def plausible_reading(dx_m, length_m, rms_m):
    """True when a scan with spacing ``dx_m``, length ``length_m`` and rms height ``rms_m``
    [m] is one a road or microscope profiler can give (module notes).

    Parameters
    ----------
    dx_m, length_m, rms_m : float
        Spacing, length and rms height [m].

    Returns
    -------
    bool
    """
    if not (np.isfinite(rms_m) and np.isfinite(dx_m)):
        return True  # nothing to judge: other checks refuse it
    if not DX_RANGE_M[0] <= dx_m <= DX_RANGE_M[1]:
        return False
    if rms_m > SQ_MAX_M or rms_m > ROUGH_MAX * length_m:
        return False
    return rms_m == 0 or rms_m >= SMOOTH_MIN * dx_m


def check_coordinate_units(path, dx_file, n_nodes, z_file, units, what="x", notes=None, found=None):
    """Check the reading of coordinates with no stated unit in the heights' unit.

    Parameters
    ----------
    path : str or Path
        For the message.
    dx_file : float
        The step of the coordinate column(s) (the larger of x and y), in the file's numbers.
    n_nodes : int
        Grid nodes along the longer side.
    z_file : array
        The heights in the file's numbers.
    units : str or None
        ``--units`` (m, mm, um, nm) or None (not given: metres assumed).
    what : str
        ``"x"`` or ``"x, y"`` (for the message).
    notes : list, optional
        Receives the warning when the coordinates are read as metres with heights in ``units``
        (the one plausible reading, the older convention); without it that case is refused.
    found : str, optional
        The title line the file has (naming no unit), quoted in the message.

    Returns
    -------
    str
        The unit the coordinates are read in.

    Raises
    ------
    InputError
        When that reading is implausible and another is plausible (module notes), naming the
        unit and the flag.
    """
    from ._common import unit_factor

    f = unit_factor(units, path)
    rms = line_rms(z_file)
    if plausible_reading(dx_file * f, n_nodes * dx_file * f, rms * f):
        return units or "m"
    where = (
        f"read as {units or 'm'}, the file gives a {_len(n_nodes * dx_file * f)} profile with "
        f"{_len(dx_file * f)} spacing and {_len(rms * f)} rms heights"
    )
    if units is None:
        fits = [
            u
            for u, g in UNITS.items()
            if g != 1.0 and plausible_reading(dx_file * g, n_nodes * dx_file * g, rms * g)
        ]
        if fits:
            alt = fits[0] + "".join(f" (or {u})" for u in fits[1:])
            said = f"the title line {found!r} states no units" if found else "no title line states the units"
            raise InputError(
                path,
                f"{what} and heights look like {alt}, not metres ({where}; "
                f"{said}): give {{units}} {fits[0]}, or {{units}} m if they are "
                f"metres",
                "units",
            )
        return "m"
    # heights in `units`: are the coordinates in another unit?
    fits = [
        u
        for u, g in UNITS.items()
        if abs(g - f) > 1e-9 * f and plausible_reading(dx_file * g, n_nodes * dx_file * g, rms * f)
    ]
    if fits == ["m"] and notes is not None:
        # the one plausible reading is the older convention (unitless coordinates in metres,
        # --units for the heights only): read so, and say it
        notes.append(
            OptionNote(
                f"{what} read as metres, heights as {units}: read in {units} too ({{units}} applies to "
                f"both) the {what} would give {where[len(f'read as {units}, the file gives ') :]}, "
                f"impossible; pass {{x_units}} m to state it",
                ("units", "x_units"),
            )
        )
        return "m"
    if fits:
        u = fits[0]
        raise InputError(
            path,
            f"{what} {'look' if ',' in what else 'looks'} like {u} while "
            f"{{units}} {units} reads them in {units} ({where}): {{units}} applies "
            f"to coordinates and heights alike; give {{x_units}} {u}, or state "
            f"each column's unit in a title line, e.g. 'x ({u}), z ({units})'",
            ("units", "x_units"),
        )
    return units
