"""Fault suite, race family (issue 22): two runs writing the same output at once. Both finish
(exit 0), the output is one complete set (either run's, never a mix), nothing hidden is left,
the inputs are unchanged."""

from __future__ import annotations

import subprocess

import numpy as np
import pytest
from conftest import fourier_surface
from fault_tools import DX, cli_env, digest, hidden_leftovers, roadscan_cmd


@pytest.fixture(scope="module")
def scans(tmp_path_factory):
    d = tmp_path_factory.mktemp("races")
    for seed in (1, 2):
        np.save(d / f"s{seed}.npy", fourier_surface(128, DX, 0.8, 2e-4, seed=seed))
    return d


def _both(cmds):
    ps = [
        subprocess.Popen(
            roadscan_cmd() + c, env=cli_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
        )
        for c in cmds
    ]
    return [(p.wait(timeout=180), p.communicate()[1]) for p in ps]


def test_two_analyse_runs_into_one_folder(scans):
    out = scans / "same"
    before = [digest(scans / "s1.npy"), digest(scans / "s2.npy")]
    cmds = [
        [
            "analyse",
            str(scans / f"s{k}.npy"),
            "--spacing",
            str(DX),
            "--no-figures",
            "--no-friction",
            "--out",
            str(out),
        ]
        for k in (1, 2)
    ]
    for rc, err in _both(cmds):
        assert rc == 0 and "Traceback" not in err, err
    import json

    from pipelines.cli.app import main

    name = json.loads((out / "summary.json").read_text())["name"]
    ref = scans / "ref"
    assert main(cmds[int(name[-1]) - 1][:-1] + [str(ref)]) == 0  # that run alone
    # one run's complete set, never a mix: every file as that run writes it alone
    assert sorted(p.name for p in out.iterdir()) == sorted(p.name for p in ref.iterdir())
    assert (out / "psd.csv").read_bytes() == (ref / "psd.csv").read_bytes()
    assert hidden_leftovers(scans) == []
    assert [digest(scans / "s1.npy"), digest(scans / "s2.npy")] == before


def test_two_writers_of_one_file(scans):
    target = scans / "one.x3p"
    cmds = [["convert", str(scans / f"s{k}.npy"), str(target), "--spacing", str(DX)] for k in (1, 2)]
    for rc, err in _both(cmds):
        assert rc == 0 and "Traceback" not in err, err
    from roadscan.io import read

    got = read(target).heights_m
    assert any(np.array_equal(got, np.load(scans / f"s{k}.npy")) for k in (1, 2))
    mu = scans / "mu.csv"
    cmds = [
        [
            "friction",
            "--self-affine",
            f"H=0.{k},h0=2e-4,q0=300,q1=3e4",
            "--velocities",
            "1e-2,1",
            "--out",
            str(mu),
        ]
        for k in (7, 8)
    ]
    for rc, err in _both(cmds):
        assert rc == 0 and "Traceback" not in err, err
    import json

    summary = json.loads((scans / "mu_summary.json").read_text())
    rows = mu.read_text().splitlines()
    assert rows[0].startswith("v_m_per_s,mu") and len(rows) == 3
    mus = [float(r.split(",")[1]) for r in rows[1:]]
    assert max(mus) == pytest.approx(summary["mu_peak"], rel=1e-5)  # the CSV and summary of one run
    assert hidden_leftovers(scans) == []


def test_clean_up_leaves_a_folder_in_use_alone(tmp_path):
    """The lock itself: a temporary folder held by a run survives another run's clean-up; one
    left by a killed run (no lock) is removed."""
    import os

    from roadscan.io.atomic import TMP_TAG, _hold, recover_output_dir

    busy, stale = tmp_path / f".out{TMP_TAG}busy", tmp_path / f".out{TMP_TAG}stale"
    busy.mkdir()
    stale.mkdir()
    fd = _hold(busy)
    try:
        recover_output_dir(tmp_path / "out")
        assert busy.is_dir() and not stale.exists()
    finally:
        os.close(fd)
    recover_output_dir(tmp_path / "out")
    assert not busy.exists()
