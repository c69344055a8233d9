"""The wet model of ``roadscan dry-vs-wet --wet-model persson`` (the default): the dry scan's
friction with what water changes (:mod:`friction.wet`): the pools the contact seals
(:func:`roadscan.sealing.seal_pools` at the engine's percolation magnification), the film left
under a tread block after the dwell time, the adhesion water removes, and the speed where the
contact is lost. Both curves use the friction model of the run's settings (isothermal unless
``--flash``: the dry curve is analyse's, so the wet one is comparable with it; with
``--flash`` both include the rubber's heating, and the mechanism shares then say how much of
the wet-dry difference is the water's, the fall of the dry curve itself being the heating's).

Also the figures road engineers compare it with: the speed constant of an exponential fitted to
mu_wet over 20-100 km/h (as ASTM E1960 writes wet friction, F(S) = F60 exp((60 - S)/Sp)) next
to the surface's IFI speed constant Sp = 14.2 + 89.7 MPD (MPD in mm, ISO 13473-1 on the scan).
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["persson_wet", "speed_constant_kmh", "fall_split", "wet_model_keys", "SP_FIT_KMH"]

#: the speed range of the fitted speed constant [km/h] (the IFI's 20-100 km/h)
SP_FIT_KMH = (20.0, 100.0)


def speed_constant_kmh(v_m_per_s, mu):
    """Sp [km/h] of ``mu = F exp(-S / Sp)`` fitted (least squares in ln mu) over 20-100 km/h;
    None with fewer than two speeds there or when mu does not fall.

    Parameters
    ----------
    v_m_per_s, mu : array_like
        The curve.

    Returns
    -------
    float or None
    """
    S = np.asarray(v_m_per_s, float) * 3.6
    mu = np.asarray(mu, float)
    sel = (S >= SP_FIT_KMH[0] * (1 - 1e-9)) & (S <= SP_FIT_KMH[1] * (1 + 1e-9)) & (mu > 0)
    if sel.sum() < 2:
        return None
    slope = np.polyfit(S[sel], np.log(mu[sel]), 1)[0]
    return float(-1.0 / slope) if slope < 0 else None


def fall_split(v_m_per_s, mu_dry, mu_wet):
    """How much mu_wet falls from 20 to 100 km/h, and which part of that the dry curve (the
    rubber's own speed dependence; with ``--flash`` its heating) and the water give:
    ``wet(20) - wet(100) = [dry(20) - dry(100)] + [loss(100) - loss(20)]``, loss = dry - wet
    (mu interpolated linearly in log v). None when the speeds do not span 20-100 km/h.

    Parameters
    ----------
    v_m_per_s, mu_dry, mu_wet : array_like
        The curves.

    Returns
    -------
    dict or None
        ``mu_wet``, ``dry_curve``, ``water`` (mu differences, positive = a fall).
    """
    v = np.asarray(v_m_per_s, float)
    lo, hi = SP_FIT_KMH[0] / 3.6, SP_FIT_KMH[1] / 3.6
    if v.min() > lo * (1 + 1e-9) or v.max() < hi * (1 - 1e-9):
        return None
    at = [np.interp(np.log([lo, hi]), np.log(v), np.asarray(m, float)) for m in (mu_dry, mu_wet)]
    (d20, d100), (w20, w100) = at
    return {
        "mu_wet": float(w20 - w100),
        "dry_curve": float(d20 - d100),
        "water": float((d100 - w100) - (d20 - w20)),
    }


def wet_model_keys(name, connectivity=4, max_depth_m=None, water_film_m=None, conditions=None, settings=None):
    """``comparison.json``'s ``wet_model``: the model's name and its parameters (with the
    sources of the persson model's defaults; the fill model also says what it covers).

    Parameters
    ----------
    name : {"persson", "fill"}
        The wet model.
    connectivity, max_depth_m, water_film_m : optional
        The rain fill's neighbourhood and limits [m] (fill).
    conditions : friction.wet.WetConditions, optional
        Water and tyre (persson; default its defaults).
    settings : FrictionSettings, optional
        Friction options (the friction model of both curves).

    Returns
    -------
    dict
    """
    from friction.wet.water import DEFAULT_SOURCES, WetConditions
    from pipelines.output.headline import WET_MODEL, WET_MODEL_PERSSON

    flash = bool(settings is not None and settings.flash)
    model = "flash temperature" if flash else "isothermal"
    sigma0 = None if settings is None else settings.sigma0_Pa  # the chain's nominal pressure
    if name == "fill":
        return {
            "name": "fill",
            **WET_MODEL,
            "friction_model": model,
            "parameters": {
                "connectivity": connectivity,
                "max_depth_m": max_depth_m,
                "water_film_m": water_film_m,
                "sigma0_Pa": sigma0,
            },
        }
    cond = conditions or WetConditions()
    params = {
        k: getattr(cond, k)
        for k in (
            "water_depth_m",
            "water_temperature_C",
            "footprint_m",
            "block_size_m",
            "shear_stress_Pa",
            "percolation_contact_fraction",
        )
    }
    params["water_viscosity_Pa_s"] = cond.viscosity_Pa_s
    params["sigma0_Pa"] = sigma0
    default = WetConditions()
    return {
        "name": "persson",
        **WET_MODEL_PERSSON,
        "parameters": params,
        "given": [k for k in params if k in DEFAULT_SOURCES and params[k] != getattr(default, k)],
        "sources": {k: src for k, (_, src) in DEFAULT_SOURCES.items()},
        "friction_model": model,
        "adhesion": (
            "included, tau_f given"
            if cond.shear_stress_Pa is not None
            else "left out: no --shear-stress given"
        ),
    }


def _by_speed(v, x):
    return {f"{float(a):g}": (None if not np.isfinite(b) else float(b)) for a, b in zip(v, x)}


def _no_rougher(psd_sealed, psd_dry):
    """The sealed spectrum, nowhere above the dry one: ``C_s(q) = min(C_sealed(q), C(q))``.

    Water in a pool only hides roughness: its surface is free, and the kink where it meets the
    rim is a meniscus the rubber does not have to follow. On the filled map that kink is a
    step in slope, which puts spectral power at short wavelengths (and the small change of a
    few pools moves the periodogram's estimate by a few per cent either way); taking the
    minimum keeps sealing from ever adding hysteresis.
    """
    from friction import TabulatedPSD

    q = psd_sealed.q_per_m
    return TabulatedPSD(
        q,
        np.minimum(psd_sealed.C_m4, psd_dry.C(q)),
        q0_per_m=psd_sealed.q0_per_m,
        q1_per_m=min(psd_sealed.q1_per_m, psd_dry.q1_per_m),
    )


def persson_wet(dry_map, an_dry, rb_dry, outcome, settings, conditions, window_alpha=0.25):
    """The wet curve of the persson model beside the dry outcome of the chain.

    Parameters
    ----------
    dry_map : HeightMap
        The levelled scan [m].
    an_dry, rb_dry : SurfaceAnalysis, ReliableBand
        Its analysis and band (:func:`pipelines.chain.steps.measure`).
    outcome : FrictionOutcome
        Its dry friction (:func:`pipelines.chain.steps.scan_friction`).
    settings : FrictionSettings
        Friction options (the engine of both curves).
    conditions : friction.wet.WetConditions
        Water and tyre.
    window_alpha : float, optional
        Tukey window of the sealed map's spectrum.

    Returns
    -------
    (friction.wet.WetFriction, dict)
        The curves, and the ``comparison.json`` keys of the wet model (``wet_model``,
        ``film_m``, ``mechanisms``, ``contact_lost_v_m_per_s``, ``sealing``).
    """
    from friction.wet import wet_friction
    from friction.wet.sealing import sealing_wave_vector
    from pipelines.chain.steps import friction_of, friction_psd
    from pipelines.chain.surface import analyse_surface
    from roadscan.sealing import seal_pools

    dry = outcome.result
    frac = conditions.percolation_contact_fraction
    q_c = sealing_wave_vector(dry.q_per_m, dry.P[0], frac)
    # every region out of contact is a pool: the scan lies inside the footprint, whose edge and
    # not the scan's lets water out, and at the percolation threshold the non-contact clusters
    # are finite (open at the scan's border, 0.6 % of a 12 cm asphalt map was sealed, not 44 %)
    sealed = seal_pools(
        dry_map,
        q_seal_per_m=q_c,
        contact_fraction=frac,
        water_film_m=conditions.water_depth_m,
        open_border=False,
    )
    psd_s = None
    if sealed.pool_count:
        an_s = analyse_surface(sealed.wet, window_alpha=window_alpha)
        psd_s = _no_rougher(
            friction_psd(an_s.spectrum, an_dry.fit, rb_dry, settings, say=False)[0], outcome.psd
        )

    def engine(psd, v, sigma):
        return friction_of(psd, dataclasses.replace(settings, sigma0_Pa=sigma), v)

    wf = wet_friction(
        dry=dry,
        psd=outcome.psd,
        engine=engine,
        sigma0_Pa=settings.sigma0_Pa,
        conditions=conditions,
        psd_sealed=psd_s,
        sealed_fraction=sealed.sealed_fraction,
        q_seal_per_m=q_c,
    )
    v = wf.v_m_per_s
    keys = {
        "wet_model": wet_model_keys("persson", conditions=conditions, settings=settings),
        "film_m": _by_speed(v, wf.film_m),
        "mechanisms": {k: _by_speed(v, x) for k, x in wf.shares.items()},
        "mechanisms_mu": {k: _by_speed(v, x) for k, x in wf.parts.items()},
        "separation_m": _by_speed(v, wf.separation_m),
        "texture_height_m": wf.meta["texture_height_m"],
        "dynamic_lift_share": _by_speed(v, wf.lift_share),  # friction.wet.inertia
        "horne_dreher_v_m_per_s": wf.meta["horne_dreher_v_m_per_s"],
        "contact_lost_v_m_per_s": wf.contact_lost_v_m_per_s,
        "sealing": {
            "q_seal_per_m": q_c,
            "sealed_fraction": sealed.sealed_fraction,
            "pool_count": sealed.pool_count,
            "sealed_water_m3_per_m2": sealed.volume_m3_per_m2,
            "scan_border": "closed",
        },
    }
    return wf, keys
