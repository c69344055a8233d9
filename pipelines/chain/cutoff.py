"""The large-wavevector cut-off q1 of the friction integrals: which rule chose it, and why.

mu(v) = 1/2 int_{q0}^{q1} q^3 C(q) P(q) M(q) dq needs an upper end q1. In order:

1. ``--q1`` given: the user's (``"given by --q1"``).
2. The reliable band's short end (:mod:`roadscan.reliable_band`: Nyquist, the lateral
   resolution, or the noise floor), when the measurement supports it: the band ends where
   aliasing or the resolution stop the scan, or it ends at the noise floor with an rms slope
   up to it of at most :data:`SLOPE_TRUSTED` (1).
3. **Persson's criterion** when the band ends at the noise floor and the rms slope up to it,
   xi(q1) = sqrt(2 pi int_{q0}^{q1} q^3 C(q) dq), exceeds 1: q1 is put where xi reaches 1
   (:func:`slope_cutoff`). The steep part of such a band sits next to the noise, where C is
   already lifted by it, and Persson's theory takes the rubber to follow the roughness only up
   to wave vectors where the surface's rms slope is of order one (Persson et al., J. Phys.:
   Condens. Matter 17, R1 (2005), doi:10.1088/0953-8984/17/1/R01, the cut-off discussion of its
   rubber-friction section; Lorenz et al., Eur. Phys. J. E 34, 129 (2011),
   doi:10.1140/epje/i2011-11129-1; the choices of cut-off are compared by Genovese et al.,
   Lubricants 7, 85 (2019), doi:10.3390/lubricants7100085). The roughness finer than that q1,
   trusted or not, does not enter mu; a warning says so and names ``--q1``.

Friction is refused only where no decade of the spectrum can be trusted: the band ends at the
noise floor, its rms slope there exceeds 1 and the band spans less than
:data:`MIN_TRUSTED_DECADES` (one decade of q; :func:`pipelines.chain.steps.judge_fine_end`).

The rule is reported as ``friction.q1_rule`` beside ``friction.q1_per_m`` in ``summary.json``,
in the report and in the command's headline.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "SLOPE_TRUSTED",
    "MIN_TRUSTED_DECADES",
    "slope_cutoff",
    "q1_rule",
    "trusted_decades",
    "cut_warning",
    "RULE_GIVEN",
    "PERSSON",
]

#: rms slope up to q1 above which a band ending at the noise floor is cut (Persson's criterion)
SLOPE_TRUSTED = 1.0
#: decades of q the reliable band must span for friction to be computed at all
MIN_TRUSTED_DECADES = 1.0
#: the rule text when the user gave q1
RULE_GIVEN = "given by --q1"
#: the literature behind the slope criterion, as the rule text names it
PERSSON = "Persson's criterion, J. Phys.: Condens. Matter 17, R1 (2005)"


def slope_cutoff(psd, q0_per_m, q_hi_per_m, target=SLOPE_TRUSTED, n=2000):
    """The wave vector where the rms slope of ``psd`` from ``q0_per_m`` first reaches ``target``.

    xi(q)^2 = 2 pi int_{q0}^{q} q'^3 C(q') dq' (an isotropic surface's rms gradient), on a
    logarithmic grid of ``n`` nodes over [q0, q_hi] (trapezoids in ln q: q^3 C dq = q^4 C d ln q),
    the crossing interpolated linearly in ln q.

    Parameters
    ----------
    psd : friction.TabulatedPSD or SelfAffinePSD
        The spectrum, callable as ``psd.C(q)`` [m^4] for q [1/m].
    q0_per_m : float
        Lower end of the slope integral [1/m] (the friction band's q0).
    q_hi_per_m : float
        Highest q searched [1/m].
    target : float, optional
        The rms slope sought (default :data:`SLOPE_TRUSTED`, 1).
    n : int, optional
        Grid nodes.

    Returns
    -------
    float or None
        q [1/m] with xi(q) = ``target``; None when xi stays below it up to ``q_hi_per_m``.
    """
    lq = np.linspace(math.log(q0_per_m), math.log(q_hi_per_m), n)
    q = np.exp(lq)
    f = 2 * np.pi * q**4 * np.asarray(psd.C(q), float)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(lq))])
    goal = target * target
    above = np.nonzero(cum >= goal)[0]
    if above.size == 0:
        return None
    i = int(above[0])
    if i == 0:
        return float(q[0])
    t = (goal - cum[i - 1]) / (cum[i] - cum[i - 1])
    return float(math.exp(lq[i - 1] + t * (lq[i] - lq[i - 1])))


def trusted_decades(rb):
    """Decades of q the reliable band ``rb`` spans, log10(hi / lo) (0 without a band).

    Parameters
    ----------
    rb : ReliableBand or None
        The band (or the band read back from ``psd_band.json``).

    Returns
    -------
    float
    """
    if rb is None or not getattr(rb, "valid", False) or not rb.lo_per_m > 0:
        return 0.0
    return float(math.log10(rb.hi_per_m / rb.lo_per_m))


def q1_rule(rb, settings, cut=None):
    """The ``q1_rule`` text: which rule put q1 where it is (module docstring).

    Parameters
    ----------
    rb : ReliableBand or None
        The reliable band.
    settings : FrictionSettings
        The friction options (``q1_per_m`` given or None).
    cut : tuple of float, optional
        (band end [1/m], rms slope up to it) when Persson's criterion lowered q1.

    Returns
    -------
    str
    """
    from pipelines.output.units import quantity

    if settings.q1_per_m is not None:
        return RULE_GIVEN
    if cut is not None:
        hi, slope = cut
        return (
            f"where the rms slope reaches {SLOPE_TRUSTED:g} ({PERSSON}); the reliable band's "
            f"end at the noise floor, {quantity('q_per_m', hi)}, is steeper ({slope:.3g})"
        )
    if rb is None or not getattr(rb, "valid", False):
        return "the spectrum's last wave vector (no reliable band of a factor 2 was found)"
    why = getattr(rb, "hi_reason", None)
    if why is None and getattr(rb, "noise_floor_end", False):
        why = "noise floor"
    what = f" ({why.split(':')[0]})" if why else ""
    return f"the reliable band's short end{what}"


def cut_warning(q1_per_m, band_end_per_m, rms_slope_to_band_end):
    """The warning of a q1 lowered by Persson's criterion: where, why, what is left out and the
    flag that chooses otherwise.

    Parameters
    ----------
    q1_per_m : float
        The q1 used [1/m].
    band_end_per_m : float
        The reliable band's end at the noise floor [1/m].
    rms_slope_to_band_end : float
        The rms slope up to that end.

    Returns
    -------
    str
    """
    from pipelines.output.units import quantity

    dec = math.log10(band_end_per_m / q1_per_m)
    return (
        f"friction integrated up to q1 = {quantity('q1_per_m', q1_per_m)}, where the rms "
        f"slope reaches {SLOPE_TRUSTED:g} ({PERSSON}), not to the reliable band's end "
        f"{quantity('q_per_m', band_end_per_m)}: the band ends at the spectrum's noise floor "
        f"with an rms slope of {rms_slope_to_band_end:.3g} there, so its finest {dec:.1f} "
        f"decades do not enter μ; --q1 to choose the end"
    )
