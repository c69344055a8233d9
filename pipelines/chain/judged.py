"""Where two measured spectra may be compared, and the largest ratio there.

A ratio C/C_ref of two measured spectra says something about the surfaces only where both
spectra are trusted: inside each scan's reliable band (:mod:`roadscan.reliable_band`: above the
field of view's leakage, below Nyquist, the lateral resolution and the noise floor) and inside
each scan's fit band (the straight self-affine stretch found inside it,
:func:`pipelines.chain.band.reliable_fit`). Outside, one of the two is an instrument's artefact
(window leakage, aliasing, noise), and a ratio of 60 at a wavelength one scan does not resolve
is the instrument's, not the road's. :func:`judged_band` is one scan's band,
:func:`common_band` the band of several, :func:`largest_ratio` the largest ratio inside it
(``comparison.json``'s ``largest_psd_ratio``: ``ratio``, ``q_per_m``, ``band_per_m``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["judged_band", "common_band", "ratio_in_band", "largest_ratio"]


def judged_band(an, rb):
    """(lo, hi) [1/m]: where the spectrum of analysed scan ``an`` is both reliable and fitted
    (its reliable band ``rb`` intersected with its fit band); the fit band alone when the scan
    has no reliable band of a factor 2 (``rb`` None or not valid).

    Parameters
    ----------
    an : SurfaceAnalysis
        The analysed scan (its ``fit.fit_band_per_m``).
    rb : ReliableBand or None
        Its reliable band.

    Returns
    -------
    tuple of float or None
        (lo, hi) [1/m]; None when the two do not overlap.
    """
    flo, fhi = (float(x) for x in an.fit.fit_band_per_m)
    if rb is None or not getattr(rb, "valid", False):
        return (flo, fhi) if flo < fhi else None
    lo, hi = max(flo, float(rb.lo_per_m)), min(fhi, float(rb.hi_per_m))
    return (lo, hi) if lo < hi else None


def common_band(bands):
    """The band inside every one of ``bands`` ((lo, hi) or None) -> (lo, hi) or None.

    Parameters
    ----------
    bands : iterable of tuple or None
        Bands [1/m].

    Returns
    -------
    tuple of float or None
    """
    bands = list(bands)
    if not bands or any(b is None for b in bands):
        return None
    lo, hi = max(b[0] for b in bands), min(b[1] for b in bands)
    return (float(lo), float(hi)) if lo < hi else None


def ratio_in_band(spec_ref, spec, band):
    """(q, log10 C/C_ref) on the reference's wave vectors inside ``band``, the compared
    spectrum interpolated linearly in log-log; empty arrays when fewer than 2 lie inside.

    Parameters
    ----------
    spec_ref, spec : roadscan.Spectrum
        Reference and compared spectra.
    band : tuple of float
        (lo, hi) [1/m].

    Returns
    -------
    q : ndarray
    log10_ratio : ndarray
    """
    q = np.asarray(spec_ref.q_per_m, float)
    lo, hi = band
    keep = (q >= lo * (1 - 1e-9)) & (q <= hi * (1 + 1e-9))
    keep &= (q >= spec.q_per_m[0]) & (q <= spec.q_per_m[-1])
    keep &= np.asarray(spec_ref.C_m4) > 0
    q = q[keep]
    if q.size < 2:
        return np.empty(0), np.empty(0)
    c_ref = np.asarray(spec_ref.C_m4, float)[keep]
    pos = np.asarray(spec.C_m4, float) > 0
    c = np.exp(
        np.interp(np.log(q), np.log(np.asarray(spec.q_per_m)[pos]), np.log(np.asarray(spec.C_m4)[pos]))
    )
    return q, np.log10(c / c_ref)


def largest_ratio(q, log10_ratio, band):
    """The largest ratio (farthest from 1 either way) -> ``{"ratio", "q_per_m", "band_per_m"}``.

    Parameters
    ----------
    q, log10_ratio : ndarray
        From :func:`ratio_in_band`.
    band : tuple of float
        The band they were judged in [1/m].

    Returns
    -------
    dict or None
        None when there is no point.
    """
    if len(q) == 0:
        return None
    i = int(np.argmax(np.abs(log10_ratio)))
    return {
        "ratio": float(10 ** log10_ratio[i]),
        "q_per_m": float(q[i]),
        "band_per_m": [float(band[0]), float(band[1])],
    }
