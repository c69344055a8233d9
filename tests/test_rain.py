"""Rain fill (roadscan.rain): against scikit-image, an independent priority-flood, analytic
pits, and properties of the definition in DESIGN.md section 3."""

import heapq

import numpy as np
import pytest
from conftest import unit_fourier_surface
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from skimage.morphology import reconstruction

from roadscan.heightmap import HeightMap
from roadscan.rain import footprint, full_fill, rain_fill


def priority_flood(h, connectivity):
    """Independent reference: Barnes et al. (2014) priority-flood depression filling."""
    ny, nx = h.shape
    if connectivity == 4:
        nbrs = [(-1, 0), (1, 0), (0, -1), (0, 1)]
    else:
        nbrs = [(a, b) for a in (-1, 0, 1) for b in (-1, 0, 1) if (a, b) != (0, 0)]
    out = h.copy()
    done = np.zeros(h.shape, bool)
    pq = []
    for i in range(ny):
        for j in range(nx):
            if i in (0, ny - 1) or j in (0, nx - 1):
                heapq.heappush(pq, (h[i, j], i, j))
                done[i, j] = True
    while pq:
        z, i, j = heapq.heappop(pq)
        for a, b in nbrs:
            k, m = i + a, j + b
            if 0 <= k < ny and 0 <= m < nx and not done[k, m]:
                done[k, m] = True
                out[k, m] = max(h[k, m], z)
                heapq.heappush(pq, (out[k, m], k, m))
    return out


def skimage_fill(h, connectivity):
    seed = np.full_like(h, h.max())
    seed[0], seed[-1], seed[:, 0], seed[:, -1] = h[0], h[-1], h[:, 0], h[:, -1]
    return reconstruction(seed, h, method="erosion", footprint=footprint(connectivity))


def hm_of(h, dx=1e-4):
    return HeightMap(h, dx, dx)


@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("seed", [0, 1])
def test_full_fill_identical_to_skimage_and_priority_flood(connectivity, seed):
    h = 1e-3 * unit_fourier_surface(64, seed=seed)
    h += 1e-5 * np.random.default_rng(seed).standard_normal(h.shape)  # many small pits
    filled = full_fill(h, connectivity)
    np.testing.assert_array_equal(filled, skimage_fill(h, connectivity))
    np.testing.assert_array_equal(filled, priority_flood(h, connectivity))
    r = rain_fill(hm_of(h), connectivity=connectivity)
    np.testing.assert_array_equal(r.wet.heights_m, filled)
    assert r.connectivity == connectivity
    assert 0 < r.wetted_fraction < 1
    assert r.water_volume_m3_per_m2 == pytest.approx(np.mean(filled - h), rel=1e-12)


def test_default_connectivity_is_4_and_diagonal_gap_matters():
    # a 1-deep pit whose rim has one diagonal leak: 8-connected water escapes, 4 does not
    h = np.full((7, 7), 0.0)
    h[1:6, 1:6] = 2.0
    h[2:5, 2:5] = 1.0  # pit floor at 1, rim at 2
    h[3, 3] = 0.5  # lowest point
    h[1, 1] = 0.0  # rim corner removed: the pit touches (1,1) only diagonally via (2,2)
    r4 = rain_fill(hm_of(h))
    r8 = rain_fill(hm_of(h), connectivity=8)
    assert r4.connectivity == 4
    np.testing.assert_allclose(r4.wet.heights_m[2:5, 2:5], 2.0)  # filled to the rim
    np.testing.assert_allclose(r8.wet.heights_m[2:5, 2:5], np.maximum(h[2:5, 2:5], 1.0))
    assert r4.wetted_fraction == pytest.approx(9 / 49)
    assert r4.water_volume_m3_per_m2 == pytest.approx((8 * 1.0 + 1.5) / 49)


def pit():
    """A square pit: rim 3, floor rising from 0 at the centre (terraced)."""
    h = np.full((9, 9), 3.0)
    h[0, :] = h[-1, :] = h[:, 0] = h[:, -1] = 0.0  # outside the rim: drains
    yy, xx = np.mgrid[-3:4, -3:4]
    h[1:8, 1:8] = 3.0
    h[2:7, 2:7] = np.maximum(np.abs(yy[1:6, 1:6]), np.abs(xx[1:6, 1:6])) * 1.0  # 0,1,2 rings
    return h


def test_max_depth_analytic():
    h = pit()
    # floor: centre 0, ring of 8 at 1, ring of 16 at 2; spill level 3
    r = rain_fill(hm_of(h), max_depth_m=1.5)
    d = r.depth_m
    assert d[4, 4] == pytest.approx(1.5)
    assert d[3, 3] == pytest.approx(0.5)
    assert d[2, 2] == 0.0 and d[0, 0] == 0.0
    assert r.wetted_fraction == pytest.approx(9 / 81)
    assert r.water_volume_m3_per_m2 == pytest.approx((1.5 + 8 * 0.5) / 81)
    full = rain_fill(hm_of(h), max_depth_m=10.0)
    np.testing.assert_allclose(full.depth_m, rain_fill(hm_of(h)).depth_m)
    assert full.meta["all_full"]


def test_water_film_exact_inverse():
    h = pit()
    capacity = (3 + 8 * 2 + 16 * 1) / 81
    # a film that fills up to level 1.5 stores (1.5 + 8*0.5)/81
    r = rain_fill(hm_of(h), water_film_m=(1.5 + 8 * 0.5) / 81)
    assert r.meta["max_depth_m"] == pytest.approx(1.5)
    assert r.meta["capacity_m3_per_m2"] == pytest.approx(capacity)
    big = rain_fill(hm_of(h), water_film_m=2 * capacity)
    assert big.meta["all_full"]
    assert big.water_volume_m3_per_m2 == pytest.approx(capacity)


def test_unmeasured_points_are_transparent_and_stay_nan():
    h = pit()
    hb = h.copy()
    hb[4, 4] = np.nan  # dropout at the bottom: pit still fills to its rim
    r = rain_fill(hm_of(hb))
    assert np.isnan(r.depth_m[4, 4]) and np.isnan(r.wet.heights_m[4, 4])
    assert r.wet.unmeasured[4, 4]
    np.testing.assert_allclose(r.wet.heights_m[2:7, 2:7][~np.isnan(hb[2:7, 2:7])], 3.0)
    assert r.wetted_fraction == pytest.approx(24 / 80)  # per measured point
    hr = h.copy()
    hr[1, 4] = np.nan  # dropout in the rim: never a barrier, water drains to 2
    r2 = rain_fill(hm_of(hr))
    assert np.nanmax(r2.wet.heights_m[2:7, 2:7]) == pytest.approx(2.0)
    hd = h.copy()
    hd[0, 4] = np.nan  # dropout on the border next to the rim: pit unaffected
    np.testing.assert_allclose(rain_fill(hm_of(hd)).wet.heights_m[2:7, 2:7], 3.0)


surfaces = arrays(
    np.float64,
    st.tuples(st.integers(3, 14), st.integers(3, 14)),
    elements=st.floats(-1.0, 1.0, allow_nan=False, width=32),
)


@settings(max_examples=60, deadline=None)
@given(surfaces)
def test_properties_of_full_fill(h):
    f4 = full_fill(h, 4)
    f8 = full_fill(h, 8)
    assert np.all(f4 >= h) and np.all(f8 >= h)  # wet >= dry
    assert np.all(f8 <= f4)  # 8-conn <= 4-conn
    np.testing.assert_array_equal(full_fill(f4, 4), f4)  # idempotent
    np.testing.assert_array_equal(full_fill(f8, 8), f8)
    np.testing.assert_array_equal(f4, priority_flood(h, 4))


@settings(max_examples=40, deadline=None)
@given(surfaces, st.sampled_from([4, 8]), st.floats(0.0, 1.0))
def test_properties_of_limited_water(h, conn, frac):
    hm = hm_of(h)
    dry = rain_fill(hm, conn, max_depth_m=0.0)
    assert np.all(dry.depth_m == 0) and dry.water_volume_m3_per_m2 == 0
    full = rain_fill(hm, conn)
    caps = np.linspace(0, 2.5, 11)
    vols = [rain_fill(hm, conn, max_depth_m=c).water_volume_m3_per_m2 for c in caps]
    assert np.all(np.diff(vols) >= -1e-12)  # monotone in the cap
    assert vols[-1] == pytest.approx(full.water_volume_m3_per_m2)  # range 2 < 2.5: all full
    w = frac * full.water_volume_m3_per_m2
    film = rain_fill(hm, conn, water_film_m=w)
    assert film.water_volume_m3_per_m2 == pytest.approx(w, rel=1e-9, abs=1e-12)
    d = film.meta["max_depth_m"]
    assert np.all(film.depth_m <= full.depth_m + 1e-12)
    if w > 0 and frac < 1:  # smallest such cap
        less = rain_fill(hm, conn, max_depth_m=max(d - 1e-6, 0.0)).water_volume_m3_per_m2
        assert less < w


def test_bad_arguments():
    hm = hm_of(pit())
    with pytest.raises(ValueError):
        rain_fill(hm, connectivity=6)
    with pytest.raises(ValueError):
        rain_fill(hm, max_depth_m=1.0, water_film_m=0.1)
    with pytest.raises(ValueError):
        rain_fill(hm, max_depth_m=-1.0)


# --- the command ------------------------------------------------------------------------------


def test_cli_rain_fill(tmp_path, capsys):
    import json

    from pipelines.cli.app import main
    from roadscan.level import level

    h = 1e-3 * unit_fourier_surface(48, seed=3)
    h[10:12, 20:23] = np.nan  # a dropout
    f = tmp_path / "scan.npy"
    np.save(f, h * 1e3)  # millimetres, no spacing in the file
    out = tmp_path / "rf"
    assert (
        main(
            [
                "rain-fill",
                str(f),
                "--out",
                str(out),
                "--spacing",
                "1e-4",
                "--units",
                "mm",
                "--water-film",
                "2e-5",
            ]
        )
        == 0
    )
    assert "wetted" in capsys.readouterr().out
    js = json.loads((out / "rainfill.json").read_text())
    expect = rain_fill(level(HeightMap(h, 1e-4, 1e-4)), water_film_m=2e-5)
    assert js["connectivity"] == 4
    assert js["water_film_m"] == 2e-5
    assert js["water_volume_m3_per_m2"] == pytest.approx(2e-5, rel=1e-9)
    assert js["wetted_fraction"] == pytest.approx(expect.wetted_fraction)
    assert js["max_depth_m"] == pytest.approx(expect.meta["max_depth_m"])
    depth = np.load(out / "depth.npy")
    wet = np.load(out / "wet.npy")
    assert np.isnan(depth[10, 20]) and np.isnan(wet[10, 20])
    np.testing.assert_allclose(depth, expect.depth_m, atol=1e-15)
    np.testing.assert_allclose(wet, expect.wet.heights_m, atol=1e-15)

    assert main(["rain-fill", str(f), "--out", str(out), "--spacing", "1e-4", "--max-depth", "-1"]) == 2
    assert "--max-depth" in capsys.readouterr().err
    with pytest.raises(SystemExit):  # argparse: mutually exclusive
        main(["rain-fill", str(f), "--out", str(out), "--max-depth", "1", "--water-film", "1"])
    assert main(["rain-fill", str(tmp_path / "none.npy"), "--out", str(out), "--spacing", "1e-4"]) == 2
