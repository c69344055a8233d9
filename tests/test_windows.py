"""roadscan.windows reproduces the scipy.signal functions it replaces (so roadscan need not
import scipy.signal): Tukey window, 2nd-order Butterworth design and zero-phase filtering."""

import numpy as np
import pytest
from scipy.signal import butter, sosfiltfilt
from scipy.signal.windows import tukey as scipy_tukey

from roadscan.windows import butter2_lowpass, filtfilt2, tukey


@pytest.mark.parametrize("alpha", [0.0, 0.1, 0.25, 0.5, 0.999, 1.0, 2.0])
def test_tukey_matches_scipy(alpha):
    for n in (1, 2, 3, 4, 7, 64, 65, 978, 1088):
        np.testing.assert_allclose(tukey(n, alpha), scipy_tukey(n, alpha), rtol=0, atol=1e-15)


@pytest.mark.parametrize("wn", [0.05, 0.4166666, 0.8333333])
def test_butterworth_and_filtfilt_match_scipy(wn):
    sos = butter(2, wn, btype="low", output="sos")
    b, a = butter2_lowpass(wn)
    np.testing.assert_allclose(b, sos[0, :3], rtol=1e-12)
    np.testing.assert_allclose(a, sos[0, 3:], rtol=1e-12, atol=1e-15)
    x = np.random.default_rng(3).standard_normal((4, 257)).cumsum(axis=1)
    np.testing.assert_allclose(
        filtfilt2(b, a, x), sosfiltfilt(sos, x, axis=1), rtol=0, atol=1e-11 * np.abs(x).max()
    )


def test_lowpass_gain_is_half_power_at_cutoff():
    # |H(f_c)|^2 = 1/2 for a Butterworth at its cut-off; filtfilt squares it: amplitude 1/2
    wn = 0.2
    b, a = butter2_lowpass(wn)
    z = np.exp(1j * np.pi * wn)
    H = (b[0] + b[1] / z + b[2] / z**2) / (1 + a[1] / z + a[2] / z**2)
    assert abs(abs(H) ** 2 - 0.5) < 1e-12
    with pytest.raises(ValueError):
        butter2_lowpass(1.2)
