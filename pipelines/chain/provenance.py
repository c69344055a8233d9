"""Where mu comes from: the share carried by extrapolated roughness, and why a mu is implausible.

**extrapolated_share** (per speed): the part of mu carried by wave vectors beyond the last
measured one, q_m (the spectrum's last point; a model spectrum measures nothing):

    share(v) = 1 - mu(v; q1 = q_m) / mu(v; q1),

with the same rubber, pressure and model, so 0 when q1 <= q_m. Persson's integrand is
cumulative in q (mu = 1/2 int_{q0}^{q1} q^3 C S P M dq, with P(q) depending on q' < q only),
so for the isothermal model this is exactly the integral's share above q_m; with flash
temperatures it is the drop of mu when the extension is removed.

**Plausibility.** Tread rubber on road surfaces gives peak mu between about 0.3 and 3
(:data:`MU_PLAUSIBLE`; Persson, J. Phys.: Condens. Matter 18, 7789 (2006); Lorenz et al., Eur.
Phys. J. E 34, 129 (2011); dry to wet, 0.3 to 2 in road tests). Outside it,
:func:`implausible_cause` names the most likely cause and the flag that changes it: units
(rms height outside 1 um..20 mm: ``--units``), cut-off (over 30 % of mu from extrapolated
wave vectors: ``--q1``), band (rms slope over the integrated band above 1: ``--q1``; whether
the band's fine end holds noise is the measurement's call, :func:`pipelines.chain.steps.judge_fine_end`,
the same whatever the rubber), rubber (the default thesis rubber is not a
tread compound: ``--rubber``).
"""

from __future__ import annotations

import numpy as np

from pipelines.output.units import length, quantity

__all__ = [
    "extrapolated_share",
    "rms_slope",
    "implausible_cause",
    "MU_PLAUSIBLE",
    "rubber_label",
    "units_from_file",
    "edge_warning",
]

MU_PLAUSIBLE = (0.3, 3.0)
SHARE_CUTOFF = 0.3
SLOPE_BAND = 1.0
RMS_RANGE_M = (1e-6, 20e-3)


def extrapolated_share(psd, mu, q_measured, recompute):
    """Per speed, the share of ``mu`` from q above ``q_measured`` [1/m] (None: a model
    spectrum, every share 0). ``recompute(psd_cut)`` returns mu on the same speeds.

    Parameters
    ----------
    psd : spectrum
        The integrated spectrum.
    mu : ndarray
        mu per speed.
    q_measured : float or None
        Last measured wave vector [1/m].
    recompute : callable
        mu of a cut spectrum.

    Returns
    -------
    ndarray
        Share in [0, 1] per speed.
    """
    mu = np.asarray(mu, float)
    if q_measured is None or not psd.q1_per_m > q_measured * (1 + 1e-9):
        return np.zeros_like(mu)
    from friction import TabulatedPSD
    from friction.band import integration_band

    if isinstance(psd, TabulatedPSD):
        cut, _ = integration_band(psd, None, q_measured)
    else:
        cut = psd.with_q1(q_measured)
    mu_cut = np.asarray(recompute(cut), float)
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.where(mu > 0, 1.0 - mu_cut / mu, 0.0)
    return np.clip(np.nan_to_num(share), 0.0, 1.0)


def rms_slope(psd, q0=None, q1=None, n=400):
    """rms slope sqrt(2 pi int q^3 C dq) of ``psd`` over [q0, q1] [1/m] (an area's; a profile's
    is 1/sqrt(2) of it).

    Parameters
    ----------
    psd : spectrum
        The spectrum.
    q0, q1 : float, optional
        Band [1/m].
    n : int, optional
        Quadrature nodes.

    Returns
    -------
    float
    """
    q0 = psd.q_min_per_m if q0 is None else q0
    q1 = psd.q1_per_m if q1 is None else q1
    lq = np.linspace(np.log(q0), np.log(q1), n)
    q = np.exp(lq)
    f = 2 * np.pi * q**4 * psd.C(q)  # q^3 C dq = q^4 C d(ln q)
    return float(np.sqrt(max(0.0, np.trapezoid(f, lq))))


def rubber_label(rubber, sigma0_Pa, T0_C):
    """'thesis SLS rubber, T0 = 60 C, sigma0 = 0.2 MPa' (the name, temperature and pressure
    printed on every friction figure and report).

    Parameters
    ----------
    rubber : rubber model
        The rubber.
    sigma0_Pa : float
        Nominal pressure [Pa].
    T0_C : float
        Temperature [C].

    Returns
    -------
    str
    """
    if rubber is None:
        from pipelines.output.headline import RUBBER_ILLUSTRATIVE

        name = f"default rubber: {RUBBER_ILLUSTRATIVE}"
    else:
        name = getattr(rubber, "name", None) or type(rubber).__name__
    if T0_C is None:
        T0_C = getattr(rubber, "T_ref_C", None)
        if T0_C is None:
            import friction

            T0_C = friction.thesis_rubber().T_ref_C
    return f"{name}, T0 = {T0_C:.3g} °C, σ0 = {sigma0_Pa / 1e6:.3g} MPa"


def implausible_cause(
    mu_peak,
    *,
    share_at_peak=0.0,
    slope=None,
    rms_height_m=None,
    default_rubber=True,
    q1_per_m=None,
    units_from_file=False,
):
    """None when ``mu_peak`` is within :data:`MU_PLAUSIBLE`, else one line: the likely cause
    and the flag that changes it.

    Parameters
    ----------
    mu_peak : float
        Largest mu.
    share_at_peak : float, optional
        Extrapolated share there.
    slope : float, optional
        Rms slope of the band.
    rms_height_m : float, optional
        Rms height [m].
    default_rubber : bool, optional
        The thesis rubber was used.
    q1_per_m : float, optional
        Upper band end [1/m].
    units_from_file : bool, optional
        The heights' unit is the one the file states (x3p, plu, opd, sur, al3d, a text title,
        :func:`units_from_file`): an rms height that is not a road's is then named as the
        surface's, never as a ``--units`` slip.

    Returns
    -------
    str or None
    """
    lo, hi = MU_PLAUSIBLE
    if lo <= mu_peak <= hi:
        return None
    side = "above" if mu_peak > hi else "below"
    causes = []
    if rms_height_m is not None and not (RMS_RANGE_M[0] <= rms_height_m <= RMS_RANGE_M[1]):
        if units_from_file:  # the file states its unit: not a --units question
            causes.append(
                f"surface (rms height {length(rms_height_m)}, in the unit the file "
                f"states, is not a road's texture)"
            )
        else:
            causes.append(f"units (rms height {rms_height_m * 1e3:.3g} mm is not a road's: --units)")
    if mu_peak > hi and share_at_peak > SHARE_CUTOFF:
        causes.append(
            f"cut-off ({100 * share_at_peak:.0f} % of mu from wave vectors beyond the scan: a lower --q1)"
        )
    if mu_peak > hi and slope is not None and slope > SLOPE_BAND:
        causes.append(
            f"band (rms slope {slope:.3g} up to q1 = {quantity('q1_per_m', q1_per_m)}: "
            f"steep roughness carries much of mu; a lower --q1 if the finest "
            f"wavelengths are not road texture)"
        )
    if mu_peak < lo and slope is not None and slope < 0.1:
        causes.append(f"band (rms slope {slope:.3g}: too smooth or too short a band: --q1)")
    if default_rubber:
        causes.append("rubber (the default thesis rubber is not your tread compound: --rubber)")
    if not causes:
        causes.append("the rubber model or the band (--rubber, --q0/--q1)")
    return (
        f"peak mu {mu_peak:.3g} is {side} the {lo:g}-{hi:g} that tread rubber gives on roads; "
        f"likely cause: {'; '.join(causes)}"
    )


def units_from_file(scan):
    """True when the scan's height unit is the one its file states (the reader recorded
    ``meta["height_unit"]["from"] == "file"``: x3p, vendor formats, a text title), not a flag
    and not a default.

    Parameters
    ----------
    scan : HeightMap or Profile
        A read scan.

    Returns
    -------
    bool
    """
    meta = getattr(scan, "meta", None) or {}
    info = meta.get("height_unit") if isinstance(meta, dict) else None
    return isinstance(info, dict) and info.get("from") == "file"


def edge_warning(v_m_per_s, mu):
    """The warning when the largest mu of a curve sits at an end of its speed range (no peak
    inside it: :func:`pipelines.output.headline.peak_keys`), naming ``--velocities``; None
    when the peak is inside.

    Parameters
    ----------
    v_m_per_s, mu : array_like
        The friction curve.

    Returns
    -------
    str or None
    """
    from pipelines.output.headline import peak_keys

    k = peak_keys(v_m_per_s, mu)
    if not k["peak_at_edge"]:
        return None
    return f"μ {k['peak_note']}; widen --velocities to see the peak"
