"""The fast paths of the texture set give the results of slow, independent computations:
prominences of every maximum against a union-find over the points (rough and quantised
surfaces, ties included), the autocorrelation against direct sums of products, and the MPD
with its segment table from one pass against the separate calls."""

import numpy as np
import pytest

from roadscan.areal_features import feature_parameters, prominences
from roadscan.areal_spatial import MAX_POINTS, autocorrelation, spatial_parameters


def _union_find_prominences(z):
    """Independent: points from the highest down in the order (z, flattened index); a point
    joins the components of its already-added 8 neighbours; where two meet, the lower one's
    summit gets (its height - the point's height). Returns {summit: prominence}."""
    ny, nx = z.shape
    flat = z.ravel()
    order = np.lexsort((np.arange(flat.size), flat))[::-1]
    parent = np.full(flat.size, -1, dtype=np.int64)
    rank = np.empty(flat.size, np.int64)
    rank[order[::-1]] = np.arange(flat.size)
    summit, prom = {}, {}

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i in order.tolist():
        parent[i] = i
        summit[i] = i
        r, c = divmod(i, nx)
        roots = set()
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                rr, cc = r + dr, c + dc
                if (dr or dc) and 0 <= rr < ny and 0 <= cc < nx and parent[rr * nx + cc] >= 0:
                    roots.add(find(rr * nx + cc))
        if not roots:
            prom[i] = np.inf  # a new maximum
            continue
        roots = sorted(roots, key=lambda k: rank[summit[k]])
        top = roots[-1]
        for k in roots[:-1]:  # the lower components end here
            prom[summit[k]] = flat[summit[k]] - flat[i]
            parent[k] = top
        parent[i] = top
    return prom


@pytest.mark.parametrize("kind", ["rough", "quantised", "smooth"])
def test_prominences_match_a_union_find_over_the_points(kind):
    from scipy.ndimage import gaussian_filter

    rng = np.random.default_rng({"rough": 1, "quantised": 2, "smooth": 3}[kind])
    z = rng.normal(size=(90, 110))
    if kind == "smooth":
        z = gaussian_filter(z, 2.0)
    if kind == "quantised":  # many equal heights: plateaus, flat saddles
        z = np.round(gaussian_filter(z, 1.0) * 4) / 4
    summits, prom = prominences(z)
    ref = _union_find_prominences(z)
    assert sorted(ref) == summits.tolist()
    expect = np.array([ref[s] for s in summits.tolist()])
    assert np.array_equal(np.isinf(prom), np.isinf(expect))
    fin = np.isfinite(expect)
    np.testing.assert_allclose(prom[fin], expect[fin], rtol=0, atol=1e-12)


def test_pits_are_the_peaks_of_the_reversed_surface():
    from scipy.ndimage import gaussian_filter

    z = gaussian_filter(np.random.default_rng(4).normal(size=(120, 100)), 1.5)
    up, down = feature_parameters(z, 1e-4, 1e-4), feature_parameters(-z, 1e-4, 1e-4)
    assert up["S5v_m"] == pytest.approx(down["S5p_m"])
    assert up["S5p_m"] == pytest.approx(down["S5v_m"])
    # pits counted on -z as peaks: the same count as the significant peaks of -z
    T = 0.05 * float(np.ptp(z))
    ref = _union_find_prominences(-z)
    ny, nx = z.shape
    n = sum(1 for s, p in ref.items() if p >= T and 0 < s // nx < ny - 1 and 0 < s % nx < nx - 1)
    assert down["Spd_per_m2"] * (ny * 1e-4) * (nx * 1e-4) == pytest.approx(n)


def test_autocorrelation_matches_direct_sums():
    rng = np.random.default_rng(5)
    z = rng.normal(size=(23, 31))
    z -= z.mean()
    acf, _, _ = autocorrelation(z)
    hy, hx = 23 // 2, 31 // 2
    norm = (z * z).sum()
    for ty, tx in ((0, 0), (1, 0), (0, 3), (hy, hx), (-hy, hx), (5, -hx), (-3, -7)):
        a = z[max(ty, 0) : 23 + min(ty, 0), max(tx, 0) : 31 + min(tx, 0)]
        b = z[max(-ty, 0) : 23 + min(-ty, 0), max(-tx, 0) : 31 + min(-tx, 0)]
        assert acf[hy + ty, hx + tx] == pytest.approx((a * b).sum() / norm, abs=2e-6)


def test_large_map_short_sal_uses_the_central_window():
    """A map over MAX_POINTS whose Sal is short: Sal, Str and Std are those of the central
    window at full resolution (one ACF), and the note says so."""
    from roadscan.areal_spatial import MAX_SIDE

    n = int(np.ceil(np.sqrt(MAX_POINTS))) + 64
    from scipy.ndimage import gaussian_filter

    z = gaussian_filter(np.random.default_rng(6).normal(size=(n, n)), 2.0)
    r = spatial_parameters(z, 1e-4, 1e-4)
    assert "central" in r["spatial_note"]
    y0 = (n - MAX_SIDE) // 2
    w = spatial_parameters(z[y0 : y0 + MAX_SIDE, y0 : y0 + MAX_SIDE], 1e-4, 1e-4)
    assert r["Sal_m"] == pytest.approx(w["Sal_m"])
    assert r["Std_deg"] == pytest.approx(w["Std_deg"])


def test_mpd_and_segments_equal_the_separate_calls():
    from roadscan import roughness
    from roadscan.heightmap import HeightMap
    from roadscan.io import read
    from roadscan.texture_depth import mpd_and_segments, mpd_segments

    prof = read("sample_scans/captif_station_1_excerpt.dat")
    rng = np.random.default_rng(7)
    hm = HeightMap(rng.normal(scale=5e-4, size=(6, 2400)), 5e-5, 5e-5)
    short = HeightMap(rng.normal(scale=5e-4, size=(6, 300)), 5e-5, 5e-5)
    for obj, mpd_fn in (
        (prof, roughness.mean_profile_depth),
        (hm, roughness.mean_profile_depth_area),
        (short, roughness.mean_profile_depth_area),
    ):
        for settings in ({}, {"spike_alpha": 6.0}):
            mpd, note, seg = mpd_and_segments(obj, **settings)
            assert (mpd, note) == mpd_fn(obj, **settings)
            ref = mpd_segments(obj, **settings)
            if ref is None:
                assert seg is None
                continue
            assert seg.note == ref.note and seg.reason == ref.reason
            assert np.array_equal(seg.msd_m, ref.msd_m) and np.array_equal(seg.valid, ref.valid)
            assert (seg.mpd_m, seg.mpd_valid) == (ref.mpd_m, ref.mpd_valid)


def test_single_threaded_blas_restores_the_thread_count_and_the_fill_is_unchanged():
    from threadpoolctl import threadpool_info

    from roadscan._biharmonic import biharmonic_fill_values
    from roadscan.blas_threads import single_threaded_blas

    rng = np.random.default_rng(8)
    h = rng.normal(size=(60, 70))
    bad = rng.random(h.shape) < 0.2
    bad[20:35, 30:50] = True  # one large cluster (block elimination)

    def counts():
        return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]

    before = counts()
    with single_threaded_blas():
        assert all(n == 1 for n in counts())
    assert counts() == before
    a = biharmonic_fill_values(h, bad)
    from skimage.restoration import inpaint_biharmonic

    ref = inpaint_biharmonic(h - h[~bad].mean(), bad) + h[~bad].mean()
    np.testing.assert_allclose(a, ref[bad], atol=1e-10 * np.ptp(h))
