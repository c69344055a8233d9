"""TIFF height images through :mod:`tifffile`.

Reading: one image, rows along y, columns along x, NaN where unmeasured; multi-page,
multi-sample (RGB) and palette-colour TIFFs are refused unless ``channel`` chooses a page,
sample or the palette indices (:mod:`roadscan.io.tiff_pages`). Heights are metres unless ``units`` says
otherwise (integer images are converted with the same factor). The spacing comes, in this order, from
``spacing=``; from the JSON description roadscan writes (``dx_m``, ``dy_m``, ``units``); from a
GeoTIFF ModelPixelScaleTag (assumed metres: a projected CRS); from the resolution tags when they
carry real units (centimetre, or inch with a value other than the screen/print defaults 72, 96,
150, 300 and 600 dpi, which image programs write without meaning it). Otherwise ``spacing`` is
required.

Writing: float64 (or float32 on request, ``write(path, hmap, dtype="float32")``); metres, NaN unmeasured,
resolution tags in pixels per centimetre and a JSON description with ``dx_m``, ``dy_m``.

A Park Systems TIFF (private tag 50432, its magic) keeps its heights in a private tag while the
image is a coloured preview: it is handed to SurfaceTopography's Park Systems reader
(:mod:`roadscan.io.vendor`), never read as a picture.
"""

from __future__ import annotations

import contextlib
import logging

import numpy as np

from ..errors import InputError
from ._common import (
    NO_SPACING,
    check_compression_ratio,
    check_declared_size,
    check_file,
    make_heightmap,
    resolve_spacing,
    unit_factor,
)
from ._registry import register_reader, register_writer
from .calibration import pick_spacing, pick_units
from .tiff_pages import select_page, select_sample

__all__ = ["read_tiff", "write_tiff"]

_DEFAULT_DPI = {72.0, 96.0, 150.0, 300.0, 600.0}
#: Park Systems' magic tag: the heights are in private tags, the image is a preview
_PARK_SYSTEMS_TAG = 50432


def _ratio(value):
    if isinstance(value, tuple):
        num, den = value
        return num / den if den else float("nan")
    return float(value)


def _spacing_from_tags(tif, page):
    """(dx, dy, how) in metres from the file, or None."""
    try:
        meta = tif.shaped_metadata
    except Exception:  # noqa: BLE001 - tifffile raises several kinds on odd descriptions
        meta = None
    if meta:
        m = meta[0]
        if "dx_m" in m and "dy_m" in m:
            return float(m["dx_m"]), float(m["dy_m"]), "roadscan description"
    tags = page.tags
    scale = tags.get("ModelPixelScaleTag")
    if scale is not None:
        sx, sy = float(scale.value[0]), float(scale.value[1])
        if sx > 0 and sy > 0:
            return sx, sy, "GeoTIFF ModelPixelScaleTag (assumed metres)"
    xr, yr, unit = tags.get("XResolution"), tags.get("YResolution"), tags.get("ResolutionUnit")
    if xr is None or yr is None or unit is None:
        return None
    unit = int(unit.value)
    xres, yres = _ratio(xr.value), _ratio(yr.value)
    if not (np.isfinite(xres) and np.isfinite(yres) and xres > 0 and yres > 0):
        return None
    if unit == 3:  # centimetre
        return 1e-2 / xres, 1e-2 / yres, "resolution tags (per cm)"
    if unit == 2 and not (xres in _DEFAULT_DPI and yres in _DEFAULT_DPI):
        return 0.0254 / xres, 0.0254 / yres, "resolution tags (per inch)"
    return None


def _check_page_size(path, page):
    """Refuse before decoding: more points than the limit, or a compressed strip/tile set that
    claims far more data than the file holds (a TIFF zip bomb)."""
    itemsize = np.dtype(page.dtype).itemsize if page.dtype is not None else 8
    n = check_declared_size(path, tuple(page.shape), itemsize)
    stored = sum(int(c) for c in (page.databytecounts or ()))
    check_compression_ratio(path, n * itemsize, stored)


@contextlib.contextmanager
def _tifffile_notes(notes):
    """Collect tifffile's log warnings ('incorrect StripByteCounts count', 'invalid offset to
    first page') into ``notes`` instead of stray stderr lines: a refusal states the problem in
    one line, a file read despite them has them in its warnings (summary.json)."""

    log = logging.getLogger("tifffile")

    class _Keep(logging.Handler):
        def emit(self, record):
            notes.append(record.getMessage().splitlines()[0] if record.getMessage() else "")

    keep, propagate = _Keep(logging.WARNING), log.propagate
    log.addHandler(keep)
    log.propagate = False
    try:
        yield
    finally:
        log.removeHandler(keep)
        log.propagate = propagate


@register_reader(".tif", ".tiff")
def read_tiff(path, spacing=None, units=None, channel=None):
    """Read a TIFF height image (see the module notes for the spacing rules; ``channel``
    chooses a page, sample or palette indices: :mod:`roadscan.io.tiff_pages`).

    Parameters
    ----------
    path : str or Path
        The TIFF file.
    spacing, units : optional
        For files that carry none.
    channel : int or str, optional
        Page, sample or palette choice.

    Returns
    -------
    HeightMap
    """
    import tifffile

    check_file(path)
    factor = unit_factor(units, path)
    sp = resolve_spacing(spacing, path)
    notes = []
    try:
        with _tifffile_notes(notes), tifffile.TiffFile(path) as tif:
            page = tif.pages.first
            park = _PARK_SYSTEMS_TAG in page.tags
            meta = {"format": "tiff"}
            if not park:
                page, rest = select_page(path, tif, channel, meta)
                _check_page_size(path, page)
                arr = select_sample(path, page, page.asarray(), rest, meta)
                from_file = _spacing_from_tags(tif, page)
                desc_units = None
                try:
                    m = tif.shaped_metadata
                    if m and "units" in m[0]:
                        desc_units = str(m[0]["units"])
                except Exception:  # noqa: BLE001
                    pass
    except InputError:
        raise
    except Exception as exc:  # noqa: BLE001 - tifffile raises many types for broken files
        why = notes[0] if notes else f"{exc.__class__.__name__}: {exc}"  # tifffile's own words
        raise InputError(path, f"not a readable TIFF ({why})") from None
    if park:
        from .vendor import read_vendor

        return read_vendor(path, spacing=spacing, units=units, formats=("ps",), channel=channel)
    arr = np.squeeze(arr)
    if arr.ndim != 2:
        raise InputError(path, f"expected one 2D height image, got shape {arr.shape}")
    if not np.issubdtype(arr.dtype, np.number) or np.iscomplexobj(arr):
        raise InputError(path, f"heights are not real numbers (dtype {arr.dtype})")
    meta["dtype"] = str(arr.dtype)
    if notes:  # tifffile's complaints about a damaged file
        meta.setdefault("read_warnings", []).extend(f"TIFF reader: {n}" for n in notes)
    if desc_units is not None:
        factor = pick_units(path, units, desc_units, unit_factor(desc_units, path), meta)
        meta["units"] = desc_units
    else:
        meta["units"] = units or "m"
    sp = pick_spacing(path, sp, None if from_file is None else tuple(from_file[:2]), meta)
    if sp is None:
        raise InputError(path, NO_SPACING)
    if from_file is not None:
        meta["spacing_from"] = from_file[2]
    return make_heightmap(path, arr.astype(np.float64) * factor, sp[0], sp[1], meta=meta)


@register_writer(".tif", ".tiff")
def write_tiff(path, hmap, dtype="float64"):
    """Write heights [m] as float64 (or ``dtype="float32"``, half the size) with spacing tags.

    Parameters
    ----------
    path : str or Path
        Output file.
    hmap : HeightMap
        The map.
    dtype : str, optional
        ``"float64"`` or ``"float32"``.

    Returns
    -------
    None
    """
    import tifffile

    if getattr(hmap, "dy_m", None) is None:
        raise TypeError("TIFF stores height maps, not profiles")
    dtype = np.dtype(dtype)
    if dtype not in (np.float32, np.float64):
        raise ValueError(f"TIFF heights are float32 or float64, not {dtype}")
    data = hmap.heights_m.astype(dtype, copy=False)
    tifffile.imwrite(
        path,
        data,
        resolution=(1e-2 / hmap.dx_m, 1e-2 / hmap.dy_m),
        resolutionunit="CENTIMETER",
        metadata={"dx_m": hmap.dx_m, "dy_m": hmap.dy_m, "units": "m", "writer": "roadscan"},
    )
