"""Candidate fits on several processes (``roadscan diagnose --workers``,
pipelines/diagnosis/fit/parallel.py) give the diagnosis of one process to the last bit, and the
friction engine's phi table, which made that hard, is a function of its request alone."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import friction
from friction import grids
from pipelines.cli.app import main as cli
from pipelines.diagnosis.effects import get
from pipelines.diagnosis.fit.calibration import parse_uncertain
from pipelines.diagnosis.fit.parallel import fit_map, use_workers, workers
from pipelines.diagnosis.inputs import build_context
from pipelines.diagnosis.measured import MeasuredCurve
from pipelines.diagnosis.model import simulate
from pipelines.diagnosis.verdict.search import diagnose_friction

SAMPLES = Path(__file__).resolve().parents[1] / "sample_scans"
PSD = friction.SelfAffinePSD(0.8, 5e-4, 2000.0, 2e5)


def test_phi_table_values_do_not_depend_on_what_the_process_computed_before():
    """The same friction call gives the same bits after calls that need other reduced
    frequencies (a colder rubber, faster sliding): the table is never grown in place."""
    rubber = friction.thesis_rubber()
    v = np.logspace(-4, 0, 9)
    grids._CACHE.clear()
    first = friction.mu_isothermal(PSD, rubber, v).mu
    friction.mu_isothermal(PSD, rubber, v, T0_C=-10.0)
    friction.mu_isothermal(PSD, rubber, v * 1e3)
    friction.mu_flash(PSD, rubber, v[::4])
    assert np.array_equal(friction.mu_isothermal(PSD, rubber, v).mu, first)


def _work(x):
    if x == 3:
        warnings.warn(f"item {x} warns", UserWarning, stacklevel=1)
    return {"x": x, "square": x * x}


def test_fit_map_keeps_item_order_and_raises_worker_warnings_here():
    items = list(range(6))
    with use_workers(2):
        assert workers() == 2
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            out = fit_map(_work, items, cost=lambda x: -x)  # the cheapest last: handed out first
    assert [o["square"] for o in out] == [x * x for x in items]
    assert [str(w.message) for w in caught] == ["item 3 warns"]
    with pytest.raises(ValueError, match="at least 1"), use_workers(0):
        pass


def _boom(x):
    if x == 1:
        raise ArithmeticError("fit 1 failed")
    return x


def test_fit_map_raises_a_worker_exception_as_the_serial_loop_would():
    with use_workers(2), pytest.raises(ArithmeticError, match="fit 1 failed"):
        fit_map(_boom, [0, 1, 2])


def _diagnosis(n_workers):
    v = np.logspace(-5, 0.5, 24)
    n = v.size
    curve = MeasuredCurve(v, np.ones(n), np.full(n, np.nan), np.full(n, 2e5), np.zeros(n, bool), False, "t")
    ctx = build_context(curve, PSD)
    shifted = build_context(curve, PSD)
    shifted.base = shifted.base.with_(T0_shift_C=6.0, sigma0_scale=1.3)
    mu = simulate(shifted.base, shifted) * np.exp(0.02 * np.random.default_rng(5).standard_normal(n))
    with use_workers(n_workers):
        return diagnose_friction(
            ctx,
            mu,
            effects=[get("temperature_offset"), get("contact_correction"), get("adhesion")],
            uncertain=parse_uncertain("sigma0=0.1MPa:0.4MPa"),
            default_q1=False,
        )


def test_two_workers_give_the_diagnosis_of_one_to_the_last_bit():
    """Every stage that fits on several processes (each effect alone and the calibration, each
    effect with the calibration, the evidence over every point) gives what one process gives."""
    one, two = _diagnosis(1), _diagnosis(2)
    assert [c.name for c in one.candidates] == [c.name for c in two.candidates]
    assert len(one.candidates) >= 6  # three effects, the calibration, three effects with it
    for a, b in zip(one.candidates, two.candidates):
        assert a.params == b.params and np.array_equal(a.pred, b.pred)
        assert [e.name for e in a.effects] == [e.name for e in b.effects]
        assert [e.params for e in a.effects] == [e.params for e in b.effects]
        assert a.gap_heldout == b.gap_heldout and a.score == b.score
    strip = {"evidence"}
    assert {k: v for k, v in one.verdict.items() if k not in strip} == {
        k: v for k, v in two.verdict.items() if k not in strip
    }
    assert repr(one.verdict.get("evidence")) == repr(two.verdict.get("evidence"))


def test_workers_flag_refuses_zero_in_one_line(tmp_path, capsys):
    code = cli(
        [
            "diagnose",
            "--measured",
            str(SAMPLES / "measured_mu_example.csv"),
            "--psd",
            str(SAMPLES / "asphalt_psd.csv"),
            "--out",
            str(tmp_path / "d"),
            "--workers",
            "0",
        ]
    )
    err = capsys.readouterr().err.strip()
    assert code == 2 and "--workers 0" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "d").exists()


def test_a_stop_request_during_a_stage_ends_at_once_and_leaves_no_worker(tmp_path):
    """SIGTERM while the workers fit: one line, exit 143 within seconds (not after the stage's
    fits), no output folder, and every worker gone (killed; on Linux they also die with the
    command, prctl(PR_SET_PDEATHSIG))."""
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "d"
    argv = [
        sys.executable,
        "-m",
        "pipelines.cli",
        "diagnose",
        "--measured",
        str(SAMPLES / "measured_mu_example.csv"),
    ]
    argv += [
        "--psd",
        str(SAMPLES / "asphalt_psd.csv"),
        "--out",
        str(out),
        "--uncertain",
        "sigma0=0.15MPa:0.3MPa",
    ]
    proc = subprocess.Popen(argv, stderr=subprocess.PIPE, text=True, cwd=SAMPLES.parent)
    children, t_end = [], time.monotonic() + 60
    while not children and proc.poll() is None and time.monotonic() < t_end:  # a stage fitting
        time.sleep(0.05)
        for task in Path(f"/proc/{proc.pid}/task").glob("*/children"):
            children += [int(p) for p in task.read_text().split()]
    assert children, "no worker process while a stage fits"
    t0 = time.monotonic()
    proc.send_signal(signal.SIGTERM)
    rest = proc.stderr.read()
    code = proc.wait(timeout=30)
    assert code == 143 and time.monotonic() - t0 < 5.0
    assert rest.strip().splitlines()[-1] == "roadscan diagnose: interrupted (SIGTERM)"
    assert "Traceback" not in rest and not out.exists()
    time.sleep(0.2)
    alive = [
        p
        for p in children
        if Path(f"/proc/{p}").exists() and "Z" not in Path(f"/proc/{p}/stat").read_text().split()[2]
    ]
    assert alive == [], f"workers left running: {alive}"
