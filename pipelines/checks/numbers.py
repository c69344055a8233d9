"""Numbers a user gives by flag (spacing, rms height, pressure, Poisson ratio, temperature) and
the limits of every check (the table in :mod:`pipelines.checks.validate`, which re-exports every name).
"""

from __future__ import annotations

import math

from pipelines.checks.run_warnings import warn
from roadscan.errors import InputError

__all__ = [
    "finite_number",
    "check_spacing",
    "check_spacing_option",
    "check_rms_height",
    "check_pressure",
    "check_poisson",
    "wlf_pole_C",
    "check_temperature",
]

KELVIN = 273.15
SPACING_RANGE_M = (1e-9, 1.0)
SPACING_USUAL_M = (1e-7, 1e-2)
MIN_SIDE = 8
MIN_MEASURED = 16
MIN_MEASURED_FRACTION = 0.01
SPIKE_FACTOR = 1e4
MAX_ABS_HEIGHT_M = 1e3
MIN_RMS_HEIGHT_M = 1e-12
Q_MAX_PER_M = 1e11
#: the longest wavelength a surface spectrum may reach: 2 pi / 1e-4 = 63 km (a survey line)
Q_MIN_PER_M = 1e-4
PRESSURE_RANGE_PA = (0.0, 1e9)
POISSON_RANGE = (0.0, 0.5)
WLF_POLE_MARGIN_K = 5.0
T_MAX_C = 1000.0
MAX_PSD_SLOPE = 1.0
MU_MAX = 100.0
MU_WARN = 5.0


def _where(flag=None, path=None):
    return path, (f"{flag} " if flag else "")


def finite_number(value, flag=None, path=None, what="value"):
    """``float(value)``, refusing NaN, infinity and non-numbers (one line naming flag/file).

    Parameters
    ----------
    value : object
        The value.
    flag : str, optional
        Flag named in errors.
    path : str or Path, optional
        File named in errors.
    what : str, optional
        What it is.

    Returns
    -------
    float
    """
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise InputError(path, f"{flag or what} {value!r}: not a number") from None
    if not math.isfinite(v):
        raise InputError(path, f"{flag or what} {value!r}: must be finite")
    return v


def check_spacing(dx_m, dy_m=None, flag="--spacing", path=None, warn_unusual=True):
    """Grid spacing [m]: refused outside [1e-9, 1] m, warned (once, for dx and dy together)
    outside [1e-7, 1e-2] m.

    Parameters
    ----------
    dx_m : float
        Spacing [m].
    dy_m : float, optional
        Spacing along y [m].
    flag : str, optional
        Flag named.
    path : str or Path, optional
        File named.
    warn_unusual : bool, optional
        Warn about an unusual spacing (False where the scan read with it is checked next and
        warns itself, naming its file: one warning, not two).

    Returns
    -------
    None
    """
    unusual = []
    for v in (dx_m,) if dy_m is None else (dx_m, dy_m):
        v = finite_number(v, flag, path, "spacing")
        lo, hi = SPACING_RANGE_M
        if not lo <= v <= hi:
            raise InputError(
                path,
                f"{flag} {v:g} m: implausible grid spacing (expected {lo:g}..{hi:g} m; is the unit metres?)",
            )
        ulo, uhi = SPACING_USUAL_M
        if not ulo <= v <= uhi and v not in unusual:
            unusual.append(v)
    if unusual and warn_unusual:
        ulo, uhi = SPACING_USUAL_M
        warn(
            f"{path + ': ' if path else ''}spacing {' x '.join(f'{v:g}' for v in unusual)} m "
            f"is unusual for a road scan ({ulo:g}..{uhi:g} m)"
        )


def check_spacing_option(text, flag="--spacing", warn_unusual=True):
    """The CLI's ``--spacing DX[,DY]`` [m]: parsed by :func:`roadscan.io.resolve_spacing` and
    checked by :func:`check_spacing`; every refusal names the flag and the value given.

    Parameters
    ----------
    text : str
        ``DX[,DY]``.
    flag : str, optional
        Flag named.
    warn_unusual : bool, optional
        As :func:`check_spacing`.

    Returns
    -------
    tuple of float
    """
    from roadscan.io import resolve_spacing

    try:
        dx, dy = resolve_spacing(text, None)
    except InputError as exc:
        raise InputError(None, f"{flag} {text!r}: {exc.problem}") from None
    check_spacing(dx, dy, flag=flag, warn_unusual=warn_unusual)
    return dx, dy


def check_rms_height(rms_m, flag="--rms"):
    """An rms height [m] asked for (``roadscan synth``): within [1e-12, 1e3] m. Below a
    picometre the heights underflow to zeros on rescaling; above MAX_ABS_HEIGHT_M no road.

    Parameters
    ----------
    rms_m : float
        Rms height [m].
    flag : str, optional
        Flag named.

    Returns
    -------
    float
    """
    v = finite_number(rms_m, flag)
    if not MIN_RMS_HEIGHT_M <= v <= MAX_ABS_HEIGHT_M:
        raise InputError(
            None,
            f"{flag} {v:g} m: implausible rms height (expected "
            f"{MIN_RMS_HEIGHT_M:g}..{MAX_ABS_HEIGHT_M:g} m; is the unit metres?)",
        )
    return v


def check_pressure(sigma0_Pa, flag="--sigma0"):
    """Nominal contact pressure [Pa] in (0, 1e9].

    Parameters
    ----------
    sigma0_Pa : float
        Pressure [Pa].
    flag : str, optional
        Flag named.

    Returns
    -------
    float
    """
    v = finite_number(sigma0_Pa, flag)
    lo, hi = PRESSURE_RANGE_PA
    if not lo < v <= hi:
        raise InputError(None, f"{flag} {v:g} Pa: must be a pressure in ({lo:g}, {hi:g}] Pa")
    return v


def check_poisson(nu, flag="--nu"):
    """Poisson ratio in [0, 0.5] (rubber is nearly incompressible, 0.5).

    Parameters
    ----------
    nu : float
        Poisson's ratio.
    flag : str, optional
        Flag named.

    Returns
    -------
    float
    """
    v = finite_number(nu, flag)
    lo, hi = POISSON_RANGE
    if not lo <= v <= hi:
        raise InputError(None, f"{flag} {v:g}: a Poisson ratio lies in [{lo:g}, {hi:g}]")
    return v


def wlf_pole_C(rubber):
    """The temperature [C] where the rubber's WLF shift diverges, or None (no WLF shift).

    ``log10 aT = -C1 (T - T_s) / (C2 + T - T_d)`` with ``T_d = T_g`` (thesis form) or ``T_s``:
    the pole is ``T_d - C2`` (-81.5 C for the thesis rubber).

    Parameters
    ----------
    rubber : rubber model
        The rubber.

    Returns
    -------
    float or None
        Pole temperature [C].
    """
    wlf = getattr(rubber, "shift", None)
    c2 = getattr(wlf, "C2_K", None)
    td = getattr(wlf, "T_g_C", None)
    if td is None:
        td = getattr(wlf, "T_s_C", None)
    if c2 is None or td is None:
        return None
    return float(td) - float(c2)


def check_temperature(T_C, rubber=None, flag="--temperature"):
    """Temperature [C]: above absolute zero, below 1000 C, and more than 5 K above the
    rubber's WLF pole ``T_d - C2`` (at the pole log a_T diverges; below it WLF is meaningless).

    Parameters
    ----------
    T_C : float or None
        Temperature [C].
    rubber : rubber model, optional
        Its WLF pole is checked.
    flag : str, optional
        Flag named.

    Returns
    -------
    float or None
    """
    if T_C is None:
        return None
    v = finite_number(T_C, flag)
    if v <= -KELVIN:
        raise InputError(None, f"{flag} {v:g} C: below absolute zero (-273.15 C)")
    if v > T_MAX_C:
        raise InputError(None, f"{flag} {v:g} C: implausible for rubber (above {T_MAX_C:g} C)")
    pole = wlf_pole_C(rubber) if rubber is not None else None
    if pole is not None and v <= pole + WLF_POLE_MARGIN_K:
        raise InputError(
            None,
            f"{flag} {v:g} C: at or below the rubber's WLF pole "
            f"(T_d - C2 = {pole:.4g} C); the shift factor diverges there",
        )
    return v
