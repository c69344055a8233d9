"""``campaign.csv`` (and ``campaign.parquet`` when pyarrow is already installed).

One row per input in input order (per section with ``--section-length``). Columns: ``file``,
``label``, ``chainage_m``, ``status`` (``ok``/``error``), ``error`` (one line), then every
scalar of the scans' ``summary.json`` flattened as :mod:`.records` documents (in order of
first appearance over the rows). Floats are written with full precision (``repr``), missing
values as empty cells.

The anisotropy sectors of area scans (``anisotropy.sector_angle_deg.*``,
``anisotropy.sector_power_fraction.*``: 72 columns) go to a side file,
``campaign_anisotropy.csv`` (``file``, ``label``, ``chainage_m``, ``status`` and the sector
columns, same rows), so that ``campaign.csv`` stays readable; the summary figures
of the anisotropy (``anisotropy.power_ratio_x_to_y``...) stay in ``campaign.csv``.

The road engineer's texture set is there too: ``mpd_valid`` (``true``/``false``: whether the
MPD is valid per ISO 13473-1) right after ``mpd_m``, ``etd_m`` (empty when the MPD is not
valid), and the ISO 25178-2 / 21920-2 figures ``roughness.Sk_m`` ... ``roughness.S5v_m``
(``roughness.Rk_m`` ... for profiles) with the ``filters`` they were taken with. ``roadscan
batch --columns`` picks the columns (names or shell-style patterns, comma separated, e.g.
``mpd_m,mpd_valid,etd_m,roughness.S*``): the fixed columns always come first, then the chosen
ones in their usual order.
"""

from __future__ import annotations

import csv
import io

from roadscan.io.atomic import atomic_path, atomic_write_text

__all__ = [
    "FIXED_COLUMNS",
    "SIDE_PREFIXES",
    "ANISOTROPY_FILE",
    "columns_of",
    "write_campaign_csv",
    "write_campaign_parquet",
    "pick_columns",
    "parse_columns",
]

FIXED_COLUMNS = ("file", "label", "chainage_m", "status", "error")
#: columns that go to ``campaign_anisotropy.csv`` instead of ``campaign.csv``
SIDE_PREFIXES = ("anisotropy.sector_",)
ANISOTROPY_FILE = "campaign_anisotropy.csv"


def _side(k):
    return k.startswith(SIDE_PREFIXES)


def columns_of(records, side=False):
    """The columns of ``campaign.csv`` (``side=True``: of ``campaign_anisotropy.csv``).

    Parameters
    ----------
    records : list of dict
        The rows.
    side : bool, optional
        The anisotropy table's columns.

    Returns
    -------
    list of str
    """
    cols = list(FIXED_COLUMNS) if not side else ["file", "label", "chainage_m", "status"]
    seen = set(cols)
    for r in records:
        for k in r["values"]:
            if k not in seen and (_side(k) == side or (side and k in ("section", "section_start_m"))):
                seen.add(k)
                cols.append(k)
    return cols


def _cell(x):
    if x is None:
        return ""
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, float):
        return repr(x)
    return " ".join(str(x).split()) if isinstance(x, str) else str(x)


def _row(r, cols):
    fixed = {
        "file": r["file"],
        "label": r["label"],
        "chainage_m": r["chainage_m"],
        "status": r["status"],
        "error": r["error"],
    }
    return [_cell(fixed[c] if c in fixed else r["values"].get(c)) for c in cols]


def _write_table(path, records, cols):
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(cols)
    for r in records:
        w.writerow(_row(r, cols))
    atomic_write_text(path, buf.getvalue())


def parse_columns(text):
    """``--columns`` text -> list of names or patterns (None: all columns).

    Parameters
    ----------
    text : str or None
        Comma-separated column names or shell-style patterns.

    Returns
    -------
    list of str or None

    Raises
    ------
    roadscan.InputError
        When the text holds no name.
    """
    if text is None:
        return None
    from roadscan.errors import InputError

    pats = [t.strip() for t in str(text).split(",") if t.strip()]
    if not pats:
        raise InputError(
            None,
            f"{{columns}} {text!r}: expected column names or patterns, "
            f"comma separated (e.g. mpd_m,mpd_valid,roughness.S*)",
            hint_option="columns",
        )
    return pats


def pick_columns(cols, patterns):
    """The fixed columns and those of ``cols`` matching a pattern, in ``cols``' order.

    Parameters
    ----------
    cols : list of str
        All columns.
    patterns : list of str or None
        Names or shell-style patterns (``fnmatch``, case-sensitive); None keeps all.

    Returns
    -------
    (list of str, list of str)
        The kept columns, and the patterns that matched no column.
    """
    from fnmatch import fnmatchcase

    if not patterns:
        return cols, []
    keep = [c for c in cols if c in FIXED_COLUMNS or any(fnmatchcase(c, p) for p in patterns)]
    unused = [p for p in patterns if not any(fnmatchcase(c, p) for c in cols)]
    return keep, unused


def write_campaign_csv(path, records, columns=None):
    """``campaign.csv`` and, when some scan has anisotropy sectors, ``campaign_anisotropy.csv``
    next to it. Returns the columns of ``campaign.csv``.

    Parameters
    ----------
    path : str or Path
        Output CSV.
    records : list of dict
        The rows.
    columns : list of str, optional
        Names or patterns of the columns to keep (:func:`pick_columns`; None: all); a pattern
        that matches nothing is named in a note on stderr.

    Returns
    -------
    list of str
        The columns.
    """
    cols = columns_of(records)
    if columns:
        cols, unused = pick_columns(cols, columns)
        if unused:
            import sys

            print(f"note: --columns {', '.join(unused)}: no such column in this campaign", file=sys.stderr)
    _write_table(path, records, cols)
    side = columns_of(records, side=True)
    if any(_side(c) for c in side):
        from pathlib import Path

        _write_table(Path(path).with_name(ANISOTROPY_FILE), records, side)
    return cols


def write_campaign_parquet(path, records):
    """Write ``campaign.parquet`` (every column, the anisotropy sectors too) if pyarrow is
    importable; return True when written.

    Parameters
    ----------
    path : str or Path
        Output file.
    records : list of dict
        The rows.

    Returns
    -------
    bool
    """
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return False
    cols = columns_of(records)  # parquet keeps the anisotropy sectors as well
    cols += [c for c in columns_of(records, side=True) if _side(c)]
    data = {c: [] for c in cols}
    for r in records:
        for c in cols:
            v = r[c] if c in FIXED_COLUMNS else r["values"].get(c)
            data[c].append(v)
    try:
        table = pa.table({c: pa.array(v, from_pandas=True) for c, v in data.items()})
    except (pa.ArrowInvalid, pa.ArrowTypeError):  # mixed types in a column: text
        table = pa.table({c: pa.array([None if x is None else str(x) for x in v]) for c, v in data.items()})
    with atomic_path(path) as tmp:
        pq.write_table(table, tmp)
    return True
