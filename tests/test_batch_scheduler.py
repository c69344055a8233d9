"""``roadscan batch --scheduler``: a real ``dask scheduler`` and two ``dask worker`` processes."""

import csv
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, fourier_surface

from pipelines.cli.app import main

DASK = Path(sys.executable).with_name("dask")


@pytest.fixture
def cluster(tmp_path):
    if not DASK.exists():
        pytest.skip("dask CLI not installed beside the interpreter")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    sfile = tmp_path / "scheduler.json"
    procs = [
        subprocess.Popen(
            [
                str(DASK),
                "scheduler",
                "--scheduler-file",
                str(sfile),
                "--port",
                "0",
                "--no-dashboard",
                "--host",
                "127.0.0.1",
            ],
            env=env,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    ]
    try:
        for _ in range(300):
            if sfile.exists() and sfile.stat().st_size:
                break
            time.sleep(0.1)
        for _ in range(2):
            procs.append(
                subprocess.Popen(
                    [
                        str(DASK),
                        "worker",
                        "--scheduler-file",
                        str(sfile),
                        "--nthreads",
                        "1",
                        "--no-nanny",
                        "--no-dashboard",
                        "--resources",
                        "scan=1",
                    ],
                    env=env,
                    stdout=subprocess.DEVNULL,
                    stderr=subprocess.DEVNULL,
                )
            )
        from distributed import Client

        with Client(scheduler_file=str(sfile), timeout="30s") as c:
            c.wait_for_workers(2, timeout=60)
            address = c.scheduler.address
        yield address
    finally:
        for p in procs[::-1]:
            if p.poll() is None:
                p.terminate()
        for p in procs[::-1]:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()


def test_batch_on_an_existing_cluster(cluster, tmp_path):
    src = tmp_path / "scans"
    src.mkdir()
    for i in range(6):
        np.save(src / f"s{i}.npy", fourier_surface(64, 1e-4, 0.8, 2e-4, seed=60 + i))
    (src / "broken.npy").write_text("nope")
    out = tmp_path / "out"
    rc = main(
        [
            "batch",
            str(src / "*.npy"),
            "--spacing",
            "1e-4",
            "--no-friction",
            "--out",
            str(out),
            "--scheduler",
            cluster,
        ]
    )
    assert rc == 2
    with open(out / "campaign.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["status"] for r in rows] == ["error"] + ["ok"] * 6
    hosts = set()
    for r in rows[1:]:
        stem = Path(r["file"]).stem
        s = json.loads((out / stem / "summary.json").read_text())
        assert (float(r["hurst"]) if r["hurst"] else None) == s["hurst"]  # empty when null
        hosts.add(stem)
    assert len(hosts) == 6
    # identical to analyse in this process
    a = tmp_path / "a"
    assert main(["analyse", str(src / "s2.npy"), "--spacing", "1e-4", "--no-friction", "--out", str(a)]) == 0
    for name in ("summary.json", "psd.csv"):
        assert (a / name).read_bytes() == (out / "s2" / name).read_bytes()


def test_unreachable_scheduler_is_one_line(tmp_path, capsys):
    f = tmp_path / "a.npy"
    np.save(f, np.zeros((8, 8)))
    rc = main(
        [
            "batch",
            str(f),
            "--spacing",
            "1e-4",
            "--out",
            str(tmp_path / "o"),
            "--scheduler",
            "tcp://127.0.0.1:9",
        ]
    )
    assert rc == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--scheduler tcp://127.0.0.1:9" in err[0]
