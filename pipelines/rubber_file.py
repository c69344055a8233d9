"""Read a rubber model from a TOML file (format: friction/RUBBER_TOML.md).

The TOML is parsed with :mod:`tomllib`; tables that reference data files
(``[master_curve] file = "x.csv"``, ``[shift] file = "y.csv"``) are loaded here, relative to the
TOML's folder, and the resulting plain dict goes to :func:`friction.rubber_from_dict` (the
friction package reads no files).

Master-curve CSV: columns ``f, E_stor, E_loss`` (frequency [Hz], storage and loss moduli);
an optional second line of units (``Hz, MPa, MPa``) or ``units = "MPa"`` in the TOML sets the
modulus unit (Pa, kPa, MPa or GPa; default Pa). Shift CSV: columns ``T, log_aT`` (T [C],
decimal log of aT), optional units line. A UTF-8 byte-order mark and spaces after commas are
accepted (as in the pyvisco files of ../shared/data/rubber/).
"""
from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np

from roadscan.errors import InputError

from .csv_files import read_csv_rows

__all__ = ["load_rubber", "read_master_curve_csv", "read_shift_csv"]

_UNITS = {"pa": 1.0, "kpa": 1e3, "mpa": 1e6, "gpa": 1e9}
_F_NAMES = ("f", "f_hz", "freq", "frequency")
_E1_NAMES = ("e_stor", "e_storage", "e_storage_pa", "e'", "storage")
_E2_NAMES = ("e_loss", "e_loss_pa", "e''", "loss")
_T_NAMES = ("t", "t_c", "temperature")
_A_NAMES = ("log_at", "log10_at", "log_a_t", "logat")


def _read_table(path):
    """Rows of a small CSV: (header names, optional units row, float data (n, k))."""
    head, body = read_csv_rows(path)
    if not body:
        raise InputError(path, "expected a header line and data rows")
    head = [h.lower() for h in head]
    units = None
    try:
        float(body[0][0])
    except (ValueError, IndexError):
        units, body = [u.lower() for u in body[0]], body[1:]
    try:
        data = np.array([[float(c) for c in r] for r in body], dtype=float)
    except ValueError:
        raise InputError(path, "non-numeric data") from None
    if data.ndim != 2 or data.shape[0] < 2 or data.shape[1] != len(head):
        raise InputError(path, f"expected {len(head)} numeric columns on every row and >= 2 rows")
    if not np.all(np.isfinite(data)):
        raise InputError(path, "non-finite values in data")
    return head, units, data


def _col(head, names, path, what):
    for i, h in enumerate(head):
        if h in names:
            return i
    raise InputError(path, f"no {what} column (expected one of {', '.join(names)}; header {','.join(head)})")


def read_master_curve_csv(path, units=None):
    """-> (f_Hz, E_storage_Pa, E_loss_Pa) from a master-curve CSV (see module docstring)."""
    head, urow, d = _read_table(path)
    i_f = _col(head, _F_NAMES, path, "frequency")
    i1 = _col(head, _E1_NAMES, path, "storage modulus")
    i2 = _col(head, _E2_NAMES, path, "loss modulus")
    u = units if units is not None else (urow[i1] if urow else "Pa")
    if urow and urow[i_f] not in ("hz", ""):
        raise InputError(path, f"frequency unit must be Hz, not {urow[i_f]!r}")
    scale = _UNITS.get(str(u).strip().lower())
    if scale is None:
        raise InputError(path, f"unknown modulus unit {u!r} (Pa, kPa, MPa, GPa)")
    f, E1, E2 = d[:, i_f], d[:, i1] * scale, d[:, i2] * scale
    if np.any(f <= 0) or np.any(E1 <= 0) or np.any(E2 <= 0):
        raise InputError(path, "frequencies and moduli must be positive")
    return f, E1, E2


def read_shift_csv(path):
    """-> (T_C, log10_aT) from a shift-factor CSV."""
    head, _, d = _read_table(path)
    return d[:, _col(head, _T_NAMES, path, "temperature")], d[:, _col(head, _A_NAMES, path, "log_aT")]


def load_rubber(path):
    """Rubber model from a TOML file; raises :class:`roadscan.errors.InputError` on bad input."""
    import friction

    path = Path(path)
    try:
        with open(path, "rb") as fh:
            d = tomllib.load(fh)
    except FileNotFoundError:
        raise InputError(path, "no such file") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(path, f"invalid TOML ({exc})") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(path, f"cannot read ({exc})") from None
    base = path.parent
    mc = d.get("master_curve")
    if isinstance(mc, dict) and "file" in mc:
        f, E1, E2 = read_master_curve_csv(base / str(mc["file"]), mc.get("units"))
        d["master_curve"] = {"f_Hz": f, "E_storage_Pa": E1, "E_loss_Pa": E2}
    sh = d.get("shift")
    if isinstance(sh, dict) and "file" in sh:
        T, a = read_shift_csv(base / str(sh["file"]))
        d["shift"] = {"kind": "table", "T_C": T, "log10_aT": a}
    try:
        return friction.rubber_from_dict(d)
    except (ValueError, TypeError) as exc:
        raise InputError(path, str(exc)) from None
