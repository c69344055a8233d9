"""The shortcuts texture_parameters takes give the figures of the direct route: the feature
figures from the heights and their mean (no copy about the mean) and with the pits not counted
(only the five deepest significant ones found) are those of feature_parameters on the heights
less their mean; texture_parameters equals the three modules called on them."""

import numpy as np
import pytest
from scipy.ndimage import gaussian_filter

from roadscan.areal_features import feature_parameters
from roadscan.areal_spatial import spatial_parameters
from roadscan.heightmap import HeightMap
from roadscan.iso25178 import AREAL_KEYS, texture_parameters
from roadscan.material_ratio import areal_material_parameters


def _surface(seed, shape=(180, 150), quantised=False):
    rng = np.random.default_rng(seed)
    z = gaussian_filter(rng.normal(size=shape), rng.uniform(0.7, 3.0)) * 1e-3 + 2e-3
    return np.round(z * 4e4) / 4e4 if quantised else z


def _figures(d):
    return {k: v for k, v in d.items() if not k.endswith("_note")}


@pytest.mark.parametrize("seed", range(12))
def test_features_from_the_mean_and_without_counting_pits(seed):
    z = _surface(seed, quantised=seed % 3 == 0)
    fraction = (0.01, 0.05, 0.2)[seed % 3]
    m = z.mean()
    ref = feature_parameters(z - m, 1e-4, 2e-4, fraction)
    shifted = feature_parameters(z, 1e-4, 2e-4, fraction, mean=m, z_min=z.min(), z_max=z.max())
    assert shifted == ref
    fast = feature_parameters(z, 1e-4, 2e-4, fraction, mean=m, count_pits=False)
    assert _figures(fast) == _figures(ref)
    assert "pits not counted" in fast["features_note"]


def test_texture_parameters_is_the_modules_on_the_levelled_heights():
    z = _surface(3, (240, 200))
    figs, notes = texture_parameters(HeightMap(z, 1e-4, 1e-4))
    zc = z - z.mean()
    ref = {
        **areal_material_parameters(z),
        **spatial_parameters(zc, 1e-4, 1e-4),
        **feature_parameters(zc, 1e-4, 1e-4),
    }
    for k in AREAL_KEYS:
        if k in ("Sal_m", "Str", "Std_deg"):
            assert figs[k] == pytest.approx(ref[k], rel=1e-7, abs=1e-4 if k == "Std_deg" else 0)
        else:
            assert figs[k] == ref[k], k
    assert notes["features"].endswith("(pits not counted further)")
