"""Text height files: ASCII grids, x,y,z point lists and x,z line profiles.

One reader for ``.txt``, ``.csv``, ``.asc`` and ``.xyz``; the layout is recognised from the
content (see :mod:`roadscan.io.text_table` for the table syntax):

- **ESRI ASCII grid** (header ``ncols``, ``nrows``, ``xllcorner``/``xllcenter``,
  ``yllcorner``/``yllcenter``, ``cellsize`` or ``dx``/``dy``, optional ``NODATA_value``):
  a height map; ``cellsize`` is taken as metres, the first data row is the north (largest y)
  edge, so rows are flipped to make row index increase with y. NODATA becomes unmeasured.
- **Gwyddion ASCII export** (``# Width: 5.00 mm``, ``# Height: ...``, ``# Value units: m``):
  a height map whose spacing is width / columns and height / rows, heights in the stated units.
- **1 column**: a profile of heights; ``spacing`` required.
- **2 columns x, z**: a line profile. x must be on a regular grid (missing x values become
  unmeasured points); the spacing comes from x. Units: a title line naming units in brackets
  (``distance (mm), height (mm)``) gives each column's unit; otherwise x and z are both in
  ``units`` (default m), a reading checked by :mod:`roadscan.io.text_units` (a mm profile read
  as metres is refused naming ``--units mm``), and ``spacing`` replaces the step of x with a note.
- **3 columns x, y, z** (any order of points): a point list that must fill a regular x,y grid
  (points may be missing: they become unmeasured); spacing from the coordinates; x, y, z in the
  units of a title line, else x, y and z in ``units`` (checked as for x,z profiles).
- **4 or more columns**: a matrix of heights, rows along y, columns along x; ``spacing``
  required (unless a Gwyddion or ESRI header gives it).

Decimal commas: :func:`roadscan.io.text_table.decimal_mark` (one rule, FORMATS.md).

A ``spacing=`` or ``units=`` that contradicts what the file states (header, coordinates, unit
titles) follows :mod:`roadscan.io.calibration` (refused unless overridden). Heights without
stated units are metres unless ``units`` says otherwise.
"""

from __future__ import annotations

import re

import numpy as np

from ..errors import InputError, OptionNote
from ._common import (
    NO_SPACING,
    check_declared_size,
    make_heightmap,
    make_profile,
    parse_units,
    regular_axis,
    resolve_spacing,
    unit_factor,
)
from ._registry import register_reader
from .calibration import current_x_units, pick_spacing, pick_units
from .text_columns import column_factors, index_column, mark_dropouts
from .text_table import ESRI_KEYS, read_table, read_text
from .text_titles import Titles, find_titles, read_preamble

__all__ = ["read_text_heights", "grid_from_points"]

_GWY_LINE = re.compile(r"^#\s*(width|height|value units)\s*:\s*(.+?)\s*$", re.IGNORECASE)


def _esri_header(header):
    out = {}
    for line in header:
        toks = line.split()
        if len(toks) == 2 and toks[0].lower() in ESRI_KEYS:
            out[toks[0].lower()] = toks[1]
    return out if {"ncols", "nrows"} <= out.keys() else None


def _gwy_header(header, path):
    out = {}
    for line in header:
        m = _GWY_LINE.match(line)
        if m:
            out[m.group(1).lower()] = m.group(2)
    if not out:
        return None
    res = {}
    for key in ("width", "height"):
        if key in out:
            parts = out[key].split()
            try:
                val = float(parts[0])
            except ValueError:
                raise InputError(path, f"bad Gwyddion header '{key}: {out[key]}'") from None
            res[key] = val * (parse_units(parts[1], path) if len(parts) > 1 else 1.0)
    if "value units" in out:
        res["value units"] = out["value units"]
    return res


def _decimal_comma_header(line):
    """A Gwyddion or ESRI header line of a decimal-comma file with its commas as points
    (``# Width: 5,00 mm`` -> ``# Width: 5.00 mm``); other header lines unchanged."""
    toks = line.split()
    if _GWY_LINE.match(line) or (len(toks) == 2 and toks[0].lower() in ESRI_KEYS):
        return re.sub(r"(\d),(\d)", r"\1.\2", line)
    return line


def _float(value, path, key):
    try:
        return float(value)
    except ValueError:
        raise InputError(path, f"bad header value {key} = {value!r}") from None


@register_reader(".txt", ".csv", ".asc", ".xyz")
def read_text_heights(path, spacing=None, units=None):
    """Read a text height file (grid, x,y,z list or x,z profile; see the module notes).

    Parameters
    ----------
    path : str or Path
        The text file.
    spacing : float or tuple, optional
        Spacing [m] for files that carry none.
    units : str, optional
        Height unit for files that carry none.

    Returns
    -------
    HeightMap or Profile
    """
    text = read_text(path)
    table = read_table(path, text)
    sp = resolve_spacing(spacing, path)
    factor = unit_factor(units, path)
    values, header = table.values, table.header
    meta = {"format": "text"}
    if table.decimal == ",":
        header = [_decimal_comma_header(h) for h in header]
        meta["decimal_mark"] = ","

    esri = _esri_header(header)
    if esri is not None:
        return _esri(path, values, esri, sp, factor, units, meta)
    gwy = _gwy_header(header, path)
    if gwy is not None and values.shape[1] >= 2:
        return _gwy_matrix(path, values, gwy, sp, factor, units, meta)

    ncol = values.shape[1]
    titles = find_titles(header, ncol)
    if titles is None and ncol >= 4:  # "Height (um)" above a matrix
        titles = find_titles(header, 1)
    pre = read_preamble(path, header[: len(header) - titles.n_lines] if titles else header, table.decimal)
    if pre.other:
        meta["preamble"] = pre.other
    if table.markers:
        meta["missing_markers"] = table.markers
    if (
        titles is not None
        and ncol in (3, 4)
        and len(titles.names) == ncol
        and index_column(titles.names, values[:, 0])
    ):
        meta["index_column_dropped"] = titles.names[0] or "(untitled)"
        values, ncol = values[:, 1:], ncol - 1
        titles = Titles(titles.names[1:], titles.units[1:], titles.text, titles.n_lines)
    mark_dropouts(path, values if ncol >= 4 else values[:, -1], pre.nodata, meta)
    fac = column_factors(path, titles, pre, ncol, units, current_x_units(), meta)
    if ncol == 1 or ncol >= 4:
        if fac is not None:
            factor = fac[-1]
        else:
            meta["units"] = units or "m"
        sp = pick_spacing(path, sp, _preamble_spacing(path, pre, sp, ncol >= 4), meta)
        if sp is None:
            raise InputError(path, NO_SPACING)
        if ncol == 1:
            meta["layout"] = "heights column"
            return make_profile(path, values[:, 0] * factor, sp[0], meta=meta)
        meta["layout"] = "matrix"
        return make_heightmap(path, values * factor, sp[0], sp[1], meta=meta)
    if fac is None:
        fac = _unstated_factors(path, ncol, factor, units, meta)
        meta["_titles_text"] = titles.text if titles is not None else None
    else:
        meta["_stated"] = True
    pre_dx = _preamble_spacing(path, pre, sp, ncol == 3, fac[0])
    obj = (_profile if ncol == 2 else _xyz)(path, values, fac, sp, units, meta)
    if pre_dx is not None:
        _check_step(path, pre, pre_dx, (obj.dx_m,) if ncol == 2 else (obj.dx_m, obj.dy_m))
    return obj


def _preamble_spacing(path, pre, sp, two_d, coord_factor=None):
    """The preamble's spacing [m] ((dx,) or (dx, dy)), or None; a spacing without a unit takes
    the preamble's or the coordinates' unit, else is refused unless ``spacing`` is given."""
    if pre.spacing is None:
        return None
    out = []
    for entry in (pre.spacing, pre.dy or pre.spacing) if two_d else (pre.spacing,):
        v, unit, line = entry
        if unit is None:
            side = pre.x_units or pre.units
            if side is not None:
                unit = side[0]
            elif coord_factor is not None:
                out.append(v * coord_factor)
                continue
            elif sp is not None:
                return None  # the flag decides
            else:
                raise InputError(
                    path,
                    f"preamble line {line!r} gives the spacing without a unit: "
                    f"write its unit ('{v:g} mm') or give {{spacing}}",
                    "spacing",
                )
        out.append(v * parse_units(unit, path) if unit != "cm" else v * 1e-2)
    return tuple(out)


def _check_step(path, pre, want, got):
    """Refuse a preamble spacing the coordinates contradict (relative difference > 1e-3)."""
    for w, g in zip(want, got):
        if abs(w - g) > 1e-3 * abs(w):
            raise InputError(
                path,
                f"preamble line {pre.spacing[2]!r} says {w:.6g} m, the "
                f"coordinates step {g:.6g} m: correct one",
            )


def _unstated_factors(path, ncol, factor, units, meta):
    """Factors of columns whose unit the file does not state: coordinates in ``x_units``
    (:func:`roadscan.io.read`) or, by default, with the heights in ``units`` (default m), a
    reading checked by :func:`_unstated_spacing`."""
    xu = current_x_units()
    if xu is not None:
        meta["units"] = f"coordinates {xu}, heights {units or 'm'}"
        return [unit_factor(xu, path)] * (ncol - 1) + [factor]
    meta["units"] = f"coordinates and heights {units or 'm'}"
    return [factor] * ncol


def _esri(path, values, hdr, sp, factor, units, meta):
    nrows = int(_float(hdr["nrows"], path, "nrows"))
    ncols = int(_float(hdr["ncols"], path, "ncols"))
    check_declared_size(path, (nrows, ncols), 8)
    if values.size != nrows * ncols:
        raise InputError(path, f"header says {nrows} x {ncols} values, file has {values.size}")
    h = values.reshape(nrows, ncols)[::-1].copy()  # first row is the north edge
    if "nodata_value" in hdr:
        h[h == _float(hdr["nodata_value"], path, "NODATA_value")] = np.nan
    from_file = None
    if "cellsize" in hdr:
        c = _float(hdr["cellsize"], path, "cellsize")
        from_file = (c, c)
    elif "dx" in hdr and "dy" in hdr:
        from_file = (_float(hdr["dx"], path, "dx"), _float(hdr["dy"], path, "dy"))
    sp = pick_spacing(path, sp, from_file, meta)
    if sp is None:
        raise InputError(path, NO_SPACING)
    meta.update(layout="ESRI ASCII grid (rows flipped: row 0 is the south edge)", units=units or "m")
    return make_heightmap(path, h * factor, sp[0], sp[1], meta=meta)


def _gwy_matrix(path, values, gwy, sp, factor, units, meta):
    ny, nx = values.shape
    from_file = None
    if "width" in gwy:
        dx = gwy["width"] / nx
        from_file = (dx, gwy.get("height", dx * ny) / ny)
    sp = pick_spacing(path, sp, from_file, meta)
    if sp is None:
        raise InputError(path, NO_SPACING)
    if "value units" in gwy:
        zu = gwy["value units"]
        factor = pick_units(path, units, zu, parse_units(zu, path), meta)
        meta["units"] = zu
    else:
        meta["units"] = units or "m"
    meta["layout"] = "Gwyddion ASCII export"
    return make_heightmap(path, values * factor, sp[0], sp[1], meta=meta)


def _unstated_spacing(path, sp, d_file, factors, n_nodes, z_file, units, meta, what, titles_text=None):
    """Spacing [m] of coordinates whose unit no title line states (:mod:`roadscan.io.text_units`).

    ``--spacing`` replaces the spacing inferred from the coordinates (with a note); without it
    the coordinates are read in ``units`` (default m), refused in one line when that reading is
    implausible for a profiler and another unit is plausible."""
    from .calibration import current_x_units
    from .text_units import check_coordinate_units

    inferred = tuple(d * f for d, f in zip(d_file, factors))
    xu = current_x_units()
    meta["coordinate_unit"] = xu  # stated by x_units, else judged below
    if sp is not None:
        given = tuple(sp)[: len(inferred)]
        if any(abs(g - i) > 1e-6 * i for g, i in zip(given, inferred)):
            shown = " x ".join(f"{d:.6g}" for d in d_file)
            meta.setdefault("read_warnings", []).append(
                OptionNote(
                    f"{{spacing}} {' x '.join(f'{g:.6g}' for g in given)} m replaces the spacing inferred "
                    f"from the {what} column ({shown} in the file's numbers; no title line states "
                    f"their unit)",
                    "spacing",
                )
            )
            meta["spacing_from"] = OptionNote("{spacing} (replacing the coordinates' step)", "spacing")
        return given
    if xu is None:
        unit = check_coordinate_units(
            path,
            max(d_file),
            n_nodes,
            z_file,
            units,
            what,
            notes=meta.setdefault("read_warnings", []),
            found=titles_text,
        )
        meta["coordinate_unit"] = unit
        if unit != (units or "m"):  # metre coordinates beside --units heights
            scale = unit_factor(unit, path) / unit_factor(units, path)
            inferred = tuple(i * scale for i in inferred)
            for key in ("x0_m", "y0_m"):
                if key in meta:
                    meta[key] *= scale
        if not meta["read_warnings"]:
            del meta["read_warnings"]
    return inferred


def _profile(path, values, fac, sp, units, meta):
    fx, fz = fac
    titles_text, stated = meta.pop("_titles_text", None), meta.pop("_stated", False)
    x, z = values[:, 0], values[:, 1]
    if not np.all(np.isfinite(x)):
        raise InputError(path, "x column contains NaN")
    order = np.argsort(x, kind="stable")
    x, z = x[order], z[order]
    x0, dx, idx = regular_axis(x, path, "x")
    h = np.full(idx[-1] + 1, np.nan)
    h[idx] = z
    meta.update(layout="x,z profile", x0_m=x0 * fx, missing_points=int(h.size - x.size))
    if not stated:
        (dx_m,) = _unstated_spacing(
            path, None if sp is None else sp[:1], (dx,), (fx,), h.size, h, units, meta, "x", titles_text
        )
    else:
        (dx_m,) = pick_spacing(path, None if sp is None else sp[:1], (dx * fx,), meta)
    return make_profile(path, h * fz, dx_m, meta=meta)


def _clusters(v, path, what):
    """Distinct values of a coordinate that carries rounding noise."""
    s = np.sort(v)
    gaps = np.diff(s)
    if gaps.size == 0 or gaps.max() <= 0:
        raise InputError(path, f"all {what} coordinates are equal: not a grid")
    cut = np.flatnonzero(gaps > 0.1 * gaps.max())
    groups = np.split(s, cut + 1)
    centres = np.array([g.mean() for g in groups])
    return centres


def grid_from_points(path, x, y, z):
    """Place x,y,z points on the regular grid they sample.

    Returns ``(heights (ny, nx) with NaN at missing nodes, x0, dx, y0, dy)`` in the units of
    the input. Raises :class:`InputError` when the points are not on a regular grid, when two
    points share a node, or when fewer than half of the nodes are present.

    Parameters
    ----------
    path : str or Path
        File named in errors.
    x, y, z : ndarray
        Point coordinates and heights.

    Returns
    -------
    heights : ndarray, shape (ny, nx)
        Heights, NaN at missing nodes.
    x0, dx, y0, dy : float
        Grid origin and steps, in the input's units.
    """
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise InputError(path, "x or y column contains NaN")
    xs, ys = _clusters(x, path, "x"), _clusters(y, path, "y")
    x0, dx, _ = regular_axis(xs, path, "x")
    y0, dy, _ = regular_axis(ys, path, "y")
    ix = np.rint((x - x0) / dx).astype(np.int64)
    iy = np.rint((y - y0) / dy).astype(np.int64)
    if max(np.abs(x - (x0 + ix * dx)).max() / dx, np.abs(y - (y0 + iy * dy)).max() / dy) > 0.25:
        raise InputError(path, "x,y points are not on a regular grid")
    nx, ny = ix.max() + 1, iy.max() + 1
    flat = iy * nx + ix
    if np.bincount(flat, minlength=nx * ny).max() > 1:
        raise InputError(path, "x,y points are not on a regular grid (two points share a node)")
    if flat.size < 0.5 * nx * ny:
        raise InputError(
            path, f"x,y points are not on a regular grid ({flat.size} points for {nx} x {ny} nodes)"
        )
    h = np.full(nx * ny, np.nan)
    h[flat] = z
    return h.reshape(ny, nx), x0, dx, y0, dy


def _xyz(path, values, fac, sp, units, meta):
    fx, fy, fz = fac
    titles_text, stated = meta.pop("_titles_text", None), meta.pop("_stated", False)
    h, x0, dx, y0, dy = grid_from_points(path, values[:, 0], values[:, 1], values[:, 2])
    meta.update(
        layout="x,y,z points", x0_m=x0 * fx, y0_m=y0 * fy, missing_points=int(h.size - values.shape[0])
    )
    if not stated:
        sp = _unstated_spacing(
            path, sp, (dx, dy), (fx, fy), max(h.shape), h, units, meta, "x, y", titles_text
        )
    else:
        sp = pick_spacing(path, sp, (dx * fx, dy * fy), meta)
    return make_heightmap(path, h * fz, sp[0], sp[1], meta=meta)
