"""Instrument vendors' height files through SurfaceTopography (MIT, contact.engineering):
which reader opens which file.

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

The channel is converted by :mod:`roadscan.io.vendor_channel` (orientation, units, mask, size
and value checks) and its metadata by :mod:`roadscan.io.vendor_meta`. A ``spacing`` or ``units``
that contradicts the file's follows :mod:`roadscan.io.calibration` (refused unless
overridden, recorded either way).

Reference: L. Pastewka et al., SurfaceTopography, https://github.com/ContactEngineering/
SurfaceTopography (MIT); the file formats are documented in its ``SurfaceTopography/IO``.
"""

from __future__ import annotations

import warnings
from pathlib import Path

from ..errors import InputError
from ._common import check_file, resolve_spacing
from ._registry import register_reader
from .vendor_channel import MAX_ABS_M, MIN_NONZERO_M, read_channel
from .vendor_meta import LENGTH_UNITS, instrument_block, one_line

__all__ = [
    "read_vendor",
    "VENDOR_EXTENSIONS",
    "OWN_EXTENSIONS",
    "vendor_available",
    "vendor_version",
    "instrument_block",
    "LENGTH_UNITS",
    "MIN_VERSION",
    "MAX_ABS_M",
    "MIN_NONZERO_M",
]

#: oldest SurfaceTopography whose readers are tested here (the shared real files)
MIN_VERSION = (1, 27)

#: extensions SurfaceTopography 1.27 reads that roadscan routes to it, with its reader's format
#: id (for the documentation; at read time the installed registry decides). A test checks this
#: table against the installed package.
VENDOR_FORMATS = {
    ".sdf": "sdf",
    ".hfm": "xyz",
    ".spm": "di",
    ".001": "di",
    ".002": "di",
    ".003": "di",
    ".004": "di",
    ".005": "di",
    ".mat": "mat",
    ".mdt": "mdt",
    ".opd": "opd",
    ".opdx": "opdx",
    ".ibw": "ibw",
    ".mi": "mi",
    ".xlsx": "mitutoyo",
    ".nc": "nc",
    ".datx": "datx",
    ".h5": "h5",
    ".sur": "sur",
    ".tmd": "tmd",
    ".vk3": "vk",
    ".vk4": "vk",
    ".vk6": "vk",
    ".vk7": "vk",
    ".zmg": "zmg",
    ".zon": "zon",
    ".os3d": "os3d",
    ".al3d": "al3d",
    ".ezd": "ezd",
    ".nid": "ezd",
    ".bcr": "bcr",
    ".bcrf": "bcr",
    ".plu": "plu",
    ".apx": "plu",
    ".frt": "frt",
    ".lext": "lext",
    ".oir": "oir",
    ".poir": "poir",
    ".cur": "wsxm",
    ".stp": "wsxm",
    ".tom": "wsxm",
    ".top": "wsxm",
    ".plux": "plux",
    ".jpk": "jpk",
    ".mnt": "mnt",
    ".qep": "qep",
    ".zip": "nmm",
    ".nms": "nms",
    ".hgt": "hgt",
}
VENDOR_EXTENSIONS = tuple(VENDOR_FORMATS)
#: extensions SurfaceTopography also reads but roadscan reads itself (``.dat``: CAPTIF first,
#: then SurfaceTopography; ``.tif``: Park Systems TIFFs go to SurfaceTopography)
OWN_EXTENSIONS = (".x3p", ".gwy", ".npy", ".npz", ".tif", ".tiff", ".txt", ".asc", ".csv", ".xyz", ".dat")


def vendor_version():
    """Installed SurfaceTopography version string, or None (without importing it).

    Parameters
    ----------
    None

    Returns
    -------
    str or None
    """
    from importlib import metadata  # 30 ms of every read: only when a report asks for it

    try:
        return metadata.version("SurfaceTopography")
    except metadata.PackageNotFoundError:
        return None


def vendor_available():
    """True if SurfaceTopography can be imported.

    Parameters
    ----------
    None

    Returns
    -------
    bool
    """
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
        raise InputError(
            path,
            f"reading {ext} files needs the optional extra: "
            "pip install 'roadscan[vendor]' (SurfaceTopography)",
        ) from None
    version = vendor_version() or getattr(__import__("SurfaceTopography"), "__version__", "0")
    if _version_tuple(version) < MIN_VERSION:
        raise InputError(
            path,
            f"SurfaceTopography {version} is too old (need >= "
            f"{'.'.join(map(str, MIN_VERSION))}): pip install -U 'roadscan[vendor]'",
        )
    return stio, version


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
            errors.append(f"{cls.name()}: {one_line(exc)}")
    raise InputError(path, "cannot read (" + "; ".join(errors) + ")")


@register_reader(*VENDOR_EXTENSIONS)
def read_vendor(path, spacing=None, units=None, formats=None, channel=None):
    """Read an instrument's height file with SurfaceTopography (see the module notes).

    Parameters
    ----------
    path : str or Path
    spacing : None, float, (float, float) or str
        Grid spacing [m]; required when the file states no size (else see calibration).
    units : {"m", "mm", "um", "nm"}, optional
        Height unit of a file that states none (else see calibration).
    formats : sequence of str, optional
        SurfaceTopography format ids to try (default: the readers listing the extension).
    channel : int or str, optional
        Channel index (from 0) or name; default the reader's default height channel.

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
        return read_channel(reader, path, version, sp, units, channel)
    finally:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # e.g. scipy's netcdf mmap note on close
                reader.close()
        except Exception:  # noqa: BLE001
            pass
