"""How well a rubber's data support a friction run: the frequencies the run needs against the
master curve's measured range, and how well WLF describes a shift table.

Frequencies. At sliding speed v a wave vector q excites the rubber at ``omega = q v cos(phi)``;
Persson's integrals need ``f = v q / (2 pi)`` from ``v_min q0 / 2 pi`` to ``v_max q1 / 2 pi``
at the temperature T of the rubber. A master curve is tabulated at ``T_ref``; by
time-temperature superposition ``E(omega, T) = E_ref(omega a)`` with ``log10 a`` from
:func:`friction.rubber.log10_shift`, so the run reads the curve at ``f a``. With flash heating
T spans ``[T0, T_max]``; aT falls with T, so the hottest state sets the lowest frequency.
"""

from __future__ import annotations

import warnings
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from .rubber import MasterCurve, Rubber, ShiftTable, log10_shift

__all__ = ["frequency_coverage", "wlf_fit_report"]


def frequency_coverage(
    rubber: Rubber,
    v_m_per_s: ArrayLike,
    q0_per_m: float,
    q1_per_m: float,
    T0_C: float | None = None,
    T_max_C: float | None = None,
    wlf_form: Literal["relative", "literal"] = "relative",
    T_q_C: ArrayLike | None = None,
    q_per_m: ArrayLike | None = None,
) -> dict[str, Any]:
    """Frequencies [Hz] a run needs, read on the reference-temperature curve, vs the curve's.

    Parameters
    ----------
    rubber : rubber model
        Any rubber; the curve's range is reported for a :class:`MasterCurve` only.
    v_m_per_s : array_like
        Speeds [m/s].
    q0_per_m, q1_per_m : float
        Integration band [1/m].
    T0_C : float, optional
        Background temperature [C] (None: ``T_ref``).
    T_max_C : float, optional
        Hottest flash temperature [C] (None: isothermal).
    T_q_C, q_per_m : ndarray, optional
        Flash temperatures (nv, nq) on the run's wave vectors (nq,): the needed range is then the
        exact one, min/max of ``v q aT(T_q(v, q)) / 2 pi``.

    Returns
    -------
    dict
        ``f_needed_Hz`` [lo, hi] (at T_ref, i.e. ``v q a / 2 pi``), ``log10_shift`` [at T0, at
        T_max], ``f_curve_Hz`` [lo, hi] or None, ``extrapolated_decades_below`` and ``_above``
        (>= 0; None without a curve) and ``extrapolated_decades`` (their max).
    """
    v = np.asarray(v_m_per_s, dtype=float)
    T0 = rubber.T_ref_C if T0_C is None else float(T0_C)
    Ts = [T0] if T_max_C is None else [T0, float(T_max_C)]
    with np.errstate(over="ignore", invalid="ignore"):
        sh = np.clip(np.asarray(log10_shift(rubber, np.asarray(Ts), wlf_form, T0), float), -300, 300)
    lo = float(np.log10(v.min() * q0_per_m / (2 * np.pi)) + sh.min())
    hi = float(np.log10(v.max() * q1_per_m / (2 * np.pi)) + sh.max())
    if T_q_C is not None and q_per_m is not None:
        with np.errstate(over="ignore", invalid="ignore"):
            s_q = np.clip(
                np.asarray(log10_shift(rubber, np.asarray(T_q_C, float), wlf_form, T0), float), -300, 300
            )
        lf = np.log10(v[:, None] * np.asarray(q_per_m, float)[None, :] / (2 * np.pi)) + s_q
        lo, hi = float(lf.min()), float(lf.max())
    out: dict[str, Any] = dict(
        f_needed_Hz=[10.0**lo, 10.0**hi],
        temperatures_C=Ts,
        log10_shift=[float(x) for x in sh],
        f_curve_Hz=None,
        extrapolated_decades_below=None,
        extrapolated_decades_above=None,
        extrapolated_decades=None,
    )
    if isinstance(rubber, MasterCurve):
        a, b = rubber.f_range_Hz()
        below = max(0.0, float(np.log10(a)) - lo)
        above = max(0.0, hi - float(np.log10(b)))
        out.update(
            f_curve_Hz=[a, b],
            extrapolated_decades_below=below,
            extrapolated_decades_above=above,
            extrapolated_decades=max(below, above),
            extrapolate=rubber.extrapolate,
        )
    return out


def wlf_fit_report(shift: object, T_s_C: float | None = None) -> dict[str, Any] | None:
    """WLF constants fitted to a :class:`ShiftTable` and the misfit in decades.

    ``log10 aT = -C1 (T - T_s) / (C2 + T - T_s)`` fitted by :func:`friction.fit_wlf` (least
    squares in log10 aT; T_s where the table crosses log10 aT = 0 unless given).

    Returns
    -------
    dict or None
        ``C1``, ``C2_K``, ``T_s_C``, ``rms_decades``, ``max_abs_decades``, ``n_points``; None
        when ``shift`` is not a table or the fit fails.

    Parameters
    ----------
    shift : object
        The rubber's shift (only a :class:`friction.ShiftTable` is fitted).
    T_s_C : float, optional
        Reference temperature of the WLF form [C].
    """
    from .fitting import fit_wlf

    if not isinstance(shift, ShiftTable):
        return None
    T, y = shift.T_C, shift.log10_aT_values

    try:
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            w = fit_wlf(T, y, T_s_C)
            r = w.log10_aT(T) - y
    except (RuntimeError, ValueError, TypeError, np.linalg.LinAlgError):
        return None
    if not np.all(np.isfinite(r)):
        return None
    return dict(
        C1=float(w.C1),
        C2_K=float(w.C2_K),
        T_s_C=float(w.T_s_C),
        rms_decades=float(np.sqrt(np.mean(r * r))),
        max_abs_decades=float(np.max(np.abs(r))),
        n_points=int(T.size),
    )
