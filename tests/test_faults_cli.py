"""Fault suite, new-user family (issue 22): ``--version``, "did you mean" for a mistyped
command or option, one summary line of ``batch`` on success and on ``--resume``."""

from __future__ import annotations

import re
import subprocess

import pytest
from fault_tools import DX, cli_env, roadscan_cmd, small_scan


def _run(args):
    return subprocess.run(roadscan_cmd() + args, env=cli_env(), capture_output=True, text=True, timeout=120)


def test_version_from_package_metadata():
    from importlib import metadata

    r = _run(["--version"])
    assert r.returncode == 0 and r.stdout.strip() == f"roadscan {metadata.version('roadscan')}"


@pytest.mark.parametrize(
    "argv, suggestion",
    [
        (["analyze", "x.npy"], "'analyse'"),
        (["rainfill", "x.npy"], "'rain-fill'"),
        (["analyse", "x.npy", "--output", "o"], "--out"),
        (["analyse", "x.npy", "--out", "o", "--spacng", "1e-4"], "--spacing"),
        (["friction", "--psd", "p.csv", "--velocitys", "1,2"], "--velocities"),
        (["rubber", "mastr"], "'master'"),
        (["stitch", "a.csv", "--blend", "feathr", "--out", "o.x3p"], "'feather'"),
    ],
)
def test_did_you_mean(capsys, argv, suggestion):
    from pipelines.cli.app import main

    with pytest.raises(SystemExit) as exc:
        main(argv)
    err = capsys.readouterr().err
    assert exc.value.code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert f"did you mean {suggestion}?" in err, err


def test_no_suggestion_when_nothing_is_close(capsys):
    from pipelines.cli.app import main

    with pytest.raises(SystemExit):
        main(["zzzzqqq"])
    assert "did you mean" not in capsys.readouterr().err


def test_batch_summary_line_on_success_and_resume(tmp_path, capsys):
    from pipelines.cli.app import main

    a, b = small_scan(tmp_path / "a.npy", seed=1), small_scan(tmp_path / "b.npy", seed=2)
    out = tmp_path / "camp"
    argv = [
        "batch",
        str(a),
        str(b),
        "--spacing",
        str(DX),
        "--no-friction",
        "--workers",
        "1",
        "--out",
        str(out),
    ]
    capsys.readouterr()
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 1 and re.search(r"2 done, 0 skipped, 0 failed", lines[0]), lines
    assert main(argv + ["--resume"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 1 and re.search(r"0 done, 2 skipped, 0 failed", lines[0]), lines
