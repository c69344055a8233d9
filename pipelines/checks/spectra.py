"""Plausibility of spectra, wave vectors, fits and friction results (the spectra rows of the
table in :mod:`pipelines.checks.validate`, which re-exports every name): refuse with a one-line
:class:`roadscan.InputError`, or warn (:func:`pipelines.checks.run_warnings.warn`).
"""

from __future__ import annotations

import numpy as np

from pipelines.checks.numbers import MAX_PSD_SLOPE, MU_MAX, MU_WARN, Q_MAX_PER_M, Q_MIN_PER_M, finite_number
from pipelines.checks.run_warnings import warn
from roadscan.errors import InputError

__all__ = ["check_psd_rows", "check_psd_shape", "check_wave_vector", "check_q1", "check_fit", "check_mu"]


def check_psd_rows(q, C, path=None):
    """Every row of a tabulated PSD must have finite q > 0 and finite C > 0; the first bad row
    is refused by its number among the data rows (1 = first row after the header).

    Parameters
    ----------
    q, C : ndarray
        Wave vectors [1/m] and C [m^4].
    path : str or Path, optional
        File named.

    Returns
    -------
    None
    """
    q = np.asarray(q, dtype=float)
    C = np.asarray(C, dtype=float)
    bad = ~(np.isfinite(q) & (q > 0) & np.isfinite(C) & (C > 0))
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError(
            path,
            f"data row {i + 1}: q = {q[i]:g}, C = {C[i]:g}: need finite q > 0 "
            f"and C > 0 ({int(bad.sum())} such row{'s' if bad.sum() > 1 else ''})",
        )
    out = (q < Q_MIN_PER_M) | (q > Q_MAX_PER_M)
    if out.any():
        i = int(np.argmax(out))
        raise InputError(
            path,
            f"data row {i + 1}: q = {q[i]:g} 1/m is outside {Q_MIN_PER_M:g} .. "
            f"{Q_MAX_PER_M:g} 1/m (wavelengths 63 km .. 0.06 nm): units?",
        )


def check_psd_shape(q, C, path=None):
    """A surface's PSD falls with q: refuse a spectrum whose least-squares log-log slope over
    its band is above +1 (e.g. rising as q^3).

    Parameters
    ----------
    q, C : ndarray
        Wave vectors [1/m] and C [m^4].
    path : str or Path, optional
        File named.

    Returns
    -------
    None
    """
    q = np.asarray(q, dtype=float)
    C = np.asarray(C, dtype=float)
    ok = np.isfinite(q) & np.isfinite(C) & (q > 0) & (C > 0)
    if ok.sum() < 3:
        raise InputError(path, f"the PSD has {int(ok.sum())} usable rows (need at least 3)")
    lq, lc = np.log(q[ok]), np.log(C[ok])
    if np.ptp(lq) == 0:
        raise InputError(path, "the PSD has a single wave vector")
    slope = float(np.polyfit(lq, lc, 1)[0])
    if slope > MAX_PSD_SLOPE:
        raise InputError(
            path,
            f"the PSD rises with q (log-log slope {slope:+.2f}): not the "
            f"spectrum of a surface, which falls as q^-2(1+H)",
        )


def check_wave_vector(q_per_m, flag):
    """A wave vector [1/m] given by a flag: finite, from 1e-4 1/m (2 pi / q = 63 km, longer
    than any surveyed line) to 1e11 1/m (0.06 nm: Persson's cut-offs stop at the atomic scale,
    about 1e10 1/m). Below, the self-affine C(q0) overflows (a fuzz finding: q0 = 2.2e-308).

    Parameters
    ----------
    q_per_m : float
        Wave vector [1/m].
    flag : str
        Flag named.

    Returns
    -------
    float
    """
    v = finite_number(q_per_m, flag)
    if not Q_MIN_PER_M <= v <= Q_MAX_PER_M:
        raise InputError(
            None,
            f"{flag}{'' if flag.endswith('=') else ' '}{v:g} 1/m: must be a wave vector from "
            f"{Q_MIN_PER_M:g} 1/m (a wavelength of 63 km) to {Q_MAX_PER_M:g} 1/m "
            f"(a wavelength of 0.06 nm)",
        )
    return v


def check_q1(q1_per_m, q_lo_per_m, flag="--q1"):
    """q1 [1/m] must be finite and above the spectrum's lowest wave vector ``q_lo``.

    Parameters
    ----------
    q1_per_m : float or None
        q1 [1/m].
    q_lo_per_m : float
        Lowest wave vector of the spectrum [1/m].
    flag : str, optional
        Flag named.

    Returns
    -------
    float or None
    """
    if q1_per_m is None:
        return None
    v = finite_number(q1_per_m, flag)
    if not v > q_lo_per_m:
        raise InputError(
            None, f"{flag} {v:g} 1/m: must exceed the spectrum's lowest wave vector q0 = {q_lo_per_m:.4g} 1/m"
        )
    return v


def check_fit(fit, name=""):
    """Warn when a self-affine fit is outside its meaning: Hurst exponent outside [0, 1]
    (e.g. a white-noise or a trend-dominated scan) or a non-finite h0.

    Parameters
    ----------
    fit : SelfAffineFit
        The fit.
    name : str, optional
        Scan name.

    Returns
    -------
    None
    """
    h = getattr(fit, "hurst", None)
    if h is None or not np.isfinite(h):
        raise InputError(name or None, "the self-affine fit failed (Hurst exponent not finite)")
    if not 0.0 <= h <= 1.0:
        undefined = " (h0 is undefined for H <= 0: null in summary.json)" if h <= 0 else ""
        warn(
            f"{name + ': ' if name else ''}Hurst exponent {h:.3g} lies outside [0, 1]: the spectrum "
            f"is not self-affine over the fitted band; H, h0 and mu(v) are not meaningful{undefined}"
        )


def check_mu(mu, what="mu", warn_high=True):
    """Friction results: refuse non-finite values and mu > 100 (no physical meaning);
    warn when mu > 5 (unless ``warn_high`` is False: the caller diagnoses it, as analyse does
    with :mod:`pipelines.chain.provenance`).

    Parameters
    ----------
    mu : ndarray
        Friction coefficients.
    what : str, optional
        Name in messages.
    warn_high : bool, optional
        Warn above 5.

    Returns
    -------
    ndarray
    """
    mu = np.asarray(mu, dtype=float)
    if mu.size and not np.all(np.isfinite(mu)):
        n = int(np.count_nonzero(~np.isfinite(mu)))
        raise InputError(
            None, f"{what}: {n} of {mu.size} values are not finite (check h0, the PSD and the rubber model)"
        )
    top = float(np.max(mu)) if mu.size else 0.0
    if top > MU_MAX:
        raise InputError(
            None,
            f"{what} reaches {top:.3g}: not physical (> {MU_MAX:g}); check the "
            f"PSD (does it fall with q?) and the rubber model",
        )
    if top > MU_WARN and warn_high:
        warn(
            f"{what} reaches {top:.3g}, unusually high for rubber on a road: likely the band "
            f"(its short end in the noise, or extended beyond the spectrum: --q1), the units "
            f"(--units) or the rubber (--rubber)"
        )
    return mu
