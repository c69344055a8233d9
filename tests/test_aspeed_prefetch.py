"""The texture figures computed beside the chain equal the direct computation; they are handed
over only for the surface they were started on; an error in the thread reaches the caller."""

import numpy as np
import pytest

import pipelines.jobs.texture.prefetch as tp
from pipelines.jobs.texture.prefetch import TextureFigures
from roadscan.heightmap import HeightMap
from roadscan.iso25178 import texture_parameters


@pytest.fixture(autouse=True)
def small_maps_threaded(monkeypatch):
    monkeypatch.setattr(tp, "MIN_POINTS", 1)


def _map(seed, n=96):
    """A random map; the tests lower MIN_POINTS so that small maps use the thread."""
    z = np.random.default_rng(seed).standard_normal((n, n + 7)) * 1e-4
    z[5, 9] = np.nan
    return HeightMap(z, 1e-4, 1e-4)


def test_background_figures_equal_the_direct_ones():
    a, b = _map(0), _map(1)
    pre = TextureFigures()
    pre.start(a)
    assert pre._thread is not None or (__import__("os").cpu_count() or 1) < 2
    assert pre.get(a) == texture_parameters(a)
    assert pre.get(b) == texture_parameters(b)  # another surface: computed on the spot
    assert pre.get(b) != pre.get(a)


def test_an_error_in_the_thread_is_raised_by_get(monkeypatch):
    import roadscan.iso25178 as iso

    def boom(obj):
        raise RuntimeError("boom")

    monkeypatch.setattr(iso, "texture_parameters", boom)
    a = _map(2)
    pre = TextureFigures()
    pre.start(a)
    with pytest.raises(RuntimeError, match="boom"):
        pre.get(a)


def test_background_spectrum_equals_the_direct_one():
    from roadscan.texture_spectrum import texture_spectrum

    a = _map(3, n=400)
    pre = TextureFigures("x")
    pre.start(a)
    got, want = pre.spectrum(a, "x"), texture_spectrum(a, direction="x")
    assert got.level_dB.size and np.array_equal(got.level_dB, want.level_dB)
    other = pre.spectrum(a, "y")  # another direction: computed on the spot
    assert np.array_equal(other.level_dB, texture_spectrum(a, direction="y").level_dB)
    assert pre.get(a) == texture_parameters(a)


def _short_scan(seed):
    """A 60 mm x 20 mm map at 0.1 mm (shorter than one 100 mm segment) with dropouts."""
    rng = np.random.default_rng(seed)
    z = rng.standard_normal((200, 600)) * 3e-4
    z[rng.random(z.shape) < 0.03] = np.nan
    return HeightMap(z, 1e-4, 1e-4)


def test_background_short_depth_for_that_scan_and_settings_only(monkeypatch):
    import os

    from roadscan import texture_depth as td

    if (os.cpu_count() or 1) < 2:
        pytest.skip("no second thread on one core")
    src = _short_scan(4)
    levelled = HeightMap(src.heights_m - 1e-5, src.dx_m, src.dy_m)
    pre = TextureFigures("x")
    with tp.levelled_from(levelled, src, {"spike_alpha": 3.5}):
        pre.start(levelled)
    want = td.short_segment_depth(src, spike_alpha=3.5)
    assert want[0] is not None
    pre._short_done.wait()  # the thread took the real function
    calls = []
    monkeypatch.setattr(td, "short_segment_depth", lambda obj, **kw: calls.append(kw) or ("spot", None, ""))
    assert pre.short_depth(src, {"spike_alpha": 3.5}) == want  # from the thread
    assert not calls
    copy = HeightMap(src.heights_m.copy(), src.dx_m, src.dy_m)
    assert pre.short_depth(copy, {"spike_alpha": 3.5})[0] == "spot"  # equal, not the same
    assert pre.short_depth(src, None)[0] == "spot"  # other settings
    assert calls == [{"spike_alpha": 3.5}, {}]


def test_no_background_short_depth_along_y_or_for_long_rows():
    src = _short_scan(5)
    pre = TextureFigures("y")  # rows along y: transposed by the caller
    pre.start(src, src)
    assert pre._source is None
    long_rows = HeightMap(np.zeros((20, 1100)), 1e-4, 1e-4)  # 110 mm rows: an MPD
    pre = TextureFigures("x")
    pre.start(long_rows, long_rows)
    assert pre._source is None


def test_an_error_of_the_short_depth_is_raised_by_short_depth(monkeypatch):
    import roadscan.texture_depth as td

    def boom(obj, **kw):
        raise RuntimeError("short boom")

    monkeypatch.setattr(td, "short_segment_depth", boom)
    src = _short_scan(6)
    pre = TextureFigures("x")
    pre.start(src, src)
    with pytest.raises(RuntimeError, match="short boom"):
        pre.short_depth(src)
    assert pre.get(src) == texture_parameters(src)  # the figures are still handed over


def test_lattice_prepared_ahead_gives_the_same_spectrum_and_anisotropy():
    from roadscan import anisotropy as an
    from roadscan import rings
    from roadscan.inpaint import fill_unmeasured
    from roadscan.spectrum import anisotropy, psd_area

    m, _ = fill_unmeasured(_map(7, n=130))
    rings._ring_runs.cache_clear()
    an._sector_runs.cache_clear()
    thread = tp.prepare_lattice_ahead(m)
    if thread is not None:
        thread.join()
    assert rings._ring_runs.cache_info().currsize == 1 or thread is None
    spec, spec2d = psd_area(m)
    aniso = anisotropy(spec2d)
    if thread is not None:
        assert rings._ring_runs.cache_info().hits == 1
        assert an._sector_runs.cache_info().hits == 1
    rings._ring_runs.cache_clear()
    an._sector_runs.cache_clear()
    spec_b, spec2d_b = psd_area(m)
    assert np.array_equal(spec.C_m4, spec_b.C_m4) and np.array_equal(spec.q_per_m, spec_b.q_per_m)
    assert anisotropy(spec2d_b) == aniso


def test_short_depth_read_ahead_for_that_scan_with_default_settings_only(monkeypatch):
    from roadscan import texture_depth as td

    src = _short_scan(8)
    thread = tp.prepare_lattice_ahead(src)
    if thread is None:
        pytest.skip("no second thread on one core")
    thread.join()
    want = td.short_segment_depth(src)
    monkeypatch.setattr(td, "short_segment_depth", lambda obj, **kw: ("spot", None, ""))
    pre = TextureFigures("x")
    pre.start(src, src)
    assert pre._source is None  # read ahead already: not done again
    assert pre.short_depth(src) == want
    assert pre.short_depth(src, {"spike_alpha": 3.5})[0] == "spot"
    assert pre.short_depth(HeightMap(src.heights_m, src.dx_m, src.dy_m))[0] == "spot"
