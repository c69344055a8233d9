"""The lateral resolution of a measurement: where it comes from and its plausible range.

The lateral resolution is the wavelength an instrument passes at 50 % amplitude (ISO 25178-600
calls the related figure the lateral period limit); the reliable band of a spectrum ends where
the instrument still passes 80 % (:mod:`roadscan.reliable_band`). It is given by the caller or
read from the file's metadata; every front end bounds it the same way.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .heightmap import HeightMap, Profile

__all__ = ["RESOLUTION_MAX_M", "resolution_of", "resolution_problem"]

#: the largest lateral resolution accepted [m]: a road instrument resolves millimetres; a value
#: above 1 m is a unit slip (millimetres given as metres)
RESOLUTION_MAX_M = 1.0

#: metadata keys that may hold it [m], in the order they are read (the instrument block first)
_KEYS = ("lateral_resolution_m", "resolution_m")


def _positive(v):
    try:
        v = float(v)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) and v > 0 else None


def resolution_of(obj: HeightMap | Profile, given_m: float | None = None) -> tuple[float | None, str | None]:
    """The lateral resolution of a scan and where it came from.

    Parameters
    ----------
    obj : HeightMap or Profile
        Its ``meta`` may carry ``lateral_resolution_m`` or ``resolution_m`` [m], in an
        ``"instrument"`` block or at the top level.
    given_m : float or None
        The caller's value [m]; wins when not None.

    Returns
    -------
    (float or None, str or None)
        (resolution [m], ``"given"`` or ``"file metadata"``), or (None, None) when neither gives
        a positive finite value.
    """
    if given_m is not None:
        return float(given_m), "given"
    found = getattr(obj, "meta", None)
    meta: dict = found if isinstance(found, dict) else {}
    found = meta.get("instrument")
    inst: dict = found if isinstance(found, dict) else {}
    for block in (inst, meta):
        for key in _KEYS:
            v = _positive(block.get(key))
            if v is not None:
                return v, "file metadata"
    return None, None


def resolution_problem(value_m: float) -> str | None:
    """Why ``value_m`` [m] is no lateral resolution, or None when it is one.

    Accepted: finite, 0 < r <= :data:`RESOLUTION_MAX_M`.

    Parameters
    ----------
    value_m : float
        Candidate lateral resolution [m].

    Returns
    -------
    str or None
        The problem, or None.
    """
    try:
        v = float(value_m)
    except (TypeError, ValueError):
        return "not a number"
    if not math.isfinite(v) or v <= 0:
        return "must be a positive length in metres"
    if v > RESOLUTION_MAX_M:
        return f"over {RESOLUTION_MAX_M:g} m: metres expected (e.g. 5e-6)"
    return None
