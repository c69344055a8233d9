"""ISO 25178-72 X3P through the ``x3pio`` package (read and write).

X3P stores coordinates in metres; unmeasured points are NaN (x3pio applies the file's validity
information). Surfaces on an incremental (regular) grid become a :class:`HeightMap` (rows along
y, columns along x, as in x3pio); regular profiles a :class:`Profile`. The first layer is read;
irregular grids and point clouds are refused. ``units`` is ignored (the file is in metres).

Writing stores float64 heights by default (z_scale 1, so no quantisation; float32 on request): a write-then-read gives the same
heights, spacings and unmeasured points bit for bit.
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..heightmap import HeightMap, Profile
from ._common import (check_compression_ratio, check_declared_size, check_file, make_heightmap,
                      make_profile, resolve_spacing)
from ._registry import register_reader, register_writer

__all__ = ["read_x3p", "write_x3p"]


#: bytes per point of the X3P data types (I int16, L int32, F float32, D float64)
_X3P_BYTES = {"I": 2, "L": 4, "F": 4, "D": 8}
#: largest main.xml read to check the declared size [bytes]
_MAX_XML_BYTES = 16 * 1024**2


def _local(tag):
    return tag.rsplit("}", 1)[-1]


def precheck_x3p(path):
    """Refuse, before x3pio allocates anything, an X3P whose main.xml declares more points than
    the size limit (:func:`roadscan.io._common.check_declared_size`) or far more data than the
    archive stores (zip bomb: :func:`roadscan.io._common.check_compression_ratio`)."""
    import xml.etree.ElementTree as ET
    import zipfile

    try:
        with zipfile.ZipFile(path) as zf:
            infos = {i.filename: i for i in zf.infolist()}
            xml_info = infos.get("main.xml")
            if xml_info is None:
                raise InputError(path, "not an X3P file (no main.xml in the archive)")
            if xml_info.file_size > _MAX_XML_BYTES:
                raise InputError(path, f"main.xml declares {xml_info.file_size / 1e6:.3g} MB: refused "
                                       f"(an X3P header is a few kB)")
            root = ET.fromstring(zf.read(xml_info))
    except zipfile.BadZipFile as exc:
        raise InputError(path, f"not a readable X3P file (BadZipFile: {exc})") from None
    except ET.ParseError as exc:
        raise InputError(path, f"not a readable X3P file (main.xml: {exc})") from None
    fields = {}
    for el in root.iter():
        name = _local(el.tag)
        if name in ("SizeX", "SizeY", "SizeZ", "ListDimension", "PointDataLink") and el.text:
            fields.setdefault(name, el.text.strip())
        if name == "CZ":
            for sub in el:
                if _local(sub.tag) == "DataType" and sub.text:
                    fields["z_type"] = sub.text.strip().upper()
    try:
        if "ListDimension" in fields:
            shape = (int(fields["ListDimension"]),)
        else:
            shape = tuple(int(fields.get(k, "1")) for k in ("SizeZ", "SizeY", "SizeX"))
    except ValueError:
        raise InputError(path, "X3P main.xml: matrix dimensions are not whole numbers") from None
    itemsize = _X3P_BYTES.get(fields.get("z_type", "D"), 8)
    n = check_declared_size(path, shape, itemsize)
    link = fields.get("PointDataLink")
    if link is not None and link in infos:
        check_compression_ratio(path, n * itemsize, infos[link].compress_size)


@register_reader(".x3p")
def read_x3p(path, spacing=None, units=None):
    """Read an X3P profile or surface (first layer); the declared size is checked first
    (:func:`precheck_x3p`)."""
    import x3pio

    check_file(path)
    precheck_x3p(path)
    try:
        f = x3pio.read(str(path))
    except x3pio.X3pError as exc:
        raise InputError(path, f"not a readable X3P file ({exc.__class__.__name__}: {exc})") from None
    except Exception as exc:  # noqa: BLE001 - zip/xml errors of broken files
        raise InputError(path, f"not a readable X3P file ({exc.__class__.__name__}: {exc})") from None
    kind = type(f).__name__
    if kind == "PointCloud":
        raise InputError(path, "X3P point cloud: only regular profiles and surfaces are supported")
    if not f.is_regular_grid:
        raise InputError(path, f"X3P {kind.lower()} on an irregular grid: not supported")
    layer = f.layers[0]
    meta = {"format": "x3p", "units": "m", "layers": len(f.layers), "feature": kind}
    md = f.metadata
    if md is not None:
        inst = md.instrument
        meta["instrument"] = " ".join(s for s in (inst.manufacturer, inst.model, inst.version) if s)
        if md.date is not None:
            meta["date"] = md.date.isoformat()
        if md.comment:
            meta["comment"] = md.comment
    if units is not None:
        meta["units_ignored"] = units
    sp = resolve_spacing(spacing, path)
    z = np.array(layer.z, dtype=np.float64)
    if kind == "Profile":
        dx = f.header.x.increment if sp is None else sp[0]
        return make_profile(path, z.ravel(), dx, meta=meta)
    dx, dy = (f.header.x.increment, f.header.y.increment) if sp is None else sp
    return make_heightmap(path, z, dx, dy, meta=meta)


@register_writer(".x3p")
def write_x3p(path, obj, dtype="float64"):
    """Write a height map (surface) or profile as X3P: metres, NaN unmeasured, float64 (exact)
    or ``dtype="float32"`` (half the size)."""
    import x3pio

    dtype = np.dtype(dtype)
    z_types = {np.dtype(np.float64): x3pio.DataType.FLOAT64, np.dtype(np.float32): x3pio.DataType.FLOAT32}
    if dtype not in z_types:
        raise ValueError(f"X3P heights are written as float32 or float64, not {dtype}")
    h = obj.heights_m.astype(dtype, copy=False)
    if isinstance(obj, HeightMap):
        x3pio.write(str(path), h, x_scale=obj.dx_m, y_scale=obj.dy_m, z_type=z_types[dtype])
    elif isinstance(obj, Profile):
        x3pio.write(str(path), h, x_scale=obj.dx_m, z_type=z_types[dtype])
    else:
        raise TypeError(f"cannot write {type(obj).__name__} as X3P")
