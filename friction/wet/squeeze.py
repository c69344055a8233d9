"""Squeeze-out of the water film under a tread block: the mean separation after the dwell time.

Averaged Reynolds flow (Patir & Cheng's averaging, with Persson's pressure flow factor) under a
block of equal-area disk radius R pressed with nominal pressure p0, part of which the asperity
contact carries, ``p_cont(u)`` (:mod:`friction.wet.gap`)::

    du/dt = -(2 u^3 phi_p(u) / (3 eta R^2)) (p0 - p_cont(u))

(Lorenz & Persson, Eur. Phys. J. E 32, 281 (2010)). With phi_p = 1 and p_cont = 0 it is
Stefan's squeeze of a flat disk, ``dh/dt = -2 h^3 p / (3 eta R^2)``, whose solution
``t = 3 eta R^2 / (4 p) (1/h^2 - 1/h0^2)`` the tests check. The equation is autonomous, so the
time to go from u0 down to u is the quadrature ``t(u) = int_u^u0 du' / |du/dt|``, computed once
per speed and inverted at the dwell time ``t_c = footprint / v``.

The pressure flow factor phi_p is Bruggeman's two-dimensional effective medium (the treatment
Persson applies to the interface, J. Phys.: Condens. Matter 22, 265004 (2010)) for a two-phase
interface: a closed fraction c (the real contact, conductivity 0) and the open rest with the
gap ``u / (1 - c)`` (conductivity its cube). Bruggeman's ``c (0 - s_e)/(0 + s_e) + (1 - c)
(s_o - s_e)/(s_o + s_e) = 0`` gives ``s_e = (1 - 2c) s_o``, so

    phi_p = (1 - 2c) / (1 - c)^3  (c < 1/2),   0 beyond (the 2D threshold: the water is sealed)

with c the engine's contact area at the finest scale scaled by the load the contact carries,
``c = (A/A0)(p0) p_cont / p0`` (A proportional to load in Persson's theory at small A).
"""

from __future__ import annotations

import numpy as np

from ..contact import cumulative_G

__all__ = ["flow_factor", "squeeze_film", "squeeze_time", "stefan_time"]


def flow_factor(contact_fraction):
    """Pressure flow factor phi_p = (1 - 2c) / (1 - c)^3 of a two-phase interface with a closed
    fraction c, by Bruggeman's 2D effective medium (module docstring); 0 for c >= 1/2.

    Parameters
    ----------
    contact_fraction : array_like
        Closed (contact) area fraction c, 0 <= c <= 1.

    Returns
    -------
    ndarray
        phi_p [-], relative to a uniform gap of the same mean.

    References
    ----------
    D.A.G. Bruggeman, Ann. Phys. 416, 636 (1935), doi:10.1002/andp.19354160705.
    B.N.J. Persson, J. Phys.: Condens. Matter 22, 265004 (2010), doi:10.1088/0953-8984/22/26/265004.
    """
    c = np.clip(np.asarray(contact_fraction, dtype=float), 0.0, 1.0)
    # the floor 0.5 only touches the branch not taken (c >= 0.5), where 1 - c can be 0
    return np.where(c < 0.5, (1.0 - 2.0 * c) / np.maximum(1.0 - c, 0.5) ** 3, 0.0)


def stefan_time(h_m, h0_m, p_Pa, eta_Pa_s, R_m):
    """Stefan's squeeze time of a flat disk from gap h0 to h [s]:
    ``t = 3 eta R^2 / (4 p) (1/h^2 - 1/h0^2)``.

    Parameters
    ----------
    h_m, h0_m : float or array_like
        Final and initial gaps [m].
    p_Pa : float
        Mean pressure on the disk [Pa].
    eta_Pa_s : float
        Viscosity [Pa s].
    R_m : float
        Disk radius [m].

    Returns
    -------
    float or ndarray
        Time [s].

    References
    ----------
    J. Stefan, Sitzungsber. Akad. Wiss. Wien 69, 713 (1874).
    """
    return 3.0 * eta_Pa_s * R_m**2 / (4.0 * p_Pa) * (1.0 / np.square(h_m) - 1.0 / np.square(h0_m))


def squeeze_film(u0_m, t_c_s, *, p0_Pa, eta_Pa_s, R_m, u_table, p_table, contact_area=0.0, nodes=1200):
    """Mean separation [m] after dwell times ``t_c_s`` for one speed's contact mechanics.

    Integrates ``du/dt = -(2 u^3 phi_p (p0 - p_cont(u)) / (3 eta R^2))`` from ``u0_m`` (module
    docstring) as ``t(u) = int du / |du/dt|`` on nodes log-spaced in ``u - u_dry`` (u_dry: the
    separation where the contact alone carries p0), inverted at each t_c.

    Parameters
    ----------
    u0_m : float
        Separation when the block lands [m]; below u_dry nothing is squeezed (u_dry returned).
    t_c_s : array_like
        Dwell times [s].
    p0_Pa : float
        Nominal pressure [Pa].
    eta_Pa_s : float
        Water viscosity [Pa s].
    R_m : float
        Squeeze radius [m].
    u_table, p_table : ndarray, shape (np,)
        ``u(p)`` (:func:`friction.wet.gap.mean_separation`) on increasing pressures that reach
        p0; None for a rigid flat disk (p_cont = 0, Stefan).
    contact_area : float, optional
        A/A0 at p0 (finest scale) for the flow factor; 0 for phi_p = 1.
    nodes : int, optional
        Quadrature nodes.

    Returns
    -------
    ndarray
        u(t_c) [m], shaped like ``t_c_s``.
    """
    t_c = np.asarray(t_c_s, dtype=float)
    u_dry, lx, T = _time_table(p0_Pa, eta_Pa_s, R_m, u_table, p_table, contact_area, nodes)
    if not u0_m > u_dry:
        return np.full(t_c.shape, max(u_dry, float(u0_m)))
    x0 = _film(u0_m, u_dry)
    with np.errstate(divide="ignore"):
        lT = np.log(T)
        T0 = np.exp(np.interp(np.log(x0), lx[::-1], lT[::-1])) if x0 < 1.0 else 0.0
        target = np.log(T0 + t_c)
    out = np.exp(np.interp(target, lT[1:], lx[1:]))
    return u_dry + np.where(T0 + t_c >= T[-1], np.exp(lx[-1]), out)


def squeeze_time(u0_m, u1_m, *, p0_Pa, eta_Pa_s, R_m, u_table, p_table, contact_area=0.0, nodes=1200):
    """Time [s] the squeeze of :func:`squeeze_film` takes from separation ``u0_m`` down to ``u1_m``
    (0 when ``u1_m >= u0_m``; inf when the flow stalls above ``u1_m``, e.g. sealed water).

    Parameters
    ----------
    u0_m, u1_m : float
        Separations at the start and the end [m].
    p0_Pa, eta_Pa_s, R_m, u_table, p_table, contact_area, nodes
        As :func:`squeeze_film`.

    Returns
    -------
    float
        Time [s]; with ``u_table`` None, Stefan's :func:`stefan_time`.
    """
    if not u1_m < u0_m:
        return 0.0
    u_dry, lx, T = _time_table(p0_Pa, eta_Pa_s, R_m, u_table, p_table, contact_area, nodes)
    if not u1_m > u_dry:
        return float("inf")
    x0, x1 = _film(u0_m, u_dry), u1_m - u_dry
    if x1 < np.exp(lx[-1]):
        return float("inf")

    def at(x):
        return 0.0 if x >= 1.0 else float(np.exp(np.interp(np.log(x), lx[::-1], np.log(T)[::-1])))

    with np.errstate(divide="ignore"):
        return at(x1) - at(x0)


def _film(u0_m, u_dry):
    if u0_m - u_dry >= 1.0:
        raise ValueError("a water film of a metre or more is not a film")
    return u0_m - u_dry


def _time_table(p0_Pa, eta_Pa_s, R_m, u_table, p_table, contact_area, nodes):
    """(u_dry, ln x nodes, T(x)): the time to squeeze from 1 m above u_dry down to u_dry + x, on
    nodes down to a floor, cut at the first stall (T infinite beyond)."""
    from .gap import contact_pressure

    rigid = u_table is None
    u_dry = 0.0
    if not rigid:
        # u(p) interpolated in (ln p, ln u); a separation of 0 (full contact of a very smooth
        # band) stands as 1e-300 m, which the exponential returns as 0 to within that
        lu = np.log(np.maximum(np.asarray(u_table, dtype=float), 1e-300))
        u_dry = float(np.exp(np.interp(np.log(p0_Pa), np.log(p_table), lu)))
    # one node set for every u0 (so that more water never squeezes to less film): from 1 m
    # above u_dry down to a floor, T(x) = time to get from 1 m down to u_dry + x
    floor = 1e-10 * max(u_dry, 1e-6)
    lx = np.linspace(0.0, np.log(floor), nodes)
    x = np.exp(lx)
    u = u_dry + x
    p_c = 0.0 if rigid else contact_pressure(u, u_table, p_table)
    phi = flow_factor(contact_area * np.asarray(p_c) / p0_Pa)
    rate = 2.0 * u**3 * phi * np.maximum(p0_Pa - p_c, 0.0) / (3.0 * eta_Pa_s * R_m**2)
    with np.errstate(divide="ignore"):
        dtdl = np.where(rate > 0, x / rate, np.inf)  # dt / d(-ln x)
    fin = np.isfinite(dtdl)
    n = int(np.argmin(fin)) if not fin.all() else lx.size  # nodes before the first stall
    T = np.full(lx.shape, np.inf)
    T[:n] = cumulative_G(dtdl[:n], -np.diff(lx[:n])) if n > 1 else 0.0
    return u_dry, lx[:n], T[:n]  # each interval exact for dt/d(ln x) a power of x (Stefan's)
