"""Any interrupted campaign resumes: ``roadscan batch`` killed with SIGKILL at several moments
(while its Dask cluster starts, while workers write scan folders, after the first scans are
done; the command alone or its whole process group), then ``--resume``: exit 0, every scan
done, results identical to an uninterrupted run, nothing hidden left. Plus what a kill can
leave, built by hand: temporary and set-aside scan folders, the table's temporary file, a
folder a live writer still holds."""

from __future__ import annotations

import csv
import fcntl
import os
import signal
import subprocess
import time

import numpy as np
import pytest
from conftest import fourier_surface
from fault_tools import DX, cli_env, hidden_leftovers, roadscan_cmd

from pipelines.campaign.folder import SIDECAR, campaign_leftovers, earlier_campaign, recover_campaign

N = 4
#: per-scan outputs compared byte for byte with the uninterrupted run
COMPARED = ("summary.json", "psd.csv", "mu.csv")


@pytest.fixture(scope="module")
def scans(tmp_path_factory):
    d = tmp_path_factory.mktemp("killed")
    src = d / "scans"
    src.mkdir()
    for i in range(N):
        np.save(src / f"k{i}.npy", fourier_surface(96, DX, 0.7 + 0.05 * i, 2e-4, seed=300 + i))
    ref = d / "ref"
    r = subprocess.run(_cmd(src, ref), env=cli_env(), capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return src, ref


def _cmd(src, out, *extra):
    return roadscan_cmd() + [
        "batch",
        *(str(src / f"k{i}.npy") for i in range(N)),
        "--spacing",
        str(DX),
        "--workers",
        "2",
        "--out",
        str(out),
        *extra,
    ]


def _rows(out):
    with open(out / "campaign.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    return [{k: v for k, v in r.items() if k != "dir"} for r in rows]


def _wait(p, ready, timeout=120):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout and p.poll() is None:
        if ready():
            return True
        time.sleep(0.005)
    return False


def _group_gone(pgid, timeout=30):
    """Wait until no process of the killed command's session is left (its Dask workers die
    with it); True when gone."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.05)
    return False


def _has_tmp(out):
    return out.is_dir() and any(".roadscan-tmp-" in p.name for p in out.iterdir())


def _has_done(out):
    return out.is_dir() and any((p / SIDECAR).is_file() for p in out.iterdir() if p.is_dir())


MOMENTS = {
    "right-after-start": lambda out: True,
    "cluster-starting": lambda out: out.is_dir(),
    "workers-writing": _has_tmp,
    "first-scan-done": _has_done,
}


@pytest.mark.parametrize(
    "moment, group",
    [
        ("right-after-start", False),
        ("cluster-starting", False),
        ("workers-writing", False),
        ("workers-writing", True),
        ("first-scan-done", True),
    ],
)
def test_sigkill_then_resume_finishes_identically(scans, tmp_path, moment, group):
    src, ref = scans
    out = tmp_path / "out"
    p = subprocess.Popen(
        _cmd(src, out),
        env=cli_env(),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    reached = _wait(p, lambda: MOMENTS[moment](out))
    if group:
        os.killpg(p.pid, signal.SIGKILL)
    else:
        p.send_signal(signal.SIGKILL)
    p.wait(timeout=60)
    if p.returncode == 0 or not reached:
        pytest.skip(f"the campaign finished before {moment}")
    assert p.returncode == -signal.SIGKILL
    _group_gone(p.pid)  # its Dask workers die with it (a live one is left to finish)
    left = [x.name for x in campaign_leftovers(out)] if out.exists() else []
    r = subprocess.run(_cmd(src, out, "--resume"), env=cli_env(), capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, (left, r.stderr)
    assert "Traceback" not in r.stderr
    assert hidden_leftovers(out) == [], left
    assert _rows(out) == _rows(ref)
    for i in range(N):
        for name in COMPARED:
            assert (out / f"k{i}" / name).read_bytes() == (ref / f"k{i}" / name).read_bytes(), (i, name)


# --------------------------------------------------------------------- the states, built by hand
def _scan_folder(path, text):
    path.mkdir()
    (path / "summary.json").write_text(text)
    (path / SIDECAR).write_text("{}")


def test_leftovers_are_cleaned_and_an_old_set_put_back(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    half = out / ".k0.roadscan-tmp-ab12cd34"  # a scan killed mid-write
    half.mkdir()
    (half / "summary.json").write_text('{"half')
    _scan_folder(out / ".k1.roadscan-old-ef56gh78", "old k1")  # set aside, new one not in yet
    (out / ".campaign.abcd_123.csv").write_text("file,label")  # the table's temporary file
    (out / ".report.zz99yy88.html").write_text("<html>")
    (out / ".campaign_distributions.png").write_bytes(b"\x89PNG")  # the report's figure
    (out / "..campaign_chainage.k2j4h5g6.png").write_bytes(b"\x89PNG")
    assert earlier_campaign(out)  # only a killed campaign's leftovers
    removed = recover_campaign(out)
    assert sorted(os.listdir(out)) == ["k1"]  # the old complete set is back
    assert (out / "k1" / "summary.json").read_text() == "old k1"
    assert len(removed) == 6 and campaign_leftovers(out) == []


def test_a_held_temporary_folder_and_user_files_are_left_alone(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    held = out / ".k2.roadscan-tmp-live0001"
    held.mkdir()
    (out / ".notes.txt").write_text("mine")  # a user's hidden file: not ours
    fd = os.open(held, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)  # a live writer holds it
        assert not earlier_campaign(out)  # .notes.txt: not only leftovers
        recover_campaign(out)
        assert held.is_dir() and (out / ".notes.txt").read_text() == "mine"
    finally:
        os.close(fd)
    recover_campaign(out)
    assert not held.exists() and (out / ".notes.txt").exists()


def test_an_empty_or_user_folder_is_no_campaign(tmp_path):
    assert not earlier_campaign(tmp_path / "missing")
    (tmp_path / "data.txt").write_text("x")
    assert not earlier_campaign(tmp_path)
    assert campaign_leftovers(tmp_path) == []
