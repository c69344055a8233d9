"""NumPy ``.npy`` and ``.npz`` height files.

- ``.npy``: a 2D array of heights, rows along y, columns along x, NaN where unmeasured, in
  metres unless ``units`` says otherwise. The file has no spacing: ``spacing`` is required.
- ``.npz``: keys ``heights`` (2D, or 1D for a profile), ``dx`` and ``dy`` [m] (``dy`` absent for
  a profile), optional boolean ``unmeasured``. A ``spacing`` that contradicts ``dx``/``dy``
  follows :mod:`roadscan.io.calibration` (refused unless overridden). Heights are metres
  unless ``units`` says otherwise.

Writers store metres (float64, or float32 with ``dtype="float32"``) and NaN at unmeasured points.
"""

from __future__ import annotations

import os
import zipfile

import numpy as np

from ..errors import InputError
from ..heightmap import HeightMap, Profile
from ._common import (
    NO_SPACING,
    check_compression_ratio,
    check_declared_size,
    check_file,
    make_heightmap,
    make_profile,
    resolve_spacing,
    unit_factor,
)
from ._registry import register_reader, register_writer
from .calibration import pick_spacing

__all__ = ["read_npy", "read_npz", "write_npy", "write_npz"]


def _load(path, **kw):
    try:
        return np.load(path, allow_pickle=False, **kw)
    except (ValueError, OSError, EOFError, zipfile.BadZipFile) as exc:
        raise InputError(path, f"not a readable NumPy file ({exc.__class__.__name__}: {exc})") from None


def _read_header(fh, path, member=None):
    """(shape, dtype) of a ``.npy`` stream from its header only (nothing allocated)."""
    where = f" (member {member})" if member else ""
    try:
        version = np.lib.format.read_magic(fh)
        if version == (1, 0):
            shape, _, dtype = np.lib.format.read_array_header_1_0(fh)
        elif version in ((2, 0), (3, 0)):
            # format 3.0 differs from 2.0 only by a UTF-8 (not Latin-1) header, which matters
            # for structured field names alone (refused below as not heights): numpy's public
            # 2.0 header reader reads it (no private numpy function)
            shape, _, dtype = np.lib.format.read_array_header_2_0(fh)
        else:
            raise ValueError(f"unknown .npy format version {version[0]}.{version[1]}")
    except (ValueError, OSError, EOFError, SyntaxError, TypeError, UnicodeDecodeError) as exc:
        raise InputError(
            path, f"not a readable NumPy file{where} ({exc.__class__.__name__}: {exc})"
        ) from None
    return shape, dtype


def _check_header(path, shape, dtype, stored_bytes=None, member=None):
    """Refuse before allocating: complex, non-numeric, too large, or a zip bomb."""
    what = "heights" if member in (None, "heights.npy") else f"'{member[:-4]}'"  # .npz: name the member
    if dtype.names is not None or dtype.hasobject:
        raise InputError(path, f"{what} are not numbers (dtype {dtype})")
    if np.issubdtype(dtype, np.complexfloating):
        raise InputError(path, f"{what} are complex numbers: save real values")
    if not (np.issubdtype(dtype, np.number) or dtype.kind == "b"):
        raise InputError(path, f"{what} are not numbers (dtype {dtype})")
    n = check_declared_size(path, shape, max(dtype.itemsize, 8))
    if stored_bytes is not None:
        check_compression_ratio(path, n * dtype.itemsize, stored_bytes)
    else:
        size = os.path.getsize(path)
        if n * dtype.itemsize > size:
            raise InputError(
                path,
                f"header declares shape {tuple(shape)} ({n * dtype.itemsize} bytes) "
                f"but the file holds {size} bytes: truncated",
            )


@register_reader(".npy")
def read_npy(path, spacing=None, units=None):
    """Read a ``.npy`` height array; ``spacing`` [m] is required.

    Parameters
    ----------
    path : str or Path
        The ``.npy`` file.
    spacing : float or tuple
        Spacing [m] (required).
    units : str, optional
        Height unit (default m).

    Returns
    -------
    HeightMap or Profile
    """
    check_file(path)
    with open(path, "rb") as fh:
        shape, dtype = _read_header(fh, path)
    _check_header(path, shape, dtype)
    arr = _load(path)
    factor = unit_factor(units, path)
    sp = resolve_spacing(spacing, path)
    if arr.dtype.names is not None or not (np.issubdtype(arr.dtype, np.number) or arr.dtype == bool):
        raise InputError(path, f"heights are not numbers (dtype {arr.dtype})")
    if arr.ndim == 1:
        if sp is None:
            raise InputError(path, NO_SPACING)
        return make_profile(path, arr * factor, sp[0], meta={"format": "npy", "units": units or "m"})
    if arr.ndim != 2:
        raise InputError(path, f"expected a 2D height array, got shape {arr.shape}")
    if sp is None:
        raise InputError(path, NO_SPACING)
    return make_heightmap(
        path, _scaled_float64(arr, factor), sp[0], sp[1], meta={"format": "npy", "units": units or "m"}
    )


def _scaled_float64(arr, factor):
    """``arr`` (freshly loaded, owned here) as float64 heights [m] times ``factor``, in place
    where it can be: one array of the scan's size, not three."""
    h = arr.astype(np.float64, copy=False)
    if factor != 1.0:
        if h is arr and not arr.flags.writeable:
            return h * factor
        h *= factor
    return h


def _npz_spacing(path, z, key):
    """``z[key]`` (``dx`` or ``dy``) as one float [m]; anything else is one line naming it."""
    v = z[key]
    if v.size != 1 or not (np.issubdtype(v.dtype, np.number) and not np.iscomplexobj(v)):
        raise InputError(
            path,
            f"'{key}' must be one number (the spacing in metres), got {v.size} value(s) of dtype {v.dtype}",
        )
    return float(v.reshape(()))


@register_reader(".npz")
def read_npz(path, spacing=None, units=None):
    """Read a ``.npz`` with keys ``heights``, ``dx``, ``dy`` [m] and optional ``unmeasured``.

    Parameters
    ----------
    path : str or Path
        The ``.npz`` file.
    spacing : optional
        Only where the file has no ``dx``.
    units : str, optional
        Height unit (default m).

    Returns
    -------
    HeightMap or Profile
    """
    check_file(path)
    factor = unit_factor(units, path)
    sp = resolve_spacing(spacing, path)
    _check_npz_members(path)
    with _load(path) as z:
        keys = set(z.files)
        if "heights" not in keys:
            raise InputError(path, f"no 'heights' array (keys: {', '.join(sorted(keys)) or 'none'})")
        h = z["heights"]
        unmeasured = z["unmeasured"] if "unmeasured" in keys else None
        dx, dy = (_npz_spacing(path, z, k) if k in keys else None for k in ("dx", "dy"))
    if not (np.issubdtype(h.dtype, np.number) or h.dtype == bool):
        raise InputError(path, f"heights are not numbers (dtype {h.dtype})")
    if unmeasured is not None and unmeasured.shape != h.shape:
        raise InputError(path, f"'unmeasured' has shape {unmeasured.shape}, heights {h.shape}")
    meta = {"format": "npz", "units": units or "m"}
    if h.ndim == 1:
        got = pick_spacing(path, None if sp is None else sp[:1], None if dx is None else (dx,), meta)
        if got is None:
            raise InputError(path, NO_SPACING)
        return make_profile(path, h * factor, got[0], unmeasured=unmeasured, meta=meta)
    if h.ndim != 2:
        raise InputError(path, f"expected a 2D height array, got shape {h.shape}")
    if dx is not None and dy is None:
        dy = dx
    got = pick_spacing(path, sp, None if dx is None or dy is None else (dx, dy), meta)
    if got is None:
        raise InputError(path, NO_SPACING)
    dx, dy = got
    return make_heightmap(path, _scaled_float64(h, factor), dx, dy, unmeasured=unmeasured, meta=meta)


def _check_npz_members(path):
    """Check every member's header (size limit, complex, zip-bomb ratio) before loading any."""
    try:
        with zipfile.ZipFile(path) as zf:
            names = [info.filename for info in zf.infolist()]
            dup = sorted({n for n in names if names.count(n) > 1})
            if dup:  # numpy would take the last one silently
                raise InputError(
                    path,
                    f".npz archive holds several members named {dup[0]!r} "
                    f"(which one is meant is undefined): refused",
                )
            for info in zf.infolist():
                if not info.filename.endswith(".npy"):
                    continue
                with zf.open(info) as fh:
                    shape, dtype = _read_header(fh, path, info.filename)
                _check_header(path, shape, dtype, stored_bytes=info.compress_size, member=info.filename)
    except (zipfile.BadZipFile, OSError, EOFError, ValueError) as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError(path, f"not a readable NumPy .npz file ({exc.__class__.__name__}: {exc})") from None


def _float_dtype(dtype):
    dtype = np.dtype(dtype)
    if dtype not in (np.float32, np.float64):
        raise ValueError(f"heights are written as float32 or float64, not {dtype}")
    return dtype


@register_writer(".npy")
def write_npy(path, obj, dtype="float64"):
    """Heights [m] with NaN at unmeasured points (float64, or float32 on request); the spacing
    is not stored.

    Parameters
    ----------
    path : str or Path
        Output file.
    obj : HeightMap or Profile
        The scan.
    dtype : str, optional
        ``"float64"`` or ``"float32"``.

    Returns
    -------
    None
    """
    with open(path, "wb") as f:
        np.save(f, obj.heights_m.astype(_float_dtype(dtype), copy=False))


@register_writer(".npz")
def write_npz(path, obj, dtype="float64"):
    """``heights`` [m, NaN unmeasured; float64 or float32 on request], ``dx`` (and ``dy`` for a
    map) [m], ``unmeasured``; compressed.

    Parameters
    ----------
    path : str or Path
        Output file.
    obj : HeightMap or Profile
        The scan.
    dtype : str, optional
        ``"float64"`` or ``"float32"``.

    Returns
    -------
    None
    """
    arrays = {
        "heights": obj.heights_m.astype(_float_dtype(dtype), copy=False),
        "dx": np.float64(obj.dx_m),
        "unmeasured": obj.unmeasured,
    }
    if isinstance(obj, HeightMap):
        arrays["dy"] = np.float64(obj.dy_m)
    elif not isinstance(obj, Profile):
        raise TypeError(f"cannot write {type(obj).__name__}")
    with open(path, "wb") as f:
        np.savez_compressed(f, **arrays)
