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

__all__ = ["persson_wet", "speed_constant_kmh", "SP_FIT_KMH"]

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


def _by_speed(v, x):
    return {f"{float(a):g}": (None if not np.isfinite(b) else float(b)) for a, b in zip(v, x)}


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
    from friction.wet.water import DEFAULT_SOURCES
    from pipelines.chain.steps import friction_of, friction_psd
    from pipelines.chain.surface import analyse_surface
    from roadscan.sealing import seal_pools

    dry = outcome.result
    frac = conditions.percolation_contact_fraction
    q_c = sealing_wave_vector(dry.q_per_m, dry.P[0], frac)
    sealed = seal_pools(dry_map, q_seal_per_m=q_c, contact_fraction=frac,
                        water_film_m=conditions.water_depth_m)
    psd_s = None
    if sealed.pool_count:
        an_s = analyse_surface(sealed.wet, window_alpha=window_alpha)
        psd_s = friction_psd(an_s.spectrum, an_dry.fit, rb_dry, settings, say=False)[0]

    def engine(psd, v, sigma):
        return friction_of(psd, dataclasses.replace(settings, sigma0_Pa=sigma), v)

    wf = wet_friction(dry=dry, psd=outcome.psd, engine=engine, sigma0_Pa=settings.sigma0_Pa,
                      conditions=conditions, psd_sealed=psd_s,
                      sealed_fraction=sealed.sealed_fraction, q_seal_per_m=q_c)
    v = wf.v_m_per_s
    params = {k: getattr(conditions, k) for k in ("water_depth_m", "water_temperature_C",
                                                  "footprint_m", "block_size_m", "shear_stress_Pa",
                                                  "percolation_contact_fraction")}
    params["water_viscosity_Pa_s"] = conditions.viscosity_Pa_s
    keys = {
        "wet_model": {"name": "persson", "parameters": params,
                      "sources": {k: s for k, (_, s) in DEFAULT_SOURCES.items()},
                      "friction_model": "flash temperature" if settings.flash else "isothermal",
                      "adhesion": ("included, tau_f given" if conditions.shear_stress_Pa is not None
                                   else "left out: no --shear-stress given")},
        "film_m": _by_speed(v, wf.film_m),
        "mechanisms": {k: _by_speed(v, x) for k, x in wf.shares.items()},
        "contact_lost_v_m_per_s": wf.contact_lost_v_m_per_s,
        "sealing": {"q_seal_per_m": q_c, "sealed_fraction": sealed.sealed_fraction,
                    "pool_count": sealed.pool_count,
                    "sealed_water_m3_per_m2": sealed.volume_m3_per_m2},
    }
    return wf, keys
