"""The CSV tables of a rubber: master curves, shift factors, raw DMA sweeps and WLF constants,
read into SI arrays (a rubber TOML names them; ``roadscan friction --master-curve`` and
``--shift-table`` and ``roadscan rubber`` read them directly).

Master-curve CSV: columns ``f, E_stor, E_loss`` (frequency [Hz], storage and loss moduli);
an optional second line of units (``Hz, MPa, MPa``), units in the header (``E_stor_MPa``,
``E_stor [MPa]``) or ``units = "MPa"`` in the TOML set the modulus unit (Pa, kPa, MPa or GPa;
default Pa). Shift CSV: columns ``T`` [C] and ``log_aT``/``log10_aT`` (decimal log of aT) or
``aT`` (linear). A UTF-8 byte-order mark and spaces after commas are accepted (as in the
pyvisco files of ../shared/data/rubber/). :mod:`pipelines.settings.rubber_file` re-exports
the public readers.
"""

from __future__ import annotations

import re

import numpy as np

from pipelines.output.csv_files import read_csv_rows
from roadscan.errors import InputError

__all__ = ["read_master_curve_csv", "read_shift_csv", "orient_shift", "read_dma_sweeps_csv", "read_wlf_csv"]

_UNITS = {"pa": 1.0, "kpa": 1e3, "mpa": 1e6, "gpa": 1e9}
_F_NAMES = ("f", "freq", "frequency")
_OMEGA_NAMES = ("omega", "w", "angular_frequency")
_E1_NAMES = (
    "e_stor",
    "e_storage",
    "e'",
    "storage",
    "e1",
    "estor",
    "e_prime",
    "storage_modulus",
    "re_e",
    "ree",
    "e_re",
    "e_real",
    "real_e",
    "storage modulus",
)
_E2_NAMES = (
    "e_loss",
    "e''",
    "loss",
    "e2",
    "eloss",
    "e_double_prime",
    "loss_modulus",
    "im_e",
    "ime",
    "e_im",
    "e_imag",
    "imag_e",
    "loss modulus",
)
_T_NAMES = ("t", "temp", "temperature")
_LOGA_NAMES = (
    "log_at",
    "log10_at",
    "log_a_t",
    "log10_a_t",
    "logat",
    "log10at",
    "lg_at",
    "log(at)",
    "log10(at)",
    "log_a",
)
_LINA_NAMES = ("at", "a_t", "a", "shift_factor")
_COL_UNITS = ("hz", "rad/s", "rad_s", "c", "k", "pa", "kpa", "mpa", "gpa", "-", "1")


def _split_name(cell):
    """Header cell -> (base name, unit or None): ``E_stor [MPa]``, ``E_stor (MPa)``,
    ``E_storage_Pa``, ``T_C``, ``f_Hz`` and ``omega_rad_s`` are understood (case-insensitive)."""
    c = cell.strip().strip('"').lower()
    for o, e in (("[", "]"), ("(", ")")):
        if c.endswith(e) and o in c and not c.startswith("log"):
            i = c.rindex(o)
            return c[:i].strip().rstrip("_ "), c[i + 1 : -1].strip()
    for u in sorted(_COL_UNITS, key=len, reverse=True):
        for sep in ("_", " "):
            if c.endswith(sep + u.replace("/", "_")) and len(c) > len(u) + 1:
                return c[: -len(u) - 1].rstrip("_ "), u
    return c, None


def _read_table(path):
    """Rows of a small CSV: (base names, units per column (None if unknown), data (n, k)).

    The units come from a second, non-numeric line (``Hz, MPa, MPa``) when there is one, else
    from the header cells themselves (``E_stor_MPa``, ``T [C]``)."""
    head, body = read_csv_rows(path)
    if len(head) == 1 and len(head[0].replace(";", " ").split()) > 1:  # whitespace or ; separated
        head = head[0].replace(";", " ").split()
        body = [r[0].replace(";", " ").split() if len(r) == 1 else r for r in body]
    if not body:
        raise InputError(path, "expected a header line and data rows")
    names, units = zip(*(_split_name(h) for h in head))
    units = list(units)
    try:
        float(body[0][0])
    except (ValueError, IndexError):
        urow, body = [u.strip().lower() for u in body[0]], body[1:]
        units = [(urow[i] if i < len(urow) and urow[i] else units[i]) for i in range(len(head))]
    try:
        data = np.array([[float(c) for c in r] for r in body], dtype=float)
    except ValueError:
        raise InputError(path, "non-numeric data") from None
    if data.ndim != 2 or data.shape[0] < 2 or data.shape[1] != len(head):
        raise InputError(path, f"expected {len(head)} numeric columns on every row and >= 2 rows")
    if not np.all(np.isfinite(data)):
        raise InputError(path, "non-finite values in data")
    return list(names), units, data


def _col(names, choices, path, what, required=True):
    for i, h in enumerate(names):
        if h in choices:
            return i
    if not required:
        return None
    raise InputError(
        path, f"no {what} column (expected one of {', '.join(choices)}; header {','.join(names)})"
    )


def _modulus_scale(u, path, col):
    scale = _UNITS.get(str(u).strip().lower())
    if scale is None:
        raise InputError(path, f"unknown modulus unit {u!r} for column {col} (Pa, kPa, MPa, GPa)")
    return scale


_LOG_CALL = re.compile(r"^(?:log10|log|lg)\s*\(\s*([^)]*?)\s*\)\s*(.*)$")  # log10(E') [Pa]
_LOG_PREFIX = re.compile(r"^(?:log10|log|lg)[_ ]+(.+)$")  # log10_E_stor_Pa


def _unlog(names, urow, d, known):
    """Columns of decimal logarithms (``log10_f``, ``log_omega``, ``log10(E_stor) [Pa]``,
    ``lg_E_loss_MPa``) of a known quantity -> that quantity (10**value, its unit kept)."""
    for i, n in enumerate(names):
        m = _LOG_CALL.match(n)
        if m:
            inner, unit = _split_name(m.group(1))
            rest = m.group(2).strip().strip("[]()").strip()
            unit = rest or unit
        else:
            m = _LOG_PREFIX.match(n)
            if not m:
                continue
            inner, unit = _split_name(m.group(1))
        if inner in known:
            names[i] = inner
            urow[i] = urow[i] or unit
            with np.errstate(over="ignore"):
                d[:, i] = 10.0 ** d[:, i]
    return names, urow, d


def read_master_curve_csv(path, units=None):
    """-> (f_Hz, E_storage_Pa, E_loss_Pa) from a master-curve CSV (see module docstring).

    Frequency: a column ``f`` (Hz) or ``omega`` (rad/s, divided by 2 pi). Moduli: ``E_stor``
    and ``E_loss`` (or ``E'``/``E''``, ``ReE``/``ImE``, ``E_real``/``E_imag``) in the unit of
    the units line, the header (``E_stor_MPa``, ``E' [MPa]``) or ``units`` (which overrides
    both); default Pa. Any of them may be given as its decimal logarithm (``log10_omega``,
    ``log10_E_stor_Pa``, ``log(E'') [MPa]``).

    Parameters
    ----------
    path : str or Path
        The CSV.
    units : str, optional
        Modulus unit when the file names none.

    Returns
    -------
    f_Hz, E_storage_Pa, E_loss_Pa : ndarray
    """
    names, urow, d = _unlog(*_read_table(path), _F_NAMES + _OMEGA_NAMES + _E1_NAMES + _E2_NAMES)
    i_f = _col(names, _F_NAMES, path, "frequency", required=False)
    if i_f is None:
        i_f = _col(names, _OMEGA_NAMES + _F_NAMES, path, "frequency (f [Hz] or omega [rad/s])")
        f = d[:, i_f] / (2 * np.pi)
        if urow[i_f] not in (None, "", "rad/s", "rad_s", "1/s"):
            raise InputError(path, f"angular frequency unit must be rad/s, not {urow[i_f]!r}")
    else:
        f = d[:, i_f]
        if urow[i_f] not in (None, "", "hz"):
            raise InputError(path, f"frequency unit must be Hz, not {urow[i_f]!r}")
    i1 = _col(names, _E1_NAMES, path, "storage modulus")
    i2 = _col(names, _E2_NAMES, path, "loss modulus")
    s1 = _modulus_scale(units if units is not None else (urow[i1] or "Pa"), path, names[i1])
    s2 = _modulus_scale(units if units is not None else (urow[i2] or "Pa"), path, names[i2])
    E1, E2 = d[:, i1] * s1, d[:, i2] * s2
    if np.any(f <= 0) or np.any(E1 <= 0) or np.any(E2 <= 0):
        raise InputError(path, "frequencies and moduli must be positive")
    if E1.max() < 1e4:
        raise InputError(
            path,
            f"storage modulus at most {E1.max():.3g} Pa: no rubber is that soft; "
            "are the moduli in MPa? add a units line (Hz, MPa, MPa), name the "
            'columns E_stor_MPa/E_loss_MPa or set units = "MPa" in the TOML',
        )
    return f, E1, E2


def _temperature_C(names, urow, d, path):
    """The temperature column [C] (C or K in the file); every value above absolute zero and at
    most 1000 C (:data:`pipelines.checks.validate.T_MAX_C`), else a one-line refusal naming the row."""
    from pipelines.checks.numbers import KELVIN, T_MAX_C

    i = _col(names, _T_NAMES, path, "temperature")
    u = (urow[i] or "c").replace("°", "")
    if u in ("c", "degc", "deg_c", "celsius"):
        T = d[:, i]
    elif u in ("k", "kelvin"):
        T = d[:, i] - 273.15
    else:
        raise InputError(path, f"temperature unit must be C or K, not {urow[i]!r}")
    bad = ~(np.isfinite(T) & (T > -KELVIN) & (T <= T_MAX_C))
    if bad.any():
        k = int(np.argmax(bad))
        raise InputError(
            path,
            f"data row {k + 1}: temperature {T[k]:g} C is not physical for a "
            f"rubber test (above absolute zero, at most {T_MAX_C:g} C)",
        )
    return T


def read_shift_csv(path):
    """-> (T_C, log10_aT) from a shift-factor CSV.

    Columns: a temperature ``T`` (C, or K when the header or units line says so) and either the
    decimal log of the shift factor (``log_aT``, ``log10_aT``) or the shift factor itself
    (``aT``, linear, must be positive; converted with log10). Convention: ``E(omega, T) =
    E(omega aT(T) / aT(T_ref), T_ref)``, so aT falls as T rises.

    Parameters
    ----------
    path : str or Path
        The CSV.

    Returns
    -------
    T_C, log10_aT : ndarray
    """
    names, urow, d = _read_table(path)
    T = _temperature_C(names, urow, d, path)
    il = _col(names, _LOGA_NAMES, path, "log_aT", required=False)
    if il is not None:
        return T, d[:, il]
    ia = _col(names, _LINA_NAMES, path, "shift factor", required=False)
    if ia is None:
        raise InputError(
            path, f"no shift-factor column (expected log10_aT/log_aT or linear aT; header {','.join(names)})"
        )
    a = d[:, ia]
    if np.any(a <= 0):
        raise InputError(path, "linear shift factors aT must be positive (use a log10_aT column for logs)")
    return T, np.log10(a)


def orient_shift(T_C, log10_aT, path, log=None):
    """aT must fall as T rises (relaxation speeds up when warm). A table rising with T uses the
    inverse convention (the factor divides omega): it is inverted, with a one-line note.

    Parameters
    ----------
    T_C, log10_aT : ndarray
        The table.
    path : str or Path
        File named in the note.
    log : callable, optional
        Says the note (:func:`pipelines.checks.run_warnings.note`).

    Returns
    -------
    T_C, log10_aT : ndarray
    """
    T, y = np.asarray(T_C, float), np.asarray(log10_aT, float)
    if T.size >= 2 and np.ptp(T) > 0 and np.polyfit(T, y, 1)[0] > 0:
        from pipelines.checks.run_warnings import note

        (log or note)(
            f"note: {path}: aT rises with temperature (inverse convention); using 1/aT so that "
            "E(omega, T) = E_ref(omega aT(T)/aT(T_ref)) with aT falling as T rises"
        )
        return T, -y
    return T, y


_SET_NAMES = ("set", "sweep", "segment", "set_id", "sweep_id")


def read_dma_sweeps_csv(path):
    """Raw DMA frequency sweeps -> (f_Hz, E_storage_Pa, E_loss_Pa, T_C, set_id or None).

    Columns: ``f`` [Hz] (or ``omega`` [rad/s]), ``E_stor``, ``E_loss`` (unit from a units line
    such as ``Hz, MPa, MPa, C, -``, or the header, ``E_stor_MPa``; default Pa), ``T`` [C] (or
    K) and optionally ``Set`` (the sweep each row belongs to; without it rows are grouped by
    temperature). The pyvisco layout (BOM, spaces after commas, units line) is one such file.

    Parameters
    ----------
    path : str or Path
        The CSV.

    Returns
    -------
    tuple
        (f_Hz, E_storage_Pa, E_loss_Pa, T_C, set_id or None).
    """
    f, E1, E2 = read_master_curve_csv(path)
    names, urow, d = _read_table(path)
    T = _temperature_C(names, urow, d, path)
    i_s = _col(names, _SET_NAMES, path, "set", required=False)
    sid = d[:, i_s] if i_s is not None else None
    return f, E1, E2, T, sid


def read_wlf_csv(path):
    """WLF constants from a one-row CSV ``C1,C2_K,T_s_C[,T_g_C]`` (``C2`` and ``T_s``/``T_ref``
    are accepted as names) -> dict for ``[shift] kind = "wlf"``; None when the file is a table.

    Parameters
    ----------
    path : str or Path
        The CSV.

    Returns
    -------
    dict or None
    """
    head, body = read_csv_rows(path)
    names = [h.strip().lower() for h in head]
    if "c1" not in names:
        return None
    alias = {
        "c1": "C1",
        "c2": "C2_K",
        "c2_k": "C2_K",
        "t_s_c": "T_s_C",
        "t_s": "T_s_C",
        "ts": "T_s_C",
        "t_ref_c": "T_s_C",
        "t_ref": "T_s_C",
        "t_g_c": "T_g_C",
        "tg": "T_g_C",
        "t_g": "T_g_C",
    }
    rows = [r for r in body if r and r[0].strip()]
    try:
        float(rows[0][0])
    except (ValueError, IndexError):
        rows = rows[1:]  # a units line
    if len(rows) != 1:
        raise InputError(path, "WLF constants: expected one data row C1,C2_K,T_s_C")
    out = {}
    for n, v in zip(names, rows[0]):
        if n in alias:
            try:
                out[alias[n]] = float(v)
            except ValueError:
                raise InputError(path, f"WLF constant {n} = {v!r} is not a number") from None
    missing = {"C1", "C2_K", "T_s_C"} - set(out)
    if missing:
        raise InputError(path, "WLF constants: missing " + ", ".join(sorted(missing)))
    return out
