"""Small CSV files the commands read: one reader for rows, one for ``psd.csv``.

All accept a UTF-8 byte-order mark, blank lines, ``#`` comment lines and spaces after commas,
and raise :class:`roadscan.errors.InputError` naming the file on any problem.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from roadscan.errors import InputError

__all__ = ["read_csv_rows", "read_psd_csv"]


def read_csv_rows(path, expected="a header line and data rows"):
    """-> (header cells, data rows), every cell stripped of surrounding blanks.

    ``expected`` is named in the message when the file has no header.

    Parameters
    ----------
    path : str or Path
        CSV file.
    expected : str, optional
        What the message says is expected.

    Returns
    -------
    header : list of str
    rows : list of list of str
    """
    path = Path(path)
    if not path.exists():
        raise InputError(path, "no such file")
    if path.is_dir():
        raise InputError(path, f"is a directory, expected a CSV with {expected}")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(path, f"cannot read ({exc})") from None
    rows = [
        [c.strip() for c in r]
        for r in csv.reader(
            line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")
        )
    ]
    if not rows:
        raise InputError(path, f"empty file, expected {expected}")
    # a row with more values than the header has names: decimal commas read as separators
    # (q 110,103893 and C 5,687e-15 give four fields under 'q_per_m,C_m4'), or a stray field
    width = len([c for c in rows[0] if c])
    for k, r in enumerate(rows[1:], start=2):
        if len([c for c in r if c]) > width:
            raise InputError(
                path,
                f"data row {k} has {len([c for c in r if c])} values but the "
                f"header names {width} columns (decimal commas? separate fields "
                f"with ',' and write decimals with '.')",
            )
    return rows[0], rows[1:]


def read_psd_csv(path):
    """``psd.csv`` (columns ``q_per_m`` [1/m], ``C_m4`` [m^4], Persson's normalisation, as
    ``roadscan analyse`` writes it) -> :class:`friction.TabulatedPSD`.

    A row with non-finite or non-positive q or C is refused naming the row, and so is a
    spectrum rising with q (:mod:`pipelines.checks.validate`); rows are sorted by q. The engine
    integrates the table from its lowest to its highest q (docs: Theory).

    Parameters
    ----------
    path : str or Path
        The ``psd.csv``.

    Returns
    -------
    friction.TabulatedPSD
    """
    from friction import TabulatedPSD
    from pipelines.checks.validate import check_psd_rows, check_psd_shape

    head, body = read_csv_rows(path, "a header q_per_m,C_m4")
    if "q_per_m" not in head or "C_m4" not in head:
        raise InputError(path, f"missing column q_per_m or C_m4 (header is {','.join(head)!r})")
    iq, ic = head.index("q_per_m"), head.index("C_m4")
    try:
        d = np.array([[float(r[iq]), float(r[ic])] for r in body], float).reshape(-1, 2)
    except (ValueError, IndexError):
        raise InputError(path, "non-numeric or missing q_per_m/C_m4 values") from None
    check_psd_rows(d[:, 0], d[:, 1], path)
    d = d[np.argsort(d[:, 0])]
    if d.shape[0] < 4 or np.any(np.diff(d[:, 0]) <= 0):
        raise InputError(path, "need at least 4 rows with distinct positive q and positive C")
    check_psd_shape(d[:, 0], d[:, 1], path)
    from pipelines.checks.psd_plausibility import check_psd_table

    check_psd_table(path, d[:, 0], d[:, 1])  # wavelengths, rms height and slope a profiler gives
    return TabulatedPSD(d[:, 0], d[:, 1])
