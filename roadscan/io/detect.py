"""Format detection by content, for files whose extension roadscan does not know.

Instrument software and users rename files (Bruker Nanoscope scans come as ``.di``, ``.000``,
or without extension; exports get ``.bin`` or ``.dat``). When the extension is not in
``READERS``, the first bytes decide:

- ``\\x93NUMPY`` -> ``.npy``; ``GWYP`` -> ``.gwy``; ``II*\\0`` / ``MM\\0*`` -> ``.tif``;
- a zip holding ``main.xml`` -> ``.x3p``, one holding only ``.npy`` members -> ``.npz``;
- text (no NUL byte in the first 4 kB, or a UTF-16 byte-order mark): CAPTIF marker -> CAPTIF
  ``.dat``, else the text reader,
  and SurfaceTopography when the text reader finds no table (a long text header over binary
  data); a Bruker Nanoscope header (``\\*File list``) goes to SurfaceTopography directly;
- anything else: SurfaceTopography's detection by content (``SurfaceTopography.IO.
  detect_format``: each reader whose magic bytes do not rule the file out tries to open it),
  then its reader of that format (:func:`roadscan.io.vendor.read_vendor`).

The format found is recorded in ``meta["detected_by_content"]``. Nothing found: one line
naming the file and the known extensions.
"""

from __future__ import annotations

import inspect
import warnings
import zipfile
from pathlib import Path

from ..errors import InputError

__all__ = ["sniff_extension", "read_by_content"]

_CAPTIF_MARK = b"*****DATA*****"


def sniff_extension(path):
    """The roadscan extension whose reader fits the content of ``path``, ``"vendor"`` for a
    binary file left to SurfaceTopography, or None for an empty file.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    str or None
        An extension such as ``".npy"``, ``"vendor"``, or None.
    """
    with open(path, "rb") as f:
        head = f.read(4096)
    if not head:
        return None
    if head.startswith(b"\x93NUMPY"):
        return ".npy"
    if head.startswith(b"GWYP"):
        return ".gwy"
    if head[:4] in (b"II*\x00", b"MM\x00*"):
        return ".tif"
    if head.startswith(b"PK\x03\x04"):
        try:
            with zipfile.ZipFile(path) as zf:
                names = zf.namelist()
        except (zipfile.BadZipFile, OSError, ValueError):
            return "vendor"
        if "main.xml" in names:
            return ".x3p"
        if names and all(n.endswith(".npy") for n in names):
            return ".npz"
        return "vendor"
    if head[:2] in (b"\xff\xfe", b"\xfe\xff"):  # UTF-16 text (a spreadsheet's "Unicode text")
        return ".txt"
    if head.lstrip().startswith(b"\\*"):  # Bruker Nanoscope: "\*File list" header
        return "vendor"
    if b"\x00" not in head:
        with open(path, "rb") as f:
            if _CAPTIF_MARK in f.read(1 << 16):
                return ".dat"
        return ".txt"
    return "vendor"


def read_by_content(path, readers, spacing=None, units=None, channel=None):
    """Read ``path`` (an unknown extension) with the reader its content calls for.

    Parameters
    ----------
    path : str or Path
        The file.
    readers : dict
        Extension -> reader.
    spacing, units, channel : optional
        As :func:`roadscan.io.read` takes them.

    Returns
    -------
    HeightMap or Profile
    """
    kind = sniff_extension(path)
    ext = Path(path).suffix.lower() or "(none)"
    if kind is None:
        raise InputError(path, "empty file")
    extra = {} if channel is None else {"channel": channel}
    if kind != "vendor":
        reader = readers[kind]
        if extra and "channel" not in inspect.signature(reader).parameters:
            raise InputError(
                path, f"{{channel}} {channel}: a {kind} file holds one height channel", "channel"
            )
        try:
            obj = reader(path, spacing=spacing, units=units, **extra)
        except InputError as exc:
            if kind == ".txt" and _has_binary_tail(path):  # a text header over binary data
                try:
                    return _read_vendor_by_content(path, ext, readers, spacing, units, extra)
                except InputError:
                    pass
            raise exc.reworded(
                path, f"unknown file extension {ext!r}, read by its content as {kind}: "
            ) from None
        obj.meta["detected_by_content"] = kind.lstrip(".")
        return obj
    return _read_vendor_by_content(path, ext, readers, spacing, units, extra)


def _has_binary_tail(path, limit=1 << 22):
    """True if a NUL byte occurs in the first ``limit`` bytes (binary data under a text
    header); a text table never holds one."""
    with open(path, "rb") as f:
        return b"\x00" in f.read(limit)


def _read_vendor_by_content(path, ext, readers, spacing, units, extra):
    """SurfaceTopography's detection by content, then its reader of the format found."""
    from .vendor import _import_io, read_vendor

    stio, _ = _import_io(path)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fmt = stio.detect_format(str(path))
    except (MemoryError, KeyboardInterrupt):
        raise
    except Exception:  # noqa: BLE001 - CannotDetectFileFormat and the readers' own errors
        known = ", ".join(sorted(readers))
        raise InputError(
            path,
            f"unknown file extension {ext!r} and its content matches no "
            f"format roadscan or SurfaceTopography reads; known: "
            f"{known}",
        ) from None
    try:
        obj = read_vendor(path, spacing=spacing, units=units, formats=(fmt,), **extra)
    except InputError as exc:
        raise exc.reworded(path, f"unknown file extension {ext!r}, read by its content as {fmt}: ") from None
    obj.meta["detected_by_content"] = fmt
    return obj
