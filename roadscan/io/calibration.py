"""What wins when a flag and a file both state a calibration (spacing or height unit).

A flag never silently overrides what a file carries. Three policies, chosen by the
caller of :func:`roadscan.io.read` (``calibration=``) and seen by the readers through a context
variable:

- ``"strict"`` (default, every single-scan command): ``--spacing`` or ``--units`` on a file that
  carries its own (X3P, .gwy, vendor files, .npz with dx/dy, TIFF with resolution, text with
  coordinates or a header) is refused in one line, unless they agree (relative difference
  below 1e-6, or the same unit);
- ``"override"`` (``--override-calibration``): the flag wins and the reader records
  ``meta["calibration_override"]`` (what the file said, what was used), copied to
  ``summary.json``;
- ``"default"`` (a batch's shared flags): the file wins; the flag applies only to files that
  carry none, and what was set aside is recorded in ``meta["calibration_ignored"]`` and as a
  warning.

Units override: heights are rescaled from the file's unit to the flag's,
``h_m = h_file * f(flag)`` instead of ``h_file * f(file)`` (``f`` = metres per unit).
"""

from __future__ import annotations

import contextvars
from contextlib import contextmanager

from ..errors import InputError, OptionNote

__all__ = [
    "POLICIES",
    "calibration_policy",
    "current_policy",
    "current_x_units",
    "pick_spacing",
    "pick_units",
]

POLICIES = ("strict", "override", "default")
_POLICY = contextvars.ContextVar("roadscan_calibration_policy", default="strict")
#: the unit of a text file's coordinate columns when no title states it (``x_units``)
_X_UNITS = contextvars.ContextVar("roadscan_x_units", default=None)
_REL = 1e-6


@contextmanager
def calibration_policy(policy, x_units=None):
    """Context in which readers apply ``policy`` (one of :data:`POLICIES`).

    Parameters
    ----------
    policy : str
        One of :data:`POLICIES`.
    x_units : str or None
        Unit (m, mm, um, nm) of the coordinate columns of text files without unit titles
        (``read(..., x_units=)``); None: the heights' unit (:mod:`roadscan.io.text_units`).

    Yields
    ------
    None

    Returns
    -------
    contextlib.AbstractContextManager
        Use with ``with``.
    """
    if policy not in POLICIES:
        raise ValueError(f"calibration policy must be one of {POLICIES}, got {policy!r}")
    token = _POLICY.set(policy)
    token_x = _X_UNITS.set(x_units)
    try:
        yield
    finally:
        _X_UNITS.reset(token_x)
        _POLICY.reset(token)


def current_x_units():
    """The ``x_units`` of the current :func:`calibration_policy` context (None: not given).

    Returns
    -------
    str or None

    Parameters
    ----------
    None
    """
    return _X_UNITS.get()


def current_policy():
    """The policy readers apply now (``"strict"`` outside :func:`calibration_policy`).

    Parameters
    ----------
    None

    Returns
    -------
    str
        ``"strict"``, ``"override"`` or ``"fill"``.
    """
    return _POLICY.get()


def _fmt(values):
    return " x ".join(f"{v:.6g}" for v in values)


def _record(meta, key, what, file_value, flag_value):
    block = meta.setdefault(key, {})
    block[what] = {"file": file_value, "flag": flag_value}
    if key == "calibration_ignored":
        meta.setdefault("read_warnings", []).append(
            OptionNote(
                f"{{{what}}} {flag_value} ignored: the file carries its own {what} ({file_value})", what
            )
        )


def _decide(path, meta, what, file_value, flag_value, conflict):
    """``"flag"`` or ``"file"``: which wins under the current policy (recorded in ``meta``);
    under ``"strict"`` the ``conflict`` is refused in one line."""
    policy = current_policy()
    if policy == "strict":
        raise InputError(
            path,
            f"{conflict}; drop {{{what}}}, or add {{override_calibration}} to use "
            f"yours (recorded in the outputs)",
            (what, "override_calibration"),
        )
    key = "calibration_override" if policy == "override" else "calibration_ignored"
    _record(meta, key, what, file_value, flag_value)
    return "flag" if policy == "override" else "file"


def pick_spacing(path, given, from_file, meta):
    """The spacing to use, (dx, dy) [m] or (dx,) for profiles.

    Parameters
    ----------
    path : str or Path
        For the error message.
    given : tuple of float or None
        ``--spacing`` [m] (already resolved), or None.
    from_file : tuple of float or None
        The spacing the file carries [m], or None.
    meta : dict
        The reader's meta; receives ``calibration_override`` / ``calibration_ignored``.

    Returns
    -------
    tuple of float
        The spacing [m].
    """
    if given is None:
        return from_file
    if from_file is None:
        return given
    n = len(from_file)
    given = tuple(given)[:n]
    if all(abs(g - f) <= _REL * abs(f) for g, f in zip(given, from_file)):
        return from_file
    won = _decide(
        path,
        meta,
        "spacing",
        list(from_file),
        list(given),
        f"the file carries its own spacing {_fmt(from_file)} m: {{spacing}} {_fmt(given)} would override it",
    )
    return given if won == "flag" else from_file


def pick_units(path, given, file_unit, file_factor, meta):
    """Metres per height unit to use: the file's ``file_factor`` unless overridden.

    ``given`` is ``--units`` (m, mm, um, nm) or None; ``file_unit`` the file's unit as it spells
    it. Records ``meta["height_unit"]`` (unit, metres per unit, from "file" or "flag") and
    ``meta["units_ignored"]`` when the file's unit is kept against a flag.

    Parameters
    ----------
    path : str or Path
        File named in errors.
    given : str or None
        ``--units``.
    file_unit : str or None
        The file's unit as spelled there.
    file_factor : float
        Metres per file unit.
    meta : dict
        Reader metadata (updated).

    Returns
    -------
    float
        Metres per height unit.
    """
    from ._common import unit_factor

    meta["height_unit"] = {"unit": str(file_unit), "m_per_unit": float(file_factor), "from": "file"}
    if given is None:
        return file_factor
    f_given = unit_factor(given, path)
    if abs(f_given - file_factor) <= _REL * file_factor:
        return file_factor
    won = _decide(
        path,
        meta,
        "units",
        str(file_unit),
        str(given),
        f"the file states its heights in {file_unit}: {{units}} {given} would override it",
    )
    if won == "flag":
        meta["height_unit"] = {"unit": str(given), "m_per_unit": f_given, "from": "flag"}
        return f_given
    meta["units_ignored"] = given
    return file_factor
