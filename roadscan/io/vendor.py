"""Instrument vendors' height files through SurfaceTopography (MIT, contact.engineering).

``pip install 'roadscan[vendor]'`` installs `SurfaceTopography <https://github.com/
ContactEngineering/SurfaceTopography>`_ (>= 1.27). It is imported only when such a file is read
(``import roadscan`` stays light); without it the reader raises :class:`InputError` naming the
extra.

Routing. Every extension SurfaceTopography 1.27 reads (``SurfaceTopography.IO.readers``, each
reader's ``file_extensions()``) is registered here, except those roadscan reads with its own
readers: ``.x3p`` (x3pio), ``.gwy`` (gwyfile), ``.npy``/``.npz``, ``.tif``/``.tiff``,
``.txt``/``.asc``/``.csv``/``.xyz`` (text) and ``.dat`` (CAPTIF). A ``.dat`` without the CAPTIF
marker and a TIFF carrying the Park Systems tags are handed here by ``captif.py`` and
``tiff.py``. At read time the installed package's registry decides which readers may open an
extension; those whose magic bytes rule the file out are skipped, the others are tried in
the registry's order.

What is returned. The first height channel (the reader's default channel when it holds
heights, as it does for every reader of SurfaceTopography 1.27; otherwise the first channel
whose ``data_kind`` is a height), as a :class:`HeightMap` with

- rows along y and columns along x: SurfaceTopography's ``heights()`` is indexed ``[x, y]``,
  so it is transposed;
- heights and spacings converted from the topography's length unit to metres
  (``h_m = h_file * f(unit)``, ``dx = L_x / n_x * f(unit)`` with ``f`` = 1 for m, 1e-3 for mm,
  1e-6 for um, 1e-9 for nm, 1e-10 for Angstrom...); an unknown unit is refused;
- undefined points (SurfaceTopography's mask, or NaN) as NaN with ``unmeasured`` True.

Line scans and non-uniform topographies are refused (one line). A file that states no
lateral size needs ``spacing``; one that states no unit needs ``units`` (never a silent
default for an instrument file). ``spacing`` overrides the file's (the file's is kept in
``meta["file_spacing_m"]``); ``units`` is ignored when the file states its unit (noted in
``meta["units_ignored"]``).

Never silently wrong (checked after reading, each failure one :class:`InputError` line):
the declared grid (``nb_grid_pts``) is checked against the size limit (``--max-pixels``) and
the file's size before any height is read, and against the array actually returned; infinite
heights, denormal heights (0 < |h| < 1e-30 m: an instrument writes none; misread bytes do), and
heights beyond 10 km (an unmasked invalid-point marker or a wrong unit) are refused; spacings
must be positive and finite.

Metadata (``meta``, JSON-safe): ``format`` (SurfaceTopography's format id), ``format_name``,
``reader`` (package, version and reader class), ``units`` (the file's unit), ``channel``,
``channels`` (all channel names when there are several), ``undefined_points``, and
``instrument``: a small block (:func:`instrument_block`) with name, vendor, serial, software,
acquisition date, objective, magnification, lateral resolution and tip radius [m] where the
file records them, plus units, undefined points, reader and channel. ``roadscan analyse``
copies it into ``summary.json`` and the report's header; ``roadscan convert`` into X3P's
Record2.

Reference: L. Pastewka et al., SurfaceTopography, https://github.com/ContactEngineering/
SurfaceTopography (MIT); the file formats are documented in its ``SurfaceTopography/IO``.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..errors import InputError
from ._common import (check_compression_ratio, check_declared_size, check_file, make_heightmap,
                      resolve_spacing, unit_factor)
from ._registry import register_reader

__all__ = ["read_vendor", "VENDOR_EXTENSIONS", "OWN_EXTENSIONS", "vendor_available",
           "vendor_version", "instrument_block", "LENGTH_UNITS", "MIN_VERSION"]

#: oldest SurfaceTopography whose readers are tested here (the shared real files, issue 9)
MIN_VERSION = (1, 27)

#: extensions SurfaceTopography 1.27 reads that roadscan routes to it, with its reader's format
#: id (for the documentation; at read time the installed registry decides). A test checks this
#: table against the installed package.
VENDOR_FORMATS = {
    ".sdf": "sdf", ".hfm": "xyz", ".spm": "di", ".001": "di", ".002": "di", ".003": "di",
    ".004": "di", ".005": "di", ".mat": "mat", ".mdt": "mdt", ".opd": "opd", ".opdx": "opdx",
    ".ibw": "ibw", ".mi": "mi", ".xlsx": "mitutoyo", ".nc": "nc", ".datx": "datx", ".h5": "h5",
    ".sur": "sur", ".tmd": "tmd", ".vk3": "vk", ".vk4": "vk", ".vk6": "vk", ".vk7": "vk",
    ".zmg": "zmg", ".zon": "zon", ".os3d": "os3d", ".al3d": "al3d", ".ezd": "ezd", ".nid": "ezd",
    ".bcr": "bcr", ".bcrf": "bcr", ".plu": "plu", ".apx": "plu", ".frt": "frt", ".lext": "lext",
    ".oir": "oir", ".poir": "poir", ".cur": "wsxm", ".stp": "wsxm", ".tom": "wsxm",
    ".top": "wsxm", ".plux": "plux", ".jpk": "jpk", ".mnt": "mnt", ".qep": "qep", ".zip": "nmm",
    ".nms": "nms", ".hgt": "hgt",
}
VENDOR_EXTENSIONS = tuple(VENDOR_FORMATS)
#: extensions SurfaceTopography also reads but roadscan reads itself (``.dat``: CAPTIF first,
#: then SurfaceTopography; ``.tif``: Park Systems TIFFs go to SurfaceTopography)
OWN_EXTENSIONS = (".x3p", ".gwy", ".npy", ".npz", ".tif", ".tiff", ".txt", ".asc", ".csv",
                  ".xyz", ".dat")

#: metres per length unit as SurfaceTopography writes them (its ``length_units`` and the
#: spellings its readers normalise to)
LENGTH_UNITS = {
    "km": 1e3, "m": 1.0, "dm": 1e-1, "cm": 1e-2, "mm": 1e-3, "µm": 1e-6, "μm": 1e-6, "um": 1e-6,
    "nm": 1e-9, "Å": 1e-10, "A": 1e-10, "pm": 1e-12, "fm": 1e-15,
}
#: SurfaceTopography's spelling of roadscan's --units
_ST_UNIT = {"m": "m", "mm": "mm", "um": "µm", "µm": "µm", "μm": "µm", "micron": "µm", "nm": "nm"}

#: smallest non-zero |height| an instrument writes [m] (below: misread bytes, e.g. denormals)
MIN_NONZERO_M = 1e-30
#: largest |height| accepted [m] (beyond: an unmasked invalid-point marker or a wrong unit)
MAX_ABS_M = 1e4


def vendor_version():
    """Installed SurfaceTopography version string, or None (without importing it)."""
    from importlib import metadata

    try:
        return metadata.version("SurfaceTopography")
    except metadata.PackageNotFoundError:
        return None


def vendor_available():
    """True if SurfaceTopography can be imported."""
    try:
        import SurfaceTopography.IO  # noqa: F401
    except ImportError:
        return False
    return True


def _version_tuple(text):
    out = []
    for part in str(text).split(".")[:2]:
        digits = "".join(c for c in part if c.isdigit())
        out.append(int(digits) if digits else 0)
    return tuple(out)


def _import_io(path):
    """``SurfaceTopography.IO``, or a one-line error naming the extra."""
    ext = Path(path).suffix.lower() or "this"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import SurfaceTopography.IO as stio
    except ImportError:
        raise InputError(path, f"reading {ext} files needs the optional extra: "
                               "pip install 'roadscan[vendor]' (SurfaceTopography)") from None
    version = vendor_version() or getattr(__import__("SurfaceTopography"), "__version__", "0")
    if _version_tuple(version) < MIN_VERSION:
        raise InputError(path, f"SurfaceTopography {version} is too old (need >= "
                               f"{'.'.join(map(str, MIN_VERSION))}): pip install -U 'roadscan[vendor]'")
    return stio, version


def _one_line(exc, limit=240):
    text = f"{type(exc).__name__}: {exc}"
    s = " ".join(part.strip() for part in text.splitlines() if part.strip())
    return s if len(s) <= limit else s[: limit - 3] + "..."


def _candidates(stio, path, formats):
    """Reader classes that may open ``path``: the given format ids, else every registered reader
    listing the file's extension, minus those whose magic bytes rule the file out."""
    ext = Path(path).suffix.lower().lstrip(".")
    if formats is not None:
        classes = [stio.lookup_reader_by_format[f] for f in formats if f in stio.lookup_reader_by_format]
    else:
        classes = []
        for cls in stio.readers:
            try:
                exts = [e.lower() for e in cls.file_extensions()]
            except Exception:  # noqa: BLE001 - a reader without extensions
                continue
            if ext in exts:
                classes.append(cls)
    with open(path, "rb") as f:
        magic = f.read(getattr(stio, "MAGIC_BUFFER_SIZE", 512))
    kept = []
    for cls in classes:
        try:
            ruled_out = cls.can_read(magic) == stio.MagicMatch.NO
        except Exception:  # noqa: BLE001
            ruled_out = False
        if not ruled_out:
            kept.append(cls)
    return classes, kept


def _open(stio, version, path, formats):
    classes, kept = _candidates(stio, path, formats)
    ext = Path(path).suffix.lower()
    if not classes:
        raise InputError(path, f"SurfaceTopography {version} has no reader for {ext} files")
    if not kept:
        names = ", ".join(c.name() for c in classes)
        raise InputError(path, f"not a {names} file (its first bytes do not match the format)")
    errors = []
    for cls in kept:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                return stio.open_topography(str(path), format=cls.format())
        except (MemoryError, KeyboardInterrupt):
            raise
        except Exception as exc:  # noqa: BLE001 - the readers raise many kinds on broken files
            errors.append(f"{cls.name()}: {_one_line(exc)}")
    raise InputError(path, "cannot read (" + "; ".join(errors) + ")")


def _length_factor(unit, path, what):
    if unit is None:
        return None
    key = str(unit).strip()
    if key in LENGTH_UNITS:
        return LENGTH_UNITS[key]
    raise InputError(path, f"{what} unit {unit!r} is not a length unit roadscan knows "
                           f"({', '.join(LENGTH_UNITS)})")


def _pick_channel(reader, path):
    channels = list(reader.channels)
    if not channels:
        raise InputError(path, "holds no data channel")
    heights = [c for c in channels if getattr(c, "is_height_channel", True)]
    if not heights:
        kinds = ", ".join(f"{c.name} ({getattr(getattr(c, 'data_kind', None), 'value', '?')})"
                          for c in channels)
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
    if dim is not None and dim != 2 or n is not None and len(n) != 2:
        npts = f" of {n[0]} points" if n else ""
        raise InputError(path, f"channel {ch.name!r} is a line scan{npts}: roadscan reads area "
                               f"scans from this format (export the profile as text to read it)")
    if ch.is_uniform is False:
        raise InputError(path, f"channel {ch.name!r} is a non-uniform (irregularly sampled) "
                               f"topography: roadscan needs a regular grid")
    if n is None:
        return None
    nx, ny = n
    return int(ny), int(nx)


@register_reader(*VENDOR_EXTENSIONS)
def read_vendor(path, spacing=None, units=None, formats=None):
    """Read an instrument's height file with SurfaceTopography (see the module notes).

    Parameters
    ----------
    path : str or Path
    spacing : None, float, (float, float) or str
        Grid spacing [m]; overrides the file's, required when the file states no size.
    units : {"m", "mm", "um", "nm"}, optional
        Height unit of a file that states none; ignored otherwise.
    formats : sequence of str, optional
        SurfaceTopography format ids to try (default: the readers listing the extension).

    Returns
    -------
    HeightMap
        Heights [m], rows along y, NaN and ``unmeasured`` at undefined points.

    Raises
    ------
    InputError
        Missing extra, unreadable or inconsistent file, line scan, non-uniform grid, unknown
        unit, missing spacing/units, size above the limit.
    """
    path = check_file(path)
    stio, version = _import_io(path)
    sp = resolve_spacing(spacing, path)
    reader = _open(stio, version, path, formats)
    try:
        return _read_open(reader, path, version, sp, units)
    finally:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")   # e.g. scipy's netcdf mmap note on close
                reader.close()
        except Exception:  # noqa: BLE001
            pass


def _read_open(reader, path, version, sp, units):
    ch, channels = _pick_channel(reader, path)
    declared = _declared_grid(ch, path)
    if declared is not None:
        n = check_declared_size(path, declared, 8)
        # at most ~200x compression of real height data (zip-bomb guard above 64 MiB)
        check_compression_ratio(path, n * 4, Path(path).stat().st_size)
    file_unit = ch.unit
    kwargs = {}
    if file_unit is None:
        if units is None:
            raise InputError(path, "the file states no length unit: pass --units (m, mm, um, nm)")
        unit_factor(units, path)
        file_unit = _ST_UNIT.get(units, units)
        kwargs["unit"] = file_unit
    f_file = _length_factor(file_unit, path, "the file's")
    if ch.physical_sizes is None:
        if sp is None:
            raise InputError(path, "the file states no lateral size: pass --spacing DX[,DY] in metres")
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
        raise InputError(path, f"cannot read the heights ({_one_line(exc)})") from None
    if topo.dim != 2:
        raise InputError(path, f"channel {ch.name!r} is a line scan: roadscan reads area scans "
                               f"from this format")
    if not getattr(topo, "is_uniform", True):
        raise InputError(path, f"channel {ch.name!r} is a non-uniform topography: roadscan needs "
                               f"a regular grid")
    unit = topo.unit if topo.unit is not None else file_unit
    f = _length_factor(unit, path, "the topography's")
    nx, ny = (int(v) for v in topo.nb_grid_pts)
    data = np.ma.getdata(raw)
    if data.shape != (nx, ny):
        raise InputError(path, f"declares {nx} x {ny} points but holds an array of shape "
                               f"{data.shape}")
    if declared is not None and declared != (ny, nx):
        raise InputError(path, f"the header declares {declared[1]} x {declared[0]} points, the "
                               f"data {nx} x {ny}")
    if not np.issubdtype(data.dtype, np.number) or np.iscomplexobj(data):
        raise InputError(path, f"heights are not real numbers (dtype {data.dtype})")
    mask = np.ma.getmaskarray(raw)
    h_file = np.array(data, dtype=np.float64).T         # [x, y] -> rows along y
    undefined = mask.T | np.isnan(h_file)
    _check_values(path, h_file, f, undefined)
    h = h_file * f                                        # metres
    del h_file
    h[undefined] = np.nan
    sx, sy = (float(v) * f for v in topo.physical_sizes)
    file_dx, file_dy = sx / nx, sy / ny
    for name, v in (("dx", file_dx), ("dy", file_dy)):
        if not (np.isfinite(v) and v > 0):
            raise InputError(path, f"the file's {name} = {v!r} m is not a positive length")
    dx, dy = (file_dx, file_dy) if sp is None else sp
    n_undef = int(undefined.sum())
    fmt_id = reader.format()
    meta = {
        "format": fmt_id,
        "format_name": reader.name(),
        "reader": f"SurfaceTopography {version} ({type(reader).__name__})",
        "units": str(unit),
        "channel": str(ch.name),
        "undefined_points": n_undef,
    }
    if len(channels) > 1:
        meta["channels"] = [str(c.name) for c in channels]
        meta["channel_note"] = (f"channel {ch.index} {ch.name!r} of {len(channels)} read "
                                f"(the first height channel)")
    if sp is not None:
        meta["file_spacing_m"] = [file_dx, file_dy]
    if units is not None and "unit" not in kwargs:
        meta["units_ignored"] = units
    if caught:
        meta["reader_warnings"] = sorted({_one_line(w.message, 160) for w in caught})[:5]
    info = _info_dict(topo, ch)
    meta["instrument"] = instrument_block(info, units=str(unit), undefined_points=n_undef,
                                          reader=meta["reader"], channel=str(ch.name),
                                          format_name=reader.name())
    return make_heightmap(path, h, dx, dy, unmeasured=undefined, meta=meta)


def _check_values(path, h_file, f, undefined):
    """Refuse what an instrument does not write, among the defined heights ``h_file`` (in the
    file's unit, ``f`` metres each): infinities; denormals (0 < |h| below float32's smallest
    normal number, 1.2e-38, in the file's unit, or below 1e-30 m: misread bytes, such as the
    shifted Sensofar values of issue 9); heights beyond 10 km (an unmasked invalid-point marker
    or a wrong unit)."""
    vals = h_file[~undefined]
    inf = ~np.isfinite(vals)
    if inf.any():
        raise InputError(path, f"{int(inf.sum())} heights are infinite (misread data)")
    a = np.abs(vals)
    tiny = (a > 0) & ((a < np.finfo(np.float32).tiny) | (a * f < MIN_NONZERO_M))
    if tiny.any():
        raise InputError(path, f"{int(tiny.sum())} heights are denormal (0 < |h| < "
                               f"{np.finfo(np.float32).tiny:.3g} in the file's unit), which no "
                               f"instrument writes: the file is misread or damaged")
    top = float(a.max()) * f if a.size else 0.0
    if top > MAX_ABS_M:
        raise InputError(path, f"heights reach {top:.3g} m: an unmasked invalid-point marker "
                               f"or a wrong unit (refused above {MAX_ABS_M:g} m)")


def _info_dict(topo, ch):
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


def instrument_block(info, units=None, undefined_points=None, reader=None, channel=None,
                     format_name=None):
    """The JSON-safe ``meta["instrument"]`` block from a SurfaceTopography ``info`` dict.

    Keys (present only when known): ``name``, ``vendor``, ``serial``, ``software``,
    ``acquired`` (ISO 8601), ``objective``, ``magnification``, ``lateral_resolution_m``,
    ``tip_radius_m``, ``comment``, and always ``format``, ``units``, ``undefined_points``,
    ``reader``, ``channel`` when given. Strings are one line, at most 200 characters.
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
