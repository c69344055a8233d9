"""Output folders appear whole or not at all (issue 14): atomic_output_dir, umask, kill -9."""

import json
import os
import random
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, fourier_surface

from pipelines.cli.app import main
from roadscan.errors import InputError
from roadscan.io.atomic import OLD_TAG, TMP_TAG, atomic_output_dir, atomic_write_text, recover_output_dir


def _hidden(folder):
    return sorted(p.name for p in Path(folder).rglob(".*"))


def test_new_folder_appears_only_on_success(tmp_path):
    target = tmp_path / "out"
    with pytest.raises(RuntimeError):
        with atomic_output_dir(target) as tmp:
            (tmp / "a.csv").write_text("1\n")
            raise RuntimeError("boom")
    assert not target.exists()
    assert list(tmp_path.iterdir()) == []  # temporary folder removed
    with atomic_output_dir(target) as tmp:
        (tmp / "a.csv").write_text("1\n")
        (tmp / "summary.json").write_text("{}")
        assert not target.exists()  # nothing visible before the end
    assert sorted(p.name for p in target.iterdir()) == ["a.csv", "summary.json"]
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_old_set_replaced_as_a_whole(tmp_path):
    target = tmp_path / "out"
    target.mkdir()
    (target / "summary.json").write_text('{"old": 1}')
    (target / "stale.png").write_text("old figure")
    with atomic_output_dir(target) as tmp:
        (tmp / "summary.json").write_text('{"new": 1}')
    assert sorted(p.name for p in target.iterdir()) == ["summary.json"]
    assert json.loads((target / "summary.json").read_text()) == {"new": 1}
    with pytest.raises(KeyboardInterrupt):  # a failed run leaves the old set alone
        with atomic_output_dir(target) as tmp:
            (tmp / "summary.json").write_text('{"newer": 1}')
            raise KeyboardInterrupt
    assert json.loads((target / "summary.json").read_text()) == {"new": 1}
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_refuses_files_and_foreign_folders(tmp_path):
    f = tmp_path / "file.txt"
    f.write_text("x")
    for bad in (f, f / "sub"):
        with pytest.raises(InputError, match="file"):
            with atomic_output_dir(bad):
                pass
    foreign = tmp_path / "photos"
    foreign.mkdir()
    (foreign / "holiday.jpg").write_text("x")
    with pytest.raises(InputError, match="not empty"):
        with atomic_output_dir(foreign):
            pass
    assert (foreign / "holiday.jpg").exists()
    inside = tmp_path / "d"
    inside.mkdir()
    (inside / "report.html").write_text("x")
    (inside / "scan.npy").write_text("x")
    with pytest.raises(InputError, match="contains the input"):
        with atomic_output_dir(inside, inputs=[inside / "scan.npy"]):
            pass


def test_recovery_restores_a_set_aside_old_set(tmp_path):
    # a kill between "rename old aside" and "rename new in" (fallback path)
    target = tmp_path / "out"
    old = tmp_path / f".out{OLD_TAG}abc"
    old.mkdir()
    (old / "summary.json").write_text("{}")
    tmp = tmp_path / f".out{TMP_TAG}def"
    tmp.mkdir()
    (tmp / "psd.csv").write_text("partial")
    recover_output_dir(target)
    assert sorted(p.name for p in target.iterdir()) == ["summary.json"]
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_outputs_respect_umask(tmp_path):
    old = os.umask(0o022)
    try:
        atomic_write_text(tmp_path / "a.txt", "x")
        with atomic_output_dir(tmp_path / "d") as tmp:
            (tmp / "b.txt").write_text("y")
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "a.txt").stat().st_mode) == 0o644
    assert stat.S_IMODE((tmp_path / "d").stat().st_mode) == 0o755


def test_analyse_several_inputs_all_or_nothing(tmp_path):
    good = tmp_path / "good.npy"
    np.save(good, fourier_surface(64, 5e-5, 0.8, 3e-4, seed=1))
    flat = tmp_path / "flat.npy"
    np.save(flat, np.full((64, 64), 2e-3))
    out = tmp_path / "D"
    assert (
        main(["analyse", str(good), str(flat), "--spacing", "5e-5", "--out", str(out), "--no-friction"]) == 2
    )
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["flat.npy", "good.npy"]


def test_analyse_output_files_have_normal_permissions(tmp_path):
    good = tmp_path / "good.npy"
    np.save(good, fourier_surface(64, 5e-5, 0.8, 3e-4, seed=1))
    old = os.umask(0o022)
    try:
        assert (
            main(["analyse", str(good), "--spacing", "5e-5", "--out", str(tmp_path / "o"), "--no-friction"])
            == 0
        )
    finally:
        os.umask(old)
    for p in (tmp_path / "o").iterdir():
        assert stat.S_IMODE(p.stat().st_mode) == 0o644, p


def _run_set(folder):
    return sorted(p.name for p in folder.iterdir())


def test_sigkill_at_random_moments_never_mixes_sets(tmp_path):
    """kill -9 ``analyse`` at random moments: the folder holds the old or the new set."""
    scan = tmp_path / "scan.npy"
    np.save(scan, fourier_surface(192, 5e-5, 0.8, 3e-4, seed=2))
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    base = [
        sys.executable,
        "-m",
        "pipelines.cli",
        "analyse",
        str(scan),
        "--spacing",
        "5e-5",
        "--out",
        str(out),
    ]
    old_cmd = base + ["--no-friction"]  # old set: no mu.csv / mu.png
    new_cmd = base + ["--velocities", "1e-3:1e1:5"]  # new set: with mu.csv / mu.png
    t0 = time.monotonic()
    subprocess.run(new_cmd, env=env, check=True, capture_output=True)
    t_full = time.monotonic() - t0
    new_set = _run_set(out)
    subprocess.run(old_cmd, env=env, check=True, capture_output=True)
    old_set = _run_set(out)
    assert old_set != new_set and "mu.csv" in new_set
    rng = random.Random(14)
    kills = 0
    for _ in range(4):
        p = subprocess.Popen(new_cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(rng.uniform(0.3, 1.0) * t_full)
        if p.poll() is None:
            os.kill(p.pid, signal.SIGKILL)
            kills += 1
        p.wait()
        now = _run_set(out)
        assert now in (old_set, new_set), now
        assert _hidden(out) == []
        summary = json.loads((out / "summary.json").read_text())
        assert ("friction" in summary) == (now == new_set)
        if now == new_set:  # back to the old set
            subprocess.run(old_cmd, env=env, check=True, capture_output=True)
            assert _run_set(out) == old_set
            assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "scan.npy"]  # cleaned
    assert kills >= 2
    assert _survivors(str(scan)) == []  # no figure helper outlives a killed command


def _survivors(marker, wait_s=5.0):
    """Pids of processes (Linux /proc) whose command line names ``marker``, after up to
    ``wait_s`` for them to end."""
    t0 = time.monotonic()
    while True:
        pids = []
        for d in Path("/proc").glob("[0-9]*"):
            try:
                if marker in (d / "cmdline").read_bytes().decode(errors="replace"):
                    pids.append(int(d.name))
            except OSError:
                continue
        if not pids or time.monotonic() - t0 > wait_s:
            return pids
        time.sleep(0.1)
