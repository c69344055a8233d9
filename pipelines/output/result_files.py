"""Result tables and records written atomically: ``summary.json``-style JSON (numpy values
converted, non-finite numbers as null) and CSV columns with a header line.
:mod:`pipelines.output.report` re-exports both writers.
"""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np

from roadscan.io.atomic import atomic_write_text

__all__ = ["write_json", "write_csv"]


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, (np.floating, float)):
        x = float(obj)
        return x if np.isfinite(x) else None
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.ndarray):
        return _jsonable(obj.tolist())
    return obj


def write_json(path, data):
    """Write JSON atomically; numpy scalars/arrays converted, non-finite floats -> null.

    Parameters
    ----------
    path : str or Path
        Output file.
    data : dict
        Content.

    Returns
    -------
    Path
    """
    atomic_write_text(path, json.dumps(_jsonable(data), indent=2) + "\n")
    return Path(path)


def write_csv(path, header, columns):
    """Write columns (equal-length 1D arrays) as CSV with ``header`` (list of names).

    Parameters
    ----------
    path : str or Path
        Output file.
    header : list of str
        Column names.
    columns : list of array_like
        Columns.

    Returns
    -------
    Path
    """
    buf = io.StringIO()
    buf.write(",".join(header) + "\n")
    np.savetxt(
        buf, np.column_stack([np.asarray(c, dtype=float) for c in columns]), delimiter=",", fmt="%.10g"
    )
    atomic_write_text(path, buf.getvalue())
    return Path(path)
