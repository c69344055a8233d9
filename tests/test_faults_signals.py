"""Fault suite, signal family (issue 22): SIGINT, SIGTERM and SIGHUP sent to a running
``roadscan analyse`` at several moments (while it starts, while the hidden output folder is
being filled). Every case: exit code 128 + signal, one line on stderr, no traceback, no hidden
temporary folder left, the input unchanged, the output folder absent or the complete earlier
set."""

from __future__ import annotations

import signal
import subprocess
import time

import numpy as np
import pytest
from conftest import fourier_surface
from fault_tools import DX, cli_env, digest, hidden_leftovers, roadscan_cmd, snapshot

SIGNALS = [signal.SIGINT, signal.SIGTERM, signal.SIGHUP]


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    d = tmp_path_factory.mktemp("signals")
    np.save(d / "scan.npy", fourier_surface(512, DX, 0.8, 2e-4, seed=3))  # runs ~1 s
    return d


def _start(work, out):
    cmd = roadscan_cmd() + [
        "analyse",
        str(work / "scan.npy"),
        "--spacing",
        str(DX),
        "--out",
        str(out),
        "--velocities",
        "1e-3:1e1:9",
    ]
    return subprocess.Popen(cmd, env=cli_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _wait_for_tmp(work, p, timeout=60):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout and p.poll() is None:
        if any(".roadscan-tmp-" in q.name for q in work.iterdir()):
            return True
        time.sleep(0.01)
    return False


def _check(work, p, sig, out, earlier):
    _, err = p.communicate(timeout=120)
    if p.returncode == 0:
        return False  # finished before the signal: nothing to check
    assert p.returncode == 128 + sig, (sig, p.returncode, err)
    # the stop adds one line; warnings the command printed before the signal came may precede it
    lines = err.splitlines()
    assert "Traceback" not in err and lines and "interrupted" in lines[-1], err
    assert all(": warning: " in line for line in lines[:-1]), err
    assert hidden_leftovers(work) == []
    if earlier is None:
        assert not out.exists()
    else:
        assert snapshot(out) == earlier
    return True


@pytest.mark.parametrize("sig", SIGNALS, ids=[s.name for s in SIGNALS])
def test_signal_while_starting_and_while_writing(work, sig):
    if sig == getattr(signal, "SIGHUP", None) and signal.getsignal(sig) == signal.SIG_IGN:
        pytest.skip(
            "SIGHUP is ignored here (run under nohup): the command keeps it ignored, "
            "as test_ignored_sighup_stays_ignored checks"
        )
    before = digest(work / "scan.npy")
    out = work / f"out_{sig.name}"
    checked = 0
    p = _start(work, out)  # 1. while importing / reading
    time.sleep(0.4)
    p.send_signal(sig)
    checked += _check(work, p, sig, out, None)
    p = _start(work, out)  # 2. while the hidden output folder is filled
    if _wait_for_tmp(work, p):
        p.send_signal(sig)
    checked += _check(work, p, sig, out, None)
    assert checked >= 1
    assert digest(work / "scan.npy") == before


def test_sigterm_keeps_the_earlier_set(work):
    """An earlier complete output stays as it was when a new run over it is stopped."""
    out = work / "out_keep"
    subprocess.run(
        roadscan_cmd()
        + [
            "analyse",
            str(work / "scan.npy"),
            "--spacing",
            str(DX),
            "--out",
            str(out),
            "--no-figures",
            "--no-friction",
        ],
        env=cli_env(),
        check=True,
        capture_output=True,
    )
    earlier = snapshot(out)
    p = _start(work, out)
    if _wait_for_tmp(work, p):
        p.send_signal(signal.SIGTERM)
    if not _check(work, p, signal.SIGTERM, out, earlier):
        pytest.skip("the run finished before SIGTERM arrived")


def test_ignored_sighup_stays_ignored(work):
    """``nohup``: a SIGHUP the parent ignores does not stop the run."""
    import os

    out = work / "out_nohup"
    cmd = roadscan_cmd() + [
        "analyse",
        str(work / "scan.npy"),
        "--spacing",
        str(DX),
        "--out",
        str(out),
        "--no-figures",
        "--no-friction",
    ]
    p = subprocess.Popen(
        cmd,
        env=cli_env(),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGHUP, signal.SIG_IGN),
    )
    time.sleep(0.5)
    if p.poll() is None:
        os.kill(p.pid, signal.SIGHUP)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 0, err
    assert (out / "summary.json").is_file()


def test_interrupt_in_process_is_one_line_and_130(tmp_path, capsys, monkeypatch):
    """A KeyboardInterrupt (or Terminated) raised anywhere inside a command: 130 (143), one
    line, the temporary folder removed."""
    from fault_tools import run_cli, small_scan

    from pipelines.cli.signals import Terminated
    from pipelines.jobs.analyse import job as analyse_mod

    scan = small_scan(tmp_path / "s.npy")
    for exc, code in (
        (KeyboardInterrupt(), 130),
        (Terminated(signal.SIGTERM), 143),
        (Terminated(signal.SIGHUP), 129),
    ):

        def boom(*a, _exc=exc, **k):
            raise _exc

        monkeypatch.setattr(analyse_mod, "run_analysis", boom)
        rc, err = run_cli(capsys, ["analyse", scan, "--spacing", DX, "--no-figures", "--out", tmp_path / "o"])
        assert rc == code and err.count("\n") == 1 and "interrupted" in err, (rc, err)
        assert sorted(p.name for p in tmp_path.iterdir()) == ["s.npy"]


@pytest.mark.parametrize(
    "sig, delay, group",
    [(signal.SIGTERM, 1.2, False), (signal.SIGINT, 2.5, True)],
    ids=["SIGTERM-starting-cluster", "SIGINT-to-the-group-while-workers-start"],
)
def test_campaign_interrupted_while_the_cluster_starts_or_runs(work, sig, delay, group):
    """Ctrl-C or SIGTERM at any moment of a campaign (Dask cluster starting, scans running,
    cluster stopping), to the command alone or, as a terminal's Ctrl-C does, to its whole
    process group (the Dask workers too): one line, exit 128 + n, never a traceback nor exit 0,
    no hidden folder left."""
    import os

    out = work / f"camp_{sig.name}"
    cmd = roadscan_cmd() + [
        "batch",
        str(work / "scan.npy"),
        str(work / "scan.npy"),
        "--spacing",
        str(DX),
        "--workers",
        "1",
        "--out",
        str(out),
    ]
    p = subprocess.Popen(
        cmd, env=cli_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=group
    )
    time.sleep(delay)
    if group:
        os.killpg(p.pid, sig)
    else:
        p.send_signal(sig)
    _, err = p.communicate(timeout=120)
    if p.returncode == 0:
        pytest.skip("the campaign finished before the signal")
    assert p.returncode == 128 + sig, (p.returncode, err)
    assert "Traceback" not in err and err.strip().count("\n") == 0 and "interrupted" in err, err
    assert hidden_leftovers(work) == []


@pytest.mark.parametrize("own", [True, False], ids=["command", "library"])
def test_a_signal_after_the_work_finished_keeps_the_exit_code(own):
    """Once the command's outputs are in place (``work_finished``), a SIGINT has nothing left
    to stop: the command ends with its own code. A program that did not hand its process to
    the command (a notebook calling ``main(argv)``) keeps Python's KeyboardInterrupt."""
    import sys

    code = (
        "import os, signal, sys, time\n"
        "from pipelines.cli.signals import own_the_process, work_finished\n"
        f"{'own_the_process()' if own else 'pass'}\n"
        "work_finished()\n"
        "os.kill(os.getpid(), signal.SIGINT)\n"
        "time.sleep(0.2)\n"
        "sys.exit(3)\n"
    )
    r = subprocess.run(
        [sys.executable, "-c", code], env=cli_env(), capture_output=True, text=True, timeout=60
    )
    if own:
        assert r.returncode == 3 and r.stderr == "", (r.returncode, r.stderr)
    else:
        assert r.returncode != 3 and "KeyboardInterrupt" in r.stderr, (r.returncode, r.stderr)
