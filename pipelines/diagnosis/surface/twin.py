"""The surface level's "sim": Gaussian self-affine twins of a scan.

A twin has the scan's grid and the pure power law of the scan's self-affine fit,
C(q) = C(q0) (q/q0)^(-2(H+1)) [m^4], isotropic, Gaussian, seamless. It is synthesised
(:func:`roadscan.synth.self_affine_surface`, FFT filtering of white noise) on a grid twice as
large in each direction and cropped, so that, like a measured scan, it is not periodic; then it
is levelled like the scan (mean plane). A profile's twin is a 1D Gaussian profile with the 1D
spectrum C1(q) = C(q) q sqrt(pi) Gamma(H + 1/2) / Gamma(1 + H) (the inverse of the power-law
Abel conversion of :func:`roadscan.spectrum.psd_profile`), made the same way.
"""

from __future__ import annotations

import numpy as np
from scipy.special import gammaln

__all__ = ["twin_heights", "skewed", "skewed_set"]


def _K(fit):
    return fit.C_at_q0_m4 * fit.q0_per_m ** (2.0 * (fit.hurst + 1.0))


def twin_heights(levelled, fit, seed):
    """Heights of one twin of ``levelled`` (HeightMap or Profile) [m], levelled.

    Parameters
    ----------
    levelled : HeightMap or Profile
        The levelled scan: only its shape and spacings [m] are used.
    fit : SelfAffineFit
        Its self-affine fit: the twin's C(q) = C(q0) (q / q0)^(-2 (H + 1)) [m^4].
    seed : int
        Seed of ``numpy.random.default_rng``: the same seed gives the same twin.

    Returns
    -------
    ndarray
        Gaussian heights [m] of the scan's shape, its mean plane (line) removed.
    """
    from roadscan.heightmap import Profile

    H = float(fit.hurst)
    rng = np.random.default_rng(seed)
    if isinstance(levelled, Profile):
        n = levelled.heights_m.size
        N = 2 * n
        dx = levelled.dx_m
        q = 2 * np.pi * np.fft.rfftfreq(N, dx)
        conv = np.exp(0.5 * np.log(np.pi) + gammaln(H + 0.5) - gammaln(1 + H))
        C1 = np.zeros_like(q)
        C1[1:] = _K(fit) * q[1:] ** (-2.0 * (H + 1.0)) * q[1:] * conv
        # <|FFT h|^2> = 2 pi L C1 / dx^2 for the normalisation of psd_profile
        L = N * dx
        amp = np.sqrt(2 * np.pi * L * C1) / dx
        F = (rng.standard_normal(q.size) + 1j * rng.standard_normal(q.size)) * amp / np.sqrt(2)
        F[0] = 0
        h = np.fft.irfft(F, n=N)[:n]
        x = np.linspace(-1, 1, n)
        c = np.polyfit(x, h, 1)
        return h - np.polyval(c, x)
    from roadscan.synth import self_affine_surface

    ny, nx = levelled.shape
    tw = self_affine_surface(
        2 * nx,
        2 * ny,
        dx_m=levelled.dx_m,
        dy_m=levelled.dy_m,
        hurst=min(H, 1.2),
        rms_height_m=1e-4,
        seed=int(rng.integers(2**31)),
        name="twin",
    )
    scale = np.sqrt(_K(fit) / tw.meta["model"]["prefactor_m4"])
    h = tw.heights_m[:ny, :nx] * scale
    Y, X = np.meshgrid(np.linspace(-1, 1, ny), np.linspace(-1, 1, nx), indexing="ij")
    A = np.column_stack([np.ones(h.size), X.ravel(), Y.ravel()])
    c, *_ = np.linalg.lstsq(A, h.ravel(), rcond=None)
    return h - (A @ c).reshape(h.shape)


def skewed(h, skewness):
    """``h`` rank-transformed onto a gamma law of the given skewness (same mean and std):
    a monotone map that keeps the ordering of heights (so the spectrum changes little) and
    sets the height distribution; skewness 0 gives the normal law.

    Parameters
    ----------
    h : ndarray
        Heights [m], any shape.
    skewness : float
        Moment skewness of the target law (0: normal).

    Returns
    -------
    ndarray
        Heights [m] of the shape of ``h``, with its mean and standard deviation.
    """
    from scipy import stats

    flat = h.ravel()
    r = (stats.rankdata(flat) - 0.5) / flat.size
    if abs(skewness) < 1e-6:
        z = stats.norm.ppf(r)
    else:
        k = 4.0 / skewness**2
        g = stats.gamma.ppf(r if skewness > 0 else 1 - r, k)
        z = (g - k) / np.sqrt(k) * (1 if skewness > 0 else -1)
    z = (z - z.mean()) / z.std()
    return (flat.mean() + flat.std() * z).reshape(h.shape)


def _law_quantiles(n, skewness):
    """The standardised quantiles of the law of :func:`skewed` at (i + 1/2) / n, i = 0..n-1."""
    from scipy import stats

    r = (np.arange(n) + 0.5) / n
    if abs(skewness) < 1e-6:
        z = stats.norm.ppf(r)
    else:
        k = 4.0 / skewness**2
        z = (stats.gamma.ppf(r if skewness > 0 else 1 - r, k) - k) / np.sqrt(k) * (1 if skewness > 0 else -1)
        if skewness < 0:
            z = np.sort(z)
    return (z - z.mean()) / z.std()


def skewed_set(heights, grid):
    """``{s: [skewed(h, s) for h in heights]}`` for every s in ``grid``, the quantiles of each law
    computed once and the ordering of each array once (same result as :func:`skewed` for arrays
    without ties).

    Parameters
    ----------
    heights : list of ndarray
        Height arrays [m] (e.g. twins), any shapes.
    grid : iterable of float
        Moment skewnesses of the target laws (0: normal).

    Returns
    -------
    dict
        Skewness -> list of skewed arrays, one per entry of ``heights``, each of its shape.
    """
    flat = [np.asarray(h, float).ravel() for h in heights]
    order = [np.argsort(f, kind="stable") for f in flat]
    out = {}
    for s in grid:
        zq = {}
        res = []
        for h, f, o in zip(heights, flat, order):
            if f.size not in zq:
                zq[f.size] = _law_quantiles(f.size, s)
            v = np.empty_like(f)
            v[o] = f.mean() + f.std() * zq[f.size]
            res.append(v.reshape(np.shape(h)))
        out[s] = res
    return out
