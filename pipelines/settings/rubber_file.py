"""Read a rubber model from a TOML file (format: friction/RUBBER_TOML.md).

The TOML is parsed with :mod:`tomllib`; tables that reference data files
(``[master_curve] file = "x.csv"``, ``[shift] file = "y.csv"``) are loaded here, relative to the
TOML's folder, and the resulting plain dict goes to :func:`friction.rubber_from_dict` (the
friction package reads no files).

The CSV tables (master curve, shift factors, DMA sweeps, WLF constants: their columns and
units) are read by ``pipelines.settings._rubber_tables``, whose readers are re-exported here.
"""

from __future__ import annotations

import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10: the tomli backport (a dependency there)
    import tomli as tomllib

import numpy as np

from pipelines.settings._rubber_tables import (
    orient_shift,
    read_dma_sweeps_csv,
    read_master_curve_csv,
    read_shift_csv,
    read_wlf_csv,
)
from roadscan.errors import InputError

__all__ = [
    "load_rubber",
    "read_master_curve_csv",
    "read_shift_csv",
    "rubber_from_csv_files",
    "orient_shift",
    "read_dma_sweeps_csv",
    "read_wlf_csv",
]


def _not_toml(path, exc):
    """The one-line message of a --rubber file that is not TOML: a CSV (a ``.csv`` name, or
    comma-separated lines with no ``=``) is told to go to ``--master-curve`` (a master curve) or
    ``--shift-table`` (a shift table); anything else is "invalid TOML (reason)"."""
    try:
        lines = [
            ln.strip() for ln in Path(path).read_text(encoding="utf-8-sig", errors="replace").splitlines()
        ]
    except OSError:
        lines = []
    lines = [ln for ln in lines if ln and not ln.startswith("#")][:20]
    csv_like = path.suffix.lower() in (".csv", ".tsv", ".txt") or (
        lines and all("=" not in ln and ("," in ln or ";" in ln or "\t" in ln) for ln in lines)
    )
    if csv_like:
        return (
            "is a CSV table, not a rubber TOML: give a master curve with --master-curve FILE "
            "(and its shift factors with --shift-table FILE), or write a TOML "
            "(friction/RUBBER_TOML.md) for --rubber"
        )
    return f"invalid TOML ({exc})"


def load_rubber(path):
    """Rubber model from a TOML file; raises :class:`roadscan.errors.InputError` on bad input.

    Parameters
    ----------
    path : str or Path
        Rubber TOML file.

    Returns
    -------
    StandardLinearSolid, Prony or MasterCurve
    """
    import friction

    path = Path(path)
    try:
        with open(path, "rb") as fh:  # a byte-order mark (Windows editors) is not TOML
            d = tomllib.loads(fh.read().decode("utf-8-sig"))
    except FileNotFoundError:
        raise InputError(path, "no such file") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(path, _not_toml(path, exc)) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(path, f"cannot read ({exc})") from None
    base = path.parent
    mc = d.get("master_curve")
    if isinstance(mc, dict) and "file" in mc:
        f, E1, E2 = read_master_curve_csv(base / str(mc["file"]), mc.get("units"))
        d["master_curve"] = {"f_Hz": f, "E_storage_Pa": E1, "E_loss_Pa": E2}
    sh = d.get("shift")
    if isinstance(sh, dict) and "file" in sh:
        T, a = orient_shift(*read_shift_csv(base / str(sh["file"])), base / str(sh["file"]))
        d["shift"] = {"kind": "table", "T_C": T, "log10_aT": a}
    try:
        rubber = friction.rubber_from_dict(d)
    except (ValueError, TypeError) as exc:
        raise InputError(path, str(exc)) from None
    _check_modulus_range(path, rubber)
    return rubber


def _check_modulus_range(path, rubber):
    """Refuse a rubber whose largest modulus |E(omega)| at T_ref over omega = 1e-8..1e14 rad/s
    lies outside 1e5..1e11 Pa (glassy rubber ~1e9 Pa, glass 7e10 Pa): a units slip in the
    TOML (MPa numbers under *_Pa keys give 1e3 Pa; 1e15 Pa is stiffer than diamond)."""
    try:
        top = float(np.nanmax(np.abs(rubber.modulus(np.logspace(-8, 14, 45)))))
    except (AttributeError, TypeError, ValueError):
        return
    if not 1e5 <= top <= 1e11:
        raise InputError(
            path,
            f"units? its modulus reaches at most {top:.3g} Pa, outside the "
            f"1e5..1e11 Pa of any rubber (glassy about 1e9 Pa): are the "
            f"values in Pa as the keys say?",
        )


def rubber_from_csv_files(master_csv, shift_csv=None, T_ref_C=None, units=None):
    """MasterCurve rubber from a master-curve CSV and an optional shift-table CSV (the
    ``roadscan friction --master-curve/--shift-table/--reference-temperature`` path).

    Parameters
    ----------
    master_csv : str or Path
        Master-curve CSV.
    shift_csv : str or Path, optional
        Shift table or WLF CSV.
    T_ref_C : float, optional
        Reference temperature [C].
    units : str, optional
        Modulus unit.

    Returns
    -------
    MasterCurve
    """
    import friction

    f, E1, E2 = read_master_curve_csv(master_csv, units)
    d = {"model": "master_curve", "master_curve": {"f_Hz": f, "E_storage_Pa": E1, "E_loss_Pa": E2}}
    if T_ref_C is not None:
        d["T_ref_C"] = float(T_ref_C)
    if shift_csv:
        wlf = read_wlf_csv(shift_csv)
        if wlf is not None:
            d["shift"] = {"kind": "wlf", **wlf}
        else:
            T, a = orient_shift(*read_shift_csv(shift_csv), shift_csv)
            d["shift"] = {"kind": "table", "T_C": T, "log10_aT": a}
    try:
        return friction.rubber_from_dict(d)
    except (ValueError, TypeError) as exc:
        raise InputError(shift_csv or master_csv, str(exc)) from None
