"""Command-line input options shared by every command that reads a scan."""
from __future__ import annotations

from pathlib import Path

from roadscan.errors import InputError

__all__ = ["add_scan_options", "load_scan"]

_UNITS = ("m", "mm", "um", "nm")


def add_scan_options(parser):
    """Add ``--spacing DX[,DY]`` [m] and ``--units {m,mm,um,nm}`` to an argparse parser."""
    parser.add_argument(
        "--spacing", metavar="DX[,DY]", default=None,
        help="grid spacing in metres for formats that do not carry it (e.g. 5.54e-5 or 5e-5,6e-5)",
    )
    parser.add_argument(
        "--units", choices=_UNITS, default=None,
        help="units of the heights in files that carry no units (default m)",
    )


def load_scan(path, args=None, spacing=None, units=None):
    """Read a height file (HeightMap or Profile) with the options of ``add_scan_options``.

    Any reader failure becomes an :class:`InputError` naming the file; the scan then passes the
    plausibility checks of :func:`pipelines.validate.check_scan` (spacing, grid size, measured
    points, constant grids, spikes).
    """
    from roadscan.io import read

    path = Path(path)
    if args is not None:
        spacing = getattr(args, "spacing", None) if spacing is None else spacing
        units = getattr(args, "units", None) if units is None else units
    if not path.exists():
        raise InputError(path, "no such file")
    if path.is_dir():
        raise InputError(path, "is a directory, expected a height file")
    if spacing is not None:
        from .validate import check_spacing_option

        check_spacing_option(spacing)
    try:
        obj = read(path, spacing=spacing, units=units)
    except InputError:
        raise
    except MemoryError:
        raise InputError(path, "too large for the available memory (lower --max-pixels to refuse "
                               "such files before reading)") from None
    except (ValueError, OSError, KeyError, IndexError) as exc:
        raise InputError(path, f"cannot read height data ({type(exc).__name__}: {exc})") from None
    from .validate import check_scan

    return check_scan(obj, path)
