"""The compiled priority-flood fill (roadscan._flood via roadscan.rain.full_fill(method="flood"))
against scikit-image's reconstruction by erosion (the definition, DESIGN.md section 3), on random,
tied, real and degenerate surfaces, with and without dropouts, and by its defining properties."""

from collections import deque

import numpy as np
import pytest
from conftest import unit_fourier_surface
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from skimage.morphology import reconstruction

import roadscan.rain as rain
from roadscan.heightmap import HeightMap
from roadscan.rain import footprint, full_fill, rain_fill

pytest.importorskip("numba")


def skimage_fill(h, connectivity):
    """imfill by the definition: reconstruction by erosion seeded with the border heights."""
    seed = np.full_like(h, h.max())
    seed[0], seed[-1], seed[:, 0], seed[:, -1] = h[0], h[-1], h[:, 0], h[:, -1]
    return reconstruction(seed, h, method="erosion", footprint=footprint(connectivity))


def drains_everywhere(f, connectivity):
    """True when every cell of ``f`` reaches the border by a path that never goes up, i.e. ``f``
    has no depression (no regional minimum away from the border)."""
    ny, nx = f.shape
    nb = [(-1, 0), (1, 0), (0, -1), (0, 1)]
    if connectivity == 8:
        nb += [(-1, -1), (-1, 1), (1, -1), (1, 1)]
    seen = np.zeros(f.shape, bool)
    dq = deque()
    for i in range(ny):
        for j in range(nx):
            if i in (0, ny - 1) or j in (0, nx - 1):
                seen[i, j] = True
                dq.append((i, j))
    while dq:  # climb from the border: a cell drains when a drained neighbour is <= it
        i, j = dq.popleft()
        for a, b in nb:
            k, m = i + a, j + b
            if 0 <= k < ny and 0 <= m < nx and not seen[k, m] and f[k, m] >= f[i, j]:
                seen[k, m] = True
                dq.append((k, m))
    return bool(seen.all())


@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("kind", ["self_affine_noisy", "white_noise", "integer_ties", "tilted"])
def test_flood_identical_to_reconstruction(connectivity, kind):
    rng = np.random.default_rng(7)
    if kind == "self_affine_noisy":
        h = 1e-3 * unit_fourier_surface(200, seed=3) + 1e-5 * rng.standard_normal((200, 200))
    elif kind == "white_noise":
        h = rng.standard_normal((151, 173))
    elif kind == "integer_ties":  # many flats and equal spill levels
        h = rng.integers(0, 4, (120, 90)).astype(float)
    else:  # a strong tilt: water leaves over the low edge
        h = 1e-3 * unit_fourier_surface(128, seed=1) + np.linspace(0, 5, 128)[None, :]
    f = full_fill(h, connectivity, method="flood")
    ref = skimage_fill(h, connectivity)
    np.testing.assert_array_equal(f, ref)
    assert np.count_nonzero(f > h) > 0 or kind == "tilted"
    assert drains_everywhere(f, connectivity)


@pytest.mark.parametrize("connectivity", [4, 8])
def test_flood_with_dropouts_matches_the_reconstruction_path(connectivity):
    rng = np.random.default_rng(11)
    h = 1e-3 * unit_fourier_surface(160, seed=5) + 1e-5 * rng.standard_normal((160, 160))
    h[rng.random(h.shape) < 0.05] = np.nan  # scattered dropouts
    h[40:60, 70:75] = np.nan  # a hole
    h[0, 10:30] = np.nan  # on the border
    h[:, 120] = np.nan  # a full column cuts the map in two
    a = full_fill(h, connectivity, method="flood")
    b = full_fill(h, connectivity, method="reconstruction")
    np.testing.assert_array_equal(np.isnan(a), np.isnan(h))
    np.testing.assert_array_equal(a, b)  # NaN == NaN for assert_array_equal
    for kw in ({}, {"max_depth_m": 2e-5}, {"water_film_m": 1e-6}):
        hm = HeightMap(h, 1e-4, 1e-4)
        ra = rain_fill(hm, connectivity, method="flood", **kw)
        rb = rain_fill(hm, connectivity, method="reconstruction", **kw)
        np.testing.assert_array_equal(ra.depth_m, rb.depth_m)
        np.testing.assert_array_equal(ra.wet.heights_m, rb.wet.heights_m)
        assert ra.wetted_fraction == rb.wetted_fraction > 0
        assert ra.water_volume_m3_per_m2 == rb.water_volume_m3_per_m2
        assert ra.meta == rb.meta


@pytest.mark.parametrize("shape", [(1, 1), (1, 7), (7, 1), (2, 2), (2, 9)])
def test_flood_degenerate_shapes(shape):
    h = np.random.default_rng(0).standard_normal(shape)
    for c in (4, 8):
        np.testing.assert_array_equal(full_fill(h, c, method="flood"), h)  # all border: no fill
    h3 = np.array([[3.0, 3, 3], [3, 0, 3], [3, 3, 3]])
    np.testing.assert_array_equal(full_fill(h3, 4, method="flood"), np.full((3, 3), 3.0))


def test_flood_all_nan_border_and_huge_values():
    h = np.full((6, 6), np.nan)
    h[2:4, 2:4] = [[1.0, 2.0], [3.0, 1e300]]  # measured island inside a ring of dropouts
    f = full_fill(h, 4, method="flood")
    np.testing.assert_array_equal(f, full_fill(h, 4, method="reconstruction"))
    np.testing.assert_array_equal(f[2:4, 2:4], h[2:4, 2:4])  # the island drains through them
    spike = np.ones((9, 9))
    spike[4, 4] = 0.0
    spike[1, 1] = 1e300
    f = full_fill(spike, 4, method="flood")
    assert f[4, 4] == 1.0 and f[1, 1] == 1e300


def test_real_instrument_scan(shared_data):
    """Real instrument scans (shared/data/formats): a Digital Surf file with undefined points
    and a Sensofar confocal scan (the thesis's make)."""
    pytest.importorskip("SurfaceTopography")
    from roadscan.io import read

    h = read(shared_data / "formats" / "sur-2.sur").heights_m
    assert np.isnan(h).any()
    for c in (4, 8):
        a = full_fill(h, c, method="flood")
        np.testing.assert_array_equal(a, full_fill(h, c, method="reconstruction"))
        assert np.count_nonzero(a > h) > 100
    h = read(shared_data / "formats" / "plu-1.plu").heights_m
    assert not np.isnan(h).any()
    for c in (4, 8):
        a = full_fill(h, c, method="flood")
        np.testing.assert_array_equal(a, skimage_fill(h, c))
        assert np.count_nonzero(a > h) > 100


def test_auto_threshold_and_fallback(monkeypatch):
    h = 1e-3 * unit_fourier_surface(64, seed=2)
    calls = []
    real = rain._flood_kernel

    def spy():
        calls.append(1)
        return real()

    monkeypatch.setattr(rain, "_flood_kernel", spy)
    monkeypatch.setattr(rain, "_flood_warm", lambda: False)
    ref = skimage_fill(h, 4)
    np.testing.assert_array_equal(full_fill(h), ref)  # small map: scikit-image
    assert calls == []
    monkeypatch.setattr(rain, "FLOOD_MIN_POINTS", 100)
    np.testing.assert_array_equal(full_fill(h), ref)  # above the threshold: the flood
    assert calls == [1]
    monkeypatch.setattr(rain, "_flood_kernel", lambda: None)  # numba missing: exact fallback
    np.testing.assert_array_equal(full_fill(h), ref)
    with pytest.raises(ImportError, match="numba"):
        full_fill(h, method="flood")
    with pytest.raises(ValueError, match="method"):
        full_fill(h, method="fast")


surfaces = arrays(
    np.float64,
    st.tuples(st.integers(1, 16), st.integers(1, 16)),
    elements=st.one_of(
        st.floats(-1.0, 1.0, allow_nan=False, width=32),
        st.sampled_from([0.0, 0.5, 1.0]),  # ties and flats
        st.just(np.nan),
    ),
)


@settings(max_examples=150, deadline=None)
@given(surfaces, st.sampled_from([4, 8]))
def test_flood_properties(h, conn):
    if np.isnan(h).all():
        h = np.zeros_like(h)
    f = full_fill(h, conn, method="flood")
    np.testing.assert_array_equal(f, full_fill(h, conn, method="reconstruction"))
    ok = ~np.isnan(h)
    np.testing.assert_array_equal(np.isnan(f), ~ok)
    assert np.all(f[ok] >= h[ok])  # filled >= original
    np.testing.assert_array_equal(full_fill(f, conn, method="flood"), f)  # idempotent
    if ok.all():
        assert drains_everywhere(f, conn)  # no depression left
        if conn == 4:
            assert np.all(full_fill(h, 8, method="flood") <= f)  # 8 leaks more
