"""Tile layouts for :func:`roadscan.stitch.stitch`: a regular grid, or a manifest file.

Conventions (as :mod:`roadscan.stitch`): a tile's nominal position is the (x, y) [m] of its
first sample (row 0, column 0); x runs along columns (dx), y along rows (dy). A ROWS x COLS
grid with overlap fraction f steps by (1 - f) n_x dx along x and (1 - f) n_y dy along y.

Reference: thesis section 4.1 (tiled profiler scans).
"""

from __future__ import annotations

import csv
import math
import os
from pathlib import Path

from .errors import InputError

__all__ = ["grid_positions", "read_manifest", "MANIFEST_HEADER"]

MANIFEST_HEADER = ["file", "x_m", "y_m"]


def grid_positions(
    n_rows: int, n_cols: int, tile_shape: tuple[int, int], dx_m: float, dy_m: float, overlap_fraction: float
) -> list[tuple[float, float]]:
    """Nominal positions of a ROWS x COLS grid of tiles, row-major (row 0 first).

    Parameters
    ----------
    n_rows, n_cols : int
    tile_shape : (ny, nx)
        Tile size in samples.
    dx_m, dy_m : float
        Spacing [m].
    overlap_fraction : float
        Nominal fraction of a tile shared with its neighbour, 0 <= f < 1. The step is
        ``(1 - f) * nx * dx`` along x and ``(1 - f) * ny * dy`` along y.

    Returns
    -------
    list of (x_m, y_m)
        Position of each tile's first sample; tile ``r * n_cols + c`` is at row r, column c.
    """
    if n_rows < 1 or n_cols < 1:
        raise ValueError(f"grid must have at least one row and column, got {n_rows}x{n_cols}")
    if not 0 <= overlap_fraction < 1:
        raise ValueError(f"overlap fraction must be in [0, 1), got {overlap_fraction!r}")
    ny, nx = tile_shape
    sx = (1.0 - overlap_fraction) * nx * dx_m
    sy = (1.0 - overlap_fraction) * ny * dy_m
    return [(c * sx, r * sy) for r in range(n_rows) for c in range(n_cols)]


def read_manifest(path: str | os.PathLike[str]) -> list[tuple[Path, float, float]]:
    """Read a tile manifest: CSV with header exactly ``file,x_m,y_m``.

    Each row names a tile file (relative to the manifest's folder, or absolute) and the
    nominal position [m] of its first sample (row 0, column 0; x along columns, y along rows).

    Returns
    -------
    list of (Path, float, float)

    Raises
    ------
    InputError
        Bad header, malformed row, non-finite position, missing tile file or empty manifest.

    Parameters
    ----------
    path : str or Path
        The manifest CSV.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InputError(path, "manifest not found") from None
    except (IsADirectoryError, UnicodeDecodeError) as exc:
        raise InputError(path, f"cannot read manifest: {exc}") from None
    rows = [r for r in csv.reader(text.splitlines()) if any(c.strip() for c in r)]
    if not rows:
        raise InputError(path, "empty manifest (expected header file,x_m,y_m)")
    header = [c.strip() for c in rows[0]]
    if header != MANIFEST_HEADER:
        raise InputError(path, f"manifest header must be exactly 'file,x_m,y_m', got {','.join(rows[0])!r}")
    out = []
    for n, row in enumerate(rows[1:], start=2):
        if len(row) != 3:
            raise InputError(path, f"line {n}: expected 3 fields (file,x_m,y_m), got {len(row)}")
        name, xs, ys = (c.strip() for c in row)
        try:
            x, y = float(xs), float(ys)
        except ValueError:
            raise InputError(path, f"line {n}: positions must be numbers, got {xs!r}, {ys!r}") from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise InputError(path, f"line {n}: positions must be finite")
        if not name:
            raise InputError(path, f"line {n}: empty file name")
        f = Path(name)
        if not f.is_absolute():
            f = path.parent / f
        if not f.is_file():
            raise InputError(path, f"line {n}: tile file {name!r} not found (relative to the manifest)")
        out.append((f, x, y))
    if not out:
        raise InputError(path, "manifest lists no tiles")
    return out
