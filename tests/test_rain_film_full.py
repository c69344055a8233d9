"""A water film larger than what the depressions hold fills every depression to its spill level,
and the result says so (``all_full``): the cap lowest + d equalled the spill level only to an
ulp, and an exact comparison said "not full" (report-review finding, issue 21)."""

import numpy as np
from conftest import unit_fourier_surface

from roadscan.heightmap import HeightMap
from roadscan.rain import rain_fill


def test_film_above_capacity_is_all_full():
    hm = HeightMap(1e-3 * unit_fourier_surface(64, seed=2), 1e-4, 1e-4)
    full = rain_fill(hm)
    capacity = full.meta["capacity_m3_per_m2"]
    assert full.meta["all_full"]
    film = rain_fill(hm, water_film_m=2 * capacity)
    assert film.meta["all_full"]
    np.testing.assert_allclose(film.wet.heights_m, full.wet.heights_m, rtol=0, atol=1e-15)


def test_film_below_capacity_is_not_all_full():
    hm = HeightMap(1e-3 * unit_fourier_surface(64, seed=2), 1e-4, 1e-4)
    capacity = rain_fill(hm).meta["capacity_m3_per_m2"]
    part = rain_fill(hm, water_film_m=0.3 * capacity)
    assert not part.meta["all_full"]
    assert part.water_volume_m3_per_m2 <= 0.3 * capacity * (1 + 1e-6)
