"""Instrument metadata of vendor files read through SurfaceTopography: the JSON-safe
``meta["instrument"]`` block (name, vendor, serial, software, acquisition date, objective,
magnification, lateral resolution and tip radius [m]) and the length units of its readers.

``roadscan analyse`` copies the block into ``summary.json`` and the report's header;
``roadscan convert`` into X3P's Record2 (ISO 25178-72).

Reference: L. Pastewka et al., SurfaceTopography, https://github.com/ContactEngineering/
SurfaceTopography (MIT): its readers' ``info`` dictionaries.
"""

from __future__ import annotations

import numpy as np

__all__ = ["LENGTH_UNITS", "instrument_block", "info_dict", "one_line"]

#: metres per length unit as SurfaceTopography writes them (its ``length_units`` and the
#: spellings its readers normalise to)
LENGTH_UNITS = {
    "km": 1e3,
    "m": 1.0,
    "dm": 1e-1,
    "cm": 1e-2,
    "mm": 1e-3,
    "µm": 1e-6,
    "μm": 1e-6,
    "um": 1e-6,
    "nm": 1e-9,
    "Å": 1e-10,
    "A": 1e-10,
    "pm": 1e-12,
    "fm": 1e-15,
}


def one_line(exc, limit=240):
    """``exc`` (or any object) as one line of at most ``limit`` characters.

    Parameters
    ----------
    exc : object
        Usually an exception.
    limit : int, optional
        Largest length.

    Returns
    -------
    str
    """
    text = f"{type(exc).__name__}: {exc}"
    s = " ".join(part.strip() for part in text.splitlines() if part.strip())
    s = "".join(c if c.isprintable() else "?" for c in s)  # a reader quoting binary junk: no ESC, BEL, NUL
    return s if len(s) <= limit else s[: limit - 3] + "..."


def info_dict(topo, ch):
    """The reader's ``info`` of a topography (or its channel) as a plain dict.

    Parameters
    ----------
    topo : object
        A SurfaceTopography topography or reader.
    ch : object
        Its channel.

    Returns
    -------
    dict
    """
    info = getattr(topo, "info", None)
    if info is None:
        info = getattr(ch, "info", None)
    if info is None:
        return {}
    if hasattr(info, "model_dump"):
        try:
            return info.model_dump()
        except Exception:  # noqa: BLE001
            return {}
    return dict(info) if isinstance(info, dict) else {}


def _text(value, limit=200):
    if value is None:
        return None
    if isinstance(value, bytes):
        value = value.decode("utf-8", errors="replace")
    s = " ".join(str(value).replace("\x00", " ").split())
    if not s or s.lower() in ("none", "(none)", "n/a", "unknown"):
        return None
    return s[:limit]


def _find_keys(obj, wanted, depth=0, found=None):
    """First value of each lower-case key of ``wanted`` in a nested dict/list (breadth over
    depth is not needed: vendor headers are shallow)."""
    found = {} if found is None else found
    if depth > 6:
        return found
    if isinstance(obj, dict):
        for k, v in obj.items():
            key = str(k).lower()
            for w in wanted:
                if w not in found and key == w and not isinstance(v, (dict, list)):
                    found[w] = v
        for v in obj.values():
            if isinstance(v, (dict, list)):
                _find_keys(v, wanted, depth + 1, found)
    elif isinstance(obj, list):
        for v in obj[:50]:
            if isinstance(v, (dict, list)):
                _find_keys(v, wanted, depth + 1, found)
    return found


def _value_m(model):
    """``{"value": v, "unit": u}`` -> metres (None if the unit is unknown)."""
    if not isinstance(model, dict) or model.get("value") is None:
        return None
    fac = LENGTH_UNITS.get(str(model.get("unit") or "m"))
    try:
        v = float(model["value"]) * fac if fac is not None else None
    except (TypeError, ValueError):
        return None
    return v if v is not None and np.isfinite(v) else None


def instrument_block(info, units=None, undefined_points=None, reader=None, channel=None, format_name=None):
    """The JSON-safe ``meta["instrument"]`` block from a SurfaceTopography ``info`` dict.

    Keys (present only when known): ``name``, ``vendor``, ``serial``, ``software``,
    ``acquired`` (ISO 8601), ``objective``, ``magnification``, ``lateral_resolution_m``,
    ``tip_radius_m``, ``comment``, and always ``format``, ``units``, ``undefined_points``,
    ``reader``, ``channel`` when given. Strings are one line, at most 200 characters.

    Parameters
    ----------
    info : dict
        SurfaceTopography ``info``.
    units : str, optional
        Height unit of the file.
    undefined_points : int, optional
        Count of undefined points.
    reader : str, optional
        Reader name.
    channel : str, optional
        Channel name.
    format_name : str, optional
        Format name.

    Returns
    -------
    dict
    """
    info = info or {}
    inst = info.get("instrument") or {}
    params = inst.get("parameters") or {}
    raw = info.get("raw_metadata") or {}
    out = {}
    for key in ("name", "vendor", "serial", "software"):
        v = _text(inst.get(key))
        if v:
            out[key] = v
    if not out.get("name") and _text(params.get("name")):
        out["name"] = _text(params.get("name"))
    when = info.get("acquisition_time")
    if when is not None:
        out["acquired"] = when.isoformat() if hasattr(when, "isoformat") else _text(when)
    found = _find_keys(raw, ("objective", "magnification", "comment"))
    obj = _text(found.get("objective"))
    if obj:
        out["objective"] = obj
    try:
        mag = float(found["magnification"])
        if np.isfinite(mag) and mag > 0:
            out["magnification"] = mag
    except (KeyError, TypeError, ValueError):
        pass
    res = _value_m(params.get("resolution"))
    if res is not None:
        out["lateral_resolution_m"] = res
    tip = _value_m(params.get("tip_radius"))
    if tip is not None:
        out["tip_radius_m"] = tip
    comment = _text(found.get("comment"))
    if comment:
        out["comment"] = comment
    if format_name:
        out["format"] = str(format_name)
    if units is not None:
        out["units"] = str(units)
    if undefined_points is not None:
        out["undefined_points"] = int(undefined_points)
    if reader:
        out["reader"] = str(reader)
    if channel:
        out["channel"] = str(channel)
    return out
