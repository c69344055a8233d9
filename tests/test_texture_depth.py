"""ETD, IFI (ASTM E1960), short-baseline segment depth and the spike threshold that passes
(roadscan.texture_depth, issue 21)."""

import numpy as np
import pytest

from roadscan import roughness
from roadscan.heightmap import HeightMap, Profile
from roadscan.texture_depth import (
    estimated_texture_depth,
    ifi_f60,
    ifi_speed_constant,
    short_segment_depth,
    spike_alpha_to_pass,
)


def test_etd_and_speed_constant_formulas():
    assert estimated_texture_depth(None) is None and ifi_speed_constant(None) is None
    for mpd in (0.3e-3, 1.1e-3, 3.28e-3):
        assert estimated_texture_depth(mpd) == pytest.approx(0.2e-3 + 0.8 * mpd, rel=1e-12)
        assert ifi_speed_constant(mpd) == pytest.approx(14.2 + 89.7 * mpd * 1e3, rel=1e-12)


def test_f60_by_hand():
    # MPD 1.0 mm -> Sp = 103.9 km/h; FRS 0.40 at 30 km/h -> FR60 = 0.40 exp(-30 / 103.9)
    f60, sp, fr60 = ifi_f60(0.40, 30.0, 1.0e-3, A=0.045, B=0.925, C=0.01)
    assert sp == pytest.approx(103.9)
    assert fr60 == pytest.approx(0.40 * np.exp(-30 / 103.9))
    assert f60 == pytest.approx(0.045 + 0.925 * 0.40 * np.exp(-30 / 103.9) + 0.01 * 1.0)
    assert ifi_f60(0.4, 60.0, 1e-3, 0.0, 1.0)[0] == pytest.approx(0.4)  # S = 60: FR60 = FRS
    assert ifi_f60(0.4, 30.0, None, 0.0, 1.0) is None


def test_short_scan_gets_a_labelled_short_baseline_depth():
    dx = 0.1e-3
    z = 0.5e-3 * np.sin(2 * np.pi * np.arange(542) * dx / 10e-3)  # 54.2 mm
    prof = Profile(z, dx)
    assert roughness.mean_profile_depth(prof)[0] is None
    msd, base, note = short_segment_depth(prof)
    assert base == pytest.approx(54e-3)
    assert "not ISO 13473-1" in note and "54 mm segments" in note
    # a 10 mm sine of 0.5 mm amplitude: both half-segment peaks near +0.5 mm (the 2.4 mm
    # low-pass keeps most of it)
    assert 0.4e-3 < msd < 0.5e-3
    hm = HeightMap(np.tile(z, (5, 1)), dx, dx)
    msd_a, base_a, _ = short_segment_depth(hm)
    assert base_a == base and msd_a == pytest.approx(msd, rel=1e-9)
    assert short_segment_depth(Profile(z[:80], dx))[0] is None  # 8 mm: too short


def test_spike_alpha_that_passes():
    rng = np.random.default_rng(2)
    dx, n = 0.5e-3, 2000  # 1 m: 10 segments
    z = 0.3e-3 * np.sin(2 * np.pi * np.arange(n) * dx / 20e-3)
    spikes = rng.choice(n - 1, 120, replace=False)  # 6 % of points in spikes
    z[spikes] += 2.2e-3  # jumps of 4.4 intervals
    prof = Profile(z, dx)
    assert roughness.mean_profile_depth(prof)[0] is None
    alpha, iso = spike_alpha_to_pass(prof)
    assert iso and 3.0 < alpha <= 5.0
    assert roughness.mean_profile_depth(prof, spike_alpha=alpha)[0] is not None
    nv = roughness.segment_depths(z, dx, spike_alpha=alpha)["valid"].sum()
    nv_below = roughness.segment_depths(z, dx, spike_alpha=alpha - 0.1)["valid"].sum()
    assert nv >= 5 > nv_below
    # all segments full of dropouts: no alpha helps
    bad = np.zeros(n, bool)
    bad[::5] = bad[1::5] = bad[2::5] = True
    assert spike_alpha_to_pass(Profile(z, dx, unmeasured=bad)) == (None, False)


def test_spike_alpha_on_a_big_map_uses_a_row_sample():
    rng = np.random.default_rng(8)
    dx, n, ny = 0.5e-3, 400, 600  # 200 mm rows, 600 of them
    z = np.tile(0.3e-3 * np.sin(2 * np.pi * np.arange(n) * dx / 20e-3), (ny, 1))
    spikes = rng.random(z.shape) < 0.08
    z[spikes] += 2.2e-3  # jumps of 4.4 intervals
    hm = HeightMap(z, dx, dx)
    assert roughness.mean_profile_depth_area(hm)[0] is None
    alpha, iso = spike_alpha_to_pass(hm)
    assert iso and 3.0 < alpha <= 5.0
    res = roughness.segment_depths(z, dx, spike_alpha=alpha)
    assert res["valid"].mean() >= 0.45  # the whole map passes too
