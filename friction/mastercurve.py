"""Master curves from raw DMA frequency sweeps by time-temperature superposition (TTS).

A DMA run measures E'(f) and E''(f) over a few decades of frequency f [Hz] at a series of
temperatures. For a thermorheologically simple rubber the sweep at temperature T, plotted
against ``f aT(T)``, falls on the sweep at the reference temperature T_ref (``aT(T_ref) = 1``,
aT > 1 below T_ref): ``E(f, T) = E_ref(f aT(T))`` (Ferry, *Viscoelastic properties of
polymers*, 1980, ch. 11; docs: Theory, the convention of :mod:`friction.rubber`).

Shift factors (:func:`pair_shift`, :func:`shift_factors`). Each sweep is compared with its
neighbours in temperature. A pair's relative shift is first estimated at three modulus levels
spanning the two sweeps' common modulus range (or the gap between them): from E' fitted by a
power law with an offset, ``E' = c f^b + e`` (smooths scatter, bridges gaps), and from E'' by
straight lines in log-log; the two are weighted by ``slope^2 / residual^2`` (the inverse
variance of a horizontal shift: a flat or scattered modulus locates a shift poorly, so the
glassy plateau leans on E'' and the loss peak on E'). Where the sweeps overlap by a decade or
more, the shift is refined by overlaying quadratic fits of log E' and log E'' over the common
window. All pairs then enter one weighted least-squares problem for the shifts, with the sweep
nearest T_ref fixed; pairs whose standard error exceeds half a decade (both moduli flat within
their scatter, e.g. on the rubbery plateau) are dropped, and sweeps left unconnected continue
the linear trend in T of their nearest placed neighbours (reported as such). log10 aT at T_ref
itself is interpolated and subtracted when T_ref is not a sweep temperature.

Accuracy (tests/test_rubber_master.py): sweeps sampled from pyvisco's published master curve at
its 21 temperatures and shift factors (0.1-100 Hz, 0.3 % scatter on E', 1 % on E'') give shift
factors within 0.19 decade of the published ones for the sweeps placed by overlap, and within
0.23-0.36 decade for all (the plateau sweeps placed by the trend) over 10 noise seeds (the
published curve itself has jumps of ~0.1 decade between sweeps), E' within 6 %.

WLF (:func:`friction.fit_wlf`) is fitted to the table with T_s = T_ref; a Prony series
(:func:`friction.fit_prony`) to the smoothed master curve.

Master curve (:func:`smooth_master`): the shifted points, smoothed by a local linear
regression of (log f, log E) with Gaussian weights (width ``0.2`` decade) on a log grid.

Units: f in Hz, moduli in Pa, temperatures in C, shift factors as decimal logarithms.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .rubber import WLF, MasterCurve, Prony
from .sweep_pairs import fit_power_offset, group_sweeps, pair_shift

TREND_N = 4  # placed sweeps whose linear trend in T places an unconnected sweep

__all__ = [
    "group_sweeps",
    "pair_shift",
    "shift_factors",
    "smooth_master",
    "TTSResult",
    "build_master",
    "fit_power_offset",
]


def shift_factors(
    f_Hz: ArrayLike,
    E1_Pa: ArrayLike,
    E2_Pa: ArrayLike,
    T_C: ArrayLike,
    T_ref_C: float,
    set_id: ArrayLike | None = None,
    max_sigma_decades: float = 0.5,
    reach: int = 2,
) -> tuple[NDArray[np.float64], NDArray[np.float64], list[NDArray[np.intp]], list[dict[str, Any]]]:
    """log10 aT of every sweep relative to T_ref (see module docstring).

    Every sweep is compared with its ``reach`` nearest neighbours in temperature on each side
    (:func:`pair_shift` gives ``log10 aT_j - log10 aT_i`` for the pair i, j; beyond the nearest
    neighbour only where the two sweeps overlap in frequency by a decade). A pair's standard
    error is estimated as ``1 / sqrt(w_storage + w_loss)`` (the inverse-variance weights); pairs
    above ``max_sigma_decades`` (both moduli flat within their scatter, e.g. on the rubbery
    plateau) are dropped. The shifts then solve the weighted least-squares problem
    ``sum w_ij (s_j - s_i - d_ij)^2`` with the sweep nearest T_ref fixed (redundant pairs damp the
    random walk of a neighbour-to-neighbour chain). Sweeps not connected to the reference by
    kept pairs continue the linear trend in T of the four nearest placed sweeps (method
    "trend"; a global WLF fit extrapolates worse there). Finally log10 aT(T_ref), interpolated,
    is subtracted.

    Returns (T_sweep (n,), log10_aT (n,), groups, info) with ``log10 aT(T_ref) = 0``; info is a
    list per sweep of dicts ``method`` ("reference", "overlap" or "trend") and
    ``sigma_decades`` (standard error from the least squares; NaN for "trend").

    Parameters
    ----------
    f_Hz, E1_Pa, E2_Pa : array_like
        Raw sweep points: frequency [Hz], storage and loss moduli [Pa].
    T_C : array_like
        Temperature of each point [C].
    T_ref_C : float
        Reference temperature of the master curve [C].
    set_id : array_like, optional
        Sweep label of each point (else sweeps are grouped by temperature).
    max_sigma_decades : float, optional
        Pairs with a larger standard error are dropped [decades].
    reach : int, optional
        Neighbours compared on each side.

    Returns
    -------
    T_sweep : ndarray
        Mean temperature of each sweep [C].
    log10_aT : ndarray
        Shift of each sweep, 0 at T_ref.
    groups : list of ndarray
        Rows of each sweep.
    info : list of dict
        How each shift was found, and its standard error [decades].
    """
    f, E1, E2 = (np.asarray(a, dtype=float) for a in (f_Hz, E1_Pa, E2_Pa))
    Tm, groups = group_sweeps(T_C, set_id)
    n = len(groups)
    if n < 2:
        raise ValueError("need sweeps at two or more temperatures")
    for g in groups:
        if g.size < 4 or np.unique(f[g]).size < 4:
            raise ValueError("every sweep needs at least 4 distinct frequencies")
    if not (Tm[0] - 1e-9 <= T_ref_C <= Tm[-1] + 1e-9):
        raise ValueError(
            f"reference temperature {T_ref_C:g} C lies outside the sweeps' {Tm[0]:.3g}..{Tm[-1]:.3g} C"
        )
    k = int(np.argmin(np.abs(Tm - T_ref_C)))
    rows = []
    for i in range(n):
        for j in range(i + 1, min(n, i + 1 + reach)):
            gi, gj = groups[i], groups[j]
            try:
                d, dd = pair_shift(f[gi], E1[gi], E2[gi], f[gj], E1[gj], E2[gj])
            except ValueError:
                continue
            sig = 1.0 / np.sqrt(dd["w_storage"] + dd["w_loss"])
            if j > i + 1 and dd["overlap"] is None:  # distant pairs only where the sweeps overlap
                continue
            if sig <= max_sigma_decades and np.isfinite(d):
                rows.append((i, j, d, sig))
    # the sweeps connected to the reference by kept pairs
    conn = {k}
    grew = True
    while grew:
        grew = False
        for i, j, _, _ in rows:
            if (i in conn) != (j in conn):
                conn |= {i, j}
                grew = True
    idx = sorted(conn - {k})
    la = np.full(n, np.nan)
    la[k] = 0.0
    info = [dict(method="trend", sigma_decades=float("nan")) for _ in range(n)]
    info[k] = dict(method="reference", sigma_decades=0.0)
    if idx:
        col = {s: c for c, s in enumerate(idx)}
        use = [r for r in rows if r[0] in conn and r[1] in conn]
        A = np.zeros((len(use), len(idx)))
        b = np.zeros(len(use))
        for r, (i, j, d, sig) in enumerate(use):
            if j != k:
                A[r, col[j]] += 1.0 / sig
            if i != k:
                A[r, col[i]] -= 1.0 / sig
            b[r] = d / sig
        sol, *_ = np.linalg.lstsq(A, b, rcond=None)
        cov = np.linalg.pinv(A.T @ A)
        for s_, c in col.items():
            la[s_] = sol[c]
            info[s_] = dict(method="overlap", sigma_decades=float(np.sqrt(max(cov[c, c], 0.0))))
    # unconnected sweeps, nearest to the placed ones first: the local trend
    while np.any(np.isnan(la)):
        known = np.flatnonzero(np.isfinite(la))
        miss = np.flatnonzero(np.isnan(la))
        b_ = miss[np.argmin([np.min(np.abs(Tm[known] - Tm[m])) for m in miss])]
        near = known[np.argsort(np.abs(Tm[known] - Tm[b_]))[:TREND_N]]
        if near.size >= 2 and np.ptp(Tm[near]) > 0:
            slope, icpt = np.polyfit(Tm[near], la[near], 1)
            la[b_] = float(icpt + slope * Tm[b_])
        else:
            la[b_] = la[near[0]]
    la -= np.interp(T_ref_C, Tm, la)
    return Tm, la, groups, info


def smooth_master(
    f_Hz: ArrayLike, E1_Pa: ArrayLike, E2_Pa: ArrayLike, per_decade: int = 10, width_decades: float = 0.2
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Smoothed master curve on a log grid from scattered shifted points.

    Local linear regression of log10 E on log10 f with Gaussian weights of standard deviation
    ``width_decades``, evaluated every ``1/per_decade`` decade over the points' range.
    Returns (f_grid, E1, E2) [Hz, Pa, Pa].

    Parameters
    ----------
    f_Hz, E1_Pa, E2_Pa : array_like
        Shifted points: frequency [Hz], storage and loss moduli [Pa].
    per_decade : int, optional
        Output points per decade.
    width_decades : float, optional
        Standard deviation of the Gaussian weights [decades].

    Returns
    -------
    f_grid : ndarray
        Frequencies [Hz].
    E1, E2 : ndarray
        Smoothed storage and loss moduli [Pa].
    """
    x = np.log10(np.asarray(f_Hz, float))
    ys = np.log10(np.column_stack([E1_Pa, E2_Pa]))
    g = np.arange(np.ceil(x.min() * per_decade), np.floor(x.max() * per_decade) + 1) / per_decade
    d = x[None, :] - g[:, None]  # (m, n)
    w = np.exp(-0.5 * (d / width_decades) ** 2)
    S0, S1, S2 = w.sum(1), (w * d).sum(1), (w * d * d).sum(1)
    T0 = w @ ys  # (m, 2)
    T1 = (w * d) @ ys
    den = S0 * S2 - S1 * S1
    ok = (S0 > 1e-3) & (den > 1e-12 * np.maximum(S0 * S2, 1e-300))
    y = (S2[:, None] * T0 - S1[:, None] * T1) / np.where(ok, den, 1.0)[:, None]
    return 10.0 ** g[ok], 10.0 ** y[ok, 0], 10.0 ** y[ok, 1]


@dataclass(frozen=True, eq=False)
class TTSResult:
    """What :func:`build_master` returns.

    T_ref_C : reference temperature [C].  T_sweep_C, log10_aT : the shift table (n,).
    shifted : dict of the shifted raw points ``f_Hz, E_storage_Pa, E_loss_Pa, T_C, sweep``.
    master : MasterCurve (smoothed, at T_ref, with the shift table attached).
    wlf : WLF fitted to the table; wlf_rms_decades, wlf_max_decades: its misfit.
    prony : Prony series fitted to the smoothed curve; prony_rms : its rms relative misfit of
    E' and E'' (fractions).  sweep_info : per sweep, how its shift was found and its estimated
    standard error (:func:`shift_factors`).

    Attributes
    ----------
    T_ref_C : float
        Reference temperature [C].
    T_sweep_C, log10_aT : ndarray
        The shift table.
    shifted : dict
        Shifted raw points.
    master : MasterCurve
        Smoothed master curve at the reference temperature.
    wlf : WLF
        WLF constants fitted to the table.
    wlf_rms_decades, wlf_max_decades : float
        Misfit of the WLF fit [decades].
    prony : Prony
        Prony series fitted to the master curve.
    prony_rms : float
        Rms relative misfit of the Prony series.
    sweep_info : list of dict
        How each sweep's shift was found.
    """

    T_ref_C: float
    T_sweep_C: np.ndarray
    log10_aT: np.ndarray
    shifted: dict
    master: MasterCurve
    wlf: WLF
    wlf_rms_decades: float
    wlf_max_decades: float
    prony: Prony
    prony_rms: float
    sweep_info: list


def build_master(
    f_Hz: ArrayLike,
    E1_Pa: ArrayLike,
    E2_Pa: ArrayLike,
    T_C: ArrayLike,
    T_ref_C: float,
    set_id: ArrayLike | None = None,
    prony_per_decade: float = 1.5,
) -> TTSResult:
    """Raw sweeps -> shift table, smoothed master curve, WLF fit and Prony series (see module
    docstring). Raises ValueError with a one-line reason on unusable data.

    Parameters
    ----------
    f_Hz, E1_Pa, E2_Pa : array_like
        Raw sweeps: frequency [Hz], storage and loss moduli [Pa].
    T_C : array_like
        Temperature of each point [C].
    T_ref_C : float
        Reference temperature of the master curve [C].
    set_id : array_like, optional
        Sweep label of each point.
    prony_per_decade : float, optional
        Relaxation times per decade of the fitted Prony series.

    Returns
    -------
    TTSResult
        Shift table, master curve, WLF fit and Prony series.

    References
    ----------
    J.D. Ferry, Viscoelastic Properties of Polymers, 3rd ed., Wiley (1980), chapter 11
    (time-temperature superposition).
    """

    from .fitting import fit_prony, fit_wlf
    from .rubber import ShiftTable

    f, E1, E2, T = (np.asarray(a, dtype=float) for a in (f_Hz, E1_Pa, E2_Pa, T_C))
    if not (f.shape == E1.shape == E2.shape == T.shape and f.ndim == 1):
        raise ValueError("f, E_stor, E_loss and T must be 1D arrays of equal length")
    if not (
        np.all(np.isfinite(np.stack([f, E1, E2, T]))) and np.all(f > 0) and np.all(E1 > 0) and np.all(E2 > 0)
    ):
        raise ValueError("frequencies and moduli must be positive and finite")
    Tm, la, groups, info = shift_factors(f, E1, E2, T, T_ref_C, set_id)
    sweep = np.empty(f.size, int)
    fs = np.empty(f.size)
    for i, g in enumerate(groups):
        sweep[g] = i
        fs[g] = f[g] * 10 ** la[i]
    o = np.argsort(fs, kind="stable")
    shifted = dict(f_Hz=fs[o], E_storage_Pa=E1[o], E_loss_Pa=E2[o], T_C=T[o], sweep=sweep[o])
    table = ShiftTable(Tm, la)
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        wlf = fit_wlf(Tm, la, T_s_C=T_ref_C)
    r = wlf.log10_aT(Tm) - la
    fg, g1, g2 = smooth_master(fs, E1, E2)
    master = MasterCurve(fg, g1, g2, T_ref_C=float(T_ref_C), shift=table)
    prony = fit_prony(master, per_decade=prony_per_decade)
    Ep = prony.modulus_ref(2 * np.pi * fg)
    prms = float(np.sqrt(np.mean(np.concatenate([(Ep.real / g1 - 1) ** 2, (Ep.imag / g2 - 1) ** 2]))))
    return TTSResult(
        float(T_ref_C),
        Tm,
        la,
        shifted,
        master,
        wlf,
        float(np.sqrt(np.mean(r * r))),
        float(np.max(np.abs(r))),
        prony,
        prms,
        info,
    )
