"""A measured friction curve mu(v): the "real" side of the friction-level diagnosis.

File format: CSV with a header; required columns ``v_m_per_s`` [m/s] and ``mu`` [-];
optional ``T0_C`` (background temperature [C]), ``sigma0_Pa`` (nominal pressure [Pa]) and
``condition`` (``dry`` or ``wet``). A per-row value takes precedence over the command-line
flag for its row; an empty cell falls back to the flag.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pipelines.output.csv_files import read_csv_rows
from roadscan.errors import InputError

__all__ = ["MeasuredCurve", "read_measured"]


@dataclass(frozen=True, eq=False)
class MeasuredCurve:
    """Measured mu at speeds v, with the conditions of each row.

    Attributes
    ----------
    v_m_per_s, mu : (n,) arrays
        Sliding speeds [m/s] (sorted increasing) and friction coefficients [-] (> 0).
    T0_C : (n,) array
        Background temperature of each row [C]; NaN means "the default" (the rubber's T_ref).
    sigma0_Pa : (n,) array
        Nominal pressure of each row [Pa].
    wet : (n,) bool array
        True for rows measured wet.
    has_condition : bool
        Whether the file said dry/wet at all (otherwise every row may be wet or dry).
    name : str
        The curve's name in reports: the CSV's file name without its suffix.
    """

    v_m_per_s: np.ndarray
    mu: np.ndarray
    T0_C: np.ndarray
    sigma0_Pa: np.ndarray
    wet: np.ndarray
    has_condition: bool = False
    name: str = ""

    @property
    def n(self):
        return self.v_m_per_s.size

    def subset(self, idx):
        idx = np.asarray(idx)
        return MeasuredCurve(
            self.v_m_per_s[idx],
            self.mu[idx],
            self.T0_C[idx],
            self.sigma0_Pa[idx],
            self.wet[idx],
            self.has_condition,
            self.name,
        )


def _float(cell, path, lineno, col):
    cell = (cell or "").strip()
    if cell == "":
        return np.nan
    try:
        return float(cell)
    except ValueError:
        raise InputError(path, f"line {lineno}: column {col!r} value {cell!r} is not a number") from None


def read_measured(path, sigma0_Pa=0.2e6, T0_C=None, min_points=5, min_speeds=4):
    """Read a measured mu(v) CSV (see module docstring) -> :class:`MeasuredCurve`.

    ``sigma0_Pa`` and ``T0_C`` are the command-line defaults used where a row gives none
    (``T0_C=None``: the rubber's reference temperature, stored as NaN).
    Raises :class:`InputError` on a missing column, a non-number, v <= 0, mu <= 0, fewer than
    ``min_points`` rows or ``min_speeds`` distinct speeds, or an unknown condition.

    Parameters
    ----------
    path : str or Path
        The measured-curve CSV (columns as in the module docstring).
    sigma0_Pa : float, optional
        Nominal pressure [Pa] of rows without a ``sigma0_Pa`` cell (default 0.2 MPa).
    T0_C : float, optional
        Background temperature [C] of rows without a ``T0_C`` cell; None: the rubber's T_ref (NaN).
    min_points : int, optional
        Fewest data rows accepted (default 5).
    min_speeds : int, optional
        Fewest distinct speeds accepted (default 4).

    Returns
    -------
    MeasuredCurve
        The rows sorted by speed (stable), named after the file.
    """
    path = Path(path)
    header, body = read_csv_rows(path, "a header v_m_per_s,mu")
    for need in ("v_m_per_s", "mu"):
        if need not in header:
            raise InputError(path, f"missing column {need!r} (header is {','.join(header)!r})")
    col = {h: i for i, h in enumerate(header)}
    v, mu, T, s, wet = [], [], [], [], []
    has_cond = "condition" in col
    for k, row in enumerate(body, start=2):
        if len(row) < len(header):
            row = row + [""] * (len(header) - len(row))
        v.append(_float(row[col["v_m_per_s"]], path, k, "v_m_per_s"))
        mu.append(_float(row[col["mu"]], path, k, "mu"))
        t = _float(row[col["T0_C"]], path, k, "T0_C") if "T0_C" in col else np.nan
        T.append(t if np.isfinite(t) else (np.nan if T0_C is None else float(T0_C)))
        p = _float(row[col["sigma0_Pa"]], path, k, "sigma0_Pa") if "sigma0_Pa" in col else np.nan
        s.append(p if np.isfinite(p) else float(sigma0_Pa))
        c = row[col["condition"]].strip().lower() if has_cond else "dry"
        if c not in ("dry", "wet", ""):
            raise InputError(path, f"line {k}: condition {c!r} must be dry or wet")
        wet.append(c == "wet")
    v, mu, T, s, wet = (np.asarray(a) for a in (v, mu, T, s, wet))
    if v.size < min_points:
        raise InputError(path, f"only {v.size} data rows, need at least {min_points}")
    if not np.all(np.isfinite(v)) or np.any(v <= 0):
        raise InputError(path, "v_m_per_s must be positive numbers in every row")
    if not np.all(np.isfinite(mu)) or np.any(mu <= 0):
        raise InputError(path, "mu must be positive numbers in every row")
    if np.any(s <= 0):
        raise InputError(path, "sigma0_Pa must be positive")
    n_speeds = np.unique(np.round(np.log10(v), 9)).size
    if n_speeds < min_speeds:
        raise InputError(
            path,
            f"{v.size} rows at only {n_speeds} distinct speed(s): a diagnosis needs "
            f"mu at {min_speeds} or more distinct speeds",
        )
    o = np.argsort(v, kind="stable")
    return MeasuredCurve(
        v[o].astype(float),
        mu[o].astype(float),
        T[o].astype(float),
        s[o].astype(float),
        wet[o].astype(bool),
        has_cond,
        path.stem,
    )
