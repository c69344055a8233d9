"""The reliable band of a measured spectrum: the wave vectors [lo, hi] whose C(q) the scan
measures without bias, and why each end is where it is.

**lo** (long wavelengths) is the larger of

- the *field of view*: the Tukey window (alpha 0.25) and the levelling leak power of the
  modes longer than the scan into the lowest rings. For a spectrum falling as q^-beta the
  bias of C stays under about 10 % only from k(beta) x 2 pi / L on, with k = 4, 6, 12, 14 at
  beta = 2.6, 3.0, 3.6, 4.0 (interpolated, clipped to [4, 15]; measured on non-periodic
  crops of synthetic surfaces, ``tests/test_reliable_band.py``). beta is the fitted slope of
  the windowed spectrum itself (2 + 2H for an area's C, 1 + 2H for a profile's C1); a Hann
  window (alpha 1) leaks less: k = 5 at beta = 3.6 (:func:`leakage_factor`); L is the
  shorter side of an area (the leakage comes from the side with the fewest modes);
- except where a *roll-off* is detected (:func:`roadscan.rolloff.detect_roll_off`): below it
  the spectrum is flat and leaks little, so lo = max(q_r, 4 x 2 pi / L) when that is lower.

**hi** (short wavelengths) is the smallest of

- *Nyquist*: :data:`NYQUIST_FRACTION` x pi / a (a the coarser spacing): above it the power of
  wavelengths shorter than 2 a, folded back by the sampling, adds over 5 % to C for a
  spectrum falling as q^-3.6 (((2 - f) / f)^-3.6 = 0.05 at f = 0.6; 0.11 at f = 0.7);
- the *lateral resolution* r (the wavelength passed at 50 % amplitude, from the file's
  metadata or given): modelled as a Gaussian low-pass, amplitude response
  T(q) = exp(-ln 2 (q r / 2 pi)^2); the band ends where T = :data:`RESPONSE_MIN` (0.8, i.e.
  C attenuated by at most 36 %), at q = 2 pi / r x sqrt(ln(1 / 0.8) / ln 2) = 0.57 x 2 pi / r;
- the *noise floor* detected in the spectrum: the first ring from which C stays more than
  :data:`NOISE_EXCESS` (25 %) above the self-affine line fitted below it, or from which C comes
  within a factor :data:`WHITE_SHARE` (10) of a white floor (the top rings' level when they are
  flatter than q^-1, which no surface with H > -0.5 is).

Reference: Jacobs, Junge, Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017), sec. 3-4
(windows, leakage, reliability); Sanner et al., Surf. Topogr.: Metrol. Prop. 10, 035014
(2022) (reliability cut-off of instruments); ISO 25178-3 (lateral period limit, 50 %).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import InputError
from .order_stats import median
from .rolloff import detect_roll_off
from .units import length as _len

__all__ = [
    "ReliableBand",
    "reliable_band",
    "leakage_factor",
    "resolution_limit",
    "gaussian_response",
    "noise_limit",
    "NYQUIST_FRACTION",
    "RESPONSE_MIN",
    "ROLL_K_MIN",
]

NYQUIST_FRACTION = 0.6
RESPONSE_MIN = 0.8
NOISE_EXCESS = 1.25
WHITE_SHARE = 10.0
#: window alpha -> ((slope beta of the windowed spectrum, k such that C is within ~10 % from
#: k x 2 pi / L), ...): measured on non-periodic crops (128^2 of 1024^2 periodic surfaces, 192
#: crops per row; the Hann window's broader main lobe leaks far less into k >= 5)
_LEAKAGE_TABLES = {
    0.25: ((2.6, 4.0), (3.0, 6.0), (3.6, 12.0), (4.0, 14.0)),
    0.5: ((2.6, 4.0), (3.6, 6.0), (4.0, 7.0)),
    1.0: ((2.6, 4.0), (3.6, 5.0), (4.0, 6.0)),
}
_K_MIN, _K_MAX = 4.0, 15.0
#: below a roll-off the modes longer than the view are as weak as the plateau: C is measured
#: from this many 2 pi / L on (the steep part above a low knee, and a surface's plateau)
ROLL_K_MIN = 4.0


@dataclass(frozen=True)
class ReliableBand:
    """Result of :func:`reliable_band` (wave vectors in 1/m).

    ``limits`` holds every candidate end (``field_of_view``, ``roll_off``, ``nyquist``,
    ``resolution``, ``noise_floor``; None when absent), ``reasons`` one line for each end.

    Attributes
    ----------
    lo_per_m, hi_per_m : float
        Ends of the band [1/m].
    lo_reason, hi_reason : str
        Why each end is where it is (one line each).
    limits : dict
        Every candidate end [1/m] or None.
    slope : float
        Slope of log C against log q inside the band.
    q_roll_per_m : float or None
        Detected roll-off [1/m].
    noise_floor : float or None
        White noise level of C [m^4], when one was found.
    """

    lo_per_m: float
    hi_per_m: float
    lo_reason: str
    hi_reason: str
    limits: dict = field(default_factory=dict)
    slope: float = float("nan")  # fitted log-log slope of the spectrum analysed
    q_roll_per_m: float | None = None
    noise_floor: float | None = None  # white level of the spectrum analysed (its units)

    @property
    def band(self):
        return [float(self.lo_per_m), float(self.hi_per_m)]

    @property
    def reasons(self):
        return {"lo": self.lo_reason, "hi": self.hi_reason}

    @property
    def valid(self):
        """At least a factor 2 wide."""
        return bool(self.hi_per_m >= 2.0 * self.lo_per_m)

    def as_dict(self):
        return {
            "reliable_band_per_m": self.band,
            "reliable_band_reasons": self.reasons,
            "limits_per_m": dict(self.limits),
            "q_roll_per_m": self.q_roll_per_m,
        }


def leakage_factor(beta, window_alpha=0.25):
    """k(beta): C is within about 10 % of the truth from k x 2 pi / L on (see module doc), for a
    Tukey window of ``window_alpha`` (tables at 0.25, 0.5 and 1, interpolated in alpha; below
    0.25 the 0.25 table, which is optimistic for a rectangular window).

    Parameters
    ----------
    beta : float
        Slope magnitude of the spectrum, C ~ q^-beta.
    window_alpha : float, optional
        Tukey taper fraction.

    Returns
    -------
    float
        k: the band starts at k x 2 pi / L.
    """
    alphas = sorted(_LEAKAGE_TABLES)
    ks = [np.interp(beta, *zip(*_LEAKAGE_TABLES[a])) for a in alphas]
    k = np.interp(window_alpha, alphas, ks)
    return float(np.clip(k, _K_MIN, _K_MAX))


def gaussian_response(q_per_m, resolution_m):
    """Amplitude response T(q) = exp(-ln 2 (q r / 2 pi)^2) of a lateral resolution r [m]
    (T = 0.5 at the wavelength r); C is attenuated by T^2.

    Parameters
    ----------
    q_per_m : array_like
        Wave vectors [1/m].
    resolution_m : float
        Lateral resolution r [m], the wavelength passed at 50 % amplitude.

    Returns
    -------
    ndarray
        T(q), between 0 and 1.
    """
    return np.exp(-np.log(2.0) * (np.asarray(q_per_m, float) * resolution_m / (2 * np.pi)) ** 2)


def resolution_limit(resolution_m, response_min=RESPONSE_MIN):
    """Wave vector [1/m] where :func:`gaussian_response` falls to ``response_min``.

    Parameters
    ----------
    resolution_m : float
        Lateral resolution [m].
    response_min : float, optional
        Amplitude response at the limit.

    Returns
    -------
    float
        Wave vector [1/m].
    """
    return 2 * np.pi / resolution_m * np.sqrt(np.log(1.0 / response_min) / np.log(2.0))


def _line_fit(x, y, w):
    w = w / w.sum()
    xm, ym = np.sum(w * x), np.sum(w * y)
    sxx = np.sum(w * (x - xm) ** 2)
    slope = np.sum(w * (x - xm) * (y - ym)) / sxx if sxx > 0 else 0.0
    return float(slope), float(ym - slope * xm)


def noise_limit(q, C, slope, intercept, q_from):
    """Where the noise floor begins to bias C: (q_end [1/m] or None, white level or None, why).

    The band ends before the first ring of the final run above ``q_from`` where C exceeds the
    line ``10**(intercept + slope log10 q)`` by :data:`NOISE_EXCESS`, or before the first ring
    (from the bottom) where C is within :data:`WHITE_SHARE` of the white level (median C of the
    top 0.2 decade when its local slope is above -1), whichever comes first.

    Parameters
    ----------
    q, C : ndarray
        Spectrum: wave vectors [1/m] and C [m^4].
    slope, intercept : float
        The line log10 C = intercept + slope log10 q fitted below the noise.
    q_from : float
        Wave vector [1/m] above which the floor is looked for.

    Returns
    -------
    q_end : float or None
        End of the band [1/m].
    level : float or None
        White noise level [m^4].
    why : str
        One line.
    """
    from .fit import local_slopes

    x = np.log10(q)
    excess = C / 10 ** (intercept + slope * x)
    above = q > q_from
    cands, level = [], None
    high = (excess > NOISE_EXCESS) & above
    # the final run of rings above the line (the noise floor lasts to the top)
    if high[-1]:
        i = q.size - 1
        while i > 0 and high[i - 1]:
            i -= 1
        if q.size - i >= 2:  # two rings at least
            cands.append(
                (
                    i,
                    f"C (noise or aliasing) exceeds the self-affine line by over "
                    f"{100 * (NOISE_EXCESS - 1):.0f} % from {_wl(q[i])} wavelength up",
                )
            )
    top = x >= x[-1] - 0.2
    if top.sum() >= 3:
        s = local_slopes(q, C, 0.3)
        st = s[top][~np.isnan(s[top])]  # np.nanmedian, np.median: roadscan.order_stats
        if (median(st, overwrite=True) if st.size else np.nanmedian(s[top])) > -1.0:
            level = median(C[top])
            # the first ring from the bottom (noise may fill most decades) from which most rings
            # up to the top are within the factor: a lone low ring far below the floor (2
            # degrees of freedom fall under a tenth of their mean 1 time in 10) starts none
            low = C < WHITE_SHARE * level
            low[0] = False
            share_above = np.cumsum(low[::-1])[::-1] / np.arange(q.size, 0, -1)
            start = low & (share_above >= 0.5)
            if start.any():
                i = int(np.argmax(start))
                cands.append(
                    (
                        i,
                        f"white noise floor C = {level:.3g} reached within a factor "
                        f"{WHITE_SHARE:g} from {_wl(q[i])} wavelength up",
                    )
                )
    if not cands:
        return None, level, ""
    i, why = min(cands, key=lambda c: c[0])
    if i == 0:
        return None, level, ""
    return float(q[i - 1]), level, why


def _wl(q):
    """A wavelength 2 pi / q in mm or um, 3 significant digits."""
    return _len(2 * np.pi / q)


def reliable_band(q_per_m, C, count, length_m, spacing_m, resolution_m=None, min_count=1, window_alpha=0.25):
    """The reliable band of a spectrum (see module docstring).

    Parameters
    ----------
    q_per_m, C : arrays
        The windowed spectrum as measured: an area's angular average C [m^4] or a profile's
        1D C1 [m^3] (binned), increasing q.
    count : array or None
        Lattice points per ring (weights; None: equal).
    length_m : float
        Field of view L [m] (an area's shorter side, a profile's length).
    spacing_m : float
        Sampling interval a [m] (an area's coarser spacing).
    resolution_m : float, optional
        Lateral resolution r [m] (wavelength passed at 50 % amplitude).
    window_alpha : float
        The Tukey window's alpha the spectrum was made with (sets the leakage factor).

    Returns
    -------
    ReliableBand
    """
    q = np.asarray(q_per_m, float)
    C = np.asarray(C, float)
    n = np.ones_like(q) if count is None else np.asarray(count, float)
    ok = (q > 0) & (C > 0) & np.isfinite(C) & (n >= min_count)
    q, C, n = q[ok], C[ok], n[ok]
    if q.size < 5:
        raise InputError(None, "spectrum has fewer than 5 usable points: no reliable band")
    q_fov = 2 * np.pi / length_m
    q_nyq = np.pi / spacing_m
    limits = {
        "field_of_view": None,
        "roll_off": None,
        "nyquist": NYQUIST_FRACTION * q_nyq,
        "resolution": None,
        "noise_floor": None,
    }
    hi_cands = [
        (
            limits["nyquist"],
            f"Nyquist: {NYQUIST_FRACTION:g} x pi / a (a = {_len(spacing_m)}; "
            f"aliasing adds over 5 % to C above)",
        )
    ]
    if resolution_m is not None and resolution_m > 0:
        limits["resolution"] = float(resolution_limit(resolution_m))
        hi_cands.append(
            (
                limits["resolution"],
                f"lateral resolution: {_len(resolution_m)} (amplitude response "
                f"{RESPONSE_MIN:g} at {_wl(limits['resolution'])} wavelength)",
            )
        )
    # the self-affine line over the middle of the spectrum, refitted once inside the band
    x, y = np.log10(q), np.log10(C)
    w = np.sqrt(n)
    lo_b, hi_b = _middle_band(q, C, n)
    for _ in range(2):
        sel = (q >= lo_b) & (q <= hi_b)
        slope, icpt = _line_fit(x[sel], y[sel], w[sel])
        q_noise, level, why = noise_limit(q, C, slope, icpt, max(lo_b, np.sqrt(lo_b * hi_b)))
        top = min([c for c, _ in hi_cands] + ([q_noise] if q_noise else []))
        if top >= hi_b * 0.999:
            break
        hi_b = max(top, q[min(np.searchsorted(q, lo_b) + 4, q.size - 1)])
    if q_noise is not None:
        limits["noise_floor"] = q_noise
        hi_cands.append((q_noise, f"noise floor: {why}"))
    beta = -slope
    k = leakage_factor(beta, window_alpha)
    limits["field_of_view"] = k * q_fov
    lo, lo_reason = (
        k * q_fov,
        (
            f"field of view: {k:.3g} x 2 pi / L (L = {_len(length_m)}; "
            f"window leakage biases C below for a spectrum falling as "
            f"q^-{beta:.2f})"
        ),
    )
    q_roll = detect_roll_off(q, C, n if count is not None else None, slope, icpt, q_fov, hi_b)
    if q_roll is not None:
        limits["roll_off"] = q_roll
        q_lo_roll = max(q_roll, ROLL_K_MIN * q_fov)
        if q_lo_roll < lo:
            lo, lo_reason = (
                q_lo_roll,
                (
                    f"roll-off at {_wl(q_roll)} wavelength (flat below: "
                    f"little leakage; at least {ROLL_K_MIN:g} x 2 pi / L)"
                ),
            )
    hi, hi_reason = min(hi_cands, key=lambda c: c[0])
    return ReliableBand(
        float(lo),
        float(hi),
        lo_reason,
        hi_reason,
        {k_: (None if v is None else float(v)) for k_, v in limits.items()},
        slope=float(slope),
        q_roll_per_m=q_roll,
        noise_floor=level,
    )


def _middle_band(q, C, n):
    """The straight stretch of the spectrum around its middle (roadscan.fit.detect_band)."""
    from .fit import detect_band
    from .spectrum_types import Spectrum

    spec = Spectrum(q, C, count=np.rint(n).astype(np.int64))
    for min_count in (8, 1):  # as the fit: rings of under 8 points scatter widely
        try:
            lo, hi = detect_band(spec, min_count=min_count)
        except ValueError:
            continue
        # a roll-off in the middle third leaves a stretch of a few rings at the bend: under
        # MIN_STRETCH_DECADES it is no self-affine line, and a straight part above it of at
        # least that length is taken (searched again above a second short stretch: the bend
        # may be in that middle too); none: the short stretch stays
        top = hi
        for _ in range(3):
            above = q >= top
            if np.log10(hi / lo) >= MIN_STRETCH_DECADES or above.sum() < 5:
                break
            try:
                lo2, hi2 = detect_band(
                    Spectrum(q[above], C[above], count=np.rint(n[above]).astype(np.int64)),
                    min_count=min_count,
                )
            except ValueError:
                break
            if np.log10(hi2 / lo2) >= MIN_STRETCH_DECADES:
                return lo2, hi2
            top = hi2
        return lo, hi
    return float(q[0]), float(q[-1])


#: a straight stretch shorter than this (decades) is a bend, not the self-affine band
MIN_STRETCH_DECADES = 0.3
