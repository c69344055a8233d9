"""Hurst exponent on surfaces made by an independent generator (not roadscan.synth), with the
features real scans have: a roll-off, a spectral cut-off below Nyquist, a white noise floor."""

import numpy as np
import pytest

from pipelines.chain.surface import analyse_surface
from roadscan.heightmap import HeightMap

N, DX = 1024, 5e-5


def gaussian_surface(hurst, seed, q_roll=None, q1=None):
    rng = np.random.default_rng(seed)
    qx = 2 * np.pi * np.fft.fftfreq(N, DX)
    q = np.hypot(*np.meshgrid(qx, qx))
    q[0, 0] = 1.0
    amp = np.maximum(q, q_roll or 0.0) ** (-(hurst + 1))
    if q1:
        amp[q > q1] = 0.0
    amp[0, 0] = 0.0
    z = rng.normal(size=(N, N)) + 1j * rng.normal(size=(N, N))
    h = np.fft.ifft2(amp * z).real
    return h * (1e-4 / h.std())


@pytest.mark.parametrize(
    "hurst,kind,seed",
    [
        (0.9, "cutoff", 9),
        (0.3, "cutoff", 3),
        (0.7, "rolloff", 7),
        (0.5, "noise", 5),
        (0.9, "noise", 2),
    ],
)
def test_hurst_within_003(hurst, kind, seed):
    kw = {}
    if kind == "cutoff":
        kw = dict(q1=np.pi / DX / 4)
    elif kind == "rolloff":
        kw = dict(q_roll=20 * 2 * np.pi / (N * DX))
    h = gaussian_surface(hurst, seed, **kw)
    if kind == "noise":
        h = h + np.random.default_rng(seed).normal(0, 2e-6, h.shape)
    fit = analyse_surface(HeightMap(h, DX, DX)).fit
    assert fit.hurst == pytest.approx(hurst, abs=0.03)
    assert 0 < fit.hurst_stderr < 0.03
    if kind == "cutoff":
        assert fit.fit_band_per_m[1] < np.pi / DX / 4  # the empty band above q1 is not fitted
    if kind == "rolloff":
        assert fit.q_roll_per_m == pytest.approx(20 * 2 * np.pi / (N * DX), rel=0.5)
