"""A synthetic surface of known spectrum "measured" by a simulated instrument.

The surface is a Gaussian random field with Persson's C(q) = K q^(-2(H+1)) above the roll-off
q_r and C(q_r) below (:func:`roadscan.synth.model_psd`). An instrument with spacing a, n x n
points, lateral resolution r and white height noise sigma_n sees

    h_meas = S_a[ G_r * h ] + e,     e ~ N(0, sigma_n^2) per point,

where G_r is a Gaussian low-pass with amplitude response exp(-ln 2 (q r / 2 pi)^2) (50 % at
the wavelength r), S_a samples every ``oversample``-th point of a field generated at a / o
(the power above the instrument's Nyquist folds back, as in a real instrument), and the field
is a periodic one ``pad`` times larger than the view, cropped (so the view is not periodic:
its window leaks as a real scan's does). Fourier amplitudes: F_k = sqrt(N C(q_k) (2 pi)^2 / A)
times complex white noise of unit variance per point, so E|h_q|^2 = C(q) (2 pi)^2 / A exactly.

Reference: Jacobs, Junge, Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017), sec. 3.
"""

from __future__ import annotations

import numpy as np

from .heightmap import HeightMap
from .synth import model_psd

__all__ = ["measure_synthetic"]


def measure_synthetic(
    n: int,
    spacing_m: float,
    hurst: float,
    prefactor_m4: float,
    q_roll_per_m: float | None = None,
    resolution_m: float | None = None,
    noise_rms_m: float = 0.0,
    seed: int = 0,
    oversample: int = 2,
    pad: int = 4,
    name: str = "measured",
) -> HeightMap:
    """An n x n HeightMap [m] of the surface above as the instrument records it.

    Parameters
    ----------
    n : int
        Points per side of the view.
    spacing_m : float
        The instrument's sampling interval a [m].
    hurst, prefactor_m4, q_roll_per_m
        The true spectrum (see :func:`roadscan.synth.model_psd`).
    resolution_m : float, optional
        Lateral resolution r [m] (Gaussian, 50 % amplitude at wavelength r); None: perfect.
    noise_rms_m : float
        rms of the white measurement noise [m].
    seed : int
        numpy Generator seed.

    Returns
    -------
    HeightMap
        The recorded heights [m].
    """
    rng = np.random.default_rng(seed)
    m = n * pad * oversample
    d = spacing_m / oversample
    area = (m * d) ** 2
    qx = 2 * np.pi * np.fft.rfftfreq(m, d)
    qy = 2 * np.pi * np.fft.fftfreq(m, d)
    q = np.hypot(qx[None, :], qy[:, None])
    C = model_psd(q, hurst, prefactor_m4, 0.0, np.inf, q_roll_per_m)
    amp = np.sqrt(m * m * C * (2 * np.pi) ** 2 / area)
    if resolution_m:
        amp *= np.exp(-np.log(2.0) * (q * resolution_m / (2 * np.pi)) ** 2)
    F = np.fft.rfft2(rng.standard_normal((m, m))) * amp
    h = np.fft.irfft2(F, s=(m, m))[: n * oversample : oversample, : n * oversample : oversample]
    if noise_rms_m:
        h = h + rng.normal(0.0, noise_rms_m, h.shape)
    meta = {
        "model": {
            "hurst": hurst,
            "prefactor_m4": prefactor_m4,
            "q_roll_per_m": q_roll_per_m,
            "resolution_m": resolution_m,
            "noise_rms_m": noise_rms_m,
            "seed": seed,
        },
        "source": "roadscan.synth_measure.measure_synthetic",
    }
    return HeightMap(np.ascontiguousarray(h), spacing_m, spacing_m, name=name, meta=meta)
