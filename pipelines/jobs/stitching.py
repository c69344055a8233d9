"""The ``roadscan stitch`` job: overlapping tiles into one height map, written with the
residual mismatch of every overlap (``<stem>_overlaps.csv``).

Positions come from a manifest CSV (``file,x_m,y_m``: tile file relative to the manifest,
nominal position [m] of its first sample; :func:`roadscan.stitch.read_manifest`) or from a
``rows x cols`` grid with a nominal overlap fraction (:func:`roadscan.stitch.grid_positions`);
:func:`roadscan.stitch.stitch` registers each overlap by cross-correlation and blends them.
"""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path

from pipelines.settings.scan_input import load_scan
from roadscan.errors import InputError

__all__ = ["stitch_files", "overlaps_csv"]


def _load_tile(path, args):
    from roadscan.heightmap import HeightMap

    t = load_scan(path, args)
    if not isinstance(t, HeightMap):
        raise InputError(path, "a tile must be an area scan (height map), not a line profile")
    meta = dict(t.meta)
    meta["path"] = str(path)
    return t.with_heights(t.heights_m, name=t.name or Path(path).stem, meta=meta)


def _tiles_and_positions(args):
    """(tiles, nominal positions [m]) from ``args.inputs`` with ``args.grid``/``args.overlap``."""
    from roadscan.stitch import grid_positions, read_manifest

    if args.grid is None:
        if args.overlap is not None:
            raise InputError(None, "--overlap needs --grid ROWSxCOLS")
        if len(args.inputs) != 1:
            raise InputError(None, "give one manifest CSV, or tile files with --grid ROWSxCOLS --overlap F")
        entries = read_manifest(args.inputs[0])
        tiles = [_load_tile(f, args) for f, _, _ in entries]
        return tiles, [(x, y) for _, x, y in entries]
    m = re.fullmatch(r"\s*(\d+)\s*[xX]\s*(\d+)\s*", args.grid)
    if not m or int(m.group(1)) < 1 or int(m.group(2)) < 1:
        raise InputError(None, f"--grid {args.grid!r}: expected ROWSxCOLS, e.g. 2x3")
    rows, cols = int(m.group(1)), int(m.group(2))
    if args.overlap is None or not 0 <= args.overlap < 1:
        raise InputError(None, "--grid needs --overlap FRACTION with 0 <= FRACTION < 1")
    if len(args.inputs) != rows * cols:
        raise InputError(None, f"--grid {rows}x{cols} needs {rows * cols} tiles, got {len(args.inputs)}")
    tiles = [_load_tile(f, args) for f in args.inputs]
    shape = tiles[0].shape
    for t, f in zip(tiles, args.inputs):
        if t.shape != shape:
            raise InputError(
                f, f"tile shape {t.shape} differs from the first tile's {shape} (--grid needs equal tiles)"
            )
    return tiles, grid_positions(rows, cols, shape, tiles[0].dx_m, tiles[0].dy_m, args.overlap)


def _refuse_overwrite(args, out):
    """The map and its overlaps table never replace a tile or the manifest."""
    from roadscan.io.overwrite_guard import refuse_overwrite
    from roadscan.stitch import read_manifest

    inputs = list(args.inputs)
    if args.grid is None and len(args.inputs) == 1:
        inputs += [f for f, _, _ in read_manifest(args.inputs[0])]
    refuse_overwrite([out, out.with_name(out.stem + "_overlaps.csv")], inputs)


def overlaps_csv(result):
    """The overlaps table of a stitch as CSV text: one row per registered pair, its offset and
    residual mismatch.

    Parameters
    ----------
    result : object
        The :mod:`roadscan.stitch` result.

    Returns
    -------
    str
    """
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    names = result.meta["tile_names"]
    w.writerow(
        ["tile_i", "tile_j", "n_points", "rms_mismatch_m", "shift_row_px", "shift_col_px", "registered"]
    )
    for o in result.overlaps:
        w.writerow(
            [
                names[o["i"]],
                names[o["j"]],
                o["n_points"],
                f"{o['rms_mismatch_m']:.6g}",
                f"{o['shift_px'][0]:.3f}",
                f"{o['shift_px'][1]:.3f}",
                o["registered"],
            ]
        )
    return buf.getvalue()


def stitch_files(args, out):
    """Stitch the tiles ``args`` names (``inputs``, ``grid`` as (rows, cols) or None,
    ``overlap``, ``max_shift``, ``blend`` and the scan options) into the height file ``out``
    (format by extension) and its overlaps table, both or neither; returns the
    :class:`roadscan.stitch` result (``heightmap``, ``overlaps``, ``meta``).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags of ``roadscan stitch``.
    out : str or Path
        Output height file.

    Returns
    -------
    object
        The :mod:`roadscan.stitch` result.
    """
    from roadscan.io import write
    from roadscan.io.atomic import atomic_file_set, atomic_write_text
    from roadscan.stitch import stitch

    out = Path(out)
    if args.max_shift < 0:
        raise InputError(None, f"--max-shift {args.max_shift}: must be 0 or more samples")
    _refuse_overwrite(args, out)
    tiles, positions = _tiles_and_positions(args)
    if len(tiles) < 2:
        raise InputError(args.inputs[0], "need at least two tiles to stitch")
    res = stitch(tiles, positions, max_shift_px=args.max_shift, blend=args.blend)
    with atomic_file_set(out) as d:  # the map and its overlaps table: both or neither
        write(d / out.name, res.heightmap)
        atomic_write_text(d / (out.stem + "_overlaps.csv"), overlaps_csv(res))
    return res
