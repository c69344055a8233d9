"""The seam finder's median profiles: its one-sort NaN median equals numpy's, bit for bit."""

import warnings

import numpy as np

from roadscan.seams import _nanmedian


def test_nanmedian_equals_numpy_on_random_maps_with_gaps():
    rng = np.random.default_rng(7)
    for _ in range(400):
        shape = (int(rng.integers(1, 60)), int(rng.integers(1, 60)))
        x = rng.normal(size=shape) * 10.0 ** rng.integers(-6, 3)
        x[rng.random(shape) < rng.random()] = np.nan
        if rng.random() < 0.2:
            x[:, 0] = np.nan  # a line without any measured point
        for axis in (0, 1):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                want = np.nanmedian(x, axis=axis)
            np.testing.assert_array_equal(_nanmedian(x, axis), want)
