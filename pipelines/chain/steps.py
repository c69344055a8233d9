"""The one chain from a scan to friction: every command that computes mu(v) from a height file
calls these functions, so that the same scan and options give the same answer everywhere.

    scan -> level, roughness, fill -> PSD C(q) -> reliable band [lo, hi] -> self-affine fit
         -> friction spectrum over [q0, q1] -> mu(v) (Persson's theory)

:func:`measure` runs the metrology (:func:`pipelines.chain.surface.analyse_surface`) and finds
the reliable band (:mod:`roadscan.reliable_band`), fitting the spectrum once: inside the band, or
over ``--fit-band``, or the whole spectrum when there is no band. :func:`friction_psd` makes the
friction engine's spectrum over [q0, q1] (the band's ends unless ``--q0``/``--q1`` say otherwise;
above the scan C(q) continues as the fit), :func:`friction_of` runs the engine with every
friction option (rubber, sigma0, nu, contact gamma, master-curve extrapolation, flash, speeds),
and :func:`scan_friction` does both, with the judgement of the band's fine end and mu's
provenance (:mod:`pipelines.chain.provenance`). The band travels beside ``psd.csv`` in
``psd_band.json`` (:mod:`pipelines.chain.sidecar`).

**The measurement decides** the band's fine end (:mod:`pipelines.chain.cutoff`): when the
band ends at the noise floor the spectrum itself shows (:mod:`roadscan.reliable_band`: C no
longer falls as the self-affine line) and the rms slope over the band,
sqrt(2 pi int q^3 C dq), exceeds :data:`SLOPE_TRUSTED` (1), the steepness comes from the
wavelengths next to the noise, where C is already lifted by it: q1 is then put where the rms
slope reaches 1 (Persson's criterion: Persson et al., J. Phys.: Condens. Matter 17, R1 (2005),
doi:10.1088/0953-8984/17/1/R01; Lorenz et al., Eur. Phys. J. E 34, 129 (2011)), with a warning.
Friction is refused (:func:`judge_fine_end`) only where no decade of the spectrum can be
trusted (such a band spanning under a decade), naming ``--q1`` and ``--resolution`` (with
``--q1`` given, the user has chosen the end). A peak mu outside 0.3-3 stays a warning with its
likely causes (:func:`pipelines.chain.provenance.implausible_cause`), never a refusal.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from friction.psd import TabulatedPSD
    from friction.result import FrictionResult

# SLOPE_TRUSTED: rms slope above which a band ending at the noise floor is cut (module docstring)
from pipelines.chain.cutoff import MIN_TRUSTED_DECADES, SLOPE_TRUSTED

__all__ = [
    "measure",
    "friction_psd",
    "friction_of",
    "scan_friction",
    "judge_fine_end",
    "FrictionOutcome",
    "SLOPE_TRUSTED",
    "noise_floor_end",
]


def measure(
    scan,
    window_alpha=0.25,
    fit_band=None,
    despike=False,
    mpd_settings=None,
    resolution_m=None,
    on_levelled=None,
    on_spectrum2d=None,
):
    """The metrology of one scan -> (SurfaceAnalysis, ReliableBand or None), fitted once.

    ``window_alpha``: Tukey window; ``fit_band`` (lo, hi) [1/m]; ``resolution_m``: lateral
    resolution [m] (default: the file's metadata); the hooks as in
    :func:`pipelines.chain.surface.analyse_surface`. Warns (:func:`pipelines.checks.validate.check_fit`)
    when the Hurst exponent is outside [0, 1].

    Parameters
    ----------
    scan : HeightMap or Profile
        The scan [m].
    window_alpha : float, optional
        Tukey window.
    fit_band : tuple of float, optional
        Fit band [1/m].
    despike : bool, optional
        Replace spikes first.
    mpd_settings : dict, optional
        ISO 13473-1 settings.
    resolution_m : float, optional
        Lateral resolution [m].
    on_levelled, on_spectrum2d : callable, optional
        Hooks.

    Returns
    -------
    SurfaceAnalysis
        The metrology.
    ReliableBand or None
        Its reliable band.
    """
    from pipelines.chain.band import reliable_fit
    from pipelines.chain.surface import analyse_surface
    from pipelines.checks.validate import check_fit

    an = analyse_surface(
        scan,
        window_alpha=window_alpha,
        fit_band=fit_band,
        despike=despike,
        mpd_settings=mpd_settings,
        on_levelled=on_levelled,
        on_spectrum2d=on_spectrum2d,
        fit=False,
    )
    rb = reliable_fit(an, resolution_m, window_alpha, fit_band)
    check_fit(an.fit, an.name)
    return an, rb


def friction_psd(spectrum, fit, rb, settings, name="", say=True):
    """The friction engine's spectrum of a measured ``spectrum`` -> (TabulatedPSD, band dict).

    [q0, q1] are ``settings.q0_per_m``/``q1_per_m`` where given, else the reliable band's ends
    (q0 at a roll-off inside the band; :func:`pipelines.chain.band.friction_ends`); above the
    spectrum's last wave vector C(q) continues as ``fit`` (:func:`roadscan.fit.extend_spectrum`).

    Parameters
    ----------
    spectrum : roadscan.Spectrum
        The measured spectrum.
    fit : SelfAffineFit
        Its fit.
    rb : ReliableBand or None
        Its band.
    settings : FrictionSettings
        Friction options.
    name : str, optional
        Scan name for messages.
    say : bool, optional
        Print the extension note.

    Returns
    -------
    psd : friction.TabulatedPSD
    band : dict
    """
    from pipelines.chain.band import friction_ends
    from pipelines.chain.surface import surface_psd
    from pipelines.output.units import quantity
    from pipelines.settings.friction import apply_band

    q0, q1 = friction_ends(rb, fit, settings)
    psd = surface_psd(spectrum, fit, q1_per_m=q1)
    psd, band = apply_band(psd, q0, q1)
    cut = _slope_cut(psd, rb, settings)
    if cut is not None:  # Persson's criterion inside the band (pipelines.chain.cutoff)
        q1 = cut[0]
        psd, band = apply_band(surface_psd(spectrum, fit, q1_per_m=q1), q0, q1)
    if band is not None:
        from pipelines.chain.cutoff import q1_rule

        band = dict(band, q1_rule=q1_rule(rb, settings, None if cut is None else cut[1:]))
        if cut is not None:
            band["slope_cut"] = {"band_end_per_m": cut[1], "rms_slope_to_band_end": cut[2]}
    q_nyq = float(np.max(spectrum.q_per_m))
    if settings.q1_per_m is not None and settings.q1_per_m > q_nyq * (1 + 1e-9):
        dec = float(np.log10(settings.q1_per_m / q_nyq))
        band = dict(
            band or {},
            extended_by="self-affine fit",
            extended_decades=dec,
            note=(
                f"q1 = {quantity('q1_per_m', settings.q1_per_m)} is above the measured band (to "
                f"{quantity('q_per_m', q_nyq)}): C(q) extended {dec:.2f} decades by the self-affine "
                f"fit, H = {fit.hurst:.3f}"
            ),
        )
        if say:
            from pipelines.checks.run_warnings import note

            note(f"note: {name + ': ' if name else ''}{band['note']}")
    return psd, band


def friction_of(psd, settings, v_m_per_s=None, tol=None):
    """mu(v) of friction spectrum ``psd`` with every option of ``settings``
    (:class:`pipelines.settings.friction.FrictionSettings`): the engine's result
    (``v_m_per_s``, ``mu``, ``P`` (A/A0 per speed and q), ``T_q_C`` with flash).

    Parameters
    ----------
    psd : friction.TabulatedPSD or SelfAffinePSD
        The spectrum.
    settings : FrictionSettings
        Friction options.
    v_m_per_s : array_like, optional
        Speeds [m/s].
    tol : float, optional
        Relative tolerance.

    Returns
    -------
    friction.FrictionResult

    References
    ----------
    B.N.J. Persson, J. Chem. Phys. 115, 3840 (2001), doi:10.1063/1.1388626; J. Phys.: Condens.
    Matter 18, 7789 (2006), doi:10.1088/0953-8984/18/32/025.
    """
    from pipelines.chain.surface import friction_curve
    from pipelines.settings.friction import with_extrapolation

    rubber = with_extrapolation(settings.rubber, settings.extrapolate)
    v = settings.v_m_per_s if v_m_per_s is None else v_m_per_s
    return friction_curve(
        psd,
        rubber,
        v,
        settings.sigma0_Pa,
        settings.T0_C,
        settings.flash,
        settings.nu,
        settings.contact_gamma,
        warn_high=False,
        tol=tol,
    )


def noise_floor_end(rb):
    """True when the reliable band's short end is where the spectrum's noise floor begins
    (:func:`roadscan.reliable_band.noise_limit`), not Nyquist or the lateral resolution.

    Parameters
    ----------
    rb : ReliableBand or None
        The band.

    Returns
    -------
    bool
    """
    if rb is None or not getattr(rb, "valid", False):
        return False
    if hasattr(rb, "noise_floor_end"):  # a band read back from psd_band.json
        return bool(rb.noise_floor_end)
    q_noise = (getattr(rb, "limits", None) or {}).get("noise_floor")
    return q_noise is not None and abs(q_noise - rb.hi_per_m) <= 1e-9 * rb.hi_per_m


def _slope_cut(psd, rb, settings):
    """(q1 by Persson's criterion, the band's end, rms slope up to it) when the rule of
    :mod:`pipelines.chain.cutoff` lowers q1 (no ``--q1``, the band ends at the noise floor, spans
    a decade or more and is steeper than :data:`SLOPE_TRUSTED` up to its end), else None."""
    from pipelines.chain.cutoff import slope_cutoff, trusted_decades
    from pipelines.chain.provenance import rms_slope

    if settings.q1_per_m is not None or not noise_floor_end(rb):
        return None
    if trusted_decades(rb) < MIN_TRUSTED_DECADES:
        return None  # judge_fine_end refuses: no decade to trust
    slope = rms_slope(psd)
    if not slope > SLOPE_TRUSTED:
        return None
    q1 = slope_cutoff(psd, psd.q_min_per_m, psd.q1_per_m)
    if q1 is None or not q1 > psd.q_min_per_m * (1 + 1e-6):
        return None
    return q1, float(psd.q1_per_m), slope


def judge_fine_end(psd, rb, settings, name=""):
    """(rms slope over the friction band, refusal line or None), from the measurement alone
    (see the module docstring): refused when q1 is the band's end (no ``--q1``, Persson's
    criterion not applied), the band ends at the spectrum's noise floor, spans under
    :data:`MIN_TRUSTED_DECADES` decade and its rms slope up to its end exceeds
    :data:`SLOPE_TRUSTED`: no decade of the spectrum can be trusted.

    Parameters
    ----------
    psd : friction.TabulatedPSD
        The friction spectrum.
    rb : ReliableBand or None
        The band.
    settings : FrictionSettings
        Friction options.
    name : str, optional
        Scan name.

    Returns
    -------
    slope : float
        Rms slope over the band.
    refusal : str or None
        One line when friction is refused.
    """
    from pipelines.chain.cutoff import trusted_decades
    from pipelines.chain.provenance import rms_slope
    from pipelines.output.units import quantity

    slope = rms_slope(psd)
    if settings.q1_per_m is not None or not noise_floor_end(rb) or not slope > SLOPE_TRUSTED:
        return slope, None
    if psd.q1_per_m < rb.hi_per_m * (1 - 1e-6):  # q1 set inside the band by the rule
        return slope, None
    dec = trusted_decades(rb)
    return slope, (
        f"friction refused: no decade of the spectrum can be trusted (the reliable "
        f"band {quantity('q_per_m', rb.lo_per_m)} to {quantity('q_per_m', rb.hi_per_m)} "
        f"spans {dec:.2g} decades, under {MIN_TRUSTED_DECADES:g}, and ends at the "
        f"spectrum's noise floor with an rms slope of {slope:.3g} up to q1 = "
        f"{quantity('q1_per_m', psd.q1_per_m)}, over {SLOPE_TRUSTED:g}): a lower "
        f"--q1 or --resolution"
    )


@dataclass(frozen=True)
class FrictionOutcome:
    """Friction of one scan: ``result`` (the engine's, None when refused), ``psd`` (the
    integrated spectrum), ``band`` (its [q0, q1] and extension), ``provenance``
    (:func:`pipelines.chain.band.friction_provenance`), ``checks`` (rubber checks).

    Attributes
    ----------
    result : friction.FrictionResult or None
        The engine's result (None when refused).
    psd : friction.TabulatedPSD
        The integrated spectrum.
    band : dict
        Its [q0, q1] and extension.
    provenance : dict
        Where mu comes from.
    checks : dict or None
        Rubber checks.
    """

    result: FrictionResult | None
    psd: TabulatedPSD
    band: dict
    provenance: dict
    checks: dict | None = None


def scan_friction(an, rb, settings, fit=None, v_m_per_s=None, name=None):
    """Friction of analysed scan ``an`` over its reliable band ``rb`` -> :class:`FrictionOutcome`.

    ``fit`` and ``rb`` may be another scan's (dry-vs-wet integrates the wet spectrum over the
    dry scan's band, with its fit); ``v_m_per_s`` overrides the speeds (compare puts every scan
    on the first one's).

    Parameters
    ----------
    an : SurfaceAnalysis
        The analysed scan.
    rb : ReliableBand or None
        The band to integrate over.
    settings : FrictionSettings
        Friction options.
    fit : SelfAffineFit, optional
        Fit used above the spectrum (default the scan's).
    v_m_per_s : array_like, optional
        Speeds [m/s].
    name : str, optional
        Scan name.

    Returns
    -------
    FrictionOutcome
    """
    from pipelines.chain.band import friction_provenance
    from pipelines.chain.provenance import rubber_label
    from pipelines.checks.validate import warn
    from pipelines.settings.friction import run_checks, with_extrapolation

    name = an.name if name is None else name
    fit = an.fit if fit is None else fit
    psd, band = friction_psd(an.spectrum, fit, rb, settings, name)
    slope, refused = judge_fine_end(psd, rb, settings, name)
    if band and band.get("slope_cut"):
        from pipelines.chain.cutoff import cut_warning

        warn(f"{name + ': ' if name else ''}{cut_warning(psd.q1_per_m, **band['slope_cut'])}")
    from pipelines.chain.cutoff import q1_rule

    rule = (band or {}).get("q1_rule") or q1_rule(rb, settings)  # why q1 is where it is
    if refused is not None:
        warn(f"{name + ': ' if name else ''}{refused}")
        label = rubber_label(settings.rubber, settings.sigma0_Pa, settings.T0_C)
        return FrictionOutcome(
            None, psd, band, {"refused": refused, "rubber": label, "rms_slope_band": slope, "q1_rule": rule}
        )
    fr = friction_of(psd, settings, v_m_per_s)
    rubber = with_extrapolation(settings.rubber, settings.extrapolate)
    fr, prov = friction_provenance(an, an.spectrum, psd, fr, settings, rubber, name=name)
    prov = dict(prov, q1_rule=rule)
    checks = None
    if rubber is not None and fr is not None:
        T_max = None if fr.T_q_C is None else float(np.max(fr.T_q_C))
        checks = run_checks(
            rubber, fr.v_m_per_s, psd.q_min_per_m, psd.q1_per_m, fr.meta["T0_C"], T_max, result=fr
        )
    return FrictionOutcome(fr, psd, band, prov, checks)
