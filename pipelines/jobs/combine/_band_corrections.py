"""The reliable band of one ``roadscan combine`` input, adjusted to what its spectrum shows:
the noise floor once the resolution's attenuation is undone, the white noise level under the
band's top, the leakage excess of this view at the band's start, and the roll-off (the
surface's or an instrument's knee).

:mod:`pipelines.jobs.combine.sources` calls these on each input and re-exports
:func:`with_roll_off_verdict`, which combine's job calls once every input's knee is judged.
"""

from __future__ import annotations

import numpy as np

__all__ = ["with_roll_off_verdict", "LEAK_EXCESS", "WHITE_SIGMAS"]


def _noise_after_correction(band, q, corrected, n, length, spacing, alpha):
    """The band's top lowered to the noise floor seen in the spectrum with the resolution's
    attenuation undone: attenuation and a noise floor cancel in the measured C near the
    resolution limit, and the white floor shows only once C is divided by T^2."""
    from dataclasses import replace

    from roadscan.reliable_band import reliable_band

    try:
        again = reliable_band(q, corrected, n, length, spacing, window_alpha=alpha)
    except ValueError:
        return band
    q_noise = again.limits.get("noise_floor")
    if q_noise is None or q_noise >= band.hi_per_m or q_noise <= band.lo_per_m:
        return band
    limits = dict(band.limits, noise_floor=q_noise)
    return replace(
        band,
        hi_per_m=float(q_noise),
        limits=limits,
        hi_reason=f"{again.hi_reason} (in C / T(q)^2: the resolution's attenuation "
        f"undone, the noise floor shows)",
        noise_floor=again.noise_floor,
    )


#: the band's start is raised while the rings of its first 0.1 decade lie, pooled, more than
#: this far above the power law of the rest of the band (and by over 2 standard deviations)
LEAK_EXCESS = 1.25
_LEAK_WINDOW, _LEAK_MAX, _LEAK_STEP = 0.1, 0.3, 0.05  # decades


def _trim_leaky_start(band, q, C, dof):
    """The band with its low end raised past a leakage excess of this particular view.

    The window's leakage is random from view to view (it carries the power of the modes longer
    than the view, which this view happens to have): the field-of-view end bounds its mean, not
    one view's. The power law ln C = a + s ln q is fitted (weights: degrees of freedom) to the
    band above its first 0.3 decade; while the rings of the first 0.1 decade lie on average more
    than :data:`LEAK_EXCESS` above it, by over 2 standard deviations (sqrt(2 / dof) each), the
    start moves up 0.05 decade (at most 0.3). A roll-off (C below the line) is never trimmed.
    """
    from dataclasses import replace

    lo, hi = band.lo_per_m, band.hi_per_m
    ok = (q >= lo) & (q <= hi) & (C > 0)
    ref = ok & (q >= lo * 10**_LEAK_MAX)
    if ref.sum() < 5:
        return band
    x, y, w = np.log(q), np.log(np.where(C > 0, C, 1.0)), dof
    xm, ym = np.average(x[ref], weights=w[ref]), np.average(y[ref], weights=w[ref])
    slope = np.sum(w[ref] * (x[ref] - xm) * (y[ref] - ym)) / np.sum(w[ref] * (x[ref] - xm) ** 2)
    resid = y - (ym + slope * (x - xm))
    start = lo
    while start < lo * 10 ** (_LEAK_MAX - 1e-9):
        first = ok & (q >= start) & (q < start * 10**_LEAK_WINDOW)
        if not first.any():
            break
        excess = np.average(resid[first], weights=w[first])
        sd = np.sqrt(2.0 / w[first].sum())
        if not (excess > np.log(LEAK_EXCESS) and excess > 2 * sd):
            break
        start *= 10**_LEAK_STEP
    if start == lo:
        return band
    reason = (
        f"{band.lo_reason}; raised {np.log10(start / lo):.2f} decade: the lowest rings lie "
        f"over {100 * (LEAK_EXCESS - 1):.0f} % above the band's power law (this view's "
        f"window leakage)"
    )
    return replace(band, lo_per_m=float(start), lo_reason=reason)


#: a white level fitted under the band's top is taken off only when over this many standard
#: errors above zero
WHITE_SIGMAS = 3.0


def _white_level(q, measured, dof, band, resolution_m):
    """The white noise level N of a spectrum whose top shows no floor of its own, or None.

    White measurement noise adds a constant N to every ring of the periodogram; near the top of
    the band it is still far below C but biases it (by 15 % at a ring where N = 0.15 C). With
    a power law of slope s and the resolution's response T(q)^2 (1 without a resolution),
    C_i = A q_i^s T_i^2 + N is linear in A and N: fitted by weighted least squares (weights
    dof_i / C_i^2: each ring's relative variance 2 / dof_i) to the rings from the band's
    geometric middle to Nyquist, for the band's own slope and for s from -6 to 0 in steps of
    0.1 (a roll-off between the band's middle and its top changes the slope there); the s of
    least chi-square is kept. N is returned when it
    is over :data:`WHITE_SIGMAS` standard errors above zero (Jacobs, Junge, Pastewka, Surf.
    Topogr.: Metrol. Prop. 5, 013001 (2017), sec. 3: noise adds a white floor).
    """
    from roadscan.reliable_band import gaussian_response

    if not np.isfinite(band.slope):
        return None
    sel = (q >= np.sqrt(band.lo_per_m * band.hi_per_m)) & (measured > 0) & (dof > 0)
    if sel.sum() < 5:
        return None
    qs, cs, k = q[sel], measured[sel], dof[sel]
    t2 = gaussian_response(qs, resolution_m) ** 2 if resolution_m else np.ones_like(qs)
    w = k / cs**2
    best = None
    # the band's slope, or (a bend between the band's middle and its top) the slope that fits
    # these rings best
    for s in np.r_[band.slope, np.arange(-6.0, 0.01, 0.1)]:
        X = np.column_stack([(qs / qs[0]) ** s * t2, np.ones_like(qs)])
        M = X.T @ (X * w[:, None])
        try:
            cov = np.linalg.inv(M)
        except np.linalg.LinAlgError:
            continue
        coef = cov @ (X.T @ (w * cs))
        chi = float(np.sum(w * (cs - X @ coef) ** 2))
        if best is None or chi < best[0] * (1 - 1e-9):
            best = (chi, coef, cov)
    if best is None:
        return None
    _, (a, level), cov = best
    if not (a > 0 and level > WHITE_SIGMAS * np.sqrt(cov[1, 1])):
        return None
    return float(level)


def _profile_above_roll_off(band):
    """A profile's band from its roll-off up.

    The isotropic 2D estimate C(q) = C1(q) / q Gamma(1 + H) / (sqrt(pi) Gamma(H + 1/2)) holds
    for a power law: C1(q) integrates C over every 2D wave vector of modulus q or more, so below
    a roll-off, where C1 flattens and C stays flat, it puts C far above the plateau (x2 to x25
    on a synthetic profile 60 x 2 pi / L long). A band wholly under the roll-off becomes empty
    (under a factor 2: the input is left out, with its warning). Reference: Persson, Tribol.
    Lett. 63, 42 (2016) (1D and 2D spectra of road surfaces).
    """
    from dataclasses import replace

    q_r = band.q_roll_per_m
    if q_r is None or band.lo_per_m >= q_r:
        return band
    return replace(
        band,
        lo_per_m=float(q_r),
        hi_per_m=float(max(band.hi_per_m, q_r)),
        lo_reason=f"{band.lo_reason}; raised to the roll-off: a profile's 2D "
        f"estimate C1 / q x f(H) holds for a power law only",
    )


def with_roll_off_verdict(source, *, verdict):
    """The source's reliable band and bends once its knee is judged
    (:func:`roadscan.rolloff_origin.judge_roll_offs`) -> (ReliableBand, bends [1/m]).

    - the surface's knee, an area: the band reaches down into the plateau, to
      :data:`roadscan.reliable_band.ROLL_K_MIN` x 2 pi / L (or its first ring): below a roll-off
      the modes longer than the view are as weak as the plateau, so the window leaks little
      into it (mean C / C_true 0.94-1.06 from 4 to 8 x 2 pi / L over 20 synthetic road-laser
      views); the plateau's rows carry few degrees of freedom and say so in their 5-95 % band;
    - the surface's knee, a profile: the band starts at the knee (the 2D estimate C1 / q x f(H)
      holds for a power law only, :func:`_profile_above_roll_off`);
    - the instrument's knee: the band starts at the knee when below it (its rings under it are
      bent by the instrument), and at its field-of-view end when it started at the knee below
      that end (the leakage a steep spectrum suffers there was waived for a plateau that is
      not the surface's); no bend is passed to the merge when another input measures straight
      across it, else the bend is kept (rows pool no rings across it).

    Parameters
    ----------
    source : SourceSpectrum
        One input.
    verdict : roadscan.rolloff_origin.RollOffVerdict or None
        Its knee judged; None: no knee.

    Returns
    -------
    band : ReliableBand
    bends : tuple of float
    """
    from dataclasses import replace

    from roadscan.reliable_band import ROLL_K_MIN

    band = source.band
    if verdict is None:
        return band, ()
    q_r = verdict.q_roll_per_m
    if verdict.origin == "surface":
        if source.kind == "profile":
            return _profile_above_roll_off(band), (q_r,)
        lo = max(ROLL_K_MIN * source.q_fov_per_m, float(source.q_per_m[0]))
        if lo >= band.lo_per_m:
            return band, (q_r,)
        return replace(
            band,
            lo_per_m=float(lo),
            lo_reason=f"the plateau below the surface's roll-off ({verdict.reason}), "
            f"from {ROLL_K_MIN:g} x 2 pi / L: a flat spectrum leaks little "
            f"(the band's own low end was {band.lo_per_m:.3g} 1/m: "
            f"{band.lo_reason})",
        ), (q_r,)
    refuted = bool(verdict.refuted_by)
    field_end = band.limits.get("field_of_view")
    if field_end and band.lo_per_m < field_end < band.hi_per_m and band.lo_per_m >= q_r * (1 - 1e-9):
        # the band started at the knee below its field-of-view end ("flat below: little
        # leakage"): the knee not the surface's, the leakage of a steep spectrum holds again
        band = replace(
            band,
            lo_per_m=float(field_end),
            lo_reason=f"field of view: {field_end:.3g} 1/m, the knee at its low end "
            f"being the instrument's ({verdict.reason})",
        )
    elif band.lo_per_m < q_r < band.hi_per_m:
        band = replace(
            band,
            lo_per_m=float(q_r),
            lo_reason=f"{band.lo_reason}; raised to the instrument's knee ({verdict.reason})",
        )
    if source.kind == "profile":
        band = _profile_above_roll_off(band)
    return band, (() if refuted else (q_r,))
