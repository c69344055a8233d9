"""Reading and writing height files.

>>> from roadscan.io import read, write
>>> hmap = read("scan.npy", spacing=55.4e-6)          # doctest: +SKIP
>>> prof = read("station_0.dat")                       # doctest: +SKIP  (CAPTIF profile)
>>> write("scan.x3p", hmap)                            # doctest: +SKIP

The reader is chosen by the file's extension (``READERS``; one small module per format), or by
the file's content when the extension is unknown (:mod:`roadscan.io.detect`);
see ``FORMATS.md`` at the repository root for the table of formats and how each is tested.
Every problem with an input raises :class:`roadscan.errors.InputError` naming the file.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..heightmap import HeightMap, Profile
from . import ascii_text, captif, gwy, numpy_files, tiff, vendor, x3p  # noqa: F401  (registration)
from ._common import parse_spacing, parse_units, resolve_spacing
from ._registry import READERS, WRITERS, register_reader, register_writer
from .atomic import atomic_path
from .calibration import calibration_policy

__all__ = [
    "read",
    "write",
    "READERS",
    "WRITERS",
    "parse_spacing",
    "parse_units",
    "register_reader",
    "register_writer",
    "atomic_path",
]


#: exceptions that a reader's own code raises, never a file's content (the readers wrap the
#: third-party parsers they call, whose errors on broken files can be of any type)
_CODE_ERRORS = (
    TypeError,
    AttributeError,
    NameError,
    AssertionError,
    ImportError,
    RecursionError,
    NotImplementedError,
)


def read(path, spacing=None, units=None, calibration="strict", channel=None, x_units=None):
    """Read a height map or line profile, choosing the reader by the file's extension.

    Parameters
    ----------
    path : str or Path
    spacing : None, float, (float, float) or str, optional
        Grid spacing DX or (DX, DY) [m], or the CLI string ``"DX"`` / ``"DX,DY"``. Required for
        files that carry none (``.npy``, plain ASCII matrices, TIFFs without physical resolution);
        see ``calibration`` for files that carry one.
    units : {"m", "mm", "um", "nm"}, optional
        Units of the heights of a file that carries no units (default "m").
    calibration : {"strict", "override", "default"}
        What happens when ``spacing``/``units`` contradict what the file states
        (:mod:`roadscan.io.calibration`): refused (default), the flag wins and is recorded in
        ``meta["calibration_override"]``, or the file wins (``meta["calibration_ignored"]``).
    channel : int or str, optional
        Page of a multi-page TIFF, colour channel of an RGB/stack TIFF, or channel (index or
        name) of an instrument file with several; recorded in ``meta["channel"]``. Images with
        several pages or channels are refused without it.
    x_units : {"m", "mm", "um", "nm"}, optional
        Unit of the x (and y) columns of an x,z or x,y,z text file without unit titles; by
        default they are in ``units``, a reading checked by :mod:`roadscan.io.text_units`.
        Refused for other files.

    Returns
    -------
    HeightMap or Profile
        Heights [m] with NaN and ``unmeasured`` True at unmeasured points; ``meta["source"]`` is
        the path and ``meta["format"]`` the format read.

    Raises
    ------
    InputError
        Missing, empty or malformed files, unknown extensions, missing spacing, bad units.

    Examples
    --------
    >>> from roadscan.io import read
    >>> hm = read("sample_scans/asphalt.x3p")
    >>> hm.heights_m.shape, round(hm.dx_m * 1e6, 1)
    ((1088, 978), 55.4)
    """
    p = Path(path)
    ext = p.suffix.lower()
    if not p.exists():
        raise InputError(path, "no such file")
    if p.is_dir():
        raise InputError(path, "is a directory, not a height file")
    reader = READERS.get(ext)
    if units is not None:
        parse_units(units, path)
    if x_units is not None:
        parse_units(x_units, path)
    resolve_spacing(spacing, path)
    try:
        if reader is None:  # unknown extension: the content decides (roadscan/io/detect.py)
            from .detect import read_by_content

            with calibration_policy(calibration, x_units):
                return read_by_content(
                    path,
                    READERS,
                    spacing=spacing,
                    units=units,
                    channel=None if channel is None else _channel_value(channel),
                )
        extra = {} if channel is None else {"channel": _channel_option(path, reader, channel)}
        with calibration_policy(calibration, x_units):
            obj = reader(path, spacing=spacing, units=units, **extra)
        if x_units is not None and "coordinate_unit" not in obj.meta:
            raise InputError(
                path, "{x_units} applies to x,z and x,y,z text files without unit titles only", "x_units"
            )
        return obj
    except InputError:
        raise
    except (MemoryError, KeyboardInterrupt):
        raise
    except _CODE_ERRORS:  # a mistake in roadscan's code, not in the file: not bad input
        raise
    except Exception as exc:  # noqa: BLE001 - never a traceback for a bad file
        raise InputError(path, f"cannot read {ext} file ({exc.__class__.__name__}: {exc})") from None


def _channel_option(path, reader, channel):
    """``channel`` as an int when it is a number; refused for readers without channels."""

    import inspect  # only when a reader is asked for a channel: keeps `import roadscan.io` light

    if "channel" not in inspect.signature(reader).parameters:
        raise InputError(
            path,
            f"{{channel}} {channel}: a {Path(path).suffix.lower()} file holds one "
            f"height channel ({{channel}} is for TIFF pages/colours and "
            f"instrument files)",
            "channel",
        )
    return _channel_value(channel)


def _channel_value(channel):
    text = str(channel).strip()
    return int(text) if text.lstrip("-").isdigit() else text


def write(path, heightmap, **options):
    """Write a :class:`HeightMap` (or a :class:`Profile` where the format allows) atomically.

    Formats by extension: ``.x3p`` (ISO 25178-72, float64 metres, exact round trip),
    ``.npy`` (heights [m], NaN unmeasured; spacing not stored), ``.npz`` (``heights``, ``dx``,
    ``dy``, ``unmeasured``), ``.tif``/``.tiff`` (float32 or float64 metres, spacing in a JSON
    description and in resolution tags per cm). The file appears only when complete
    (:func:`roadscan.io.atomic.atomic_path`).

    ``options`` go to the format's writer: ``dtype="float32"`` (``.x3p``, ``.npy``, ``.npz``,
    ``.tif``) halves the file; the default float64 makes every round trip exact.

    Raises
    ------
    InputError
        Unknown extension (naming the path).
    TypeError
        If the object is neither a HeightMap nor a Profile, or the format cannot hold it.

    Parameters
    ----------
    path : str or Path
        Output file; its extension picks the format.
    heightmap : HeightMap or Profile
        What to write [m].
    **options
        ``dtype`` (float32 or float64) where the format allows.

    Returns
    -------
    Path
        The file written.
    """
    p = Path(path)
    ext = p.suffix.lower()
    writer = WRITERS.get(ext)
    if writer is None:
        raise InputError(
            path, f"cannot write {ext or '(no extension)'!r}; writable: {', '.join(sorted(WRITERS))}"
        )
    if not isinstance(heightmap, (HeightMap, Profile)):
        raise TypeError(f"write() takes a HeightMap or Profile, got {type(heightmap).__name__}")
    _check_float32_range(p, heightmap, options.get("dtype"))
    with atomic_path(p) as tmp:
        writer(tmp, heightmap, **options)
    return p


def _check_float32_range(path, obj, dtype):
    """Refuse float32 storage of heights beyond float32's range (|h| > 3.4e38 m would be
    stored as infinity and read back as unmeasured)."""
    import numpy as np

    if dtype is None or np.dtype(dtype) != np.float32:
        return
    h = obj.heights_m
    ok = np.isfinite(h)
    top = float(np.max(np.abs(h[ok]))) if ok.any() else 0.0
    big = float(np.finfo(np.float32).max)
    if top > big:
        raise InputError(
            path,
            f"height {top:.3g} m does not fit float32 (largest {big:.3g}); "
            f"write float64 (without {{float32}})",
            "float32",
        )
