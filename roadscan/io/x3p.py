"""ISO 25178-72 X3P through the ``x3pio`` package (read and write).

X3P stores coordinates in metres; unmeasured points are NaN (x3pio applies the file's validity
information). Surfaces on an incremental (regular) grid become a :class:`HeightMap` (rows along
y, columns along x, as in x3pio); regular profiles a :class:`Profile`. The first layer is read;
irregular grids and point clouds are refused. ``units`` is ignored (the file is in metres).

Writing stores float64 heights by default (z_scale 1, so no quantisation; float32 on request): a
write-then-read gives the same heights, spacings and unmeasured points bit for bit.
"""

from __future__ import annotations

import hashlib
import xml.etree.ElementTree as ET
import zipfile
from datetime import datetime, timezone

import numpy as np

from ..errors import InputError
from ..heightmap import HeightMap, Profile
from ._common import (
    check_compression_ratio,
    check_declared_size,
    check_file,
    make_heightmap,
    make_profile,
    resolve_spacing,
)
from ._registry import register_reader, register_writer
from .calibration import pick_spacing, pick_units

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

    try:
        with zipfile.ZipFile(path) as zf:
            listed = [i.filename for i in zf.infolist()]
            infos = {i.filename: i for i in zf.infolist()}
            if len(infos) != len(listed):
                from collections import Counter

                dup = sorted(n for n, c in Counter(listed).items() if c > 1)
                raise InputError(
                    path,
                    f"X3P archive holds several members named "
                    f"{', '.join(repr(d) for d in dup[:3])} (which one is meant "
                    f"is undefined): refused",
                )
            xml_info = infos.get("main.xml")
            if xml_info is None:
                raise InputError(path, "not an X3P file (no main.xml in the archive)")
            if xml_info.file_size > _MAX_XML_BYTES:
                raise InputError(
                    path,
                    f"main.xml declares {xml_info.file_size / 1e6:.3g} MB: refused "
                    f"(an X3P header is a few kB)",
                )
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


def _point_data_checksum_ok(path):
    """True if the point data file matches main.xml's ``MD5ChecksumPointData``, False if not,
    None if main.xml names no such checksum."""

    with zipfile.ZipFile(path) as zf:
        root = ET.fromstring(zf.read("main.xml"))
        fields = {
            _local(el.tag): (el.text or "").strip()
            for el in root.iter()
            if _local(el.tag) in ("PointDataLink", "MD5ChecksumPointData")
        }
        link, want = fields.get("PointDataLink"), fields.get("MD5ChecksumPointData")
        if not link or not want or link not in zf.namelist():
            return None
        digest = hashlib.md5()
        with zf.open(link) as fh:
            for chunk in iter(lambda: fh.read(1 << 20), b""):
                digest.update(chunk)
    return digest.hexdigest().lower() == want.lower()


@register_reader(".x3p")
def read_x3p(path, spacing=None, units=None):
    """Read an X3P profile or surface (first layer); the declared size is checked first
    (:func:`precheck_x3p`).

    Parameters
    ----------
    path : str or Path
        The ``.x3p`` file.
    spacing, units : optional
        Only to check against what the file carries.

    Returns
    -------
    HeightMap or Profile

    References
    ----------
    ISO 25178-72:2017, XML file format x3p.
    """
    import x3pio

    check_file(path)
    precheck_x3p(path)
    checksum_note = None
    try:
        try:
            f = x3pio.read(str(path))
        except x3pio.X3pChecksumError as exc:
            # some writers put the point data's checksum in md5checksum.hex, where the
            # standard wants main.xml's: accepted only if the point data's own checksum matches
            if "main.xml" not in str(exc) or _point_data_checksum_ok(path) is not True:
                raise
            f = x3pio.read(str(path), verify=False)
            checksum_note = (
                "md5checksum.hex does not match main.xml (a writer's fault); the "
                "point data match their MD5ChecksumPointData"
            )
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
    if checksum_note:
        meta["checksum_note"] = checksum_note
        meta.setdefault("read_warnings", []).append(checksum_note)
    md = f.metadata
    if md is not None:
        if md.date is not None:
            meta["date"] = md.date.isoformat()
        if md.comment:
            meta["comment"] = md.comment
    factor = pick_units(path, units, "m", 1.0, meta)  # X3P heights are metres
    sp = resolve_spacing(spacing, path)
    z = np.array(layer.z, dtype=np.float64)
    if factor != 1.0:
        z *= factor
    if md is not None:
        meta["instrument"] = _instrument_from_record2(md, int(np.count_nonzero(np.isnan(z))))
    if kind == "Profile":
        (dx,) = pick_spacing(path, None if sp is None else sp[:1], (f.header.x.increment,), meta)
        return make_profile(path, z.ravel(), dx, meta=meta)
    dx, dy = pick_spacing(path, sp, (f.header.x.increment, f.header.y.increment), meta)
    return make_heightmap(path, z, dx, dy, meta=meta)


def _instrument_from_record2(md, undefined_points):
    """The JSON-safe ``meta["instrument"]`` block (as :func:`roadscan.io.vendor.instrument_block`)
    from an X3P Record2: manufacturer -> vendor, model -> name, serial, version -> software,
    date -> acquired, probing system (its identification is the objective of a non-contacting
    instrument, else the probe), comment."""
    import x3pio

    inst = md.instrument
    out = {}
    for key, value in (
        ("name", inst.model),
        ("vendor", inst.manufacturer),
        ("serial", inst.serial),
        ("software", inst.version),
    ):
        text = " ".join(str(value or "").split())
        if text and text.lower() not in ("not available", "n/a", "none", "unknown"):
            out[key] = text[:200]
    if md.date is not None and _DATE_UNKNOWN not in (md.comment or ""):
        out["acquired"] = md.date.isoformat()
    ps = md.probing_system
    if ps is not None and ps.type is not None:
        out["probing"] = ps.type.value
        if ps.identification and ps.identification.strip():
            key = "objective" if ps.type == x3pio.ProbingType.NON_CONTACTING else "probe"
            out[key] = " ".join(ps.identification.split())[:200]
    if md.comment:
        out["comment"] = " ".join(md.comment.split())[:400]
    out.update(
        {
            "format": "X3P (ISO 25178-72)",
            "units": "m",
            "undefined_points": undefined_points,
            "reader": f"x3pio {getattr(x3pio, '__version__', '')}".strip(),
        }
    )
    return out


#: SurfaceTopography format ids by probing system (``meta["format"]`` of vendor files): optical
#: instruments (confocal, interferometer, focus variation, chromatic) and stylus or scanning-probe
#: ones; other formats (Digital Surf, SDF, HDF5, text...) come from either kind
_NON_CONTACTING = {
    "plu",
    "plux",
    "opd",
    "al3d",
    "datx",
    "metropro",
    "vk",
    "zon",
    "lext",
    "oir",
    "poir",
    "nms",
    "frt",
    "zmg",
}
_CONTACTING = {"di", "ibw", "mi", "ezd", "jpk", "wsxm", "mdt", "bcr", "ps", "opdx", "mitutoyo", "qep"}


#: said in the comment of a record whose date is the conversion's, not the acquisition's
_DATE_UNKNOWN = "acquisition date unknown: the record's date is the conversion's"


def _date(text):

    if text:
        try:
            return datetime.fromisoformat(str(text)), True
        except ValueError:
            pass
    return datetime.now(timezone.utc), False


def x3p_metadata(meta, comment=None):
    """X3P Record2 (:class:`x3pio.Metadata`) from a scan's ``meta``, or None (x3pio's default
    record of software-made data) when ``meta`` has no ``instrument`` block and no ``comment``
    is given.

    The block's vendor, name, serial and software become the instrument's manufacturer, model,
    serial and version; ``acquired`` the record's date (the current time, said in the comment,
    when the file recorded none); the objective or probe the probing system's identification,
    its kind from the source format (optical formats non-contacting, stylus and scanning-probe
    formats contacting; other formats ``Software`` with "unknown" in the identification).
    """
    import x3pio

    inst = meta.get("instrument") if isinstance(meta, dict) else None
    if not isinstance(inst, dict):
        if comment is None:
            return None
        from .. import __version__

        md = x3pio.Metadata.for_software("roadscan", __version__)
        md.comment = comment
        return md
    when, known = _date(inst.get("acquired"))
    fmt = str(meta.get("format", ""))
    ident = inst.get("objective") or inst.get("probe") or ""
    kinds = {k.value: k for k in x3pio.ProbingType}
    if inst.get("probing") in kinds:
        kind = kinds[inst["probing"]]
    elif fmt in _NON_CONTACTING:
        kind = x3pio.ProbingType.NON_CONTACTING
    elif fmt in _CONTACTING:
        kind = x3pio.ProbingType.CONTACTING
    else:
        kind = x3pio.ProbingType.SOFTWARE
        ident = (
            f"unknown probing system{': ' + ident if ident else ''} "
            f"(from {inst.get('format', fmt) or 'a file'})"
        )
    notes = [c for c in (inst.get("comment"), comment) if c]
    if not known:
        notes.append(_DATE_UNKNOWN)
    return x3pio.Metadata(
        date=when,
        instrument=x3pio.Instrument(
            manufacturer=str(inst.get("vendor", "")),
            model=str(inst.get("name", "")),
            serial=str(inst.get("serial", "")),
            version=str(inst.get("software", "")),
        ),
        probing_system=x3pio.ProbingSystem(kind, str(ident)),
        comment="; ".join(notes) or None,
    )


@register_writer(".x3p")
def write_x3p(path, obj, dtype="float64", comment=None):
    """Write a height map (surface) or profile as X3P: metres, NaN unmeasured, float64 (exact)
    or ``dtype="float32"`` (half the size). Record2 comes from ``obj.meta["instrument"]`` when
    present (:func:`x3p_metadata`; instrument, acquisition date, objective, ``comment``).

    Parameters
    ----------
    path : str or Path
        Output file.
    obj : HeightMap or Profile
        The scan [m].
    dtype : str, optional
        ``"float64"`` or ``"float32"``.
    comment : str, optional
        Record2 comment.

    Returns
    -------
    None

    References
    ----------
    ISO 25178-72:2017, XML file format x3p.
    """
    import x3pio

    dtype = np.dtype(dtype)
    z_types = {np.dtype(np.float64): x3pio.DataType.FLOAT64, np.dtype(np.float32): x3pio.DataType.FLOAT32}
    if dtype not in z_types:
        raise ValueError(f"X3P heights are written as float32 or float64, not {dtype}")
    if not isinstance(obj, (HeightMap, Profile)):
        raise TypeError(f"cannot write {type(obj).__name__} as X3P")
    h = obj.heights_m.astype(dtype, copy=False)
    md = x3p_metadata(obj.meta, comment)
    extra = {} if md is None else {"metadata": md}
    if isinstance(obj, HeightMap):
        x3pio.write(str(path), h, x_scale=obj.dx_m, y_scale=obj.dy_m, z_type=z_types[dtype], **extra)
    else:
        x3pio.write(str(path), h, x_scale=obj.dx_m, z_type=z_types[dtype], **extra)
