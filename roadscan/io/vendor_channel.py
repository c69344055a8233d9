"""One channel of an open SurfaceTopography reader as a :class:`HeightMap` in metres.

- channel: the reader's default channel when it holds heights, else the first channel whose
  ``data_kind`` is a height (``meta["channel"]``; ``meta["channels"]`` when there are several);
- rows along y and columns along x: SurfaceTopography's ``heights()`` is indexed ``[x, y]``,
  so it is transposed;
- heights and spacings converted from the topography's length unit to metres
  (``h_m = h_file * f(unit)``, ``dx = L_x / n_x * f(unit)`` with ``f`` = 1 for m, 1e-3 for mm,
  1e-6 for um, 1e-9 for nm, 1e-10 for Angstrom...); an unknown unit is refused;
- undefined points (SurfaceTopography's mask, or NaN) as NaN with ``unmeasured`` True.

Line scans and non-uniform topographies are refused (one line). A file that states no
lateral size needs ``spacing``; one that states no unit needs ``units`` (never a silent
default for an instrument file). Never silently wrong (each failure one :class:`InputError`
line): the declared grid (``nb_grid_pts``) is checked against the size limit (``--max-pixels``)
and the file's size before any height is read, and against the array actually returned;
infinite heights, denormal heights (0 < |h| < 1e-30 m: an instrument writes none; misread
bytes do), and heights beyond 10 km (an unmasked invalid-point marker or a wrong unit) are
refused; spacings must be positive and finite.

Reference: L. Pastewka et al., SurfaceTopography, https://github.com/ContactEngineering/
SurfaceTopography (MIT).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..errors import InputError
from ._common import check_compression_ratio, check_declared_size, make_heightmap, unit_factor
from .calibration import pick_spacing, pick_units
from .instrument_kind import check_lateral, fix_reader_units
from .vendor_meta import LENGTH_UNITS, info_dict, instrument_block, one_line

__all__ = ["read_channel", "MIN_NONZERO_M", "MAX_ABS_M"]

#: SurfaceTopography's spelling of roadscan's --units
_ST_UNIT = {"m": "m", "mm": "mm", "um": "µm", "µm": "µm", "μm": "µm", "micron": "µm", "nm": "nm"}

#: smallest non-zero |height| an instrument writes [m] (below: misread bytes, e.g. denormals)
MIN_NONZERO_M = 1e-30
#: largest |height| accepted [m] (beyond: an unmasked invalid-point marker or a wrong unit)
MAX_ABS_M = 1e4


def _length_factor(unit, path, what):
    if unit is None:
        return None
    key = str(unit).strip()
    if key in LENGTH_UNITS:
        return LENGTH_UNITS[key]
    raise InputError(
        path, f"{what} unit {unit!r} is not a length unit roadscan knows ({', '.join(LENGTH_UNITS)})"
    )


def _pick_channel(reader, path, channel=None):
    """(chosen channel, all channels): ``channel`` (index from 0 or name, case-insensitive)
    when given, else the reader's default channel if it holds heights, else the first height
    channel."""
    channels = list(reader.channels)
    if not channels:
        raise InputError(path, "holds no data channel")
    if channel is not None:
        names = [str(c.name) for c in channels]
        if isinstance(channel, int):
            if not 0 <= channel < len(channels):
                raise InputError(
                    path,
                    f"{{channel}} {channel}: the file holds {len(channels)} "
                    f"channels (0..{len(channels) - 1}: {', '.join(names)})",
                    "channel",
                )
            ch = channels[channel]
        else:
            hits = [c for c in channels if str(c.name).lower() == str(channel).lower()]
            if not hits:
                raise InputError(
                    path,
                    f"{{channel}} {channel!r}: no such channel (channels: {', '.join(names)})",
                    "channel",
                )
            ch = hits[0]
        if not getattr(ch, "is_height_channel", True):
            raise InputError(
                path, f"{{channel}} {channel}: channel {ch.name!r} does not hold heights", "channel"
            )
        return ch, channels
    heights = [c for c in channels if getattr(c, "is_height_channel", True)]
    if not heights:
        kinds = ", ".join(
            f"{c.name} ({getattr(getattr(c, 'data_kind', None), 'value', '?')})" for c in channels
        )
        raise InputError(path, f"holds no height channel (channels: {kinds})")
    try:
        default = reader.default_channel
    except Exception:  # noqa: BLE001
        default = None
    if default is not None and any(default is c for c in heights):
        return default, channels
    return heights[0], channels


def _declared_grid(ch, path):
    """(ny, nx) declared by the channel, or None when the reader does not say."""
    dim, n = ch.dim, ch.nb_grid_pts
    if (dim is not None and dim != 2) or (n is not None and len(n) != 2):
        npts = f" of {n[0]} points" if n else ""
        raise InputError(
            path,
            f"channel {ch.name!r} is a line scan{npts}: roadscan reads area "
            f"scans from this format (export the profile as text to read it)",
        )
    if ch.is_uniform is False:
        raise InputError(
            path,
            f"channel {ch.name!r} is a non-uniform (irregularly sampled) "
            f"topography: roadscan needs a regular grid",
        )
    if n is None:
        return None
    nx, ny = n
    return int(ny), int(nx)


def read_channel(reader, path, version, sp, units, channel=None):
    """The chosen height channel of the open ``reader`` as a HeightMap [m] (module notes).

    Parameters
    ----------
    reader : SurfaceTopography reader
        The open reader.
    path : str or Path
        The file.
    version : str
        SurfaceTopography version.
    sp : tuple or None
        Spacing [m] given by the user.
    units : str or None
        Height unit given by the user.
    channel : int or str, optional
        Channel choice.

    Returns
    -------
    HeightMap
    """
    ch, channels = _pick_channel(reader, path, channel)
    declared = _declared_grid(ch, path)
    if declared is not None:
        n = check_declared_size(path, declared, 8)
        # at most ~200x compression of real height data (zip-bomb guard above 64 MiB)
        check_compression_ratio(path, n * 4, Path(path).stat().st_size)
    meta = {}
    file_unit = ch.unit
    kwargs = {}
    if file_unit is None:
        if units is None:
            raise InputError(path, "the file states no length unit: pass {units} (m, mm, um, nm)", "units")
        unit_factor(units, path)
        file_unit = _ST_UNIT.get(units, units)
        kwargs["unit"] = file_unit
    f_file = _length_factor(file_unit, path, "the file's")
    # heights' metres per file unit: the file's, or --units under --override-calibration
    f_heights = f_file if "unit" in kwargs else pick_units(path, units, file_unit, f_file, meta)
    if ch.physical_sizes is None:
        if sp is None:
            raise InputError(
                path, "the file states no lateral size: pass {spacing} DX[,DY] in metres", "spacing"
            )
        if declared is None:
            raise InputError(path, "the file states neither its grid nor its lateral size")
        ny, nx = declared
        kwargs["physical_sizes"] = (nx * sp[0] / f_file, ny * sp[1] / f_file)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            topo = reader.topography(channel_index=ch.index, **kwargs)
            raw = topo.heights()
    except (MemoryError, KeyboardInterrupt):
        raise
    except InputError:
        raise
    except Exception as exc:  # noqa: BLE001
        raise InputError(path, f"cannot read the heights ({one_line(exc)})") from None
    if topo.dim != 2:
        raise InputError(
            path, f"channel {ch.name!r} is a line scan: roadscan reads area scans from this format"
        )
    if not getattr(topo, "is_uniform", True):
        raise InputError(
            path, f"channel {ch.name!r} is a non-uniform topography: roadscan needs a regular grid"
        )
    unit = topo.unit if topo.unit is not None else file_unit
    f = _length_factor(unit, path, "the topography's")
    nx, ny = (int(v) for v in topo.nb_grid_pts)
    data = np.ma.getdata(raw)
    if data.shape != (nx, ny):
        raise InputError(path, f"declares {nx} x {ny} points but holds an array of shape {data.shape}")
    if declared is not None and declared != (ny, nx):
        raise InputError(
            path, f"the header declares {declared[1]} x {declared[0]} points, the data {nx} x {ny}"
        )
    if not np.issubdtype(data.dtype, np.number) or np.iscomplexobj(data):
        raise InputError(path, f"heights are not real numbers (dtype {data.dtype})")
    mask = np.ma.getmaskarray(raw)
    h_file = np.array(data, dtype=np.float64).T  # [x, y] -> rows along y
    undefined = mask.T | np.isnan(h_file)
    _check_values(path, h_file, f, undefined)
    h = h_file * (f if f_heights == f_file else f * f_heights / f_file)  # metres
    del h_file
    h[undefined] = np.nan
    sx, sy = (float(v) * f for v in topo.physical_sizes)
    file_dx, file_dy = sx / nx, sy / ny
    for name, v in (("dx", file_dx), ("dy", file_dy)):
        if not (np.isfinite(v) and v > 0):
            raise InputError(path, f"the file's {name} = {v!r} m is not a positive length")
    file_dx, file_dy = fix_reader_units(reader.format(), file_dx, file_dy, meta)
    dx, dy = pick_spacing(path, sp, (file_dx, file_dy), meta)
    if "calibration_override" not in meta or "spacing" not in meta["calibration_override"]:
        check_lateral(path, reader.format(), reader.name(), dx, dy, nx, ny)
    n_undef = int(undefined.sum())
    fmt_id = reader.format()
    meta.update(
        {
            "format": fmt_id,
            "format_name": reader.name(),
            "reader": f"SurfaceTopography {version} ({type(reader).__name__})",
            "units": str(unit),
            "channel": str(ch.name),
            "undefined_points": n_undef,
        }
    )
    if len(channels) > 1:
        meta["channels"] = [str(c.name) for c in channels]
        how = "chosen by the channel option" if channel is not None else "the first height channel"
        meta["channel_note"] = f"channel {ch.index} {ch.name!r} of {len(channels)} read ({how})"
    if caught:
        meta["reader_warnings"] = sorted({one_line(w.message, 160) for w in caught})[:5]
    info = info_dict(topo, ch)
    meta["instrument"] = instrument_block(
        info,
        units=str(unit),
        undefined_points=n_undef,
        reader=meta["reader"],
        channel=str(ch.name),
        format_name=reader.name(),
    )
    return make_heightmap(path, h, dx, dy, unmeasured=undefined, meta=meta)


def _check_values(path, h_file, f, undefined):
    """Refuse what an instrument does not write, among the defined heights ``h_file`` (in the
    file's unit, ``f`` metres each): infinities; denormals (0 < |h| below float32's smallest
    normal number, 1.2e-38, in the file's unit, or below 1e-30 m: misread bytes, such as the
    shifted Sensofar values once seen); heights beyond 10 km (an unmasked invalid-point marker
    or a wrong unit)."""
    vals = h_file[~undefined]
    inf = ~np.isfinite(vals)
    if inf.any():
        raise InputError(path, f"{int(inf.sum())} heights are infinite (misread data)")
    a = np.abs(vals)
    tiny = (a > 0) & ((a < np.finfo(np.float32).tiny) | (a * f < MIN_NONZERO_M))
    if tiny.any():
        raise InputError(
            path,
            f"{int(tiny.sum())} heights are denormal (0 < |h| < "
            f"{np.finfo(np.float32).tiny:.3g} in the file's unit), which no "
            f"instrument writes: the file is misread or damaged",
        )
    top = float(a.max()) * f if a.size else 0.0
    if top > MAX_ABS_M:
        raise InputError(
            path,
            f"heights reach {top:.3g} m: an unmasked invalid-point marker "
            f"or a wrong unit (refused above {MAX_ABS_M:g} m)",
        )
