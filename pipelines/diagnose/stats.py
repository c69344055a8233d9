"""The statistics the friction-level diagnosis shares: a forward-difference Jacobian in the unit
cube, the Gauss-Newton covariance of a least-squares fit and its Laplace-approximated evidence.

Parameters live on the unit cube (each mapped onto its bounds, log or linear, see
:class:`effects.Param`). Derivatives are forward differences of a fixed step (0.02 in the unit
cube, backwards at the upper bound): the friction engine's adaptive quadrature makes tiny steps
noisy.

Gauss-Newton covariance (Bates & Watts 1988, *Nonlinear regression analysis and its
applications*, sec 2.3): cov = s^2 (J^T J)^+ with J = d r / d u at the fit and
s^2 = max(RSS / (n - k), floor^2) (the residual variance never below the measurement noise).
"""
from __future__ import annotations

import numpy as np

__all__ = ["STEP", "jacobian", "gauss_newton_cov", "unit_interval"]

STEP = 0.02


def jacobian(f, u, f0=None, step=STEP):
    """(m, k) forward-difference Jacobian of the vector function ``f`` at unit-cube point ``u``
    (a step of ``step``, taken backwards where it would leave the cube); ``f0 = f(u)`` if known.

    Parameters
    ----------
    f : callable
        Vector function of the unit cube.
    u : ndarray
        Point.
    f0 : ndarray, optional
        f(u).
    step : float, optional
        Step.

    Returns
    -------
    ndarray, shape (m, k)
    """
    u = np.asarray(u, float)
    f0 = np.asarray(f(u) if f0 is None else f0, float)
    J = np.empty((f0.size, u.size))
    for j in range(u.size):
        du = step if u[j] + step <= 1.0 else -step
        uu = u.copy()
        uu[j] += du
        J[:, j] = (np.asarray(f(uu), float) - f0) / du
    return J


def gauss_newton_cov(J, r, floor):
    """Gauss-Newton covariance s^2 (J^T J)^+ of the unit-cube parameters (see module docstring):
    ``J`` (n, k), ``r`` the n residuals at the fit, ``floor`` the noise [same units as r].

    Parameters
    ----------
    J : ndarray, shape (n, k)
        Jacobian.
    r : ndarray
        Residuals.
    floor : float
        Noise floor.

    Returns
    -------
    ndarray, shape (k, k)
    """
    n, k = J.shape
    dof = max(n - k, 1)
    s2 = max(float(r @ r) / dof, float(floor) ** 2)
    return s2 * np.linalg.pinv(J.T @ J)


def unit_interval(u, sd, z=1.96):
    """(lo, hi) of u -/+ z sd in the unit cube (the caller maps it back through the parameter).

    Parameters
    ----------
    u : float
        Parameter in the unit cube.
    sd : float
        Its standard deviation.
    z : float, optional
        Normal quantile.

    Returns
    -------
    tuple of float
    """
    return float(u - z * sd), float(u + z * sd)
