"""Wet friction versus speed: sealing, squeeze-out, adhesion lost and contact lost.

With the dry engine result at the nominal pressure p0 (:func:`friction.mu_isothermal` or
:func:`friction.mu_flash`, through an ``engine`` callable, so the wet curve uses the same
model as the dry one)::

    mu_dry(v) = mu_h(v; C, p0) + tau_f P(q1; C, p0) / p0                          (adhesion optional)
    mu_wet(v) = (p_c / p0) mu_h(v; C_s, p_c) + tau_f P(q1; C_s, p_c) (1 - a_s) / p0
    p_c       = (1 - L_w/W) p_cont(u(t_c)),  t_c = footprint / v

* **Sealing** (Persson et al., PRB 71, 035428 (2005)): C_s is the spectrum of the road with the
  pools the contact closes at its percolation magnification filled with water
  (:mod:`friction.wet.sealing`; the map is filled by :func:`roadscan.sealing.seal_pools`);
  a_s is the area those pools cover. Without a sealed spectrum C_s = C.
* **Squeeze-out** (Lorenz & Persson, EPJE 32, 281 (2010)): the water film u(t_c) left under a
  tread block after the dwell time (:mod:`friction.wet.squeeze`) carries ``p0 - p_c`` of the
  load; the contact carries p_c (:mod:`friction.wet.gap`). The rubber then reaches the road's
  roughness only with p_c: Persson's P(q) at p_c falls at every scale, most at the shortest,
  so the small-scale roughness hidden under the film contributes no hysteresis (the engine's
  own P(q) does the cut, rather than a fixed q cut-off).
* **Inertia** (Horne & Dreher, NASA TN D-2056 (1963); :mod:`friction.wet.inertia`): at the
  footprint's front, where the film has not yet thinned to the texture's height, the water's
  dynamic pressure carries ``L_w/W = min(1, v t_1 / footprint) min(1, (v / v_p)^2)`` of the
  load (v_p = 6.35 sqrt(p0 / kPa) km/h); the contact carries the rest. Its loss is counted in
  the squeeze-out film's share (the water film carrying load, viscously or by its inertia).
* **Adhesion** (:mod:`friction.wet.adhesion`): only the real contact at p_c outside the sealed
  pools keeps tau_f.
* **Contact lost** (hydroplaning): when the film left in excess of the dry separation exceeds
  the texture, ``3 h_rms`` above the mean plane (99.87 % of a Gaussian surface's heights lie
  below it), or the water's dynamic pressure carries the whole load, the block rides on water:
  mu_wet is the viscous drag of the film, ``eta v / (u p0)``. In mixed contact that Couette
  drag is below 1e-3 and is left out.

The shares of ``mu_dry - mu_wet`` at each speed: sealing ``mu_h(C, p0) - mu_h(C_s, p0)``,
squeeze-out ``mu_h(C_s, p0) - (p_c/p0) mu_h(C_s, p_c)`` (or minus the drag), adhesion the
adhesive term lost; they sum to one.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .adhesion import adhesive_mu
from .gap import contact_pressure, mean_separation
from .inertia import dynamic_lift_share, horne_dreher_speed
from .squeeze import squeeze_film, squeeze_time
from .water import WetConditions

__all__ = ["TEXTURE_RMS_MULTIPLE", "WetFriction", "band_rms", "wet_friction"]

#: the texture's height above its mean plane, in rms heights (Gaussian: 99.87 % below)
TEXTURE_RMS_MULTIPLE = 3.0
#: pressures of the u(p) table, as fractions of p0
_P_FRACTIONS = np.logspace(-12.0, 0.0, 97)


@dataclass(frozen=True, eq=False)
class WetFriction:
    """Dry and wet friction on one speed grid, with the wet model's intermediate quantities.

    Attributes
    ----------
    v_m_per_s : ndarray, shape (nv,)
        Sliding speeds [m/s].
    mu_dry, mu_wet : ndarray, shape (nv,)
        Friction coefficients (hysteresis + adhesion when tau_f is given).
    hysteresis_dry, hysteresis_sealed, hysteresis_wet : ndarray, shape (nv,)
        mu_h(C, p0), mu_h(C_s, p0) and (p_c/p0) mu_h(C_s, p_c) (or the film's drag).
    adhesion_dry, adhesion_wet : ndarray, shape (nv,)
        Adhesive terms (zeros without tau_f).
    separation_m, separation_dry_m : ndarray, shape (nv,)
        Mean separation after the dwell time, and where the contact alone carries p0 [m].
    film_m : ndarray, shape (nv,)
        Water film left in excess of the dry separation, ``separation - separation_dry`` [m].
    contact_share : ndarray, shape (nv,)
        The share of the load the contact carries: p_c / p0 after the squeeze, times
        ``1 - lift_share``.
    shares : dict of ndarray
        ``sealing``, ``squeeze_out``, ``adhesion``: shares of ``mu_dry - mu_wet`` (NaN where
        that difference is not positive).
    contact_lost : ndarray of bool, shape (nv,)
        Speeds where the block rides on water.
    contact_lost_v_m_per_s : float or None
        Lowest such speed.
    q_seal_per_m : float or None
        Percolation wave vector used for the sealed map (None: no sealing).
    sealed_fraction : float
        Area fraction of the sealed pools.
    meta : dict
        Conditions and parameters (``front_time_s``: the squeeze time to the texture height per
        speed; ``horne_dreher_v_m_per_s``: v_p at p0).
    lift_share : ndarray, shape (nv,)
        Share of the load the water's dynamic pressure carries at the footprint's front
        (:mod:`friction.wet.inertia`); counted in the squeeze-out film's share of the loss.
    """

    v_m_per_s: np.ndarray
    mu_dry: np.ndarray
    mu_wet: np.ndarray
    hysteresis_dry: np.ndarray
    hysteresis_sealed: np.ndarray
    hysteresis_wet: np.ndarray
    adhesion_dry: np.ndarray
    adhesion_wet: np.ndarray
    separation_m: np.ndarray
    separation_dry_m: np.ndarray
    film_m: np.ndarray
    contact_share: np.ndarray
    shares: dict
    contact_lost: np.ndarray
    contact_lost_v_m_per_s: float | None
    q_seal_per_m: float | None = None
    sealed_fraction: float = 0.0
    meta: dict = field(default_factory=dict)
    lift_share: np.ndarray | None = None

    @property
    def parts(self):
        """The loss ``mu_dry - mu_wet`` by mechanism, in mu (the numerators of :attr:`shares`):
        ``sealing`` mu_h(C) - mu_h(C_s), ``squeeze_out`` mu_h(C_s) - mu_h,wet, ``adhesion``
        the adhesive term lost."""
        return {
            "sealing": self.hysteresis_dry - self.hysteresis_sealed,
            "squeeze_out": self.hysteresis_sealed - self.hysteresis_wet,
            "adhesion": self.adhesion_dry - self.adhesion_wet,
        }

    @property
    def ratio(self):
        """mu_wet / mu_dry per speed (NaN where mu_dry is 0)."""
        return np.divide(
            self.mu_wet, self.mu_dry, out=np.full(self.mu_dry.shape, np.nan), where=self.mu_dry > 0
        )


def band_rms(q_per_m, C_m4):
    """rms height [m] of a spectrum on a grid, ``sqrt(2 pi int q C dq)`` (trapezoid in ln q)."""
    q, C = np.asarray(q_per_m, float), np.asarray(C_m4, float)
    g = 2 * np.pi * q * q * C
    return float(np.sqrt(np.sum(0.5 * (g[1:] + g[:-1]) * np.diff(np.log(q)))))


def wet_friction(
    *, dry, psd, engine, sigma0_Pa, conditions=None, psd_sealed=None, sealed_fraction=0.0, q_seal_per_m=None
):
    """Wet friction mu_wet(v) beside the dry one (module docstring for the model).

    Parameters
    ----------
    dry : friction.FrictionResult
        The dry engine result on ``psd`` at ``sigma0_Pa`` (its speeds are the wet curve's).
    psd : SelfAffinePSD or TabulatedPSD
        The road's spectrum (the one ``dry`` integrated) [m^4].
    engine : callable
        ``engine(psd, v_m_per_s, sigma0_Pa) -> FrictionResult``, the dry model (isothermal or
        flash, same rubber and options); ``sigma0_Pa`` may be one pressure per speed.
    sigma0_Pa : float
        Nominal pressure p0 [Pa].
    conditions : WetConditions, optional
        Water and tyre (default :class:`WetConditions`, each default with its source).
    psd_sealed : spectrum, optional
        Spectrum of the sealed road (pools filled, :func:`roadscan.sealing.seal_pools`);
        None: no sealing.
    sealed_fraction : float, optional
        Area fraction of the sealed pools.
    q_seal_per_m : float, optional
        Their percolation wave vector (reported only).

    Returns
    -------
    WetFriction

    References
    ----------
    B.N.J. Persson, U. Tartaglino, O. Albohr, E. Tosatti, Phys. Rev. B 71, 035428 (2005),
    doi:10.1103/PhysRevB.71.035428.
    B.N.J. Persson, Phys. Rev. Lett. 99, 125502 (2007), doi:10.1103/PhysRevLett.99.125502.
    B. Lorenz, B.N.J. Persson, Eur. Phys. J. E 32, 281 (2010), doi:10.1140/epje/i2010-10625-0.
    """
    cond = WetConditions() if conditions is None else conditions
    v = np.asarray(dry.v_m_per_s, dtype=float)
    q = dry.q_per_m
    C = psd.C(q)
    p0 = float(sigma0_Pa)
    eta = cond.viscosity_Pa_s
    h_rms = band_rms(q, C)
    tau = cond.shear_stress_Pa
    a_s = float(sealed_fraction) if psd_sealed is not None else 0.0

    a_dry = adhesive_mu(tau, dry.P[:, -1], p0)
    if psd_sealed is not None:
        sealed = engine(psd_sealed, v, p0)
        h_seal, A_seal = sealed.mu, sealed.P[:, -1]
    else:
        h_seal, A_seal = dry.mu, dry.P[:, -1]

    # squeeze-out: u(p) per speed from the engine's G, then u after the dwell time
    p_tab = p0 * _P_FRACTIONS
    u_tab = mean_separation(q, C, dry.G, p0, p_tab)
    t_c = cond.footprint_m / v
    u = np.empty(v.size)
    for i in range(v.size):
        u[i] = squeeze_film(
            cond.water_depth_m,
            t_c[i],
            p0_Pa=p0,
            eta_Pa_s=eta,
            R_m=cond.squeeze_radius_m,
            u_table=u_tab[i],
            p_table=p_tab,
            contact_area=float(dry.P[i, -1]),
        )[()]
    u_dry = u_tab[:, -1]
    film = np.maximum(u - u_dry, 0.0)
    share = np.array([contact_pressure(u[i], u_tab[i], p_tab)[()] for i in range(v.size)]) / p0
    share = np.clip(np.where(film > 0, share, 1.0), 0.0, 1.0)
    # the water's inertia at the footprint's front (friction.wet.inertia): the front zone is
    # where the film has not yet thinned to the texture's height
    tex = TEXTURE_RMS_MULTIPLE * h_rms
    t1 = np.array(
        [
            squeeze_time(
                cond.water_depth_m,
                u_dry[i] + tex,
                p0_Pa=p0,
                eta_Pa_s=eta,
                R_m=cond.squeeze_radius_m,
                u_table=u_tab[i],
                p_table=p_tab,
                contact_area=float(dry.P[i, -1]),
            )
            for i in range(v.size)
        ]
    )
    lift = dynamic_lift_share(v, p_Pa=p0, front_time_s=t1, footprint_m=cond.footprint_m)
    share = share * (1.0 - lift)
    lost = (film > tex) | (lift >= 1.0 - 1e-12)

    h_wet, A_wet = h_seal.copy(), A_seal.copy()
    part = (share < 1.0 - 1e-12) & ~lost
    if np.any(part):
        r = engine(psd if psd_sealed is None else psd_sealed, v[part], p0 * np.maximum(share[part], 1e-9))
        h_wet[part] = share[part] * r.mu
        A_wet[part] = r.P[:, -1]
    drag = eta * v / (np.maximum(u, 1e-12) * p0)
    h_wet = np.where(lost, drag, h_wet)
    A_wet = np.where(lost, 0.0, A_wet)
    a_wet = adhesive_mu(tau, A_wet, p0, 1.0 - a_s)

    mu_dry = dry.mu + a_dry
    mu_wet = h_wet + a_wet
    diff = mu_dry - mu_wet
    parts = {"sealing": dry.mu - h_seal, "squeeze_out": h_seal - h_wet, "adhesion": a_dry - a_wet}
    with np.errstate(divide="ignore", invalid="ignore"):
        shares = {k: np.where(diff > 0, x / diff, np.nan) for k, x in parts.items()}
    v_lost = float(v[np.argmax(lost)]) if lost.any() else None
    meta = {
        "conditions": cond,
        "viscosity_Pa_s": eta,
        "h_rms_m": h_rms,
        "sigma0_Pa": p0,
        "squeeze_radius_m": cond.squeeze_radius_m,
        "dwell_time_s": t_c,
        "texture_height_m": tex,
        "front_time_s": t1,
        "horne_dreher_v_m_per_s": float(horne_dreher_speed(p0)),
    }
    return WetFriction(
        v,
        mu_dry,
        mu_wet,
        dry.mu,
        h_seal,
        h_wet,
        a_dry,
        a_wet,
        u,
        u_dry,
        film,
        share,
        shares,
        lost,
        v_lost,
        q_seal_per_m,
        a_s,
        meta,
        lift_share=lift,
    )
