"""The texture figures computed beside the chain equal the direct computation; they are handed
over only for the surface they were started on; an error in the thread reaches the caller."""
import numpy as np
import pytest

import pipelines.texture_prefetch as tp
from pipelines.texture_prefetch import TextureFigures
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
    assert pre.get(b) == texture_parameters(b)        # another surface: computed on the spot
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
    other = pre.spectrum(a, "y")                      # another direction: computed on the spot
    assert np.array_equal(other.level_dB, texture_spectrum(a, direction="y").level_dB)
    assert pre.get(a) == texture_parameters(a)
