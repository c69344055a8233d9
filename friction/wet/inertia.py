"""The water's inertia at the front of the footprint: Horne and Dreher's dynamic hydroplaning.

Horne and Dreher (NASA TN D-2056, 1963) found that a tyre running into water deeper than its
tread and the pavement can drain is lifted off the road when the dynamic pressure of the water
reaches the inflation pressure p, ``1/2 rho v^2 C_L = p``, which they observed as::

    v_p = 9 sqrt(p / psi) knots = 6.35 sqrt(p / kPa) km/h

(the implied lift coefficient is ``C_L = 2 p / (rho v_p^2)`` ~ 0.64 for water, the same at every
p). Below v_p the dynamic pressure, growing as v^2 at fixed C_L, carries ``(v / v_p)^2`` of the
load where water stands under the tyre. Where it stands is the front zone of the footprint (the
three zones of Gough and Moore: D.F. Moore, *The Friction of Pneumatic Tyres*, Elsevier (1975)):
the part the tyre crosses before the film under it has thinned to the texture's height, so that
the rubber can reach the road. That takes the squeeze time t_1 (:func:`friction.wet.squeeze.
squeeze_time`, from the water on the road down to the texture height above the dry contact's
separation), during which the tyre advances ``v t_1`` of its footprint length L::

    L_w / W = min(1, v t_1 / L) min(1, (v / v_p)^2)

With water that cannot drain during the whole passage (t_1 >= L / v) this is Horne and Dreher's
own relation, and the tyre is lifted at v_p. On a road whose texture drains the film within
microseconds the front zone is a fraction of a millimetre and the inertial lift nil.

The nominal pressure of the friction run stands for the inflation pressure: in a tyre's
footprint the mean contact pressure is close to it (Horne and Dreher's premise).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "HORNE_DREHER_KMH_PER_SQRT_KPA",
    "horne_dreher_speed",
    "implied_lift_coefficient",
    "dynamic_lift_share",
]

#: Horne & Dreher's hydroplaning speed per square root of the inflation pressure [km/h / kPa^0.5]:
#: 9 knots per psi^0.5 (NASA TN D-2056, 1963), i.e. 9 x 1.852 / sqrt(6.894757) = 6.348
HORNE_DREHER_KMH_PER_SQRT_KPA = 9.0 * 1.852 / math.sqrt(6.894757)


def horne_dreher_speed(p_Pa):
    """Dynamic hydroplaning speed [m/s], ``v_p = 6.35 sqrt(p / kPa)`` km/h (Horne & Dreher 1963).

    Parameters
    ----------
    p_Pa : float or array_like
        Inflation (nominal contact) pressure [Pa].

    Returns
    -------
    float or ndarray
        v_p [m/s] (24.9 m/s, 89.8 km/h, at 200 kPa).

    References
    ----------
    W.B. Horne, R.C. Dreher, *Phenomena of pneumatic tire hydroplaning*, NASA TN D-2056 (1963).
    """
    return HORNE_DREHER_KMH_PER_SQRT_KPA / 3.6 * np.sqrt(np.asarray(p_Pa, dtype=float) / 1e3)


def implied_lift_coefficient(p_Pa, rho_kg_m3=998.2):
    """``C_L = 2 p / (rho v_p^2)`` [-], the lift coefficient Horne and Dreher's v_p implies.

    Parameters
    ----------
    p_Pa : float
        Inflation pressure [Pa].
    rho_kg_m3 : float, optional
        Water density [kg/m^3] (998.2 at 20 C).

    Returns
    -------
    float
        C_L (0.644 for water at 20 C, at every pressure).
    """
    return float(2.0 * p_Pa / (rho_kg_m3 * horne_dreher_speed(p_Pa) ** 2))


def dynamic_lift_share(v_m_per_s, *, p_Pa, front_time_s, footprint_m):
    """Share of the load the water's dynamic pressure carries,
    ``min(1, v t_1 / L) min(1, (v / v_p)^2)`` (module docstring).

    Parameters
    ----------
    v_m_per_s : array_like
        Speeds [m/s].
    p_Pa : float
        Inflation (nominal) pressure [Pa].
    front_time_s : array_like
        t_1 per speed: the time the film takes to thin to the texture's height [s] (0: the
        texture holds the water, no front zone; inf: it never does).
    footprint_m : float
        Footprint length L [m].

    Returns
    -------
    ndarray
        L_w / W in [0, 1]; 1 means the tyre rides on water (dynamic hydroplaning).
    """
    v = np.asarray(v_m_per_s, dtype=float)
    t1 = np.broadcast_to(np.asarray(front_time_s, dtype=float), v.shape)
    with np.errstate(invalid="ignore"):
        zone = np.where(t1 > 0, np.minimum(1.0, v * t1 / footprint_m), 0.0)
    return zone * np.minimum(1.0, (v / horne_dreher_speed(p_Pa)) ** 2)
