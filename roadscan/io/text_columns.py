"""What each column of a text table is: its unit, its dropouts, an index column.

**Units** (:func:`column_factors`). When the title line (:mod:`roadscan.io.text_titles`) or a
preamble states a unit anywhere, every column must be known, each on its own: a coordinate
column from its title, else the preamble's ``x units``/``units``, else ``x_units``; the heights
from their title, else the preamble's ``z units``/``units``, else ``units``. A column still
unknown is refused in one line that quotes the title line and names the option that decides
(``{x_units}``, ``{units}``); a title naming a token that is not a length unit (``z (a.u.)``)
is refused the same way unless that option is given (it then decides, recorded in
``meta["title_unit_ignored"]``). A title and a preamble that disagree are refused. A unit
stated by the file against ``units`` follows :mod:`roadscan.io.calibration`. Nothing stated
anywhere: None, the caller's unitless reading (:mod:`roadscan.io.text_units`).

**Dropouts** (:func:`mark_dropouts`), besides the markers of the table
(:data:`roadscan.io.text_table.MISSING_MARKERS`): heights equal to the preamble's ``nodata``
value; and heights equal to a usual sentinel (:data:`SENTINELS`: +-9999, +-99999, +-999999,
+-9999999, Surfer's 1.70141e38, +-1e30, float32's largest) when it lies beyond the range of
every other height by more than :data:`SENTINEL_SPREADS` = 20 times their 0.5-99.5 %
spread, with a warning; a sentinel value within that reach is a height, kept.

**Index column** (:func:`index_column`): a first column titled as an index (empty, ``index``,
``Unnamed: 0``, ``point``, ``no``, ``Data Point No:``...) holding consecutive integers in any
order (pandas writes 0, 1, 2...) is not a coordinate: dropped, noted in ``meta``.
"""

from __future__ import annotations

import re

import numpy as np

from ..errors import InputError, OptionNote
from .text_titles import LENGTH_UNITS

__all__ = ["SENTINELS", "SENTINEL_SPREADS", "column_factors", "mark_dropouts", "index_column"]

SENTINELS = (
    -9999.0,
    9999.0,
    -99999.0,
    99999.0,
    -999999.0,
    999999.0,
    -9999999.0,
    9999999.0,
    1.70141e38,
    -1e30,
    1e30,
    3.4028234663852886e38,
    -3.4028234663852886e38,
)
SENTINEL_SPREADS = 20.0
_INDEX_NAMES = {
    "",
    "index",
    "unnamed 0",
    "point",
    "point no",
    "point number",
    "data point no",
    "no",
    "nr",
    "n",
    "id",
    "i",
    "idx",
    "sample",
    "sample no",
    "row",
}


def _factor(unit):
    return LENGTH_UNITS[unit][1]


def index_column(names, col):
    """True when a first column titled ``names[0]`` holding ``col`` is a row index.

    Parameters
    ----------
    names : list of str
        Column titles.
    col : ndarray
        The first column's numbers.

    Returns
    -------
    bool
    """
    key = re.sub(r"[^a-z0-9]+", " ", names[0].lower()).strip()
    if key not in _INDEX_NAMES or col.size < 2 or not np.all(np.isfinite(col)):
        return False
    s = np.sort(col)
    return bool(np.all(s == np.round(s)) and np.all(np.diff(s) == 1.0))


def _unknown(path, titles, j, token, option, what):
    raise InputError(
        path,
        f"the title {titles.names[j]!r} (title line {titles.text!r}) names "
        f"{token!r}, not a length unit roadscan knows (m, cm, mm, um, nm): "
        f"give {{{option}}} for the {what}",
        option,
    )


def column_factors(path, titles, pre, ncol, units, x_units, meta):
    """Metres per unit of each column when the file states a unit anywhere (module notes).

    Parameters
    ----------
    path : str or Path
        File named in errors.
    titles : Titles or None
        The title line's reading (:func:`roadscan.io.text_titles.find_titles`).
    pre : Preamble
        The preamble's reading.
    ncol : int
        Columns: 1 (heights), 2 (x, z), 3 (x, y, z) or more (a matrix: one factor).
    units, x_units : str or None
        The options ``units`` (heights) and ``x_units`` (coordinates).
    meta : dict
        Reader metadata (``units``, ``coordinate_unit``, ``height_unit``... recorded).

    Returns
    -------
    list of float or None
        One factor per coordinate column then one for the heights; None when nothing is stated.
    """
    from ._common import unit_factor
    from .calibration import pick_units

    t_units = titles.units if titles is not None else [None] * max(ncol, 1)
    if not (any(u is not None for u in t_units) or pre.units or pre.x_units or pre.z_units):
        return None
    shown = f"title line {titles.text!r}" if titles is not None else "no title line"
    n_coord = ncol - 1 if ncol in (2, 3) else 0
    words, factors = [], []
    for j in range(n_coord):
        u = t_units[j]
        side = pre.x_units or pre.units
        if isinstance(u, tuple):
            if x_units is None:
                _unknown(path, titles, j, u[1], "x_units", "coordinates")
            meta.setdefault("title_unit_ignored", {})[titles.names[j]] = u[1]
            u = x_units
        elif u is None:
            if side is not None:
                u = side[0]
            elif x_units is not None:
                u = x_units
            else:
                name = (titles.names[j] if titles is not None else "") or "xyz"[j]
                raise InputError(
                    path,
                    f"the {shown} states no unit for the {name!r} column "
                    f"(only for the others): state it ('{name} (mm)') or give "
                    f"{{x_units}}",
                    "x_units",
                )
        else:
            if side is not None and side[0] != u:
                raise InputError(
                    path,
                    f"the title line says {titles.names[j]!r} is in {u}, the "
                    f"preamble line {side[1]!r} says {side[0]}: correct one",
                )
            if x_units is not None and abs(_factor(u) - unit_factor(x_units, path)) > 1e-12 * _factor(u):
                raise InputError(
                    path,
                    f"the title line states the coordinates in {u}: drop {{x_units}} {x_units}",
                    "x_units",
                )
        words.append(u)
        factors.append(_factor(u) if u in LENGTH_UNITS else unit_factor(u, path))
    u = t_units[-1] if titles is not None else None
    side = pre.z_units or pre.units
    if isinstance(u, tuple):
        if units is None:
            _unknown(path, titles, len(t_units) - 1, u[1], "units", "heights")
        meta.setdefault("title_unit_ignored", {})[titles.names[-1]] = u[1]
        fz = unit_factor(units, path)
        meta["height_unit"] = {"unit": units, "m_per_unit": fz, "from": "flag"}
        u = units
    elif u is None and side is None:
        if units is None:
            said = f"the {shown} states" + (" (and the preamble states)" if pre.x_units else "")
            raise InputError(
                path,
                f"{said} no unit for the heights, only for the coordinates: "
                f"state it ('z (mm)') or give {{units}}",
                "units",
            )
        fz = unit_factor(units, path)
        meta["height_unit"] = {"unit": units, "m_per_unit": fz, "from": "flag"}
        u = units
    else:
        if u is not None and side is not None and side[0] != u:
            raise InputError(
                path,
                f"the title line says the heights are in {u}, the preamble "
                f"line {side[1]!r} says {side[0]}: correct one",
            )
        u = u or side[0]
        fz = pick_units(path, units, u, _factor(u), meta)
    meta["units"] = ",".join(words + [str(u)])
    if words:
        meta["coordinate_unit"] = words[0]
    return factors + [fz]


def mark_dropouts(path, h, nodata, meta):
    """Set the missing-value markers among the heights ``h`` (file numbers, in place) to NaN.

    Parameters
    ----------
    path : str or Path
        File (unused in the reading; kept for messages).
    h : ndarray
        Heights as written in the file (a view of the table's height columns).
    nodata : float or None
        The preamble's marker.
    meta : dict
        Receives ``nodata_value``, ``dropouts_marked`` and a warning for a sentinel.

    Returns
    -------
    int
        Heights set to NaN.
    """
    if nodata is not None:
        hit = h == nodata
        n = int(np.count_nonzero(hit))
        h[hit] = np.nan
        meta["nodata_value"] = float(nodata)
        meta["dropouts_marked"] = n
        return n
    if h.size < 3 or not np.isfinite(h).any():
        return 0
    lo, hi = float(np.nanmin(h)), float(np.nanmax(h))
    found = [v for v in SENTINELS if v in (lo, hi)]
    total = 0
    for v in found:
        hit = h == v
        rest = h[~hit]
        rest = rest[np.isfinite(rest)]
        if rest.size < 2:
            continue
        step = max(1, rest.size // 200_000)
        p_lo, p_hi = np.percentile(rest[::step], [0.5, 99.5])
        spread = float(p_hi - p_lo)
        reach = float(min(abs(v - rest.min()), abs(v - rest.max())))
        if reach <= SENTINEL_SPREADS * spread:
            continue  # within reach of the heights: a height
        n = int(np.count_nonzero(hit))
        h[hit] = np.nan
        total += n
        times = f"{reach / spread:.3g} times" if spread > 0 else "far beyond"
        meta.setdefault("read_warnings", []).append(
            OptionNote(
                f"{n} heights equal to {v:g} read as dropouts: a missing-value marker, {times} the "
                f"spread of the other heights away from them (state it with a 'nodata: {v:g}' "
                f"preamble line)"
            )
        )
        meta["nodata_value"] = v
    if total:
        meta["dropouts_marked"] = total
    return total
