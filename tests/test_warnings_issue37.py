"""Warnings of issue 37: no --units hint for files that state their units; an unusual spacing
warned once; a peak mu at the end of the speed range is a warning; an MPD that is not valid per
ISO 13473-1 is a warning naming the rule its segments failed and the option that relaxes it
(and that option, given, does relax it)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


def _run(argv, capsys):
    from pipelines.cli.app import main

    rc = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return rc, cap.out, cap.err


@pytest.mark.parametrize("name", ["plu-1.plu", "opd-1.opd", "sur-2.sur", "al3d-1.al3d"])
def test_no_units_hint_for_files_that_state_their_units(tmp_path, capsys, formats_dir, name):
    out = tmp_path / "o"
    rc, _, err = _run(["analyse", formats_dir / name, "--out", out, "--no-figures"], capsys)
    assert rc == 0, err
    s = json.loads((out / "summary.json").read_text())
    implausible = [w for w in s["warnings"] if "peak mu" in w]
    assert implausible  # these microscope scans give a mu no road gives...
    for w in s["warnings"]:  # ...and the cause named is never a --units slip
        assert "--units" not in w and "units (" not in w, w
    assert "--units" not in err
    assert any("unit the file states" in w for w in implausible)


def test_units_hint_kept_for_a_file_without_units(tmp_path, capsys):
    """The hint still comes where the unit was a guess: a .npy of heights in mm read as m."""
    from pipelines.chain.provenance import implausible_cause

    line = implausible_cause(0.01, rms_height_m=0.4, slope=0.05, units_from_file=False)
    assert "--units" in line
    line = implausible_cause(0.01, rms_height_m=0.4, slope=0.05, units_from_file=True)
    assert "--units" not in line and "unit the file states" in line


def test_unusual_spacing_is_warned_once(tmp_path, capsys):
    rng = np.random.default_rng(1)
    np.save(tmp_path / "m.npy", rng.normal(size=(64, 64)) * 1e-3)
    for spacing in ("0.02", "0.02,0.03"):
        out = tmp_path / f"o{spacing}"
        rc, _, err = _run(
            [
                "analyse",
                tmp_path / "m.npy",
                "--spacing",
                spacing,
                "--units",
                "m",
                "--out",
                out,
                "--no-figures",
                "--no-friction",
            ],
            capsys,
        )
        assert rc == 0, err
        lines = [ln for ln in err.splitlines() if "unusual for a road scan" in ln]
        assert len(lines) == 1, err
        assert "m.npy" in lines[0]
        s = json.loads((out / "summary.json").read_text())
        assert sum("unusual for a road scan" in w for w in s["warnings"]) == 1


def test_peak_at_the_end_of_the_speed_range_is_a_warning(tmp_path, capsys):
    """The sample's peak is at 10 m/s: a speed range ending at 0.1 m/s has its largest mu at
    the last speed, which is a warning (not only peak_note) naming --velocities."""
    out = tmp_path / "o"
    rc, _, err = _run(
        [
            "analyse",
            ROOT / "sample_scans" / "asphalt.x3p",
            "--out",
            out,
            "--no-figures",
            "--velocities",
            "1e-3:1e-1:9",
        ],
        capsys,
    )
    assert rc == 0, err
    s = json.loads((out / "summary.json").read_text())
    mu = np.loadtxt(out / "mu.csv", delimiter=",", skiprows=1)[:, 1]
    assert int(np.argmax(mu)) == mu.size - 1 and s["friction"]["peak_at_edge"]
    w = [x for x in s["warnings"] if "no peak in the speed range" in x]
    assert len(w) == 1 and "--velocities" in w[0]
    assert "--velocities" in err
    # and a range holding the peak warns nothing of the kind
    out2 = tmp_path / "o2"
    rc, _, err = _run(
        ["analyse", ROOT / "sample_scans" / "asphalt.x3p", "--out", out2, "--no-figures"], capsys
    )
    s2 = json.loads((out2 / "summary.json").read_text())
    assert not s2["friction"]["peak_at_edge"]
    assert not any("no peak in the speed range" in x for x in s2["warnings"])


def test_invalid_mpd_names_the_rule_and_the_option_that_relaxes_it(tmp_path, capsys, shared_data):
    f = shared_data / "profiles" / "captif" / "20211011_aylesbury_dec_station_1.dat"
    out = tmp_path / "o"
    rc, _, err = _run(["analyse", f, "--out", out, "--no-figures", "--no-friction"], capsys)
    assert rc == 0, err
    s = json.loads((out / "summary.json").read_text())
    assert s["mpd_valid"] is False
    w = [x for x in s["warnings"] if "ISO 13473-1" in x and "MPD" in x]
    assert len(w) == 1
    assert "spike rule" in w[0] and "too few valid segments" in w[0]
    alpha = s["mpd_spike_alpha_to_pass"]
    assert f"--mpd-spike-alpha {alpha:g}" in w[0]
    # the named option, given, does give an MPD valid per ISO 13473-1
    out2 = tmp_path / "o2"
    rc, _, err = _run(
        ["analyse", f, "--out", out2, "--no-figures", "--no-friction", "--mpd-spike-alpha", f"{alpha:g}"],
        capsys,
    )
    s2 = json.loads((out2 / "summary.json").read_text())
    assert s2["mpd_valid"] is True and s2["etd_m"] is not None
    assert not any("not valid per ISO 13473-1" in x for x in s2["warnings"])
    html = (out / "report.html").read_text()
    assert "spike rule" in html  # the report lists it too


def test_dropout_rule_named_when_dropouts_decide():
    from pipelines.jobs.texture.mpd import invalid_mpd_warning
    from roadscan.heightmap import Profile
    from roadscan.texture_depth import mpd_segments

    rng = np.random.default_rng(3)
    dx = 0.25e-3
    x = np.arange(int(0.8 / dx)) * dx
    h = 1e-3 * np.sin(2 * np.pi * x / 0.012) + 1e-5 * rng.standard_normal(x.size)
    lost = (x % 0.1) < 0.03  # 30 % of every 100 mm segment
    h[lost] = np.nan
    seg = mpd_segments(Profile(h, dx, np.isnan(h), "p"))
    assert seg.n_valid == 0 and seg.failed_rules() == {"dropouts": seg.n_total, "spikes": 0}
    line = invalid_mpd_warning("p", seg)
    assert "dropout rule" in line and "no option relaxes the dropout rule" in line
    assert "--mpd-spike-alpha" not in line


def test_friction_command_warns_a_peak_at_the_end_of_the_speed_range(tmp_path, capsys):
    out = tmp_path / "mu.csv"
    rc, _, err = _run(
        [
            "friction",
            "--psd",
            ROOT / "sample_scans" / "asphalt_psd.csv",
            "--velocities",
            "1e-3:1e-1:9",
            "--out",
            out,
        ],
        capsys,
    )
    assert rc == 0, err
    s = json.loads((tmp_path / "mu_summary.json").read_text())
    assert s["peak_at_edge"]
    assert sum("no peak in the speed range" in w and "--velocities" in w for w in s["warnings"]) == 1
