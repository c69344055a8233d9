"""The phi table's cubic spline (friction.grids._NotAKnotSpline) against scipy's CubicSpline,
an independent implementation of the same not-a-knot spline (issue 13: written in the engine
so that every run does not pay for importing scipy.interpolate)."""

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from friction.grids import _NotAKnotSpline


@pytest.mark.parametrize("n", [4, 5, 9, 120, 700])
def test_same_spline_as_scipy(n):
    rng = np.random.default_rng(n)
    x = (np.arange(n) - n // 3) * (np.log(10.0) / 24)  # the table's lattice in ln x
    for y in (np.sin(3 * x) + x**2, rng.normal(size=n), np.log1p(np.exp(4 * x)) - 30):
        ref, ours = CubicSpline(x, y), _NotAKnotSpline(x, y)
        xi = np.concatenate([np.linspace(x[0], x[-1], 4001), x, x[:-1] + 0.37 * np.diff(x)])
        scale = np.max(np.abs(y))
        np.testing.assert_allclose(ours(xi), ref(xi), rtol=0, atol=1e-13 * scale)
        v0, d0, v1, d1 = ours.ends()
        assert v0 == pytest.approx(ref(x[0]), abs=1e-13 * scale)
        assert v1 == pytest.approx(ref(x[-1]), abs=1e-13 * scale)
        assert d0 == pytest.approx(ref(x[0], 1), abs=1e-12 * scale)
        assert d1 == pytest.approx(ref(x[-1], 1), abs=1e-12 * scale)


def test_cubics_are_reproduced_exactly():
    # not-a-knot reproduces any cubic; a wholly independent check of the end conditions
    x = np.linspace(-2.0, 3.0, 11) ** 3 / 5  # non-uniform nodes
    f = lambda t: 0.3 * t**3 - t**2 + 2 * t - 1  # noqa: E731
    s = _NotAKnotSpline(x, f(x))
    t = np.linspace(x[0], x[-1], 999)
    np.testing.assert_allclose(s(t), f(t), atol=1e-10)
    assert s.ends()[1] == pytest.approx(0.9 * x[0] ** 2 - 2 * x[0] + 2, rel=1e-9)


def test_needs_four_nodes():
    with pytest.raises(ValueError):
        _NotAKnotSpline([0.0, 1.0, 2.0], [0.0, 1.0, 0.0])
