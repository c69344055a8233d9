"""Gwyddion native ``.gwy`` files through the ``gwyfile`` package.

The first data channel (lowest channel number, ``/N/data``) is read; its title is kept in
``meta``. Spacing = ``xreal / xres`` and ``yreal / yres`` in the lateral unit of the field
(``si_unit_xy``, normally "m"), heights in ``si_unit_z`` (normally "m"); a field without a
height unit uses ``units`` (default m), one without a lateral unit needs ``spacing``.
NaN heights are unmeasured, and so are the points of the channel's mask (``/N/mask`` > 0.5):
Gwyddion's importers mark an instrument's invalid points with that mask, and SurfaceTopography
reads it the same way. A mask drawn by hand for grains or a selection is thus also taken as
unmeasured; its covered fraction is reported in ``meta["gwy_mask_fraction"]``.
"""

from __future__ import annotations

import struct

import numpy as np

from ..errors import InputError
from ._common import (
    NO_SPACING,
    check_declared_size,
    check_file,
    make_heightmap,
    parse_units,
    resolve_spacing,
    unit_factor,
)
from ._registry import register_reader
from .calibration import pick_spacing, pick_units

__all__ = ["read_gwy"]


def _unit(field, key):
    u = field.get(key)
    if u is None:
        return ""
    try:
        return str(u.unitstr or "")
    except (KeyError, AttributeError):
        return ""


_SCALAR_BYTES = {"b": 1, "c": 1, "i": 4, "q": 8, "d": 8}
_ARRAY_BYTES = {"I": 4, "Q": 8, "D": 8}
_MAX_DEPTH = 64


def _corrupt(path, what):
    return InputError(path, f"not a readable Gwyddion file (corrupt: {what})")


def _cstring_end(buf, pos, stop, path, what):
    j = buf.find(b"\0", pos, stop)
    if j < 0:
        raise _corrupt(path, f"unterminated {what} at byte {pos}")
    return j + 1


def _check_object(buf, pos, stop, path, depth=0):
    """End of the serialised GwyObject at ``pos`` after checking that its name, size and every
    component (scalars, strings, nested objects, arrays) lie within ``[pos, stop)``."""
    if depth > _MAX_DEPTH:
        raise _corrupt(path, "objects nested too deep")
    pos = _cstring_end(buf, pos, stop, path, "object name")
    if pos + 4 > stop:
        raise _corrupt(path, f"object size beyond the end at byte {pos}")
    end = pos + 4 + struct.unpack_from("<I", buf, pos)[0]
    if end > stop:
        raise _corrupt(path, f"object at byte {pos} declares more bytes than the file holds")
    pos += 4
    while pos < end:
        pos = _cstring_end(buf, pos, end, path, "component name")
        if pos >= end:
            raise _corrupt(path, f"component without a type at byte {pos}")
        t = chr(buf[pos])
        pos += 1
        if t in _SCALAR_BYTES:
            pos += _SCALAR_BYTES[t]
        elif t == "s":
            pos = _cstring_end(buf, pos, end, path, "string")
        elif t == "o":
            pos = _check_object(buf, pos, end, path, depth + 1)
        elif t in "IQDSOC":
            if pos + 4 > end:
                raise _corrupt(path, f"array length beyond the end at byte {pos}")
            n = struct.unpack_from("<I", buf, pos)[0]
            pos += 4
            if t in _ARRAY_BYTES:
                pos += n * _ARRAY_BYTES[t]
            elif t == "C" and n:  # gwyfile reads char arrays as zero-width items
                raise InputError(path, "Gwyddion char-array components are not supported")
            elif t in "SO":
                if n > end - pos:
                    raise _corrupt(path, f"array of {n} items in {end - pos} bytes")
                for _ in range(n):
                    pos = (
                        _cstring_end(buf, pos, end, path, "string")
                        if t == "S"
                        else _check_object(buf, pos, end, path, depth + 1)
                    )
        else:
            raise _corrupt(path, f"unknown component type {t!r} at byte {pos - 1}")
        if pos > end:
            raise _corrupt(path, f"component runs past its object's end (byte {end})")
    return end


def check_gwy_structure(path):
    """Check the GWY serialisation of ``path`` before gwyfile parses it: every length and
    terminator within bounds (gwyfile loops forever on an unterminated string)."""
    with open(path, "rb") as fh:
        buf = fh.read()
    if buf[:4] != b"GWYP":
        raise InputError(path, "not a readable Gwyddion file (no GWYP header)")
    _check_object(buf, 4, len(buf), path)


def _choose_channel(path, channels, titles, channel):
    """The channel number: the first, or ``channel`` as a number or a title."""
    if channel is None:
        return channels[0]
    if isinstance(channel, int):
        if channel in channels:
            return channel
    else:
        hits = [c for c in channels if titles[c].lower() == str(channel).lower()]
        if hits:
            return hits[0]
    listed = ", ".join(f"{c} ({titles[c]})" if titles[c] else str(c) for c in channels)
    raise InputError(path, f"{{channel}} {channel}: no such channel (channels: {listed})", "channel")


@register_reader(".gwy")
def read_gwy(path, spacing=None, units=None, channel=None):
    """Read a data channel of a Gwyddion ``.gwy`` file: the first, or ``channel`` (its number
    ``/N/data``, or its title); ``meta["channels"]`` lists the titles when there are several.

    Parameters
    ----------
    path : str or Path
        The ``.gwy`` file.
    spacing, units : optional
        For fields without SI units.
    channel : int or str, optional
        Channel number or title.

    Returns
    -------
    HeightMap
    """
    import gwyfile

    p = check_file(path)
    check_declared_size(path, (p.stat().st_size // 8,), 8)  # a .gwy holds float64 points
    check_gwy_structure(path)
    try:
        obj = gwyfile.load(str(path))
    except Exception as exc:  # noqa: BLE001 - gwyfile raises plain ValueError/struct errors
        raise InputError(path, f"not a readable Gwyddion file ({exc.__class__.__name__}: {exc})") from None
    channels = sorted(
        int(k[1 : -len("/data")])
        for k in obj.keys()
        if k.startswith("/") and k.endswith("/data") and k[1 : -len("/data")].isdigit()
    )
    if not channels:
        raise InputError(path, "no data channel in the Gwyddion file")
    titles = {c: str(obj.get(f"/{c}/data/title", "")) for c in channels}
    ch = _choose_channel(path, channels, titles, channel)
    field = obj[f"/{ch}/data"]
    try:
        check_declared_size(path, (int(field["yres"]), int(field["xres"])), 8)
    except (KeyError, TypeError, ValueError) as exc:
        if isinstance(exc, InputError):
            raise
    try:
        z = np.asarray(field.data, dtype=np.float64)
    except Exception as exc:  # noqa: BLE001
        raise InputError(path, f"channel {ch} is not a readable data field ({exc})") from None
    meta = {"format": "gwy", "channel": ch, "title": titles[ch]}
    if len(channels) > 1:
        meta["channels"] = [f"{c}: {titles[c]}" for c in channels]
    zu = _unit(field, "si_unit_z")
    if zu:
        factor = pick_units(path, units, zu, parse_units(zu, path), meta)
        meta["units"] = zu
    else:
        factor = unit_factor(units, path)
        meta["units"] = units or "m"
    mask = obj.get(f"/{ch}/mask")
    if mask is not None:
        try:
            masked = np.asarray(mask.data, dtype=np.float64) > 0.5
        except Exception:  # noqa: BLE001
            raise InputError(path, f"channel {ch} has an unreadable mask") from None
        if masked.shape != z.shape:
            raise InputError(
                path,
                f"channel {ch}'s mask is {masked.shape[1]} x "
                f"{masked.shape[0]}, its data {z.shape[1]} x {z.shape[0]}",
            )
        meta["gwy_mask_fraction"] = float(np.mean(masked))
        z = np.where(masked, np.nan, z)
    sp = resolve_spacing(spacing, path)
    xyu = _unit(field, "si_unit_xy")
    from_file = None
    if xyu and field.xreal is not None and field.yreal is not None:
        f = parse_units(xyu, path)
        ny, nx = z.shape
        from_file = (field.xreal * f / nx, field.yreal * f / ny)
    sp = pick_spacing(path, sp, from_file, meta)
    if sp is None:
        raise InputError(path, NO_SPACING)
    return make_heightmap(path, z * factor, sp[0], sp[1], meta=meta)
