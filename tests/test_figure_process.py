"""The figure helper process of ``roadscan analyse`` (issue 13): same PNGs, drawn elsewhere,
and every failure of the helper ends in the figure being drawn (or failing) here."""

import math
import os
import subprocess
import sys

import pytest
from conftest import ROOT

from pipelines.output.figure_process import FigureProcess, InProcess, figure_drawer

SAMPLE = ROOT / "sample_scans" / "asphalt.x3p"
PNGS = ("heightmap.png", "psd2d.png", "psd.png", "mu.png")

CHILD = """
import sys
from pipelines.cli.app import main
rc = main(["analyse", {sample!r}, "--out", {out!r}])
print("matplotlib in parent:", "matplotlib" in sys.modules, "rc:", rc)
"""


def _analyse(out, switch):
    env = dict(os.environ, PYTHONPATH=str(ROOT), ROADSCAN_FIGURE_PROCESS=switch)
    r = subprocess.run(
        [sys.executable, "-c", CHILD.format(sample=str(SAMPLE), out=str(out))],
        env=env,
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    return r.stdout


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="the helper runs only with two cores or more")
def test_analyse_draws_in_a_helper_with_identical_pngs(tmp_path):
    helped = _analyse(tmp_path / "helper", "1")
    local = _analyse(tmp_path / "local", "0")
    assert "matplotlib in parent: False rc: 0" in helped  # the parent never drew
    assert "matplotlib in parent: True rc: 0" in local
    for name in PNGS + ("summary.json", "mu.csv", "psd.csv"):
        assert (tmp_path / "helper" / name).read_bytes() == (tmp_path / "local" / name).read_bytes(), name
    html = (tmp_path / "helper" / "report.html").read_text()
    assert html == (tmp_path / "local" / "report.html").read_text()


def test_results_in_order_and_a_dead_helper_falls_back():
    with FigureProcess() as d:
        d.submit(math.hypot, 3, 4)
        d.submit(math.hypot, 5, 12)
        assert d.collect() == [5.0, 13.0]
        d.submit(math.hypot, 8, 15)
        d._proc.kill()  # the helper process dies
        d._proc.join()
        d.submit(math.hypot, 6, 8)  # cannot be sent: drawn here, after the pending one
        assert d.collect() == [17.0, 10.0]


def test_a_failure_in_the_helper_is_raised_here_as_itself():
    with FigureProcess() as d:
        d.submit(math.sqrt, -1.0)
        with pytest.raises(ValueError, match="math domain error"):
            d.collect()


def test_discard_waits_and_forgets():
    with FigureProcess() as d:
        d.submit(math.hypot, 3, 4)
        d.discard()
        d.submit(math.hypot, 1, 0)
        assert d.collect() == [1.0]


def test_drawer_choice(monkeypatch):
    monkeypatch.setenv("ROADSCAN_FIGURE_PROCESS", "0")
    assert type(figure_drawer(True)) is InProcess
    monkeypatch.setenv("ROADSCAN_FIGURE_PROCESS", "1")
    assert type(figure_drawer(False)) is InProcess


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="the helper runs only with two cores or more")
def test_one_helper_per_process(monkeypatch):
    """Commands run one after another in one process start at most one helper."""
    import pipelines.output.figure_process as fp

    monkeypatch.setenv("ROADSCAN_FIGURE_PROCESS", "1")
    monkeypatch.setattr(fp, "_started", [])
    monkeypatch.delitem(sys.modules, "matplotlib.pyplot", raising=False)
    first = fp.figure_drawer(True)
    try:
        assert type(first) is FigureProcess
        assert type(fp.figure_drawer(True)) is InProcess
    finally:
        first.close()


def test_discard_waits_for_a_figure_whose_hand_over_was_interrupted():
    """A signal inside the hand-over can leave a figure queued for the helper without its
    future: discard still returns only after the helper is done with it."""
    import time

    with FigureProcess() as d:
        hand_over = d._pool.submit

        def interrupted(fn, *args, **kwargs):
            hand_over(fn, *args, **kwargs)
            raise KeyboardInterrupt

        d._pool.submit = interrupted
        t0 = time.monotonic()
        with pytest.raises(KeyboardInterrupt):
            d.submit(time.sleep, 0.5)
        d._pool.submit = hand_over
        d.discard()
        assert time.monotonic() - t0 >= 0.5
        d.submit(math.hypot, 3, 4)
        assert d.collect() == [5.0]
