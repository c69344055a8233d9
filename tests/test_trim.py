import numpy as np
import pytest

from roadscan.heightmap import Profile
from roadscan.trim import road_section


def test_plates_removed_and_road_kept():
    rng = np.random.default_rng(0)
    h = rng.normal(0, 1e-3, 4000)
    h[100:300] = 0.047  # left plate
    h[3700:3900] = 0.047  # right plate
    p = Profile(h, 1e-4)
    r = road_section(p, margin_m=1e-3)
    assert r.n == (3700 - 10) - (300 + 10)
    assert np.nanmax(r.heights_m) < 0.01
    np.testing.assert_array_equal(r.heights_m, h[310:3690])
    assert r.meta["trimmed_m"] == pytest.approx((0.031, 0.369))


def test_profile_without_plates_unchanged():
    p = Profile(np.sin(np.linspace(0, 20, 500)) * 1e-3, 1e-4)
    assert road_section(p) is p


def test_captif_file_trimmed(shared_data):
    from roadscan.io import read

    p = read(shared_data / "profiles/captif/20211011_aylesbury_dec_station_1.dat")
    r = road_section(p)
    assert 1.5 < r.length_m < p.length_m
    assert np.nanmax(r.heights_m) - np.nanmedian(r.heights_m) < 0.02
