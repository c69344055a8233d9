"""The speed-ups of the feature segmentation (issue 34) change no answer.

- The threshold-aware change tree drops every saddle edge lying at least the pruning threshold
  below both of its summits (``roadscan.areal_features._needed``): the set of significant
  maxima must be the one the full change tree (no edge dropped, checked against a union-find
  over the points in ``tests/test_texture_speed_exactness.py``) gives, on random surfaces of
  every kind (rough, smooth, quantised with plateaus and flat saddles, anisotropic), at
  thresholds from 0.5 % to 40 % of Sz, for peaks and for pits.
- The feature figures (Spd, Spc, S5p, S5v, S10z) equal, bit for bit, those computed from the full
  prominences of the peaks and pits, written out here from the ISO 25178-2 definitions.
- OpenCV's table look-up (``roadscan.areal_critical._lookup``) equals ``np.take`` for every code.
"""

import numpy as np
import pytest
from scipy.ndimage import gaussian_filter

from roadscan.areal_critical import _critical_points, _lookup, _lower_code, _patterns
from roadscan.areal_features import _change_tree, _critical_graph, feature_parameters


def _surface(kind, seed, shape=(97, 131)):
    """A random height field [m] of one kind."""
    rng = np.random.default_rng(seed)
    z = rng.normal(size=shape)
    if kind == "smooth":
        z = gaussian_filter(z, 2.5)
    elif kind == "quantised":  # plateaus, equal saddles
        z = np.round(gaussian_filter(z, 1.2) * 5) / 5
    elif kind == "anisotropic":
        z = gaussian_filter(z, (0.7, 6.0))
    elif kind == "rough_on_smooth":
        z = gaussian_filter(z, 6.0) * 20 + z
    return 1e-4 * z


def _graph(z, pits):
    """(summit heights, edges a, b, saddle heights) of the maxima of z (of -z for pits)."""
    order, code, cand = _patterns(z, float(z.mean()))
    low = _lower_code(code)
    (maxima, psad, minima, vsad), (zmax, zps, zmin, zvs) = _critical_points(code, low, cand, z)
    label = order.view(np.int32).ravel()
    if pits:
        a, b, s = _critical_graph(low.ravel(), z.shape[1], minima, vsad, label)
        return minima, -zmin, a, b, -np.take(zvs, s)
    a, b, s = _critical_graph(code.ravel(), z.shape[1], maxima, psad, label)
    return maxima, zmax, a, b, np.take(zps, s)


KINDS = ["rough", "smooth", "quantised", "anisotropic", "rough_on_smooth"]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("pits", [False, True])
def test_dropped_edges_change_no_significant_extremum(kind, pits):
    for seed in range(4):
        z = _surface(kind, 10 * seed + KINDS.index(kind))
        _, top, a, b, saddle = _graph(z, pits)
        full = _change_tree(top, a, b, saddle)  # every prominence, no edge dropped
        sz = float(z.max() - z.min())
        for fraction in (0.005, 0.02, 0.05, 0.1, 0.2, 0.4):
            T = fraction * sz
            fast = _change_tree(top, a, b, saddle, T, few=50)  # the rounds run too
            np.testing.assert_array_equal(fast >= T, full >= T)


def _figures_from_full_prominences(z, dx, fraction):
    """Spd, Spc, S5p, S5v, S10z from every prominence (no threshold inside the tree)."""
    ny, nx = z.shape
    T = fraction * float(z.max() - z.min())
    out = {}
    for pits in (False, True):
        ext, top, a, b, saddle = _graph(z, pits)
        keep = ext[_change_tree(top, a, b, saddle) >= T]
        r, c = keep // nx, keep % nx
        inner = (r > 0) & (r < ny - 1) & (c > 0) & (c < nx - 1)
        r, c = r[inner], c[inner]
        h = (-1.0 if pits else 1.0) * (z[r, c] - z.mean())
        out[pits] = (r, c, np.sort(h)[::-1][:5])
    r, c, top5 = out[False]
    curv = (z[r, c + 1] - 2 * z[r, c] + z[r, c - 1]) / dx**2 + (
        z[r + 1, c] - 2 * z[r, c] + z[r - 1, c]
    ) / dx**2
    deep5 = out[True][2]
    return {
        "Spd_per_m2": r.size / (ny * dx * nx * dx),
        "Spc_per_m": -0.5 * float(np.mean(curv)),
        "S5p_m": float(top5.mean()),
        "S5v_m": float(deep5.mean()),
        "S10z_m": float(top5.mean()) + float(deep5.mean()),
    }


@pytest.mark.parametrize("kind", KINDS)
def test_feature_figures_equal_those_of_the_full_prominences(kind):
    dx = 5e-5
    for seed in range(3):
        z = _surface(kind, 100 + seed)
        z = z - z.mean()
        for fraction in (0.02, 0.05, 0.2):
            ref = _figures_from_full_prominences(z, dx, fraction)
            for count_pits in (True, False):
                got = feature_parameters(z, dx, dx, fraction, count_pits=count_pits)
                assert got["Spd_per_m2"] == ref["Spd_per_m2"]
                for key in ("Spc_per_m", "S5p_m", "S5v_m", "S10z_m"):
                    assert got[key] == pytest.approx(ref[key], rel=1e-12, abs=0), key


def test_lookup_equals_numpy_take_for_every_code():
    rng = np.random.default_rng(5)
    codes = np.concatenate([np.arange(256, dtype=np.uint8), rng.integers(0, 256, 100_000).astype(np.uint8)])
    for table in (rng.integers(-5000, 5000, 256).astype(np.int32), rng.integers(0, 4, 256).astype(np.uint8)):
        got = _lookup(table, codes)
        assert got.dtype == table.dtype
        np.testing.assert_array_equal(got, np.take(table, codes))
    assert _lookup(np.arange(256, dtype=np.int32), np.empty(0, np.uint8)).size == 0
