"""Self-affine fit of an angular-averaged PSD, band detection, roll-off and extension.

Model (docs: Theory, thesis appendix A), Persson's normalisation:

    C(q) = (H / 2 pi) (h0 / q0)^2 (q / q0)^(-2(H+1))       q0 <= q <= q1,

so that 2 pi int_{q0}^{q1} q C dq = (h0^2 / 2) (1 - (q1/q0)^(-2H)) and
h0 = sqrt(2) h_band / sqrt(1 - (q1/q0)^(-2H)) with h_band the rms height of the band
(``band_rms_m``). Below q0 a detected roll-off is modelled as a plateau C(q0).

The fit is ordinary least squares of log10 C against log10 q over the band (log-spaced rings
weigh every decade alike); H = -slope/2 - 1 and its standard error is half the slope's
standard error from the regression. q0 is the roll-off wave vector where one is detected,
else the lowest wave vector of the spectrum (docs: Theory); q1 is the highest.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import InputError
from .order_stats import median
from .rolloff import detect_roll_off
from .spectrum_types import Spectrum

__all__ = ["SelfAffineFit", "fit_self_affine", "detect_band", "extend_spectrum", "local_slopes"]


@dataclass(frozen=True)
class SelfAffineFit:
    """Result of :func:`fit_self_affine` (all wave vectors in 1/m, heights in m).

    Attributes
    ----------
    hurst, hurst_stderr : float
        Hurst exponent H and its standard error (regression).
    h0_m : float
        The thesis's h0 of the self-affine form on [q0, q1].
    band_rms_m : float
        rms height implied by the fitted power law on [q0, q1] (not Sq).
    fit_band_per_m : (float, float)
        The band fitted.
    q_roll_per_m : float or None
        Roll-off wave vector: where the fitted power law meets the low-q plateau.
    q0_per_m, q1_per_m : float
        Range of the self-affine form (q0 = q_roll if detected else lowest q of the spectrum;
        q1 = highest q of the spectrum).
    C_at_q0_m4 : float
        Fitted C(q0) [m^4].
    n_points : int
        Number of spectrum points in the fit.
    """

    hurst: float
    hurst_stderr: float
    h0_m: float
    band_rms_m: float
    fit_band_per_m: tuple
    q_roll_per_m: float | None
    q0_per_m: float
    q1_per_m: float
    C_at_q0_m4: float
    n_points: int

    def model_C(self, q_per_m: ArrayLike) -> NDArray[np.float64]:
        """Fitted C(q) [m^4]: C(q0) (q/q0)^(-2(H+1)) for q >= q0 (also beyond q1, for an
        extension); below q0 the plateau C(q0) if a roll-off was detected, else the power law."""
        q = np.asarray(q_per_m, dtype=np.float64)
        expo = -2.0 * (self.hurst + 1.0)
        c = self.C_at_q0_m4 * (q / self.q0_per_m) ** expo
        if self.q_roll_per_m is not None:
            c = np.where(q < self.q0_per_m, self.C_at_q0_m4, c)
        return c

    def as_dict(self) -> dict[str, Any]:
        """The fit as a plain dict (JSON-ready: the band as a list)."""
        d = dict(self.__dict__)
        d["fit_band_per_m"] = list(self.fit_band_per_m)
        return d


def _loglog_fit(q, C, lo, hi, weights=None):
    """Least squares of log10 C on log10 q over lo <= q <= hi.

    With ``weights`` (e.g. the number of lattice points averaged in each ring, to which the
    inverse variance of a ring's log C is proportional for a Gaussian surface) the fit is
    weighted; the slope's standard error is then scaled by the weighted residual variance.
    Returns (slope, intercept, slope_stderr, n).
    """
    q, C = np.asarray(q), np.asarray(C)
    s = (q >= lo * (1 - 1e-12)) & (q <= hi * (1 + 1e-12)) & (C > 0)
    x, y = np.log10(q[s]), np.log10(C[s])
    w = np.ones_like(x) if weights is None else np.asarray(weights, dtype=np.float64)[s]
    n = x.size
    if n < 3:
        raise InputError(None, f"only {n} spectrum points in the fit band [{lo:.4g}, {hi:.4g}] 1/m")
    w = w / w.sum()
    xm, ym = np.sum(w * x), np.sum(w * y)
    sxx = np.sum(w * (x - xm) ** 2)
    slope = np.sum(w * (x - xm) * (y - ym)) / sxx
    icpt = ym - slope * xm
    resid = y - (icpt + slope * x)
    # weighted residual variance per unit weight, with n_eff = 1 / sum(w^2) effective points
    n_eff = 1.0 / np.sum(w * w)
    se = np.sqrt(np.sum(w * resid**2) / sxx / max(n_eff - 2.0, 1.0))
    return float(slope), float(icpt), float(se), int(n)


def local_slopes(q: ArrayLike, C: ArrayLike, window_decades: float = 0.4) -> NDArray[np.float64]:
    """Slope of log C vs log q by least squares in a window of ``window_decades`` around
    each point (vectorised with prefix sums).

    Parameters
    ----------
    q : ndarray
        Wave vectors [1/m], increasing.
    C : ndarray
        Spectrum [m^4].
    window_decades : float, optional
        Width of the window in decades of q.

    Returns
    -------
    ndarray
        d log C / d log q at every point.
    """
    x, y = np.log10(q), np.log10(C)
    lo = np.searchsorted(x, x - window_decades / 2, side="left")
    hi = np.searchsorted(x, x + window_decades / 2, side="right")
    cs = [np.concatenate([[0.0], np.cumsum(v)]) for v in (np.ones_like(x), x, y, x * x, x * y)]
    n, sx, sy, sxx, sxy = (c[hi] - c[lo] for c in cs)
    den = n * sxx - sx**2
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, (n * sxy - sx * sy) / np.where(den > 0, den, 1.0), np.nan)


def _usable(spectrum, min_count):
    q, C = spectrum.q_per_m, spectrum.C_m4
    ok = (C > 0) & np.isfinite(C) & (q > 0)
    if spectrum.count is not None:
        ok &= np.asarray(spectrum.count) >= min_count
    return np.flatnonzero(ok)


def detect_band(
    spectrum: Spectrum, tolerance: float = 0.5, window_decades: float = 0.4, min_count: int = 8
) -> tuple[float, float]:
    """Self-affine band of a spectrum: the stretch around the middle where log C is straight.

    Local slopes of log C vs log q (window ``window_decades``) are compared with the median
    slope of the middle third of the range (in log q); the band is the contiguous run of
    points around the middle whose slope is within ``tolerance`` of it. This cuts a roll-off
    (flattening at low q) and a noise floor (flattening) or instrument cut-off (steepening)
    at high q. Rings holding fewer than ``min_count`` lattice points are not used.

    Returns
    -------
    lo, hi : float
        Wave vectors [1/m] of the first and last point of the band.

    Parameters
    ----------
    spectrum : Spectrum
        An angular-averaged spectrum.
    tolerance : float, optional
        Largest departure of a local slope from the median slope.
    window_decades : float, optional
        Window of the local slopes [decades].
    min_count : int, optional
        Fewest lattice points a ring needs to count.
    """
    idx = _usable(spectrum, min_count)
    if idx.size < 5:
        raise InputError(None, "spectrum has fewer than 5 usable points: cannot detect a band")
    q, C = spectrum.q_per_m[idx], spectrum.C_m4[idx]
    s = local_slopes(q, C, window_decades)
    x = np.log10(q)
    mid = (x >= x[0] + (x[-1] - x[0]) / 3) & (x <= x[-1] - (x[-1] - x[0]) / 3)
    if mid.sum() < 1:
        mid = np.ones_like(x, dtype=bool)
    ref = s[mid][~np.isnan(s[mid])]
    # np.nanmedian's value (roadscan.order_stats: without importing numpy.ma)
    s_ref = np.float64(median(ref, overwrite=True)) if ref.size else np.nanmedian(s[mid])
    good = np.abs(s - s_ref) <= tolerance
    # contiguous runs of good points; keep the one spanning most decades that meets the middle
    edges = np.flatnonzero(np.diff(np.r_[0, good.astype(np.int8), 0]))
    runs = [(a, b - 1) for a, b in zip(edges[::2], edges[1::2])]
    runs = [r for r in runs if mid[r[0] : r[1] + 1].any()] or runs
    if not runs:
        raise InputError(None, "no straight stretch found in the spectrum")
    i0, i1 = max(runs, key=lambda r: x[r[1]] - x[r[0]])
    if i1 - i0 < 2:
        c = (i0 + i1) // 2
        i0, i1 = max(0, c - 1), min(x.size - 1, c + 1)
    return float(q[i0]), float(q[i1])


def fit_self_affine(
    spectrum: Spectrum,
    band: tuple[float, float] | None = None,
    min_count: int = 8,
    window_decades: float = 0.4,
    roll_off: float | None = None,
) -> SelfAffineFit:
    """Fit the self-affine form to a (2D, isotropic) spectrum.

    log10 C is fitted against log10 q over the band by least squares, each ring weighted by
    the square root of the number of lattice points it averages (unweighted for spectra
    without counts); H = -slope/2 - 1, with the slope's standard error / 2.

    Parameters
    ----------
    spectrum : Spectrum
        C(q) [m^4] in Persson's normalisation (kind area, profile or model).
    band : (lo, hi), optional
        Fit band [1/m]; detected with :func:`detect_band` when omitted.
    roll_off : float, optional
        A roll-off wave vector [1/m] found elsewhere (e.g. by :mod:`roadscan.reliable_band` on
        every ring) used instead of this fit's own test.

    Returns
    -------
    SelfAffineFit

    References
    ----------
    B.N.J. Persson et al., J. Phys.: Condens. Matter 17, R1 (2005), doi:10.1088/0953-8984/17/1/R01;
    T.D.B. Jacobs, T. Junge, L. Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017),
    doi:10.1088/2051-672X/aa51f8.

    Examples
    --------
    >>> from roadscan.io import read
    >>> from roadscan.level import level
    >>> from roadscan.inpaint import fill_unmeasured
    >>> from roadscan import psd_area
    >>> from roadscan.fit import fit_self_affine
    >>> flat, _ = fill_unmeasured(level(read("sample_scans/asphalt.x3p")))
    >>> fit = fit_self_affine(psd_area(flat)[0])
    >>> 0.8 < fit.hurst < 0.95
    True
    """
    idx = _usable(spectrum, min_count)
    q, C = spectrum.q_per_m[idx], spectrum.C_m4[idx]
    if band is None:
        band = detect_band(spectrum, window_decades=window_decades, min_count=min_count)
    lo, hi = float(band[0]), float(band[1])
    if q.size and max(lo, q.min()) < min(hi, q.max()):  # a band wider than the spectrum: what is fitted
        lo, hi = max(lo, float(q.min())), min(hi, float(q.max()))
    # rings are weighted by sqrt(lattice points): inverse-variance weights (the count) would be
    # right for a perfect power law but let the top decade, where noise floors and instrument
    # cut-offs bend the spectrum, dominate; sqrt(count) halves the scatter of the low rings'
    # influence without that (checked on surfaces with cut-offs, roll-offs and white noise)
    counts = None if spectrum.count is None else np.asarray(spectrum.count, float)[idx]
    if counts is not None and not np.all(counts > 0):
        counts = None
    slope, icpt, se, n = _loglog_fit(q, C, lo, hi, weights=None if counts is None else np.sqrt(counts))
    hurst = -slope / 2.0 - 1.0
    # the broken-line test of roadscan.rolloff (the older median test of the rings
    # below the band missed the coarse sample's 14 mm roll-off); the first ring stands for 2 pi / L
    q_roll: float | None
    if roll_off is not None:
        q_roll = float(roll_off)
    else:
        q_roll = detect_roll_off(q, C, counts, slope, icpt, float(spectrum.q_per_m[0]), hi)
    if q_roll is not None and q_roll > lo * 1.5:
        q_roll = None
    q0 = q_roll if q_roll is not None else float(q[0])
    q1 = float(q[-1])
    c0 = 10 ** (icpt + slope * np.log10(q0))
    if hurst > 0:
        h0 = q0 * np.sqrt(2 * np.pi * c0 / hurst)
        band_rms = h0 / np.sqrt(2.0) * np.sqrt(max(0.0, 1.0 - (q1 / q0) ** (-2.0 * hurst)))
    else:
        h0 = float("nan")
        band_rms = float(np.sqrt(2 * np.pi * c0 * q0**2 * np.log(q1 / q0)))
    return SelfAffineFit(
        hurst=float(hurst),
        hurst_stderr=float(se / 2.0),
        h0_m=float(h0),
        band_rms_m=float(band_rms),
        fit_band_per_m=(lo, hi),
        q_roll_per_m=q_roll,
        q0_per_m=float(q0),
        q1_per_m=q1,
        C_at_q0_m4=float(c0),
        n_points=n,
    )


def extend_spectrum(
    spectrum: Spectrum, fit: SelfAffineFit, q1_per_m: float, points_per_decade: int = 20
) -> Spectrum:
    """The measured spectrum continued by the fitted power law up to ``q1_per_m``.

    Points of ``spectrum`` are kept up to its highest wave vector; above it, log-spaced
    points (``points_per_decade``) carry ``fit.model_C``. ``count`` is 0 for model points.

    Returns
    -------
    Spectrum
        kind ``"extended"``; ``meta['extended_from_per_m']`` marks the join.

    Parameters
    ----------
    spectrum : Spectrum
        The measured spectrum.
    fit : SelfAffineFit
        Its self-affine fit.
    q1_per_m : float
        Wave vector to extend to [1/m].
    points_per_decade : int, optional
        Model points per decade above the measured range.
    """
    q_top = spectrum.q_max_per_m
    meta = dict(spectrum.meta)
    meta.update(
        extended_from_per_m=q_top,
        extended_to_per_m=float(q1_per_m),
        extension_hurst=fit.hurst,
        source_kind=spectrum.kind,
    )
    cnt = (
        np.asarray(spectrum.count)
        if spectrum.count is not None
        else np.zeros(spectrum.q_per_m.size, dtype=np.int64)
    )
    if q1_per_m <= q_top:
        return Spectrum(spectrum.q_per_m, spectrum.C_m4, count=cnt, kind="extended", meta=meta)
    n = max(1, int(np.ceil(points_per_decade * np.log10(q1_per_m / q_top))))
    q_new = q_top * (q1_per_m / q_top) ** (np.arange(1, n + 1) / n)
    return Spectrum(
        np.concatenate([spectrum.q_per_m, q_new]),
        np.concatenate([spectrum.C_m4, fit.model_C(q_new)]),
        count=np.concatenate([cnt, np.zeros(n, dtype=np.int64)]),
        kind="extended",
        meta=meta,
    )
