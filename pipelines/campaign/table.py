"""``campaign.csv`` (and ``campaign.parquet`` when pyarrow is already installed).

One row per input in input order (per section with ``--section-length``). Columns: ``file``,
``label``, ``chainage_m``, ``status`` (``ok``/``error``), ``error`` (one line), then every
scalar of the scans' ``summary.json`` flattened as :mod:`.records` documents (in order of
first appearance over the rows). Floats are written with full precision (``repr``), missing
values as empty cells.
"""
from __future__ import annotations

import csv
import io

from roadscan.io.atomic import atomic_path, atomic_write_text

__all__ = ["FIXED_COLUMNS", "columns_of", "write_campaign_csv", "write_campaign_parquet"]

FIXED_COLUMNS = ("file", "label", "chainage_m", "status", "error")


def columns_of(records):
    cols = list(FIXED_COLUMNS)
    seen = set(cols)
    for r in records:
        for k in r["values"]:
            if k not in seen:
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
    fixed = {"file": r["file"], "label": r["label"], "chainage_m": r["chainage_m"],
             "status": r["status"], "error": r["error"]}
    return [_cell(fixed[c] if c in fixed else r["values"].get(c)) for c in cols]


def write_campaign_csv(path, records):
    cols = columns_of(records)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(cols)
    for r in records:
        w.writerow(_row(r, cols))
    atomic_write_text(path, buf.getvalue())
    return cols


def write_campaign_parquet(path, records):
    """Write ``campaign.parquet`` if pyarrow is importable; return True when written."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return False
    cols = columns_of(records)
    data = {c: [] for c in cols}
    for r in records:
        for c in cols:
            v = r[c] if c in FIXED_COLUMNS else r["values"].get(c)
            data[c].append(v)
    try:
        table = pa.table({c: pa.array(v, from_pandas=True) for c, v in data.items()})
    except (pa.ArrowInvalid, pa.ArrowTypeError):     # mixed types in a column: text
        table = pa.table({c: pa.array([None if x is None else str(x) for x in v]) for c, v in data.items()})
    with atomic_path(path) as tmp:
        pq.write_table(table, tmp)
    return True
