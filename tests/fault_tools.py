"""Shared pieces of the fault suite (tests/test_faults_*.py, issue 22): small inputs, a runner
of ``pipelines.cli.app.main`` that captures the exit code and stderr, and the checks every fault
case ends with (no traceback, one line, nothing left behind, inputs unchanged)."""

from __future__ import annotations

import builtins
import contextlib
import errno
import hashlib
import io
import os
import sys
from pathlib import Path

import numpy as np
from conftest import ROOT, fourier_surface

DX = 1e-4


def small_scan(path, n=64, seed=1):
    """A 64 x 64 self-affine map [m] (rms 0.2 mm at 0.1 mm spacing) saved as ``.npy``."""
    np.save(path, fourier_surface(n, DX, 0.8, 2e-4, seed=seed))
    return Path(path)


def digest(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def snapshot(folder):
    """{relative path: sha256} of every file below ``folder`` (links not followed)."""
    folder = Path(folder)
    out = {}
    for p in sorted(folder.rglob("*")):
        if p.is_file() and not p.is_symlink():
            out[str(p.relative_to(folder))] = digest(p)
        elif p.is_symlink():
            out[str(p.relative_to(folder))] = "->" + os.readlink(p)
    return out


def hidden_leftovers(folder):
    """Temporary outputs a run left (``.*roadscan-tmp-*``, ``.*roadscan-old-*``, mkstemp's
    ``.<stem>.*`` files of an atomic write), anywhere below ``folder``; a finished campaign's
    sidecar (``.roadscan-batch.json``) is an output, not a leftover."""
    from pipelines.campaign.folder import SIDECAR

    return [
        str(p)
        for p in Path(folder).rglob(".*")
        if p.name != SIDECAR and ("roadscan-" in p.name or p.is_file())
    ]


def run_cli(capsys, argv):
    """``main(argv)`` in this process -> (exit code, stderr)."""
    from pipelines.cli.app import main

    capsys.readouterr()
    rc = main([str(a) for a in argv])
    return rc, capsys.readouterr().err


def assert_one_line_error(rc, err, code=2, words=()):
    """Exit ``code``; exactly one ``roadscan CMD: error:`` line (warnings printed before it are
    allowed: each is one line too), naming each of ``words``; no traceback."""
    assert rc == code, (rc, err)
    assert "Traceback" not in err, err
    lines = err.splitlines()
    assert lines and all(line.startswith("roadscan") for line in lines), err
    errors = [line for line in lines if ": error: " in line]
    assert len(errors) == 1 and errors[0] == lines[-1], err
    assert "internal error" not in err, err
    for w in words:
        assert w.lower() in errors[0].lower(), (w, err)


def roadscan_cmd():
    """The console script when installed beside this interpreter, else ``python -m``."""
    script = Path(sys.executable).with_name("roadscan")
    if script.exists():
        return [str(script)]
    return [sys.executable, "-m", "pipelines.cli"]


def cli_env():
    return {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}


@contextlib.contextmanager
def disk_full_for(monkeypatch, suffix):
    """Inside the block, opening a file whose name ends with ``suffix`` for writing fails with
    ENOSPC (the file is created, as on a real full disk); plain ``open`` is back afterwards."""
    real_open = builtins.open

    def full_open(file, mode="r", *a, **k):
        fh = real_open(file, mode, *a, **k)
        if "w" in str(mode) and str(file).endswith(suffix):
            fh.close()
            raise OSError(errno.ENOSPC, "No space left on device")
        return fh

    monkeypatch.setattr(builtins, "open", full_open)
    monkeypatch.setattr(io, "open", full_open)
    try:
        yield
    finally:
        monkeypatch.setattr(builtins, "open", real_open)
        monkeypatch.setattr(io, "open", real_open)
