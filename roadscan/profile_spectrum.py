"""1D power spectral density of line profiles and its isotropic 2D estimate.

With L = n dx and the 1D Tukey window w,

    C1(q_k) = dx^2 |FFT(w h)_k|^2 / (2 pi L <w^2>)            [m^3],  <h^2> = 2 int_0^inf C1 dq.

For an isotropic surface C1(q_x) = int dq_y C(sqrt(q_x^2 + q_y^2)) (an Abel transform). For a
power law C ~ q^(-2(1+H)) it inverts to the conversion used here, named
``"power-law Abel inversion"`` in ``meta['conversion']``:

    C(q) = C1(q) / q * Gamma(1 + H) / (sqrt(pi) Gamma(H + 1/2)),

with H estimated from the slope of C1 (C1 ~ q^-(1 + 2H)) over its self-affine band unless given.

Reference: Persson et al., J. Phys.: Condens. Matter 17, R1 (2005); Jacobs, Junge, Pastewka,
Surf. Topogr.: Metrol. Prop. 5, 013001 (2017).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .fft_backends import fft_backend
from .heightmap import HeightMap, Profile
from .heightmap import require_filled as _require_filled
from .rings import _ring_edges, _ring_index
from .spectrum_types import NORMALISATION_1D, NORMALISATION_2D, Spectrum
from .windows import tukey_cached as _tukey

__all__ = ["psd_profile", "profile_to_area_factor"]

_lgamma = np.vectorize(math.lgamma, otypes=[float])


def profile_to_area_factor(hurst: ArrayLike) -> float | NDArray[np.float64]:
    """Gamma(1 + H) / (sqrt(pi) Gamma(H + 1/2)): C(q) = C1(q) / q times this (power law).

    Parameters
    ----------
    hurst : float or array_like
        Hurst exponent H.

    Returns
    -------
    float or ndarray
        The factor.
    """
    h = np.asarray(hurst, dtype=float)
    out = np.exp(_lgamma(1.0 + h) - _lgamma(h + 0.5)) / np.sqrt(np.pi)
    return float(out) if out.ndim == 0 else out


def _profiles_array(profiles):
    if isinstance(profiles, HeightMap):
        _require_filled(profiles)
        return profiles.heights_m, profiles.dx_m
    if isinstance(profiles, Profile):
        profiles = [profiles]
    profiles = list(profiles)
    if not profiles or not all(isinstance(p, Profile) for p in profiles):
        raise TypeError("expected a Profile, a list of Profiles or a HeightMap (rows along x)")
    n, dx = profiles[0].n, profiles[0].dx_m
    for p in profiles:
        _require_filled(p)
        if p.n != n or not np.isclose(p.dx_m, dx, rtol=1e-9):
            raise ValueError("profiles must share length and spacing")
    return np.stack([p.heights_m for p in profiles]), dx


def psd_profile(
    profiles: Profile | Sequence[Profile] | HeightMap,
    window_alpha: float = 0.25,
    hurst: float | None = None,
    rings_per_decade: int = 20,
    detrend: Literal["mean", "linear"] | None = "mean",
) -> tuple[NDArray[np.float64], NDArray[np.float64], Spectrum]:
    """1D PSD of line profiles and its isotropic 2D estimate.

    C1(q_k) = dx^2 |FFT(w h)_k|^2 / (2 pi L <w^2>) [m^3] at q_k = 2 pi k / L, k = 1 .. n/2,
    averaged over the profiles (1D Tukey window, power loss corrected). The 2D estimate uses
    the power-law Abel inversion C(q) = C1(q) / q * Gamma(1 + H) / (sqrt(pi) Gamma(H + 1/2))
    on C1 averaged in log-spaced bins (2 pi / L to pi / dx, ``rings_per_decade``).

    Parameters
    ----------
    profiles : Profile, sequence of Profile, or HeightMap
        Filled profiles of equal length and spacing; a HeightMap contributes its rows (x).
    window_alpha : float
        Tukey alpha (0.25 default).
    hurst : float, optional
        H for the conversion; by default fitted to C1 (slope -(1 + 2H)) over the band found
        by :func:`roadscan.fit.detect_band`.
    detrend : {"mean", "linear", None}
        Removed from each profile before windowing.

    Returns
    -------
    q_per_m : (n/2,) array
    C1_m3 : (n/2,) array
    Spectrum
        kind ``"profile"``; ``meta['conversion']`` names the conversion and the H used.
    """
    from .fit import _loglog_fit, detect_band  # fit does not import spectrum

    h, dx = _profiles_array(profiles)
    h = np.array(h, dtype=np.float64)
    n = h.shape[1]
    if detrend == "linear":
        x = np.linspace(-1, 1, n)
        h = h - h.mean(axis=1, keepdims=True)
        h = h - np.outer(h @ x / (x @ x), x)
    elif detrend == "mean":
        h = h - h.mean(axis=1, keepdims=True)
    elif detrend is not None:
        raise ValueError(f"detrend must be 'mean', 'linear' or None, got {detrend!r}")
    w = _tukey(n, float(window_alpha))
    w2 = float(np.mean(w**2))
    L = n * dx
    F = fft_backend(h.size).rfft(h * w[None, :], axis=1)[:, 1:]
    C1 = (np.abs(F) ** 2).mean(axis=0) * dx**2 / (2 * np.pi * L * w2)
    q = 2 * np.pi * np.arange(1, C1.size + 1) / L
    q_min, q_max = 2 * np.pi / L, np.pi / dx
    edges = _ring_edges(q_min, q_max, rings_per_decade)
    nb = edges.size - 1
    b = _ring_index(q, q_min, q_max, nb)
    s = b >= 0
    cnt = np.bincount(b[s], minlength=nb).astype(np.float64)
    keep = cnt > 0
    qb = np.bincount(b[s], weights=q[s], minlength=nb)[keep] / cnt[keep]
    c1b = np.bincount(b[s], weights=C1[s], minlength=nb)[keep] / cnt[keep]
    counts = np.rint(cnt[keep] * h.shape[0]).astype(np.int64)
    source = "given"
    if hurst is None:
        tmp = Spectrum(qb, c1b, count=counts, kind="profile")
        lo, hi = detect_band(tmp)
        slope, _, _, _ = _loglog_fit(qb, c1b, lo, hi)
        hurst = float(np.clip((-slope - 1.0) / 2.0, 0.01, 1.0))
        source = f"fitted to C1 on [{lo:.4g}, {hi:.4g}] 1/m"
    factor = profile_to_area_factor(hurst)
    meta = {
        "conversion": "power-law Abel inversion: C(q) = C1(q)/q * Gamma(1+H)/(sqrt(pi) Gamma(H+1/2))",
        "conversion_hurst": float(hurst),
        "conversion_hurst_source": source,
        "window": "tukey",
        "window_alpha": float(window_alpha),
        "window_mean_square": w2,
        "dx_m": dx,
        "n_profiles": int(h.shape[0]),
        "profile_length_m": L,
        "normalisation_1d": NORMALISATION_1D,
        "normalisation": NORMALISATION_2D,
        "rings_per_decade": rings_per_decade,
        "q_range_per_m": (q_min, q_max),
        "C1_binned_m3": c1b.tolist(),
    }
    spec = Spectrum(qb, c1b / qb * factor, count=counts, kind="profile", meta=meta)
    return q, C1, spec
