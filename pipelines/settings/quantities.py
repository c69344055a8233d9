"""Quantities given as text with a unit, as the command line and the Python API take them:
the nominal pressure (``0.3MPa``, ``300kPa``, ``3e5Pa``, a bare number in Pa) and the sliding
speeds (``LO:HI:N`` log-spaced, or a list, in m/s). Each parser returns SI numbers or raises a
one-line :class:`roadscan.errors.InputError`.
"""

from __future__ import annotations

import math
import re

from roadscan.errors import InputError

__all__ = ["MAX_SPEED_M_PER_S", "MIN_BARE_PA", "parse_pressure", "parse_velocities"]

MIN_BARE_PA = 1e3  # a bare --sigma0 below this is refused (no unit: almost surely MPa meant)
_PRESSURE_UNITS = {"pa": 1.0, "kpa": 1e3, "mpa": 1e6, "gpa": 1e9, "bar": 1e5, "n/m2": 1.0, "n/mm2": 1e6}
_PRESSURE_RE = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z/0-9]*)\s*$")


def parse_pressure(text, flag="--sigma0"):
    """``"0.3MPa"``, ``"300 kPa"``, ``"3e5Pa"``, ``"3e5"`` (Pa) -> pressure [Pa].

    Raises InputError (one line) on a malformed or non-positive value, and on a bare number
    below :data:`MIN_BARE_PA` with a hint (``--sigma0 0.3`` -> "did you mean 0.3MPa?").

    Parameters
    ----------
    text : str
        The value.
    flag : str, optional
        Flag named in errors.

    Returns
    -------
    float
        Pressure [Pa].
    """
    if isinstance(text, (int, float)):
        text = repr(float(text))
    m = _PRESSURE_RE.match(str(text))
    if not m:
        raise InputError(None, f"{flag} {text!r}: expected a pressure such as 0.3MPa, 300kPa or 3e5 (Pa)")
    val, unit = float(m.group(1)), m.group(2).lower()
    if unit and unit not in _PRESSURE_UNITS:
        raise InputError(None, f"{flag} {text!r}: unknown unit {m.group(2)!r} (Pa, kPa, MPa, GPa, bar)")
    if not (math.isfinite(val) and val > 0):
        raise InputError(None, f"{flag} {text!r}: must be a positive pressure")
    if not unit and val < MIN_BARE_PA:
        hint = f"{m.group(1)}MPa" if val <= 50 else f"{m.group(1)}kPa"
        raise InputError(
            None,
            f"{flag} {text}: a bare number is Pa and {val:g} Pa is no contact "
            f"pressure; did you mean {hint}? (write the unit: 0.3MPa, 300kPa, 3e5Pa)",
        )
    return val * _PRESSURE_UNITS.get(unit, 1.0)


#: the fastest sliding speed accepted [m/s]: far above any tyre, aircraft or rig (and above the
#: speed of sound in rubber, ~1.5e3 m/s); beyond it a log speed axis overflows float64 margins
MAX_SPEED_M_PER_S = 1e6


def _speed_cap(v, text):
    """``v`` when no speed exceeds :data:`MAX_SPEED_M_PER_S`; else an InputError naming it."""
    if v.max() > MAX_SPEED_M_PER_S:
        given = "" if text is None else f" {text!r}"
        raise InputError(
            None,
            f"--velocities{given}: {v.max():.3g} m/s is no sliding speed of rubber "
            f"(the fastest accepted is {MAX_SPEED_M_PER_S:.0e} m/s)",
        )
    return v


def parse_velocities(text):
    """``"LO:HI:N"`` -> N log-spaced speeds [m/s] from LO to HI; ``"V1,V2,..."`` -> those speeds
    (a tabulated grid, e.g. another program's), sorted. InputError when malformed or faster than
    :data:`MAX_SPEED_M_PER_S`.

    Parameters
    ----------
    text : str or array_like
        ``LO:HI:N``, a list ``V1,V2,...``, or the speeds themselves [m/s].

    Returns
    -------
    ndarray
        Speeds [m/s].
    """
    import numpy as np

    if not isinstance(text, str):  # speeds given as numbers (the Python API)
        try:
            v = np.unique(np.asarray(text, dtype=float).ravel())
        except (TypeError, ValueError):
            raise InputError(None, f"--velocities {text!r}: expected speeds in m/s") from None
        if v.size == 0 or not np.all(np.isfinite(v) & (v > 0)):
            raise InputError(None, "--velocities: speeds must be positive numbers [m/s]")
        return _speed_cap(v, None)
    if "," in text or ":" not in text:
        try:
            v = np.array([float(t) for t in text.split(",") if t.strip()])
        except ValueError:
            raise InputError(
                None, f"--velocities {text!r}: expected LO:HI:N (e.g. 1e-8:1e4:121) or a list V1,V2,... [m/s]"
            ) from None
        if v.size == 0 or not np.all(np.isfinite(v) & (v > 0)):
            raise InputError(None, f"--velocities {text!r}: speeds must be positive numbers [m/s]")
        return _speed_cap(np.unique(v), text)
    try:
        lo, hi, n = text.split(":")
        lo, hi, n = float(lo), float(hi), int(n)
    except ValueError:
        raise InputError(
            None, f"--velocities {text!r}: expected LO:HI:N, e.g. 1e-8:1e4:121, or a list V1,V2,..."
        ) from None
    if not (0 < lo < hi < np.inf) or n < 2:
        raise InputError(None, f"--velocities {text!r}: need 0 < LO < HI and N >= 2")
    return _speed_cap(np.logspace(np.log10(lo), np.log10(hi), n), text)
