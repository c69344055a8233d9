"""The window ``roadscan combine`` puts on areas, and where its leakage stops biasing C.

``combine`` windows areas with a Tukey window of alpha 0.5 (cosine tapers over a quarter of
each side at either end) rather than ``analyse``'s 0.25: its side lobes fall faster, so the
power of modes longer than the view leaks less into the lowest rings, and the merged curve
starts lower on the coarsest input (at the price of a 1.22 instead of 1.10 equivalent noise
bandwidth per axis: 23 % fewer degrees of freedom per ring). Mean bias of C over 30 non-periodic
crops of synthetic surfaces (levelled, :func:`roadscan.synth_measure.measure_synthetic`,
256 x 256 points) at k x 2 pi / L for a spectrum falling as q^-beta:

    beta      k = 4     5      6      7      8      10
    2.6     0.91   1.00   1.03   0.95   0.95   0.97
    3.0     0.97   1.04   1.05   0.96   0.96   0.97
    3.6     1.14   1.12   1.09   0.99   0.98   0.98     (Tukey 0.25: 1.49 1.52 1.39 1.36 1.23 1.08)
    4.0     1.36   1.21   1.13   1.01   0.99   0.99

(standard error 0.03-0.05), so C is within about 10 % from k(beta) x 2 pi / L with
k = 4, 4.5, 7, 7.5 at beta = 2.6, 3.0, 3.6, 4.0 (:data:`LEAKAGE_TABLE`, interpolated, clipped to
[4, 15]). The rest of the reliable band (roll-off, Nyquist, resolution, noise floor) is
:func:`roadscan.reliable_band.reliable_band`'s; only its field-of-view end is moved here.
``tests/test_combine.py`` checks the bias at the moved end.

Reference: Harris, Proc. IEEE 66, 51 (1978) (windows, side lobes); Jacobs, Junge, Pastewka,
Surf. Topogr.: Metrol. Prop. 5, 013001 (2017), sec. 3 (leakage of steep spectra).
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

__all__ = ["AREA_WINDOW_ALPHA", "LEAKAGE_TABLE", "leakage_factor_combine", "with_combine_low_end"]

AREA_WINDOW_ALPHA = 0.5
#: (slope beta of the windowed spectrum, k: C within ~10 % from k x 2 pi / L), Tukey 0.5
LEAKAGE_TABLE = ((2.6, 4.0), (3.0, 4.5), (3.6, 7.0), (4.0, 7.5))
_K_MIN, _K_MAX = 4.0, 15.0


def leakage_factor_combine(beta):
    """k(beta) of :data:`LEAKAGE_TABLE` (interpolated, clipped to [4, 15])."""
    xs, ks = zip(*LEAKAGE_TABLE)
    return float(np.clip(np.interp(beta, xs, ks), _K_MIN, _K_MAX))


def with_combine_low_end(band, length_m):
    """``band`` (a :class:`roadscan.reliable_band.ReliableBand` of a Tukey-0.5 area spectrum)
    with its low end at k(beta) x 2 pi / L of :data:`LEAKAGE_TABLE` when that is lower."""
    beta = -band.slope
    if not np.isfinite(beta):
        return band
    k = leakage_factor_combine(beta)
    lo = k * 2 * np.pi / length_m
    if lo >= band.lo_per_m:
        return band
    mm = length_m * 1e3
    reason = (f"field of view: {k:.3g} x 2 pi / L (L = {mm:.3g} mm; Tukey 0.5 window: leakage "
              f"biases C below for a spectrum falling as q^-{beta:.2f})")
    return replace(band, lo_per_m=float(lo), lo_reason=reason,
                   limits=dict(band.limits, field_of_view=float(lo)))
