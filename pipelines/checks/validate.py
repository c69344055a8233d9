"""What roadscan does with input it cannot trust: the one policy, in one place.

Every number a user (a flag) or a file gives is checked here for *physical plausibility*
before it reaches the numerics. Each check either

- **refuses**: raises :class:`roadscan.InputError` whose text is one line naming the flag or
  file and the value (the CLI prints it and exits with code 2); used when no meaningful result
  can follow (a constant grid has no roughness, a temperature at the rubber's WLF pole has no
  shift factor, a PSD rising like q^3 is not a surface), or
- **warns**: :func:`warn` prints one line ``roadscan CMD: warning: ...`` on stderr and records it
  in the current run's :class:`Warnings` (:func:`collecting`); commands that write
  ``summary.json`` store that run's list under ``"warnings"``. Used when the result
  is still meaningful but the user should look (e.g. an unusual spacing, a small grid).

Limits (SI units; chosen wide, to refuse only what no road scan or rubber can be):

============================  =========================================================
quantity                      refused outside (warned outside)
============================  =========================================================
grid spacing [m]              [1e-9, 1] (warned outside [1e-7, 1e-2])
grid size                     fewer than 8 points along a side of an area, or fewer than
                              16 measured points, or under 1 % of the points measured
rms height [m] (synth)        outside [1e-12, 1e3] (not representable / not a road)
heights [m]                   all equal, to 12 digits (no roughness); any |h - median|
                              above 1e4 x the robust spread (a spike of another scale;
                              refused naming the value, unless it is under 1 m); |h| >= 1e3 m
nominal pressure sigma0 [Pa]  (0, 1e9]
Poisson ratio nu              [0, 0.5]
temperature T [C]             below -273.15, or within 5 K above the rubber's WLF pole
                              (T_g - C2, or T_s - C2; -81.5 C for the thesis rubber),
                              or above 1000 C
wave vectors q [1/m]          q1 not above the spectrum's q0 / lowest q; non-finite; any q
                              (flag or PSD row) above 1e11 1/m (a wavelength below 0.1 nm,
                              shorter than an atom) or below 1e-4 1/m (above 63 km)
PSD C(q) [m^4]                any row with C <= 0 or non-finite (refused naming the row);
                              a log-log slope of the whole spectrum above +1 (rises with q:
                              not a surface; self-affine surfaces fall as q^-2(1+H))
friction mu                   non-finite values, or mu > 100 (refused: no physical result);
                              warned when mu > 5
============================  =========================================================

Size limits on files are in :mod:`roadscan.io._common` (``check_declared_size``,
``--max-pixels``) since the readers apply them before allocating.
"""

from __future__ import annotations

import numpy as np

from pipelines.checks.numbers import (
    KELVIN,
    MAX_ABS_HEIGHT_M,
    MIN_MEASURED,
    MIN_MEASURED_FRACTION,
    MIN_SIDE,
    SPIKE_FACTOR,
    T_MAX_C,
    check_poisson,
    check_pressure,
    check_rms_height,
    check_spacing,
    check_spacing_option,
    check_temperature,
    finite_number,
)
from pipelines.checks.run_warnings import (
    Warnings,
    collecting,
    current_warnings,
    reset_warnings,
    warn,
    warnings_list,
)
from pipelines.checks.spectra import (
    check_fit,
    check_mu,
    check_psd_rows,
    check_psd_shape,
    check_q1,
    check_wave_vector,
)
from roadscan.errors import InputError

__all__ = [
    "warn",
    "warnings_list",
    "reset_warnings",
    "Warnings",
    "collecting",
    "current_warnings",
    "check_spacing",
    "check_spacing_option",
    "check_heights",
    "check_scan",
    "check_pressure",
    "check_poisson",
    "check_temperature",
    "check_rms_height",
    "check_wave_vector",
    "check_psd_rows",
    "check_psd_shape",
    "check_q1",
    "check_mu",
    "check_fit",
    "finite_number",
    "KELVIN",
    "T_MAX_C",
]


# ------------------------------------------------------------------------------ scans
def check_heights(heights_m, path=None, unmeasured=None, area=True):
    """Plausibility of a height array [m] (see the module table); refuses with one line.

    Parameters
    ----------
    heights_m : ndarray
        Heights [m].
    path : str or Path, optional
        File named.
    unmeasured : ndarray of bool, optional
        Mask.
    area : bool, optional
        A map rather than a profile.

    Returns
    -------
    None
    """
    h = np.asarray(heights_m)
    if np.iscomplexobj(h):
        raise InputError(path, "heights are complex numbers")
    if area and h.ndim == 2 and min(h.shape) < MIN_SIDE:
        raise InputError(
            path,
            f"grid {h.shape[0]} x {h.shape[1]} is too small for a spectrum "
            f"(need at least {MIN_SIDE} points along each side)",
        )
    if not area and h.size < 2 * MIN_SIDE:
        raise InputError(path, f"profile of {h.size} points is too short (need {2 * MIN_SIDE})")
    n_ok, lo, hi = _measured_range(h, unmeasured)
    if n_ok < MIN_MEASURED or n_ok < MIN_MEASURED_FRACTION * h.size:
        raise InputError(
            path,
            f"only {n_ok} of {h.size} points are measured (need at least "
            f"{max(MIN_MEASURED, int(np.ceil(MIN_MEASURED_FRACTION * h.size)))})",
        )
    top = max(abs(lo), abs(hi))
    if top >= MAX_ABS_HEIGHT_M:
        raise InputError(path, f"height {top:.3g} m is implausible for a road scan (units? spike?)")
    spread = hi - lo
    if spread == 0.0 or spread <= 1e-12 * top:
        raise InputError(
            path, f"all measured heights are equal ({0.5 * (lo + hi):.6g}): a flat grid has no roughness"
        )
    if spread <= 1.0:  # no point can lie more than 1 m from the median: no spike to look for
        return
    ok = np.isfinite(h)
    if unmeasured is not None:
        ok &= ~np.asarray(unmeasured, dtype=bool)
    vals = h[ok]
    med = float(np.median(vals))
    dev = np.abs(vals - med)
    mad = float(np.median(dev))
    far = float(np.max(dev))
    if far > 1.0 and far > SPIKE_FACTOR * 1.4826 * mad:
        spreads = (
            f"{far / (1.4826 * mad):.3g} robust spreads" if mad else f"{far:.3g} m (most heights are equal)"
        )
        raise InputError(
            path,
            f"height {med + far:.3g} m lies {spreads} from the median: an "
            f"implausible spike (mark it unmeasured)",
        )


def _measured_range(h, unmeasured=None, chunk_bytes=4 << 20):
    """(number, min, max) of the finite heights not marked ``unmeasured``, band by band of rows
    (no copy of the measured points: the memory is one band's; :func:`roadscan.bands.measured_stats`)."""
    from roadscan.bands import measured_stats

    n, lo, hi, _ = measured_stats(h, unmeasured, chunk_bytes=chunk_bytes)
    return n, lo, hi


def check_scan(obj, path=None):
    """Check a read :class:`HeightMap` or :class:`Profile` (spacing and heights).

    Parameters
    ----------
    obj : HeightMap or Profile
        The scan.
    path : str or Path, optional
        File named.

    Returns
    -------
    HeightMap or Profile
    """
    from roadscan.heightmap import HeightMap

    area = isinstance(obj, HeightMap)
    if area:
        check_spacing(obj.dx_m, obj.dy_m, flag="spacing", path=str(path) if path else None)
    else:
        check_spacing(obj.dx_m, flag="spacing", path=str(path) if path else None)
    check_heights(obj.heights_m, path, getattr(obj, "unmeasured", None), area=area)
    return obj
