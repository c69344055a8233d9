"""The ``roadscan rain-fill`` job: a scan's cavities filled with water, written to a folder.

Writes ``wet.npy`` (wet surface [m], NaN where unmeasured), ``depth.npy`` (water depth [m], 0
where dry, NaN where unmeasured), the same two maps with their spacing as ``wet.npz`` and
``depth.npz`` (``heights``, ``dx``, ``dy`` [m], ``unmeasured``: ``roadscan analyse out/wet.npz``
needs no ``--spacing``) and ``rainfill.json`` (``dx_m``, ``dy_m`` too). The scan is levelled
(least-squares plane removed) first unless ``level=False``: water settles relative to gravity,
and a scan's tilt is the instrument's, not the road's. Unmeasured points are transparent (they
neither hold nor block water; :mod:`roadscan.rain`, after the morphological reconstruction of
Soille, *Morphological Image Analysis*, 2003, sec. 6.3.7).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Literal

from pipelines.output.job_result import returns_job_result
from pipelines.settings.option_docs import document_options
from pipelines.settings.water import check_water
from roadscan.errors import InputError

__all__ = ["rain_fill", "check_water", "rain_fill_scan", "write_rain_fill"]


@returns_job_result("rain_fill")
@document_options()
def rain_fill(
    scan: Any,
    out: str | os.PathLike[str],
    *,
    spacing: float | str | tuple[float, float] | None = None,
    units: Literal["m", "mm", "um", "nm"] | None = None,
    x_units: Literal["m", "mm", "um", "nm"] | None = None,
    override_calibration: bool = False,
    channel: int | str | None = None,
    connectivity: Literal[4, 8] = 4,
    max_depth: float | None = None,
    water_film: float | None = None,
    no_level: bool = False,
) -> dict[str, Any]:
    """``roadscan rain-fill`` as one call: the scan's cavities filled with water
    (:func:`rain_fill_scan`) and the files of the module docstring written into ``out`` (all
    or none).

    ``options`` are the command's long flags with dashes as underscores, taking what the flag
    takes (``connectivity=8``, ``max_depth=5e-4`` or ``water_film=1e-4`` [m], ``no_level=True``,
    ``spacing="5e-5"``), parsed by the command's own option definitions
    (:func:`pipelines.settings.water.add_rain_fill_options`).

    Parameters
    ----------
    scan : str, os.PathLike or HeightMap
        An area height file, or a scan in memory [m].
    out : str or Path
        Output folder, as ``--out``.
    {options}

    Returns
    -------
    dict
        The ``rainfill.json`` content: ``scan`` (the file, or the scan's name),
        ``wetted_fraction``, ``water_volume_m3_per_m2`` [m], ``connectivity``, ``max_depth_m``,
        ``water_film_m``, ``capacity_m3_per_m2`` [m], ``all_depressions_full``,
        ``measured_fraction``, ``levelled``, ``dx_m``, ``dy_m`` [m], ``unmeasured_points``,
        ``files``, how the file was read and ``warnings`` (when any).

    Raises
    ------
    TypeError
        An unknown keyword.
    roadscan.errors.InputError
        A value the flag refuses, or a scan the job cannot use (one line).
    """
    from pipelines.checks.validate import collecting
    from pipelines.settings.keywords import options_of
    from pipelines.settings.scan_input import scan_of, source_path
    from pipelines.settings.water import check_water_options
    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    args = options_of(rain_fill, locals())
    path = source_path(scan)
    inputs = [path] if path is not None else []
    with collecting():
        check_water_options(args)
        check_output_dir(out, inputs=inputs)
        obj = scan_of(scan, args)
        filled, r = rain_fill_scan(
            obj,
            connectivity=args.connectivity,
            max_depth_m=args.max_depth,
            water_film_m=args.water_film,
            level=not args.no_level,
            path=path,
        )
        with atomic_output_dir(Path(out), inputs=inputs) as tmp:
            return write_rain_fill(
                tmp, filled, r, path if path is not None else obj.name, levelled=not args.no_level
            )


def rain_fill_scan(scan, connectivity=4, max_depth_m=None, water_film_m=None, level=True, path=None):
    """(scan as filled, :class:`roadscan.rain.RainFill`) of an area scan.

    Parameters
    ----------
    scan : HeightMap
        The heights [m] (a line profile is refused: water needs an area).
    connectivity : {4, 8}
        Neighbourhood of the fill.
    max_depth_m, water_film_m : float or None
        A depth cap above each depression's lowest point [m], or the water available per area
        [m^3/m^2 = m] (at most one).
    level : bool
        Remove the least-squares plane first.
    path : str or None
        The scan's file, for messages.

    Returns
    -------
    scan : HeightMap
        The scan as filled (levelled when asked).
    fill : roadscan.rain.RainFill
        The rain fill.
    """
    from roadscan.heightmap import HeightMap
    from roadscan.rain import rain_fill

    check_water(max_depth_m, water_film_m)
    if not isinstance(scan, HeightMap):
        raise InputError(path, "rain-fill needs an area scan (a height map), not a line profile")
    if level:
        from roadscan import level as levelling

        scan = levelling.level(scan, degree=1)
    return scan, rain_fill(
        scan, connectivity=connectivity, max_depth_m=max_depth_m, water_film_m=water_film_m
    )


def write_rain_fill(out, scan, r, source, levelled=True):
    """Write the files of the module docstring into the folder ``out``; returns the summary
    (the content of ``rainfill.json``).

    Parameters
    ----------
    out : str or Path
        Output folder.
    scan : HeightMap
        The scan filled.
    r : roadscan.rain.RainFill
        The rain fill.
    source : str or Path
        The input file.
    levelled : bool, optional
        Whether the scan was levelled.

    Returns
    -------
    dict
        The content of ``rainfill.json``.
    """
    from pipelines.checks.validate import warnings_list
    from pipelines.settings.scan_input import read_record
    from roadscan.io import write
    from roadscan.io.atomic import atomic_save_npy, atomic_write_text

    out = Path(out)
    atomic_save_npy(out / "wet.npy", r.wet.heights_m)
    atomic_save_npy(out / "depth.npy", r.depth_m)
    # the same maps with their spacing (heights, dx, dy, unmeasured): read back by roadscan or
    # numpy without --spacing
    write(out / "wet.npz", r.wet)
    write(out / "depth.npz", r.wet.with_heights(r.depth_m, name="depth"))
    summary = {
        "scan": str(source),
        "wetted_fraction": r.wetted_fraction,
        "water_volume_m3_per_m2": r.water_volume_m3_per_m2,
        "connectivity": r.connectivity,
        "max_depth_m": r.meta["max_depth_m"],
        "water_film_m": r.meta["water_film_m"],
        "capacity_m3_per_m2": r.meta["capacity_m3_per_m2"],
        "all_depressions_full": r.meta["all_full"],
        "measured_fraction": r.meta["measured_fraction"],
        "levelled": bool(levelled),
        "dx_m": scan.dx_m,
        "dy_m": scan.dy_m,
        "unmeasured_points": r.meta["unmeasured_policy"],
        "files": {
            "wet.npy": "wet surface [m], NaN unmeasured (no spacing: dx_m, dy_m above)",
            "depth.npy": "water depth [m], 0 dry, NaN unmeasured (no spacing: dx_m, dy_m above)",
            "wet.npz": "wet surface with its spacing: heights [m], dx, dy [m], unmeasured",
            "depth.npz": "water depth with its spacing: heights [m], dx, dy [m], unmeasured",
        },
    }
    summary.update(read_record(scan))  # how the file was read
    if warnings_list():
        summary["warnings"] = warnings_list()
    atomic_write_text(out / "rainfill.json", json.dumps(summary, indent=2) + "\n")
    return summary
