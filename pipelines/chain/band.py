"""``analyse``: the reliable band of the scan feeds the self-affine fit and the friction.

The band (:func:`pipelines.chain.reliable.scan_band`, :mod:`roadscan.reliable_band`) is
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

    Sets ``an.fit`` (fitted here once when ``an.fit`` is None: inside the band, else over
    ``fit_band`` or the whole spectrum) and returns the
    :class:`roadscan.reliable_band.ReliableBand` (None when the spectrum has too few points for
    one).

    Parameters
    ----------
    an : SurfaceAnalysis
        The analysed scan.
    resolution_m : float, optional
        Lateral resolution [m].
    window_alpha : float, optional
        Tukey window of the spectrum.
    fit_band : tuple of float, optional
        User's fit band [1/m].

    Returns
    -------
    roadscan.reliable_band.ReliableBand or None
    """
    from pipelines.chain.reliable import scan_band
    from roadscan.fit import detect_band, fit_self_affine
    from roadscan.spectrum_types import Spectrum

    spec = an.spectrum

    def whole():  # the fit over --fit-band, or the whole spectrum
        if an.fit is None:
            an.fit = fit_self_affine(spec, band=fit_band)

    try:
        rb = scan_band(an.source, spec, resolution_m, window_alpha=window_alpha)
    except ValueError:
        whole()
        return None
    if fit_band is not None or not rb.valid:
        whole()
        return rb
    q, C = spec.q_per_m, spec.C_m4
    cnt = spec.count if spec.count is not None else np.ones(q.size, dtype=np.int64)
    top = q <= rb.hi_per_m * (1 + 1e-9)
    inner = top & (q >= rb.lo_per_m * (1 - 1e-9))
    if np.count_nonzero(inner & (C > 0)) < 5:
        whole()
        return rb  # too narrow to refit: the whole fit
    cut = Spectrum(q[top], C[top], count=np.asarray(cnt)[top], kind=spec.kind, meta=spec.meta)
    sub = Spectrum(q[inner], C[inner], count=np.asarray(cnt)[inner], kind=spec.kind)
    try:
        band = detect_band(sub)
    except ValueError:
        band = (float(q[inner][0]), float(q[inner][-1]))
    q_roll = rb.q_roll_per_m if rb.q_roll_per_m and rb.q_roll_per_m < band[0] * 1.5 else None
    try:
        an.fit = fit_self_affine(cut, band=band, roll_off=q_roll)  # the band's roll-off test
    except ValueError:  # saw every ring
        whole()
    return rb


def friction_ends(rb, fit, settings):
    """(q0, q1) [1/m] of the friction integrals: the flags where given, else the band's ends
    (q0 at a roll-off inside the band); (None, None) without a band.

    Parameters
    ----------
    rb : ReliableBand or None
        The band.
    fit : SelfAffineFit
        The fit.
    settings : FrictionSettings
        The friction options.

    Returns
    -------
    tuple
        (q0, q1) [1/m] or (None, None).
    """
    if rb is None or not rb.valid:
        return settings.q0_per_m, settings.q1_per_m
    q0 = settings.q0_per_m
    if q0 is None:
        q0 = rb.lo_per_m
        q_roll = rb.q_roll_per_m or getattr(fit, "q_roll_per_m", None)
        if q_roll is not None and rb.lo_per_m < q_roll < rb.hi_per_m / 2:
            q0 = q_roll
    q1 = settings.q1_per_m if settings.q1_per_m is not None else rb.hi_per_m
    return float(q0), float(q1)


def summary_keys(rb, name=""):
    """The ``summary.json`` keys of the band (empty without one); warns (once, after the
    friction's own checks) when the band is under a factor 2 wide.

    Parameters
    ----------
    rb : ReliableBand or None
        The band.
    name : str, optional
        Scan name for the warning.

    Returns
    -------
    dict
    """
    if rb is None:
        return {}
    if not rb.valid:
        from pipelines.checks import validate

        validate.warn(
            f"{name}: reliable band {rb.lo_per_m:.3g}-{rb.hi_per_m:.3g} 1/m is narrower "
            f"than a factor 2 (the scan is small for its spacing: {rb.lo_reason.split(':')[0]} "
            f"vs {rb.hi_reason.split(':')[0]}): fit and friction use the whole spectrum"
        )
    return {
        "reliable_band_per_m": rb.band,
        "reliable_band_reasons": rb.reasons,
        "reliable_band_limits_per_m": dict(rb.limits),
    }


def friction_provenance(an, spec, psd, fr, settings, rubber, name=None):
    """mu's provenance (:mod:`pipelines.chain.provenance`) -> (fr, info).

    ``info``: ``extrapolated_share`` per speed, ``rubber`` (name, T0, sigma0), ``rms_slope``
    over the integrated band and ``refused`` (None: whether the band's fine end is trusted is
    the measurement's decision, :func:`pipelines.chain.steps.judge_fine_end`, taken before any mu).
    A peak mu outside 0.3-3 is a warning naming its likely causes and the flags.
    """
    from pipelines.chain import provenance as mp
    from pipelines.chain.surface import friction_curve
    from pipelines.checks import validate

    name = an.name if name is None else name

    def recompute(p):
        return friction_curve(
            p,
            rubber,
            fr.v_m_per_s,
            settings.sigma0_Pa,
            settings.T0_C,
            settings.flash,
            settings.nu,
            settings.contact_gamma,
            warn_high=False,
        ).mu

    share = mp.extrapolated_share(psd, fr.mu, float(spec.q_max_per_m), recompute)
    i = int(np.argmax(fr.mu))
    slope = mp.rms_slope(psd)
    info = {
        "extrapolated_share": share,
        "extrapolated_share_at_peak": float(share[i]),
        "rubber": mp.rubber_label(settings.rubber, settings.sigma0_Pa, fr.meta.get("T0_C")),
        "rms_slope_band": slope,
        "refused": None,
    }
    cause = mp.implausible_cause(
        float(fr.mu[i]),
        share_at_peak=float(share[i]),
        slope=slope,
        rms_height_m=an.roughness.get("Sq_m", an.roughness.get("Rq_m")),
        default_rubber=settings.rubber is None,
        q1_per_m=psd.q1_per_m,
        units_from_file=mp.units_from_file(an.source),
    )
    who = f"{name}: " if name else ""  # a scan in memory has no name: no empty prefix
    if cause is not None:
        validate.warn(f"{who}{cause}")
    edge = mp.edge_warning(fr.v_m_per_s, fr.mu)
    if edge is not None:
        validate.warn(f"{who}{edge}")
    return fr, info


def add_provenance(summary, info, q0, q1):
    """Put :func:`friction_provenance`'s ``info`` into ``summary['friction']``."""
    if info is None:
        return summary
    if info["refused"]:
        summary["friction"] = {
            "refused": info["refused"],
            "rubber": info["rubber"],
            "q0_per_m": q0,
            "q1_per_m": q1,
            "rms_slope_band": info["rms_slope_band"],
        }
        if info.get("q1_rule"):
            summary["friction"]["q1_rule"] = info["q1_rule"]
        return summary
    summary["friction"].update(
        q1_rule=info.get("q1_rule"),
        rubber=info["rubber"],
        rms_slope_band=info["rms_slope_band"],
        extrapolated_share=[float(x) for x in info["extrapolated_share"]],
        extrapolated_share_at_peak=info["extrapolated_share_at_peak"],
    )
    return summary


def report_rows(summary):
    """The report's rows of the reliable band and the friction's provenance (mm/um, 3
    significant digits)."""
    from pipelines.output.units import sig3

    rows = {}
    if "reliable_band_per_m" in summary:
        lo, hi = summary["reliable_band_per_m"]
        why = summary.get("reliable_band_reasons", {})
        rows["reliable band (wavelengths)"] = f"{_wl(hi)} to {_wl(lo)}"
        rows["reliable band: long end"] = why.get("lo", "")
        rows["reliable band: short end"] = why.get("hi", "")
    fr = summary.get("friction")
    if fr:
        if fr.get("rubber"):
            rows["rubber (friction)"] = fr["rubber"]
        if fr.get("q1_per_m") is not None:  # which q1, and the rule that put it there
            from pipelines.output.units import quantity

            rows["friction band's short end q1"] = (
                f"{quantity('q1_per_m', fr['q1_per_m'])}: {fr.get('q1_rule') or 'not stated'}"
            )
        if fr.get("refused"):
            rows["friction"] = fr["refused"]
        else:
            if fr.get("peak_at_edge"):  # no peak inside the speed range: never "peak"
                rows["largest μ"] = f"{sig3(fr['mu_peak'])}, {fr['peak_note']}"
            else:
                rows["peak μ"] = sig3(fr["mu_peak"])
                rows["speed at peak [m/s]"] = sig3(fr["v_peak_m_per_s"])
            if "extrapolated_share_at_peak" in fr:
                rows["share of μ from beyond the last measured q (at peak)"] = (
                    f"{sig3(100 * fr['extrapolated_share_at_peak'])} %"
                )
    return rows


def _wl(q):
    from pipelines.output.units import wavelength_of_q

    return wavelength_of_q(q)


def warnings_section(summary):
    """("Warnings", table) for a report, or None when there are none."""
    from pipelines.output import report

    w = summary.get("warnings") or []
    return ("Warnings", report.table_html([[x] for x in w], ["warning"])) if w else None


def share_section(summary, fr):
    """("μ and its extrapolated share", table at whole decades of speed) for the report, or
    None without friction."""
    from pipelines.output import report
    from pipelines.output.units import sig3

    f = summary.get("friction") or {}
    if fr is None or "extrapolated_share" not in f:
        return None
    v = np.asarray(fr.v_m_per_s, float)
    share = np.asarray(f["extrapolated_share"], float)
    rows = []
    for d in range(int(np.floor(np.log10(v[0]))), int(np.ceil(np.log10(v[-1]))) + 1):
        i = int(np.argmin(np.abs(np.log10(v) - d)))
        if abs(np.log10(v[i]) - d) < 0.05:
            rows.append([sig3(v[i]), sig3(fr.mu[i]), f"{sig3(100 * share[i])} %"])
    return (
        "μ and the share carried by wave vectors beyond the last measured one",
        report.table_html(rows, ["v [m/s]", "μ", "extrapolated share"]),
    )
