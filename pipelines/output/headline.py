"""Headline figures that must only be given when they mean what a reader takes them to mean.

Three rules, shared by ``analyse``, ``compare``, ``dry-vs-wet`` and ``friction``:

- **Hurst exponent.** A self-affine fit is a headline only when it is one: over a band of at
  least half a decade (``log10(q_hi / q_lo) >= 0.5``) and with ``0 <= H <= 1`` (a self-affine
  surface has ``C(q) ~ q^-2(1+H)`` with ``0 < H < 1``; Persson et al., J. Phys.: Condens.
  Matter 17 (2005) R1; Jacobs, Junge and Pastewka, Surf. Topogr.: Metrol. Prop. 5 (2017)
  013001). Otherwise ``hurst`` and ``hurst_stderr`` are null and ``hurst_note`` says why; the
  fitted value stays in ``hurst_fit`` and ``hurst_fit_stderr`` (a diagnostic, not a result).
- **Friction peak.** The largest mu of a speed grid is a peak only when it lies inside the grid.
  At the first or last speed (``peak_at_edge`` true) mu is still rising (or falling) beyond the
  grid, and the text says "still rising at 100 m/s" (or "largest at the slowest speed"), never
  "peak".
- **Default rubber.** The built-in rubber (a one-relaxation-time standard linear solid, the
  thesis's illustrative model) is no tread compound: it is named :data:`RUBBER_ILLUSTRATIVE`
  wherever a mu is shown, so that a road engineer does not quote its mu as the road's.

And the scope of the wet model of ``dry-vs-wet`` (:data:`WET_MODEL`): the rain-filled surface
only changes the roughness the rubber sees (Persson's hysteresis theory applied to the filled
geometry); adhesion, squeeze-out and viscous or hydrodynamic effects of the water are not
modelled, which is why the wet/dry ratio hardly changes with speed.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "RUBBER_ILLUSTRATIVE",
    "MIN_FIT_DECADES",
    "hurst_keys",
    "hurst_text",
    "peak_keys",
    "peak_text",
    "side_keys",
    "hurst_pair_text",
    "WET_MODEL",
    "WET_MODEL_PERSSON",
    "wet_model_html",
    "friction_headline",
]

#: the name of the built-in rubber on every mu figure, report and summary
RUBBER_ILLUSTRATIVE = "illustrative (thesis SLS, not a tread compound)"
#: shortest fitted band [decades of q] for the Hurst exponent to be a headline
MIN_FIT_DECADES = 0.5


def _finite(x):
    try:
        x = float(x)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def hurst_keys(hurst, hurst_stderr, fit_band_per_m):
    """The ``summary.json`` keys of a self-affine fit's Hurst exponent.

    Parameters
    ----------
    hurst, hurst_stderr : float
        The fitted exponent H [-] and its standard error.
    fit_band_per_m : (float, float)
        The fitted band (q_lo, q_hi) [1/m].

    Returns
    -------
    dict
        ``hurst``, ``hurst_stderr`` (null unless the fit is a headline), ``hurst_fit``,
        ``hurst_fit_stderr`` (the fitted values, always) and ``hurst_note`` (null, or why H is
        not given: a band under :data:`MIN_FIT_DECADES` decades, H outside [0, 1], or no fit).
    """
    h, se = _finite(hurst), _finite(hurst_stderr)
    lo, hi = (_finite(b) for b in fit_band_per_m)
    decades = math.log10(hi / lo) if lo and hi and lo > 0 and hi > lo else 0.0
    notes = []
    if h is None:
        notes.append("the self-affine fit gave no finite H")
    if decades < MIN_FIT_DECADES:
        notes.append(
            f"the fitted band spans {decades:.2g} decades of q, under the "
            f"{MIN_FIT_DECADES:g} a Hurst exponent needs"
        )
    if h is not None and not 0.0 <= h <= 1.0:
        notes.append(f"the fitted H = {h:.3g} lies outside [0, 1] (not a self-affine surface over that band)")
    note = None
    if notes:
        fit = (
            ""
            if h is None
            else (f" (fit: {h:.3g}" + (f" ± {se:.2g}" if se is not None else "") + ", kept as hurst_fit)")
        )
        note = "H not given: " + "; ".join(notes) + fit
    return {
        "hurst": None if note else h,
        "hurst_stderr": None if note else se,
        "hurst_fit": h,
        "hurst_fit_stderr": se,
        "hurst_note": note,
    }


def hurst_text(summary, short=False):
    """``"0.812 ± 0.004"`` when ``summary['hurst']`` is a headline, else its ``hurst_note``
    (``short``: ``"not given (see hurst_note)"``, for figure titles).

    Parameters
    ----------
    summary : dict
        A summary with ``hurst``, ``hurst_stderr`` and ``hurst_note``.
    short : bool, optional
        The short form for figure titles.

    Returns
    -------
    str
    """
    h = summary.get("hurst")
    if h is None:
        if short:
            return "not given (fit not meaningful: see the report)"
        note = summary.get("hurst_note") or "not given"
        return note[2:] if note.startswith("H not given") else note  # after "H = " or "H |"
    se = summary.get("hurst_stderr")
    return f"{h:.3f}" + (f" ± {se:.3f}" if se is not None else "")


def peak_keys(v_m_per_s, mu):
    """Where the largest mu of a speed grid lies.

    Returns
    -------
    dict
        ``mu_peak`` and ``v_peak_m_per_s`` (the largest mu and its speed [m/s]),
        ``peak_at_edge`` (true when that is the first or last speed of the grid: no peak inside
        it) and ``peak_note`` (null, or "still rising at ... m/s" / "largest at the slowest
        speed ..." ).

    Parameters
    ----------
    v_m_per_s, mu : array_like
        The friction curve.
    """
    v = np.asarray(v_m_per_s, float)
    m = np.asarray(mu, float)
    i = int(np.argmax(m))
    edge = m.size > 0 and (i == 0 or i == m.size - 1)
    note = None
    if edge:
        from pipelines.output.units import sig3

        if i == m.size - 1:
            note = (
                f"still rising at {sig3(v[i])} m/s (the fastest speed computed): no peak in the speed range"
            )
        else:
            note = (
                f"largest at the slowest speed, {sig3(v[i])} m/s: falling with speed over "
                f"the whole range, no peak in it"
            )
    return {
        "mu_peak": float(m[i]),
        "v_peak_m_per_s": float(v[i]),
        "peak_at_edge": bool(edge),
        "peak_note": note,
    }


def peak_text(mu_peak, v_peak_m_per_s, peak_at_edge=False, peak_note=None):
    """``"peak μ 1.23 at 4.56 m/s"``, or, when the largest mu sits at an end of the speed grid,
    ``"μ 1.81, still rising at 100 m/s ..."`` (never "peak").

    Parameters
    ----------
    mu_peak : float
        Largest mu.
    v_peak_m_per_s : float
        Its speed [m/s].
    peak_at_edge : bool, optional
        At an end of the speed grid.
    peak_note : str, optional
        The note then.

    Returns
    -------
    str
    """
    from pipelines.output.units import sig3

    if peak_at_edge:
        return f"μ {sig3(mu_peak)}, {peak_note}"
    return f"peak μ {sig3(mu_peak)} at {sig3(v_peak_m_per_s)} m/s"


def hurst_pair_text(result, sides=("dry", "wet")):
    """``"0.863 ± 0.005 / 0.849 ± 0.008"`` from ``hurst_dry``, ``hurst_stderr_dry``,
    ``hurst_note_dry``... (a side's note when its H is not a headline).

    Parameters
    ----------
    result : dict
        Keys with ``_dry``/``_wet`` suffixes.
    sides : tuple of str, optional
        The suffixes.

    Returns
    -------
    str
    """
    return " / ".join(
        hurst_text({k: result.get(f"{k}_{s}") for k in ("hurst", "hurst_stderr", "hurst_note")})
        for s in sides
    )


def side_keys(keys, side):
    """``{"hurst": ..}`` -> ``{"hurst_dry": ..}``: the keys of one side of a dry/wet pair.

    Parameters
    ----------
    keys : dict
        Keys of one side.
    side : str
        ``"dry"`` or ``"wet"``.

    Returns
    -------
    dict
    """
    return {f"{k}_{side}": v for k, v in keys.items()}


#: what the wet (rain-filled) friction of dry-vs-wet covers and leaves out
WET_MODEL = {
    "covers": (
        "the viscoelastic (hysteresis) friction of the rubber on the rain-filled geometry: "
        "water stands in the depressions up to their spill level and the rubber slides "
        "over the filled surface (Persson's theory on the filled spectrum)"
    ),
    "leaves_out": [
        "adhesion (none in the dry mu either)",
        "squeeze-out of the water film from the contact (time and speed dependent)",
        "viscous and hydrodynamic effects of the water (lubrication, aquaplaning)",
        "the water's effect on rubber temperature",
    ],
    "consequence": (
        "the wet/dry ratio reflects only the roughness the water hides, so it "
        "changes little with speed; measured wet friction also falls with speed "
        "through the effects left out"
    ),
}


#: what the persson wet model of dry-vs-wet (the default) covers and leaves out
WET_MODEL_PERSSON = {
    "covers": (
        "the hysteresis friction of the rubber on the surface whose pools the contact seals at "
        "the magnification where it percolates (Persson et al., Phys. Rev. B 71, 035428 (2005)), "
        "the squeeze-out of the water film under a tread block during the dwell time (averaged "
        "Reynolds flow with Persson's contact pressure), the water's inertia at the footprint's "
        "front (Horne & Dreher 1963), adhesion lost where water separates the surfaces (with "
        "--shear-stress), and the viscous drag of the film where contact is lost"
    ),
    "leaves_out": [
        "the viscous film on the asperity tops (thin-film lubrication of the microtexture)",
        "roughness below the scan's resolution",
        "the tread's grooves as water storage",
        "the water's effect on rubber temperature",
    ],
    "consequence": (
        "on textured roads the squeezed film drains within the dwell time, so most of the fall "
        "of mu_wet with speed is the dry curve's own; measured wet friction falls faster "
        "through the microtexture's film, which the scan does not resolve"
    ),
}


def wet_model_html():
    """The report paragraph saying what the wet model covers and what it leaves out.

    Parameters
    ----------
    None

    Returns
    -------
    str
        HTML.
    """
    from pipelines.output.templates import render

    then = WET_MODEL["consequence"]
    return render(
        "wet_model_note.html.j2",
        covers=WET_MODEL["covers"],
        left_out=", ".join(WET_MODEL["leaves_out"]),
        then=then[0].upper() + then[1:],
    )


def friction_headline(summary):
    """The friction part of a scan's headline: ``"peak μ 1.81 at 10.0 m/s; q1 = 3.4e+04 1/m
    (λ = 185 µm): the reliable band's short end (Nyquist)"`` (which q1 and the rule that chose
    it, :mod:`pipelines.chain.cutoff`), ``"friction refused"`` or "" without friction.

    Parameters
    ----------
    summary : dict
        A ``summary.json`` of ``roadscan analyse``.

    Returns
    -------
    str
    """
    from pipelines.output.units import quantity

    fr = summary.get("friction")
    if not fr:
        return ""
    q1 = fr.get("q1_per_m")
    where = (
        f"q1 = {quantity('q1_per_m', q1)}: {fr['q1_rule']}" if q1 is not None and fr.get("q1_rule") else ""
    )
    if fr.get("refused"):
        return "friction refused" + (f" ({where})" if where else "")
    peak = peak_text(fr["mu_peak"], fr["v_peak_m_per_s"], fr.get("peak_at_edge"), fr.get("peak_note"))
    return peak + (f"; {where}" if where else "")
