"""Texture outputs of one scan and the reader's units (pipelines.jobs.texture.outputs,
pipelines.output.units; issue 21)."""

import argparse

import numpy as np
import pytest

from pipelines.jobs.texture import outputs as to
from pipelines.output.units import length, quantity, sig3
from roadscan.errors import InputError
from roadscan.heightmap import HeightMap, Profile


def _args(*argv):
    p = argparse.ArgumentParser()
    to.add_texture_options(p)
    return p.parse_args(list(argv))


def test_options_parsed_and_checked():
    st = to.texture_settings_from_args(
        _args("--friction-measurement", "0.45@30", "--ifi-constants", "0.045,0.925")
    )
    assert (st.friction, st.slip_speed_kmh, st.ifi_constants, st.direction) == (
        0.45,
        30.0,
        (0.045, 0.925, 0.0),
        "x",
    )
    st = to.texture_settings_from_args(
        _args("--direction", "y", "--friction-measurement", "0.3@65", "--ifi-constants", "0.1,0.9,0.02")
    )
    assert st.direction == "y" and st.ifi_constants == (0.1, 0.9, 0.02)
    for bad in (
        ("--friction-measurement", "0.45@30"),
        ("--ifi-constants", "1,2"),
        ("--friction-measurement", "0.45", "--ifi-constants", "1,2"),
        ("--friction-measurement", "0.45@-3", "--ifi-constants", "1,2"),
        ("--friction-measurement", "0.45@30", "--ifi-constants", "1"),
        ("--friction-measurement", "0.45@30", "--ifi-constants", "a,b"),
    ):
        with pytest.raises(InputError) as err:
            to.texture_settings_from_args(_args(*bad))
        assert "--" in str(err.value)


class _Analysis:
    def __init__(self, obj, mpd_m, note=""):
        self.source = self.levelled = obj
        self.mpd_m, self.mpd_note = mpd_m, note
        self.is_profile = isinstance(obj, Profile)
        self.name = "synthetic"


def test_keys_follow_formulas_from_mpd():
    dx = 0.5e-3
    z = 1e-3 * np.sin(2 * np.pi * np.arange(4000) * dx / 20e-3)
    an = _Analysis(Profile(z, dx), 1.234e-3)
    st = to.TextureSettings(friction=0.5, slip_speed_kmh=20.0, ifi_constants=(0.05, 0.9, 0.01))
    keys, ts = to.texture_keys(an, st)
    assert keys["etd_m"] == 0.2e-3 + 0.8 * 1.234e-3
    assert keys["ifi_speed_constant_kmh"] == 14.2 + 89.7 * 1.234e-3 * 1e3
    sp = keys["ifi_speed_constant_kmh"]
    assert keys["ifi_F60"] == pytest.approx(0.05 + 0.9 * 0.5 * np.exp((20 - 60) / sp) + 0.01 * 1.234)
    assert set(keys["texture_level_dB"]) == {f"{v:g}" for v in ts.nominal_mm}
    assert keys["texture_level_dB"]["20"] == pytest.approx(20 * np.log10(1e-3 / np.sqrt(2) / 1e-6), abs=0.5)
    assert "msd_short_m" not in keys and "texture_direction" not in keys


def test_short_area_gets_msd_short_never_mpd():
    dx = 0.1e-3
    z = 0.5e-3 * np.sin(2 * np.pi * np.arange(600) * dx / 10e-3)
    an = _Analysis(HeightMap(np.tile(z, (4, 1)), dx, dx), None, "no MPD: rows are 60.0 mm long")
    keys, _ = to.texture_keys(an, to.TextureSettings(direction="x"))
    assert keys["etd_m"] is None and keys["ifi_speed_constant_kmh"] is None
    assert keys["msd_short_baseline_m"] == pytest.approx(0.060)
    assert 0.4e-3 < keys["msd_short_m"] < 0.55e-3  # peaks of a 0.5 mm sine, slope removed
    assert "not ISO" in keys["msd_short_note"] and "mpd_m" not in keys
    assert keys["texture_direction"] == "x"


def test_csv_header_and_bar_chart(tmp_path):
    dx = 0.2e-3
    z = 1e-3 * np.sin(2 * np.pi * np.arange(10000) * dx / 50e-3)
    from roadscan.texture_spectrum import texture_spectrum

    ts = texture_spectrum(Profile(z, dx))
    to.write_texture_csv(tmp_path / "texture_spectrum.csv", ts)
    lines = (tmp_path / "texture_spectrum.csv").read_text().splitlines()
    assert lines[0] == "centre_wavelength_m,band_lo_m,band_hi_m,level_dB"
    data = np.loadtxt(tmp_path / "texture_spectrum.csv", delimiter=",", skiprows=1)
    assert np.allclose(data[:, 0], ts.centre_m) and np.allclose(data[:, 3], ts.level_dB)
    png = to.draw_texture_spectrum(to.texture_picture(ts), tmp_path / "t.png", "t")
    assert png.stat().st_size > 1000
    html = to.texture_table_html(ts)
    assert "50" in html and "dB" in html


def test_units_format():
    assert length(0.0032755905236328256) == "3.28 mm"
    assert length(0.0003974) == "397 µm"
    assert length(2.53e-3) == "2.53 mm"  # not "2.53e+03 um"
    assert length(1.849e-11) == "0.0185 nm"
    assert sig3(2530.4) == "2530" and sig3(0.0123) == "0.0123" and sig3(99.96) == "100"
    assert quantity("rms_height_m", 3.974e-4) == "397 µm"
    assert quantity("texture_dB", 45.26) == "45.3 dB"
    assert quantity("ifi_speed_constant_kmh", 308.4) == "308 km/h"
    assert "λ = 6.28 mm" in quantity("q_roll_per_m", 1000.0)


def test_many_dropouts_warned_in_summary_warnings():
    from pipelines.checks import validate

    dx = 0.5e-3
    z = 1e-3 * np.sin(2 * np.pi * np.arange(4000) * dx / 20e-3)
    bad = np.zeros(z.size, bool)
    bad[::4] = bad[1::4] = True  # half the points missing
    validate.reset_warnings()
    to.texture_keys(_Analysis(Profile(z, dx, unmeasured=bad), 1e-3))
    assert any("dropouts" in w and "dB low" in w for w in validate.warnings_list())
    validate.reset_warnings()
    to.texture_keys(_Analysis(Profile(z, dx), 1e-3))
    assert not any("dropouts" in w for w in validate.warnings_list())
