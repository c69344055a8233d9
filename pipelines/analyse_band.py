"""``analyse``: the reliable band of the scan feeds the self-affine fit and the friction.

The band (:func:`pipelines.reliable_bridge.scan_band`, :mod:`roadscan.reliable_band`) is
found on the measured spectrum; then

- the fit (unless ``--fit-band`` is given) takes the straight stretch of C(q)
  (:func:`roadscan.fit.detect_band`) *inside* the band, on the spectrum cut at the band's top
  (its roll-off test still sees the rings below the band);
- friction integrates from q0 = the band's lower end (the roll-off when one is detected inside
  the band: the macro-asperity wave vector zeta_m q0) to q1 = its upper end, unless ``--q0``
  or ``--q1`` is given (each end on its own; ``--q1`` beyond the scan extends C(q) by the fit);
- ``summary.json`` gets ``reliable_band_per_m`` [lo, hi], ``reliable_band_reasons``
  {"lo": ..., "hi": ...} and ``reliable_band_limits_per_m`` (every candidate end).
"""
from __future__ import annotations

import numpy as np

__all__ = ["reliable_fit", "friction_ends", "summary_keys"]


def reliable_fit(an, resolution_m=None, window_alpha=0.25, fit_band=None):
    """Find the band of analysed scan ``an`` and (without ``fit_band``) refit inside it.

    Sets ``an.fit`` and returns the :class:`roadscan.reliable_band.ReliableBand` (None when
    the spectrum has too few points for one: the fit is then left as it was).
    """
    from roadscan.fit import detect_band, fit_self_affine
    from roadscan.spectrum_types import Spectrum

    from .reliable_bridge import scan_band

    spec = an.spectrum
    try:
        rb = scan_band(an.source, spec, resolution_m, window_alpha=window_alpha)
    except ValueError:
        return None
    if fit_band is not None:
        return rb
    q, C = spec.q_per_m, spec.C_m4
    cnt = spec.count if spec.count is not None else np.ones(q.size, dtype=np.int64)
    top = q <= rb.hi_per_m * (1 + 1e-9)
    inner = top & (q >= rb.lo_per_m * (1 - 1e-9))
    if np.count_nonzero(inner & (C > 0)) < 5:
        return rb                                    # too narrow to refit: the fit stays
    cut = Spectrum(q[top], C[top], count=np.asarray(cnt)[top], kind=spec.kind, meta=spec.meta)
    sub = Spectrum(q[inner], C[inner], count=np.asarray(cnt)[inner], kind=spec.kind)
    try:
        band = detect_band(sub)
    except ValueError:
        band = (float(q[inner][0]), float(q[inner][-1]))
    try:
        an.fit = fit_self_affine(cut, band=band)
    except ValueError:
        pass
    return rb


def friction_ends(rb, fit, settings):
    """(q0, q1) [1/m] of the friction integrals: the flags where given, else the band's ends
    (q0 at a roll-off inside the band); (None, None) without a band."""
    if rb is None:
        return settings.q0_per_m, settings.q1_per_m
    q0 = settings.q0_per_m
    if q0 is None:
        q0 = rb.lo_per_m
        q_roll = rb.q_roll_per_m or getattr(fit, "q_roll_per_m", None)
        if q_roll is not None and rb.lo_per_m < q_roll < rb.hi_per_m / 2:
            q0 = q_roll
    q1 = settings.q1_per_m if settings.q1_per_m is not None else rb.hi_per_m
    return float(q0), float(q1)


def summary_keys(rb):
    """The ``summary.json`` keys of the band (empty without one)."""
    if rb is None:
        return {}
    return {"reliable_band_per_m": rb.band, "reliable_band_reasons": rb.reasons,
            "reliable_band_limits_per_m": dict(rb.limits)}
