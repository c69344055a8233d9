"""Build a rubber from a plain dict (the parsed rubber TOML, arrays already loaded).

Format (see RUBBER_TOML.md)::

    model = "sls" | "prony" | "master_curve"
    T_ref_C = 60.0
    [sls]          E1_Pa, a1, tau_s
    [prony]        E_inf_Pa, E_i_Pa = [...], tau_i_s = [...]
    [master_curve] f_Hz = [...], E_storage_Pa = [...], E_loss_Pa = [...]
    [shift]        kind = "wlf": C1, C2_K, T_s_C[, T_g_C]  |   kind = "table": T_C = [...], log10_aT = [...]
                   (or aT = [...], linear)
                   |  kind = "none"
    [thermal]      rho_kg_m3, c_v_J_kgK, conductivity_W_mK   (all optional)

Missing ``[shift]`` means the thesis WLF for "sls"/"prony" and no shift for "master_curve";
missing ``T_ref_C`` means 60 C (the thesis) for "sls"/"prony", and for a master curve the
temperature where its shift factor is 1 (:func:`unit_shift_temperature`). Raises ValueError naming the bad
key.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from .rubber import WLF, MasterCurve, Prony, ShiftTable, StandardLinearSolid, Thermal

__all__ = ["rubber_from_dict", "MODELS", "unit_shift_temperature"]

MODELS = ("sls", "prony", "master_curve")


def _num(d, key, where):
    if key not in d:
        raise ValueError(f"[{where}] needs '{key}'")
    try:
        x = float(d[key])
    except (TypeError, ValueError):
        raise ValueError(f"[{where}] '{key}' must be a number") from None
    if not np.isfinite(x):
        raise ValueError(f"[{where}] '{key}' must be finite")
    return x


def _arr(d, key, where):
    if key not in d:
        raise ValueError(f"[{where}] needs '{key}'")
    try:
        a = np.asarray(d[key], dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"[{where}] '{key}' must be a list of numbers") from None
    if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a)):
        raise ValueError(f"[{where}] '{key}' must be a non-empty list of finite numbers")
    return a


def _unknown(d, allowed, where):
    extra = sorted(set(d) - set(allowed))
    if extra:
        raise ValueError(f"[{where}] unknown key(s): {', '.join(extra)}")


def _shift(d, model):
    if d is None:
        return WLF.thesis() if model in ("sls", "prony") else None
    kind = str(d.get("kind", "wlf")).lower()
    if kind == "none":
        return None
    if kind == "wlf":
        _unknown(d, ("kind", "C1", "C2_K", "T_s_C", "T_g_C"), "shift")
        Tg = _num(d, "T_g_C", "shift") if "T_g_C" in d else None
        return WLF(_num(d, "C1", "shift"), _num(d, "C2_K", "shift"), _num(d, "T_s_C", "shift"), Tg)
    if kind == "table":
        _unknown(d, ("kind", "T_C", "log10_aT", "aT", "file"), "shift")
        if ("aT" in d) == ("log10_aT" in d):
            raise ValueError("[shift] kind = 'table' needs exactly one of 'log10_aT' or 'aT' (linear)")
        if "aT" in d:
            a = _arr(d, "aT", "shift")
            if np.any(a <= 0):
                raise ValueError("[shift] 'aT' (linear shift factors) must be positive")
            return ShiftTable(_arr(d, "T_C", "shift"), np.log10(a))
        return ShiftTable(_arr(d, "T_C", "shift"), _arr(d, "log10_aT", "shift"))
    raise ValueError(f"[shift] kind must be 'wlf', 'table' or 'none', not {kind!r}")


def unit_shift_temperature(shift: WLF | ShiftTable | None) -> float | None:
    """The temperature [C] where aT = 1 (log10 aT = 0): T_s of a WLF, the interpolated zero
    crossing of a table (the first one); None without a shift or a crossing.

    Parameters
    ----------
    shift : WLF, ShiftTable or None
        A rubber's temperature shift.

    Returns
    -------
    float or None
        The temperature of aT = 1 [C].
    """
    if isinstance(shift, WLF):
        return float(shift.T_s_C)
    if isinstance(shift, ShiftTable):
        T, y = shift.T_C, shift.log10_aT_values
        z = np.flatnonzero(y == 0)
        if z.size:
            return float(T[z[0]])
        c = np.flatnonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)
        if c.size:
            i = c[0]
            return float(T[i] - y[i] * (T[i + 1] - T[i]) / (y[i + 1] - y[i]))
    return None


def rubber_from_dict(d: Mapping[str, Any]) -> StandardLinearSolid | Prony | MasterCurve:
    """Rubber model from a dict (see module docstring); raises ValueError on bad content.

    Parameters
    ----------
    d : dict
        The parsed rubber TOML: ``model``, ``T_ref_C``, one table named after the model, optional
        ``shift`` and ``thermal`` tables.

    Returns
    -------
    StandardLinearSolid, Prony or MasterCurve
        The rubber model.

    Raises
    ------
    ValueError
        On unknown keys or bad values (one line).
    """
    if not isinstance(d, dict):
        raise ValueError("rubber description must be a table")
    _unknown(
        d,
        (
            "model",
            "name",
            "description",
            "source",
            "T_ref_C",
            "sls",
            "prony",
            "master_curve",
            "shift",
            "thermal",
        ),
        "top level",
    )
    model = str(d.get("model", "")).lower()
    if model not in MODELS:
        raise ValueError(f"'model' must be one of {', '.join(MODELS)}")
    shift = _shift(d.get("shift"), model)
    if "T_ref_C" in d:
        T_ref = _num(d, "T_ref_C", "top level")
    elif model == "master_curve":
        T_ref = unit_shift_temperature(shift)
        if T_ref is None:
            raise ValueError(
                "a master curve needs 'T_ref_C' (its temperature), or a shift table "
                "or WLF constants with aT = 1 somewhere"
            )
    else:
        T_ref = 60.0
    th = d.get("thermal", {})
    _unknown(th, ("rho_kg_m3", "c_v_J_kgK", "conductivity_W_mK"), "thermal")
    thermal = Thermal(**{k: _num(th, k, "thermal") for k in th})
    sec = d.get(model)
    if not isinstance(sec, dict):
        raise ValueError(f"model '{model}' needs a [{model}] table")
    if model == "sls":
        _unknown(sec, ("E1_Pa", "a1", "tau_s"), "sls")
        kw = {k: _num(sec, k, "sls") for k in sec}
        missing = [k for k in ("E1_Pa", "a1", "tau_s") if k not in sec]
        if missing:
            raise ValueError(f"[sls] is missing {', '.join(missing)} (no defaults are filled in)")
        return StandardLinearSolid(**kw, T_ref_C=T_ref, shift=shift, thermal=thermal)
    if model == "prony":
        _unknown(sec, ("E_inf_Pa", "E_i_Pa", "tau_i_s"), "prony")
        return Prony(
            _num(sec, "E_inf_Pa", "prony"),
            _arr(sec, "E_i_Pa", "prony"),
            _arr(sec, "tau_i_s", "prony"),
            T_ref,
            shift,
            thermal,
        )
    _unknown(sec, ("f_Hz", "E_storage_Pa", "E_loss_Pa", "file", "units"), "master_curve")
    return MasterCurve(
        _arr(sec, "f_Hz", "master_curve"),
        _arr(sec, "E_storage_Pa", "master_curve"),
        _arr(sec, "E_loss_Pa", "master_curve"),
        T_ref,
        shift,
        thermal,
    )
