"""Fault suite, plausible-but-wrong family (issue 22): an output that is one of the command's
inputs, for every command and every kind of input (scan, manifest and its entries, rubber TOML
and the data files it names, master curve, shift table, PSD, measured curve, raw DMA sweeps),
directly, through a link, or inside an output folder. Every case: exit code 2, one line, no
traceback, every file of the folder byte for byte as before, nothing hidden left."""

from __future__ import annotations

import os
import shutil

import numpy as np
import pytest
from conftest import ROOT
from fault_tools import DX, assert_one_line_error, hidden_leftovers, run_cli, small_scan, snapshot

SAMPLES = ROOT / "sample_scans"
FAST = ["--spacing", DX, "--no-figures", "--no-friction"]
SA = ["--self-affine", "H=0.8,h0=2e-4,q0=300,q1=3e4", "--velocities", "1e-2,1"]


@pytest.fixture
def ws(tmp_path):
    """A work folder: two scans, an earlier analyse output holding a scan, a PSD, a rubber TOML
    with its master curve and shift table, raw DMA sweeps, a measured curve, tiles and their
    manifest."""
    small_scan(tmp_path / "a.npy", seed=1)
    small_scan(tmp_path / "b.npy", seed=2)
    for name in ("freq_user_master.csv", "freq_user_master__shift_factors.csv", "freq_user_raw.csv"):
        shutil.copy(SAMPLES / "rubbers" / name, tmp_path / name)
    shutil.copy(SAMPLES / "asphalt_psd.csv", tmp_path / "psd.csv")
    shutil.copy(SAMPLES / "measured_mu_example.csv", tmp_path / "measured.csv")
    (tmp_path / "rubber.toml").write_text(
        'model = "master_curve"\nT_ref_C = -5.0\n[master_curve]\nfile = "freq_user_master.csv"\n'
        '[shift]\nkind = "table"\nfile = "freq_user_master__shift_factors.csv"\n'
    )
    tiles = tmp_path / "tiles"
    tiles.mkdir()
    for f in ("tile_r0_c0.npz", "tile_r0_c1.npz"):
        shutil.copy(SAMPLES / "tiles" / f, tiles / f)
    rows = [
        r
        for r in (SAMPLES / "tiles_manifest.csv").read_text().splitlines()
        if r.startswith("file") or "r0_c0" in r or "r0_c1" in r
    ]
    (tiles / "tiles.csv").write_text("\n".join(r.replace("tiles/", "") for r in rows) + "\n")
    done = tmp_path / "done"
    rc = __import__("pipelines.cli", fromlist=["main"]).main(
        ["analyse", str(tmp_path / "a.npy"), "--out", str(done), *map(str, FAST)]
    )
    assert rc == 0
    shutil.copy(tmp_path / "b.npy", done / "b.npy")  # a scan kept inside an output folder
    os.symlink(tmp_path / "a.npy", tmp_path / "link_to_a.npy")
    return tmp_path


def _cases(w):
    t = w / "tiles"
    return [
        # analyse and friends: the output folder is an input, holds one, or links to one
        ["analyse", w / "a.npy", "--out", w / "a.npy", *FAST],
        ["analyse", w / "done" / "b.npy", "--out", w / "done", *FAST],
        ["analyse", w / "a.npy", "--rubber", w / "done" / "b.npy", "--out", w / "done", "--spacing", DX],
        ["analyse", w / "a.npy", "--out", w / "link_to_a.npy", *FAST],
        ["rain-fill", w / "done" / "b.npy", "--spacing", DX, "--out", w / "done"],
        ["dry-vs-wet", w / "done" / "b.npy", "--spacing", DX, "--out", w / "done"],
        ["compare", w / "a.npy", w / "done" / "b.npy", "--spacing", DX, "--out", w / "done"],
        ["diagnose", "--measured", w / "done" / "psd.csv", "--psd", w / "psd.csv", "--out", w / "done"],
        ["diagnose", "--measured", w / "measured.csv", "--psd", w / "done" / "psd.csv", "--out", w / "done"],
        ["combine", w / "a.npy", w / "done" / "b.npy", "--spacing", DX, "--out", w / "done"],
        ["batch", w / "a.npy", "--spacing", DX, "--out", w / "a.npy"],
        # convert: the same file, directly or through a link
        ["convert", w / "a.npy", w / "a.npy", "--spacing", DX],
        ["convert", w / "a.npy", w / "link_to_a.npy", "--spacing", DX],
        # friction: mu.csv, its summary or its plot over the PSD, rubber, master curve, shift table
        ["friction", "--psd", w / "psd.csv", "--out", w / "psd.csv"],
        ["friction", *SA, "--rubber", w / "rubber.toml", "--out", w / "rubber.toml"],
        ["friction", *SA, "--rubber", w / "rubber.toml", "--out", w / "freq_user_master.csv"],
        ["friction", *SA, "--rubber", w / "rubber.toml", "--out", w / "freq_user_master__shift_factors.csv"],
        [
            "friction",
            *SA,
            "--master-curve",
            w / "freq_user_master.csv",
            "--reference-temperature",
            -5,
            "--shift-table",
            w / "freq_user_master__shift_factors.csv",
            "--out",
            w / "freq_user_master.csv",
        ],
        ["friction", "--psd", w / "psd_summary.json", "--out", w / "psd.csv"],
        # rubber master: the TOML or one of its data files over the raw sweeps
        [
            "rubber",
            "master",
            w / "freq_user_raw.csv",
            "--reference-temperature",
            20,
            "--out",
            w / "freq_user.toml",
        ],
        [
            "rubber",
            "master",
            w / "freq_user_raw.csv",
            "--reference-temperature",
            20,
            "--out",
            w / "freq_user_raw.csv",
        ],
        # stitch: the map over a tile or the manifest; its overlaps table over the manifest
        ["stitch", t / "tiles.csv", "--out", t / "tile_r0_c0.npz"],
        [
            "stitch",
            t / "tile_r0_c0.npz",
            t / "tile_r0_c1.npz",
            "--grid",
            "1x2",
            "--overlap",
            0.25,
            "--out",
            t / "tile_r0_c1.npz",
        ],
        ["stitch", t / "tiles.csv", "--out", t / "tiles.x3p"],
    ]


def test_no_command_writes_over_an_input(ws, capsys):
    (ws / "psd_summary.json").write_text((ws / "psd.csv").read_text())  # a PSD named like a summary
    (ws / "freq_user_raw_master.csv").write_text("f,E_stor,E_loss,T\n")  # would be written by case 2
    shutil.copy(ws / "freq_user_raw.csv", ws / "freq_user_shifted.csv")
    (ws / "tiles" / "tiles_overlaps.csv").write_text((ws / "tiles" / "tiles.csv").read_text())
    before = snapshot(ws)
    cases = _cases(ws)
    # rubber master FREQ_USER_RAW.csv --out freq_user.toml writes freq_user_shifted.csv: make the
    # raw file that one
    cases[19] = [
        "rubber",
        "master",
        ws / "freq_user_shifted.csv",
        "--reference-temperature",
        20,
        "--out",
        ws / "freq_user.toml",
    ]
    # stitch --out tiles.x3p writes tiles_overlaps.csv: make the manifest that one
    cases[-1] = ["stitch", ws / "tiles" / "tiles_overlaps.csv", "--out", ws / "tiles" / "tiles.x3p"]
    for argv in cases:
        rc, err = run_cli(capsys, argv)
        assert_one_line_error(rc, err)
        assert "input" in err.splitlines()[-1], (argv, err)
        assert snapshot(ws) == before, argv
        assert hidden_leftovers(ws) == [], argv


def test_a_rubber_toml_data_file_is_an_input_too(ws, capsys):
    """The master curve a TOML names is read, so no output may replace it, although no flag
    names it (analyse's output folder holding it)."""
    sub = ws / "done"
    shutil.copy(ws / "freq_user_master.csv", sub / "m.csv")
    shutil.copy(ws / "freq_user_master__shift_factors.csv", sub / "s.csv")
    toml = ws / "r2.toml"
    toml.write_text(
        'model = "master_curve"\nT_ref_C = -5.0\n[master_curve]\nfile = "done/m.csv"\n'
        '[shift]\nkind = "table"\nfile = "done/s.csv"\n'
    )
    before = snapshot(ws)
    rc, err = run_cli(
        capsys,
        [
            "analyse",
            ws / "a.npy",
            "--spacing",
            DX,
            "--no-figures",
            "--rubber",
            toml,
            "--velocities",
            "1e-2,1",
            "--out",
            sub,
        ],
    )
    assert_one_line_error(rc, err, words=["which this command read", "done"])
    assert snapshot(ws) == before and hidden_leftovers(ws) == []


def test_legitimate_runs_still_write(ws, capsys):
    """The checks refuse only real clashes: a new output beside the inputs is written."""
    for argv in (
        ["friction", "--psd", ws / "psd.csv", "--velocities", "1e-2,1", "--out", ws / "mu.csv"],
        ["convert", ws / "a.npy", ws / "a.x3p", "--spacing", DX],
        ["analyse", ws / "a.npy", "--out", ws / "done", *FAST],
    ):  # an earlier output replaced
        rc, err = run_cli(capsys, argv)
        assert rc == 0, (argv, err)
    assert (ws / "mu.csv").is_file() and (ws / "a.x3p").is_file()
    assert np.array_equal(np.load(ws / "a.npy"), np.load(ws / "link_to_a.npy"))


def test_refuse_overwrite_helper():
    """The one helper every command uses: same file by path, link or hard link; inside a folder."""
    import tempfile
    from pathlib import Path

    from roadscan.errors import InputError
    from roadscan.io.overwrite_guard import refuse_overwrite

    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        (d / "x").write_text("1")
        os.link(d / "x", d / "hard")
        os.symlink(d / "x", d / "soft")
        for out in (d / "x", d / "hard", d / "soft", d / "." / "x"):
            with pytest.raises(InputError, match="input"):
                refuse_overwrite([out], [d / "x"])
        with pytest.raises(InputError, match="contains the input"):
            refuse_overwrite([(d, True)], [d / "x"])
        refuse_overwrite([d / "y", (d / "sub", True)], [d / "x", d / "missing"])  # no clash: no error
        refuse_overwrite([d], [d / "x"])  # a file output named like the folder: no clash
