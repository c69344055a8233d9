"""Fitting rubber models to measurements: a Prony series to a master curve, WLF to shift factors."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .rubber import WLF, MasterCurve, Prony

__all__ = ["fit_prony", "fit_wlf"]


def fit_prony(master_curve: MasterCurve, n_terms: int | None = None, per_decade: float = 1.0) -> Prony:
    """Fit a generalized Maxwell (Prony) series to a master curve.

    Relaxation times are fixed, log-spaced over the measured range
    (``tau_i`` from ``0.1/(2 pi f_max)`` to ``10/(2 pi f_min)``; ``n_terms`` of them, default
    ``per_decade`` per decade); ``E_inf`` and ``E_i >= 0`` solve a non-negative least-squares
    problem on the relative residuals of E' and E'' (each point weighted by 1/E' and 1/E'').

    Parameters
    ----------
    master_curve : MasterCurve
        The measured master curve.
    n_terms : int, optional
        Number of relaxation times (default: ``per_decade`` per decade of the curve).
    per_decade : float, optional
        Relaxation times per decade when ``n_terms`` is None.

    Returns
    -------
    Prony
        With the master curve's ``T_ref_C``, ``shift`` and ``thermal``.

    References
    ----------
    N.W. Tschoegl, The Phenomenological Theory of Linear Viscoelastic Behavior, Springer (1989),
    doi:10.1007/978-3-642-73602-5; C.L. Lawson, R.J. Hanson, Solving Least Squares Problems,
    SIAM (1995), doi:10.1137/1.9781611971217 (non-negative least squares).
    """
    f = master_curve.f_Hz
    w = 2 * np.pi * f
    decades = np.log10(f[-1] / f[0])
    if n_terms is None:
        n_terms = max(2, int(np.ceil((decades + 2) * per_decade)) + 1)
    tau = np.logspace(np.log10(1 / w[-1]) - 1, np.log10(1 / w[0]) + 1, int(n_terms))
    wt = w[:, None] * tau[None, :]
    re = wt**2 / (1 + wt**2)
    im = wt / (1 + wt**2)
    E1, E2 = master_curve.E_storage_Pa, master_curve.E_loss_Pa
    A = np.vstack(
        [
            np.hstack([np.ones((f.size, 1)), re]) / E1[:, None],
            np.hstack([np.zeros((f.size, 1)), im]) / E2[:, None],
        ]
    )
    b = np.concatenate([np.ones(f.size), np.ones(f.size)])
    from scipy.optimize import nnls

    coef, _ = nnls(A, b, maxiter=50 * A.shape[1])
    keep = coef[1:] > 0
    return Prony(
        float(coef[0]),
        coef[1:][keep],
        tau[keep],
        master_curve.T_ref_C,
        master_curve.shift,
        master_curve.thermal,
    )


def fit_wlf(T_C: ArrayLike, log10_aT: ArrayLike, T_s_C: float | None = None) -> WLF:
    """Fit WLF constants ``log10 aT = -C1 (T - T_s)/(C2 + T - T_s)`` to a shift table.

    ``T_s_C`` defaults to the table temperature where log10 aT = 0 (interpolated), i.e. the
    master curve's reference; if the table has no zero crossing, T_s is fitted too.
    Least squares in log10 aT (scipy.optimize.curve_fit), started from the linearised form
    ``(T - T_s)/log10 aT = -C2/C1 - (T - T_s)/C1``.

    Parameters
    ----------
    T_C : array_like
        Temperatures of the shift table [C].
    log10_aT : array_like
        Decimal log of the shift factor at each temperature.
    T_s_C : float, optional
        Reference temperature of the WLF form [C]; fitted when None and the table has no zero.

    Returns
    -------
    WLF
        The fitted constants ``C1``, ``C2_K``, ``T_s_C``.

    References
    ----------
    M.L. Williams, R.F. Landel, J.D. Ferry, J. Am. Chem. Soc. 77, 3701 (1955),
    doi:10.1021/ja01619a008.
    """
    from scipy.optimize import curve_fit

    T = np.asarray(T_C, dtype=float)
    y = np.asarray(log10_aT, dtype=float)
    o = np.argsort(T)
    T, y = T[o], y[o]
    if T_s_C is None:
        s = np.nonzero(np.diff(np.sign(y)) != 0)[0]
        z = np.nonzero(y == 0)[0]
        if z.size:
            T_s_C = float(T[z[0]])
        elif s.size:
            i = s[0]
            T_s_C = float(T[i] - y[i] * (T[i + 1] - T[i]) / (y[i + 1] - y[i]))
    fit_ts = T_s_C is None
    Ts0 = float(T[np.argmin(np.abs(y))]) if fit_ts else T_s_C
    d = T - Ts0
    ok = np.abs(y) > 1e-9
    slope, icpt = np.polyfit(d[ok], d[ok] / y[ok], 1)
    C1_0 = -1.0 / slope if slope != 0 else 10.0
    C2_0 = icpt * -C1_0
    if not (C1_0 > 0 and C2_0 > 0):
        C1_0, C2_0 = 10.0, 50.0

    if T_s_C is None:

        def wlf_free(t, c1, c2, ts):  # log10 aT with T_s fitted too
            return -c1 * (t - ts) / (c2 + t - ts)

        p, _ = curve_fit(wlf_free, T, y, p0=[C1_0, C2_0, Ts0], maxfev=20000)
        return WLF(float(p[0]), float(p[1]), float(p[2]))
    T_s = float(T_s_C)

    def wlf_fixed(t, c1, c2):  # log10 aT at the given T_s
        return -c1 * (t - T_s) / (c2 + t - T_s)

    p, _ = curve_fit(wlf_fixed, T, y, p0=[C1_0, C2_0], maxfev=20000)
    return WLF(float(p[0]), float(p[1]), T_s)
