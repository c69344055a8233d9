"""The statistics the diagnosis shares: bounded multi-start least squares in the unit cube, a
forward-difference Jacobian there and the Gauss-Newton covariance of a least-squares fit.

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

__all__ = ["STEP", "jacobian", "gauss_newton_cov", "unit_interval", "multistart_lsq"]

STEP = 0.02


def jacobian(f, u, f0=None, step=STEP):
    """(m, k) forward-difference Jacobian of the vector function ``f`` at unit-cube point ``u``
    (a step of ``step``, taken backwards where it would leave the cube); ``f0 = f(u)`` if known.

    Parameters
    ----------
    f : callable
        Vector function of the unit cube.
    u : ndarray, shape (k,)
        Unit-cube point the derivatives are taken at.
    f0 : ndarray, shape (m,), optional
        ``f(u)`` when already known (saves one evaluation); None: evaluated here.
    step : float, optional
        Forward step in the unit cube (default 0.02), backwards where u + step > 1.

    Returns
    -------
    ndarray, shape (m, k)
        d f / d u, one column per parameter.
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
        Jacobian d r / d u of the residuals at the fit, u the unit-cube parameters.
    r : ndarray, shape (n,)
        Residuals at the fit (the diagnosis passes log10(measured / simulated mu)).
    floor : float
        Smallest residual standard deviation s used, in the units of ``r`` (the noise, rms log10).

    Returns
    -------
    ndarray, shape (k, k)
        Covariance of the unit-cube parameters (pseudo-inverse: a flat direction gets no variance).
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
        Standard deviation of ``u`` (unit cube), e.g. from :func:`gauss_newton_cov`.
    z : float, optional
        Standard-normal quantile: 1.96 gives a two-sided 95 % interval.

    Returns
    -------
    tuple of float
        (u - z sd, u + z sd), not clipped to [0, 1].
    """
    return float(u - z * sd), float(u + z * sd)


def multistart_lsq(resid, starts, u_best=None, c_best=np.inf, cost=None, **kw):
    """Bounded least squares in the unit cube from several starts; the best point wins.

    ``scipy.optimize.least_squares`` (trust-region reflective, bounds [0, 1]) from each start;
    each start itself and each local optimum compete on ``cost`` (default sum of resid^2), so the
    result is never worse than the best start (a fit that starts at "no effect" never loses to
    it). ``u_best``/``c_best``: a point already known (e.g. the no-effect point) and its cost;
    ``kw`` go to ``least_squares`` (``jac``, ``diff_step``, ``max_nfev``, ...). A start whose
    local fit fails (``ValueError``, ``LinAlgError``) keeps its own cost.

    Returns
    -------
    u : ndarray
        The unit-cube point of lowest cost among ``u_best``, the starts and the local optima.
    cost : float
        Its ``cost`` (default: sum of squared residuals).

    Parameters
    ----------
    resid : callable
        Residual vector of a unit-cube point.
    starts : sequence of ndarray
        Unit-cube points each local fit starts from.
    u_best : ndarray, optional
        A point already known to compete (e.g. "no effect"); None: the first start's.
    c_best : float, optional
        The cost of ``u_best`` (default inf: not yet known).
    cost : callable, optional
        Cost of a residual vector (default sum of squares).
    **kw
        Passed to ``scipy.optimize.least_squares``.
    """
    from scipy import optimize

    cost = cost or (lambda u: float(np.sum(np.asarray(resid(u)) ** 2)))
    for u0 in starts:
        u0 = np.asarray(u0, float)
        c0 = cost(u0)
        if u_best is None or c0 < c_best - 1e-12:
            u_best, c_best = u0, c0
        try:
            sol = optimize.least_squares(resid, u0, bounds=(0.0, 1.0), **kw)
        except (ValueError, np.linalg.LinAlgError):
            continue
        c1 = cost(sol.x)
        if c1 < c_best - 1e-12:
            u_best, c_best = sol.x, c1
    return u_best, c_best
