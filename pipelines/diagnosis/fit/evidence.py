"""Bayesian comparison of the explanations of a gap: evidence by Laplace approximation.

Each explanation M (the calibration of the uncertain inputs alone, or it together with one
effect; the nominal model when nothing is uncertain) has k parameters u on the unit cube, each
uniform there a priori (log-uniform within its range for a log-scaled parameter: the uncertain
inputs' ranges and each effect's physical range are the prior). Its evidence

    Z_M = int L(u) du  ~  L(u*) prod_i min(1, sqrt(2 pi / lambda_i)) prod_j m_j

(MacKay 1992, Neural Computation 4, 415, "Bayesian interpolation"; Kass & Raftery 1995,
J. Am. Stat. Assoc. 90, 773, doi:10.1080/01621459.1995.10476572): u* the best fit on every
point, lambda_i the eigenvalues of the Gauss-Newton Hessian H = J^T J / sigma_eff^2 (J = d log10
mu / d u; a direction the data do not constrain keeps the whole prior width, factor 1), m_j the
mass of the Gaussian's marginal inside [0, 1] (about 1/2 for a parameter on a bound).

Likelihood: the residuals r = log10(measured / model) are normal with an rms noise sigma known
only through its estimate s (from the data or ``--noise``) worth ``NU`` degrees of freedom;
integrating sigma out (scaled inverse chi-square prior) gives the Student-t form

    ln L = -(NU + n) / 2 ln(1 + RSS / (NU s^2)),   sigma_eff^2 = (NU s^2 + RSS) / (NU + n)

(Gelman et al. 2013, *Bayesian data analysis*, 3rd ed., sec 3.2), so that a noise estimate from
five points cannot by itself make an effect look decisive. s is at least ``NOISE_FLOOR`` (the
repeatability of a friction rig, about 1 %).

Prior odds: "no effect beyond the uncertain inputs" has prior 1/2, the other half is shared
equally by the effects tried (a multiple-comparison correction: the more effects are tried, the
stronger the evidence one of them needs). Posterior probability of M: prior x Z_M normalised.

Decided (:func:`decisive`): the most probable explanation is named when it is at least 3 times as
probable as every other explanation, one by one (posterior odds of 3: Kass & Raftery 1995 call a
factor below 3 "not worth more than a bare mention"). The prior's multiple-comparison correction
stays in those odds: against the baseline an effect needs a Bayes factor of 3 m (m effects
tried), against another effect 3. Posterior 0.9 (``P_NAME``) implies odds of 9 against every
rival; the pairwise rule also names a clear winner when the rest of the probability is spread
over several rivals, and leaves inconclusive only explanations that are about as probable as it.
Its posterior still sets its confidence (low below 0.95).
"""

from __future__ import annotations

import numpy as np
from scipy import stats as sps

from pipelines.diagnosis.fit.stats import jacobian

__all__ = [
    "NU",
    "NOISE_FLOOR",
    "METHOD",
    "REFERENCE",
    "P_NAME",
    "LOG_POSITIVE",
    "decisive",
    "loglik",
    "log_occam",
    "model_evidence",
    "posteriors",
]

NU = 4.0
NOISE_FLOOR = 0.004
PRIOR_NULL = 0.5
#: the posterior probability at which an explanation is named (the verdicts of few points and of
#: the evidence over every point)
P_NAME = 0.9
#: ln of the odds from which evidence counts as positive (Kass & Raftery 1995: 3)
LOG_POSITIVE = float(np.log(3.0))
METHOD = (
    "Bayesian model comparison: evidence of each explanation by Laplace approximation at its best "
    "fit (uniform priors on the uncertain inputs' ranges and each effect's range; Student-t "
    "likelihood with the noise estimate worth 4 degrees of freedom)"
)
REFERENCE = (
    "MacKay 1992, Neural Computation 4, 415; Kass & Raftery 1995, J. Am. Stat. Assoc. 90, 773, "
    "doi:10.1080/01621459.1995.10476572"
)


def decisive(posterior, rivals):
    """Whether the most probable explanation is decided (see the module docstring).

    Parameters
    ----------
    posterior : float
        Its posterior probability.
    rivals : sequence of float
        The posterior probability of every other explanation compared (the baseline included).

    Returns
    -------
    bool
        True when ``posterior`` is at least ``exp(LOG_POSITIVE)`` = 3 times every rival's.
    """
    return bool(posterior > 0) and all(
        np.log(posterior) - np.log(max(p, 1e-300)) >= LOG_POSITIVE for p in rivals
    )


def noise_scale(noise):
    """The noise scale s of the likelihood: the estimate, at least :data:`NOISE_FLOOR`."""
    return max(float(noise), NOISE_FLOOR)


def loglik(rss, n, s, nu=NU):
    """Student-t log-likelihood (constants common to every model dropped), see module docstring.

    Parameters
    ----------
    rss : float
        Residual sum of squares of log10(measured / model mu) [log10^2].
    n : int
        Number of points the residuals come from.
    s : float
        Noise estimate, rms log10 (callers floor it at :data:`NOISE_FLOOR`).
    nu : float, optional
        Degrees of freedom the estimate ``s`` is worth (default :data:`NU` = 4).

    Returns
    -------
    float
        -(nu + n) / 2 ln(1 + rss / (nu s^2)) [nats].
    """
    return -0.5 * (nu + n) * float(np.log1p(rss / (nu * s * s)))


def _log10_model(ctx, effects):
    from pipelines.diagnosis.fit.fitting import predict, unpack

    def f(u):
        try:
            return np.log10(predict(ctx, effects, unpack(effects, u)))
        except (ValueError, ArithmeticError, RuntimeError):
            return np.full(ctx.n, np.nan)

    return f


def log_occam(H, u):
    """ln of the Laplace integral of exp(-(v - u)^T H (v - u) / 2) over the unit cube (the Occam
    factor of a uniform prior there), and the posterior covariance pinv(H).

    Each eigen-direction contributes min(1, sqrt(2 pi / lambda)) (a direction wider than the cube
    keeps the cube's width), each parameter the mass of its marginal normal inside [0, 1] (its sd
    at most 1 / sqrt(2 pi), the width of the cube).

    Parameters
    ----------
    H : ndarray, shape (k, k)
        Gauss-Newton Hessian in the unit cube.
    u : ndarray, shape (k,)
        The fit in the unit cube.

    Returns
    -------
    occam : float
        ln of the Occam factor (<= 0: the prior volume the data rule out).
    cov : ndarray, shape (k, k)
        Posterior covariance pinv(H).

    References
    ----------
    D.J.C. MacKay, Information Theory, Inference, and Learning Algorithms, Cambridge University
    Press (2003), chapter 28.
    """
    u = np.asarray(u, float)
    lam = np.clip(np.linalg.eigvalsh(H), 0.0, None)
    occam = float(np.sum(0.5 * np.log(np.minimum(1.0, 2 * np.pi / np.maximum(lam, 1e-300)))))
    cov = np.linalg.pinv(H)
    sd = np.minimum(np.sqrt(np.clip(np.diag(cov), 0, None)), 1 / np.sqrt(2 * np.pi))
    sd = np.maximum(sd, 1e-12)
    mass = sps.norm.cdf((1 - u) / sd) - sps.norm.cdf(-u / sd)
    occam += float(np.sum(np.log(np.maximum(mass, 1e-300))))
    return occam, cov


def model_evidence(ctx, real_mu, cand, noise, nu=NU):
    """ln Z of a fitted candidate (fitted on every row; ``cand`` None: the nominal model, k = 0).

    Returns dict(name, k, rss, loglik, occam, log_z, cov, H, J) (``cov``: the unit-cube posterior
    covariance of the Laplace approximation, ``H`` its Gauss-Newton Hessian, ``J`` d log10 mu / d u;
    None for k = 0).

    Parameters
    ----------
    ctx : FrictionContext
        The measured rows and the baseline spec (the nominal model when ``cand`` is None).
    real_mu : ndarray, shape (n,)
        Measured mu at every row.
    cand : Candidate or None
        Fitted candidate (None: nominal model).
    noise : float
        Noise estimate, rms of log10(measured / simulated mu); at least :data:`NOISE_FLOOR` is used.
    nu : float, optional
        Degrees of freedom the noise estimate is worth (default :data:`NU` = 4).

    Returns
    -------
    dict
        name, k, rss [log10^2], loglik, occam and log_z = loglik + occam [nats]; cov, H (k, k) and
        J (n, k), None for the nominal model.

    References
    ----------
    D.J.C. MacKay, Information Theory, Inference, and Learning Algorithms, Cambridge University
    Press (2003), chapter 28 (Laplace approximation of the evidence).
    """
    from pipelines.diagnosis.fit.fitting import pack
    from pipelines.diagnosis.model import simulate

    y = np.log10(np.asarray(real_mu, float))
    n = y.size
    s = noise_scale(noise)
    if cand is None:
        r = y - np.log10(simulate(ctx.base, ctx))
        rss = float(r @ r)
        ll = loglik(rss, n, s, nu)
        return dict(name="nominal", k=0, rss=rss, loglik=ll, occam=0.0, log_z=ll, cov=None, H=None, J=None)
    r = y - np.log10(cand.pred)
    rss = float(r @ r)
    ll = loglik(rss, n, s, nu)
    u = np.clip(pack(cand.effects, cand.params), 0, 1)
    J = jacobian(_log10_model(ctx, cand.effects), u, f0=np.log10(cand.pred))
    J = np.where(np.isfinite(J), J, 0.0)
    s_eff2 = (nu * s * s + rss) / (nu + n)
    H = J.T @ J / s_eff2
    occam, cov = log_occam(H, u)
    return dict(
        name=cand.name, k=cand.k, rss=rss, loglik=ll, occam=occam, log_z=ll + occam, cov=cov, H=H, J=J
    )


def posteriors(ev0, evs):
    """Posterior probabilities of the null explanation ``ev0`` and of each of ``evs`` (dicts of
    :func:`model_evidence`), prior odds as in the module docstring. Returns (p0, [p]).

    Parameters
    ----------
    ev0 : dict
        :func:`model_evidence` of the null explanation (no effect beyond the uncertain inputs).
    evs : list of dict
        :func:`model_evidence` of each effect tried; they share the prior 1/2 equally.

    Returns
    -------
    p0 : float
        Posterior probability of the null explanation (1 when ``evs`` is empty).
    p : list of float
        Posterior probability of each of ``evs``, in order; with ``p0`` they sum to 1.
    """
    m = len(evs)
    logs = [np.log(PRIOR_NULL if m else 1.0) + ev0["log_z"]]
    logs += [np.log((1 - PRIOR_NULL) / m) + e["log_z"] for e in evs]
    logs = np.array(logs)
    w = np.exp(logs - logs.max())
    w = w / w.sum()
    return float(w[0]), [float(x) for x in w[1:]]
