"""Command-line input options shared by every command that reads a scan."""

from __future__ import annotations

from pathlib import Path

from roadscan.errors import InputError

__all__ = ["add_scan_options", "load_scan", "read_options", "read_record", "source_path", "scan_of"]

#: what summary.json records of how a file was read
READ_KEYS = ("calibration_override", "calibration_ignored", "channel", "channels")

_UNITS = ("m", "mm", "um", "nm")


def add_inputs_and_out(parser, inputs_help, out_help):
    """The positional ``INPUT...`` and the required ``--out DIR`` of a many-input command."""
    parser.add_argument("inputs", nargs="+", metavar="INPUT", help=inputs_help)
    parser.add_argument("--out", required=True, metavar="DIR", help=out_help)


def add_scan_options(parser):
    """Add ``--spacing DX[,DY]`` [m] and ``--units {m,mm,um,nm}`` to an argparse parser.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser.

    Returns
    -------
    None
    """
    parser.add_argument(
        "--spacing",
        metavar="DX[,DY]",
        default=None,
        help="grid spacing in metres for formats that do not carry it (e.g. 5.54e-5 or 5e-5,6e-5)",
    )
    parser.add_argument(
        "--units",
        choices=_UNITS,
        default=None,
        help="units of the heights in files that carry no units, and of the x (and y) columns of "
        "text files without unit titles (default m)",
    )
    parser.add_argument(
        "--x-units",
        choices=_UNITS,
        default=None,
        help="units of the x (and y) columns of an x,z or x,y,z text file without unit titles, "
        "when they differ from --units (e.g. x in m, heights in mm)",
    )
    parser.add_argument(
        "--override-calibration",
        action="store_true",
        help="let --spacing/--units replace the spacing/units a file carries (X3P, vendor, .npz "
        "with dx/dy...; refused otherwise); recorded as calibration_override in summary.json",
    )
    parser.add_argument(
        "--channel",
        metavar="N|NAME",
        default=None,
        help="page of a multi-page TIFF, colour channel of an RGB/stack TIFF, or channel of an "
        "instrument file with several (index from 0 or name); recorded in summary.json",
    )


def read_options(args=None, spacing=None, units=None, calibration=None, channel=None):
    """Keyword arguments of :func:`roadscan.io.read` from the parsed ``add_scan_options`` flags
    (explicit arguments win): ``spacing``, ``units``, ``calibration`` ("override" with
    ``--override-calibration``, else "strict") and ``channel``.

    Parameters
    ----------
    args : argparse.Namespace, optional
        Parsed flags.
    spacing, units, calibration, channel : optional
        Explicit values.

    Returns
    -------
    dict
    """
    if args is not None:
        spacing = getattr(args, "spacing", None) if spacing is None else spacing
        units = getattr(args, "units", None) if units is None else units
        channel = getattr(args, "channel", None) if channel is None else channel
        if calibration is None and getattr(args, "override_calibration", False):
            calibration = "override"
    opts = {"spacing": spacing, "units": units, "calibration": calibration or "strict", "channel": channel}
    x_units = getattr(args, "x_units", None) if args is not None else None
    if x_units is not None:  # text coordinates' own unit (roadscan.io.read x_units)
        opts["x_units"] = x_units
    return opts


def load_scan(path, args=None, spacing=None, units=None, calibration=None, channel=None):
    """Read a height file (HeightMap or Profile) with the options of ``add_scan_options``.

    Any reader failure becomes an :class:`InputError` naming the file; the scan then passes the
    plausibility checks of :func:`pipelines.checks.validate.check_scan` (spacing, grid size, measured
    points, constant grids, spikes) and :func:`roadscan.plausibility.check_plausible` (heights
    against the scan's own size: a units slip is refused with the flag that fixes it). The
    reader's warnings (``meta["read_warnings"]``) and steps far above the texture
    (:func:`roadscan.seams.find_steps`: stitching faults, plate edges) go to stderr and
    ``summary.json``.

    Parameters
    ----------
    path : str or Path
        Height file.
    args : argparse.Namespace, optional
        Parsed flags.
    spacing, units, calibration, channel : optional
        Explicit values.

    Returns
    -------
    HeightMap or Profile
    """
    from roadscan.io import read

    path = Path(path)
    opts = read_options(args, spacing, units, calibration, channel)
    spacing, units = opts["spacing"], opts["units"]
    if not path.exists():
        raise InputError(path, "no such file")
    if path.is_dir():
        raise InputError(path, "is a directory, expected a height file")
    from pipelines.checks.overwrite import check_kind

    check_kind(path)  # /dev/zero, a FIFO: refused, not read forever
    if spacing is not None:
        from pipelines.checks.validate import check_spacing_option

        check_spacing_option(spacing, warn_unusual=False)  # check_scan warns, naming the file
    try:
        obj = read(path, **opts)
    except InputError:
        raise
    except MemoryError:
        raise InputError(
            path,
            "too large for the available memory (lower --max-pixels to refuse such files before reading)",
        ) from None
    except OSError as exc:  # (roadscan.io.read turns what a broken file raises into InputError)
        raise InputError(path, f"cannot read height data ({type(exc).__name__}: {exc})") from None
    from pipelines.jobs.texture.prefetch import prepare_lattice_ahead

    prepare_lattice_ahead(obj)  # the spectrum's lattice, on the core idle during the checks
    from pipelines.checks.validate import check_scan, warn
    from pipelines.cli.hints import flag_text
    from roadscan.plausibility import check_plausible

    try:
        obj = check_scan(obj, path)
    except InputError as exc:
        if "units?" in str(exc):  # the absolute bound: name the flag that fixes it
            check_plausible(obj, path, units)
        raise
    check_plausible(obj, path, units)  # a units slip refused before any figure
    from roadscan.seams import find_steps

    for line in [*obj.meta.get("read_warnings", ()), *find_steps(obj)]:
        warn(f"{path}: {flag_text(line)}")  # on stderr and in summary.json
    return obj


def read_record(obj):
    """The keys of :data:`READ_KEYS` found in ``obj.meta``: for summary.json (how the file was
    read: a flag that overrode or was set aside for its calibration, the channel used).

    Parameters
    ----------
    obj : HeightMap or Profile
        A read scan.

    Returns
    -------
    dict
    """
    from pipelines.cli.hints import flag_text

    meta = getattr(obj, "meta", None) or {}
    return {k: flag_text(meta[k]) if isinstance(meta[k], str) else meta[k] for k in READ_KEYS if k in meta}


def source_path(source):
    """The path of a scan given as a file (str or os.PathLike), None for a scan in memory.

    Parameters
    ----------
    source : str, os.PathLike, HeightMap or Profile

    Returns
    -------
    str or None
    """
    import os

    return os.fspath(source) if isinstance(source, (str, os.PathLike)) else None


def scan_of(source, args):
    """The scan of an API call's source: a file read as the command reads it
    (:func:`load_scan` with the parsed flags ``args``), or a scan in memory checked as a read
    one is (:func:`pipelines.checks.validate.check_scan`).

    Parameters
    ----------
    source : str, os.PathLike, HeightMap or Profile
    args : argparse.Namespace
        The parsed flags (how a file is read).

    Returns
    -------
    HeightMap or Profile
    """
    from pipelines.checks.validate import check_scan

    path = source_path(source)
    return load_scan(path, args) if path is not None else check_scan(source)
