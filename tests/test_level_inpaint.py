"""Levelling, spike removal and filling of unmeasured points."""

import numpy as np
import pytest

from roadscan import HeightMap, Profile
from roadscan.inpaint import fill_unmeasured
from roadscan.level import level, remove_spikes


def _grid(ny=60, nx=80, d=1e-4):
    y, x = np.mgrid[0:ny, 0:nx] * d
    return x, y


@pytest.mark.parametrize("degree", [0, 1, 2, 3])
def test_level_removes_polynomial_ignoring_unmeasured(degree):
    x, y = _grid()
    rng = np.random.default_rng(degree)
    form = (
        1e-3
        + 0.05 * x * (degree >= 1)
        - 0.02 * y * (degree >= 1)
        + 3.0 * x * y * (degree >= 2)
        + 40.0 * x**3 * (degree >= 3)
    )
    bad = rng.random(x.shape) < 0.2
    h = form.copy()
    h[bad] = 1.0  # garbage under the mask must be ignored
    out = level(HeightMap(h, 1e-4, 1e-4, unmeasured=bad), degree)
    assert np.array_equal(out.unmeasured, bad)
    assert np.all(np.isnan(out.heights_m[bad]))
    assert np.max(np.abs(out.heights_m[~bad])) < 1e-12
    assert out.meta["levelled_degree"] == degree


def test_level_leaves_residual_orthogonal_to_plane():
    x, y = _grid()
    rng = np.random.default_rng(1)
    h = rng.standard_normal(x.shape) * 1e-5 + 0.01 * x + 2e-3
    out = level(HeightMap(h, 1e-4, 1e-4), 1).heights_m
    for basis in (np.ones_like(x), x, y):
        assert abs(np.sum(out * basis)) < 1e-12 * np.sum(np.abs(basis)) + 1e-15


def test_level_profile():
    x = np.arange(500) * 1e-4
    h = 0.02 * x + 1e-3 + 1e-6 * np.sin(x * 300)
    h[10:20] = np.nan
    out = level(Profile(h, 1e-4), 1)
    ok = ~out.unmeasured
    xr = x[ok] - x[ok].mean()
    assert abs(np.mean(out.heights_m[ok])) < 1e-15
    assert abs(np.sum(out.heights_m[ok] * xr)) < 1e-15
    assert out.unmeasured[10:20].all()


def test_remove_spikes_finds_injected_spikes_only():
    x, y = _grid(100, 100)
    h = 1e-4 * np.sin(x * 400) * np.cos(y * 300)
    spikes = np.zeros(h.shape, bool)
    spikes[[10, 50, 70], [20, 33, 90]] = True
    h2 = h + spikes * 5e-3
    out = remove_spikes(HeightMap(h2, 1e-4, 1e-4))
    assert np.array_equal(out.unmeasured, spikes)
    assert out.meta["spikes_removed"] == 3
    p = remove_spikes(Profile(h2[10], 1e-4))
    assert p.unmeasured[20] and p.unmeasured.sum() == 1


def test_fill_map_methods_accuracy():
    x, y = _grid(200, 200, 1e-4)
    h = 1e-4 * np.sin(x * 200) * np.cos(y * 150) + 0.01 * x
    rng = np.random.default_rng(3)
    bad = rng.random(h.shape) < 0.03
    bad[50:56, 60:66] = True
    hm = HeightMap(h, 1e-4, 1e-4, unmeasured=bad)
    for method, tol in (("biharmonic", 1e-3), ("ns", 2e-2)):
        filled, frac = fill_unmeasured(hm, method=method)
        assert not filled.unmeasured.any()
        assert frac == pytest.approx(bad.mean())
        assert np.array_equal(filled.heights_m[~bad], h[~bad])
        err = np.sqrt(np.mean((filled.heights_m[bad] - h[bad]) ** 2)) / np.std(h)
        assert err < tol, (method, err)
        assert filled.meta["fill_method"] == method
    with pytest.raises(ValueError):
        fill_unmeasured(hm, method="telea")


def test_fill_profile_linear_and_ends():
    h = np.arange(20, dtype=float) * 1e-5
    h[[0, 1, 7, 8, 9, 19]] = np.nan
    filled, frac = fill_unmeasured(Profile(h, 1e-4))
    expect = np.arange(20) * 1e-5
    expect[[0, 1]] = 2e-5
    expect[19] = 18e-5
    assert np.allclose(filled.heights_m, expect, rtol=0, atol=1e-18)
    assert frac == pytest.approx(6 / 20)


def test_fill_nothing_to_do():
    hm = HeightMap(np.ones((5, 5)), 1e-4, 1e-4)
    filled, frac = fill_unmeasured(hm)
    assert frac == 0 and np.array_equal(filled.heights_m, hm.heights_m)


def _global_biharmonic(h, bad):
    """The reference: one scikit-image solve over the whole map (as fill_unmeasured did)."""
    from skimage.restoration import inpaint_biharmonic

    ref = np.nanmean(np.where(bad, np.nan, h))
    return np.where(bad, inpaint_biharmonic(np.where(bad, ref, h) - ref, bad) + ref, h)


@pytest.mark.parametrize("direct_max", [1 << 22, 0], ids=["numpy-direct", "skimage-banded"])
def test_banded_fill_equals_one_global_solve(direct_max, monkeypatch):
    """fill_unmeasured solves the biharmonic system per dropout cluster with numpy (maps up to
    4 Mpx) or with scikit-image band by band (issue 14: memory); both must equal one global
    scikit-image solve: clusters crossing bands, dropouts on every edge, and a bowl whose
    filled bottom lies below every measured height of its band but above the map's minimum
    (the global clip range must be used, not the band's)."""
    import roadscan.inpaint as inpaint_mod

    monkeypatch.setattr(inpaint_mod, "DIRECT_MAX_POINTS", direct_max)
    ny, nx = 700, 48
    y, x = np.mgrid[0:ny, 0:nx].astype(float)
    h = 1e-6 * np.sin(x / 7.0) * np.cos(y / 11.0)
    h[20:30, 10:20] -= 1e-3  # the global minimum, top band
    bowl = ((x - 24) ** 2 + (y - 600) ** 2) * 1e-6
    h += np.where(np.hypot(x - 24, y - 600) < 12, bowl - 1.44e-4, 0.0)
    bad = np.hypot(x - 24, y - 600) < 4  # the bowl's bottom is missing
    bad[100:520, 30] = True  # one cluster across two bands
    bad[0, 5:9] = bad[-1, 40:44] = bad[300:304, 0] = bad[350:353, -1] = True
    rng = np.random.default_rng(5)
    bad |= rng.random(h.shape) < 0.01
    hm = HeightMap(h, 1e-4, 1e-4, unmeasured=bad)
    filled, _ = fill_unmeasured(hm)
    ref = _global_biharmonic(h, bad)
    assert (
        filled.heights_m[bad][np.argmin(np.abs(np.hypot(x - 24, y - 600)[bad]))]
        < h[300:700][~bad[300:700]].min()
    )  # the bowl case is exercised
    assert np.allclose(filled.heights_m, ref, rtol=0, atol=1e-12 * np.ptp(h))
    # a mask too dense for two free points in a band: the global solve is used
    dense = np.zeros((60, 40), bool)
    dense[:, ::2] = True  # every point next to a dropout
    g = h[:60, :40]
    f2, _ = fill_unmeasured(HeightMap(g, 1e-4, 1e-4, unmeasured=dense))
    assert np.allclose(f2.heights_m, _global_biharmonic(g, dense), rtol=0, atol=1e-12 * np.ptp(g))


def test_direct_biharmonic_equals_scikit_image_on_random_masks():
    """roadscan._biharmonic against one global scikit-image solve on random maps: scattered
    dropouts, blocks, rows with gaps inside a cluster, points at every edge and corner, and
    clusters above and below the batched-solve size."""
    from roadscan._biharmonic import SMALL, _clusters, biharmonic_fill_values

    rng = np.random.default_rng(11)
    sizes = []
    for _ in range(25):
        ny, nx = (int(v) for v in rng.integers(12, 90, 2))
        g = rng.normal(size=(ny, nx)).cumsum(0).cumsum(1) * 1e-4
        m = rng.random((ny, nx)) < rng.uniform(0.01, 0.3)
        m[rng.integers(0, ny, 3)[:, None], np.arange(nx)[None, :5]] = True
        m[:2, rng.integers(0, nx)] = True
        m[-1, -1] = m[0, 0] = True
        y0, x0 = rng.integers(0, ny - 8), rng.integers(0, nx - 9)
        m[y0 : y0 + rng.integers(2, 8), x0 : x0 + rng.integers(2, 9)] = True
        m[y0 + 1, :] |= rng.random(nx) < 0.5
        sizes.append(np.bincount(_clusters(m)).max())  # the largest cluster
        mine = biharmonic_fill_values(np.where(m, np.nan, g), m)
        assert np.allclose(mine, _global_biharmonic(g, m)[m], rtol=0, atol=1e-12 * np.ptp(g[~m]))
    assert min(sizes) <= SMALL < max(sizes)  # both solvers exercised


def test_direct_fill_falls_back_to_scikit_image_on_a_singular_block(monkeypatch):
    import roadscan._biharmonic as bh

    def singular(*a, **k):
        raise np.linalg.LinAlgError("Singular matrix")

    rng = np.random.default_rng(2)
    h = rng.normal(size=(40, 50)).cumsum(0).cumsum(1) * 1e-5
    bad = rng.random(h.shape) < 0.05
    hm = HeightMap(h, 1e-4, 1e-4, unmeasured=bad)
    direct, _ = fill_unmeasured(hm)
    monkeypatch.setattr(bh, "biharmonic_fill_values", singular)
    fallback, _ = fill_unmeasured(hm)
    assert np.allclose(fallback.heights_m, direct.heights_m, rtol=0, atol=1e-12 * np.ptp(h))
    assert np.allclose(fallback.heights_m, _global_biharmonic(h, bad), rtol=0, atol=1e-12 * np.ptp(h))
