"""``roadscan batch`` on a LocalCluster (issue 12): 20 small scans plus broken ones, identical
results to ``analyse``, resume, atomic folders, manifest, sections of a long profile."""

import csv
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, fourier_surface

from pipelines.campaign.folder import SIDECAR, atomic_folder
from pipelines.campaign.records import flatten_summary
from pipelines.cli.app import main

N_GOOD = 20
DX = 1e-4


def _read_campaign(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], [dict(zip(rows[0], r)) for r in rows[1:]]


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    d = tmp_path_factory.mktemp("campaign")
    src = d / "scans"
    src.mkdir()
    for i in range(N_GOOD):
        h = fourier_surface(64, DX, 0.7 + 0.01 * i, 2e-4, seed=i)
        np.save(src / f"scan{i:02d}.npy", h)
    (src / "zz_garbage.npy").write_bytes(b"this is not a numpy file\n")
    np.save(src / "zz_3d.npy", np.zeros((4, 4, 4)))
    out = d / "out"
    args = [
        "batch",
        str(src / "*.npy"),
        str(src / "missing.npy"),
        str(d / "nomatch_*.x3p"),
        "--spacing",
        str(DX),
        "--out",
        str(out),
        "--workers",
        "2",
    ]
    rc = main(args)
    return {"dir": d, "src": src, "out": out, "rc": rc, "args": args}


def test_campaign_rows_status_and_outputs(campaign):
    out = campaign["out"]
    assert campaign["rc"] == 2  # some inputs failed
    head, rows = _read_campaign(out / "campaign.csv")
    assert head[:5] == ["file", "label", "chainage_m", "status", "error"]
    names = [Path(r["file"]).name for r in rows]
    good = [f"scan{i:02d}.npy" for i in range(N_GOOD)]
    # input order: the glob's sorted matches, then the missing file, then the empty pattern
    assert names == good + ["zz_3d.npy", "zz_garbage.npy", "missing.npy", "nomatch_*.x3p"]
    for r in rows[:N_GOOD]:
        assert r["status"] == "ok" and r["error"] == ""
        stem = Path(r["file"]).stem
        files = {p.name for p in (out / stem).iterdir()}
        assert {"summary.json", "psd.csv", "mu.csv", "report.html", SIDECAR} <= files
        assert not any(f.endswith(".png") for f in files)  # no --figures
        s = json.loads((out / stem / "summary.json").read_text())
        flat = flatten_summary(s)
        # every scalar of summary.json is a column, under its (flattened) key, same value; the
        # anisotropy sectors in campaign_anisotropy.csv (issue 21), same row order
        side_head, side_rows = _read_campaign(out / "campaign_anisotropy.csv")
        side = side_rows[names.index(Path(r["file"]).name)]
        assert r["warnings"] == " | ".join(s.get("warnings", []))  # one column (issue 20)
        for k, v in flat.items():
            if k.startswith(("warnings.", "friction.extrapolated_share.")):
                assert k not in head, k  # lists kept out of the table (issue 20)
                continue
            if k.startswith("anisotropy.sector_"):
                assert k not in head and k in side_head, k
                assert float(side[k]) == v, k
                continue
            assert k in head, k
            if isinstance(v, float):
                assert float(r[k]) == v, k
            elif v is None:
                assert r[k] == ""
            elif isinstance(v, bool):  # mpd_valid, peak_at_edge
                assert r[k] == ("true" if v else "false"), k
            else:
                assert r[k] == str(v)
        assert "hurst" in head and "rms_height_m" in head and "friction.mu_peak" in head
        assert "roughness.Sq_m" in head and "fit_band_per_m.1" in head
    errors = {Path(r["file"]).name: r for r in rows[N_GOOD:]}
    assert all(r["status"] == "error" for r in errors.values())
    for r in errors.values():
        assert "\n" not in r["error"] and r["error"]
        assert r["hurst"] == ""
    assert "no such file" in errors["missing.npy"]["error"]
    assert "pattern matches no file" in errors["nomatch_*.x3p"]["error"]
    assert "zz_garbage.npy" in errors["zz_garbage.npy"]["error"]
    assert "3D" in errors["zz_3d.npy"]["error"] or "shape" in errors["zz_3d.npy"]["error"]
    assert not (out / "zz_garbage").exists() and not (out / "zz_3d").exists()
    assert not [p for p in out.iterdir() if "tmp-" in p.name]  # no temporary folder left


def test_campaign_report_links_every_scan(campaign):
    text = (campaign["out"] / "report.html").read_text()
    for i in range(N_GOOD):
        assert f"href='scan{i:02d}/'" in text
    assert "Distributions" in text and "data:image/png;base64" in text
    assert "missing.npy" in text and "no such file" in text
    assert "Along chainage" not in text  # no chainage given


@pytest.mark.parametrize("i", [0, 13])
def test_identical_to_analyse(campaign, tmp_path, i):
    f = campaign["src"] / f"scan{i:02d}.npy"
    assert main(["analyse", str(f), "--spacing", str(DX), "--out", str(tmp_path)]) == 0
    for name in ("summary.json", "psd.csv", "mu.csv"):
        assert (tmp_path / name).read_bytes() == (campaign["out"] / f.stem / name).read_bytes(), name


def test_resume_skips_unchanged_and_redoes_changed(campaign, tmp_path):
    src, out = campaign["src"], campaign["out"]
    before = {
        p.name: (p / "summary.json").stat().st_mtime_ns
        for p in out.iterdir()
        if p.is_dir() and not p.name.startswith(".")
    }
    # one input changes, one output folder is lost, one input is touched but unchanged
    np.save(src / "scan03.npy", fourier_surface(64, DX, 0.5, 4e-4, seed=99))
    import shutil

    shutil.rmtree(out / "scan05")
    os.utime(src / "scan07.npy", ns=(1, 1))
    _head0, rows0 = _read_campaign(out / "campaign.csv")
    rc = main(campaign["args"] + ["--resume"])
    assert rc == 2
    _head, rows = _read_campaign(out / "campaign.csv")
    after = {
        p.name: (p / "summary.json").stat().st_mtime_ns
        for p in out.iterdir()
        if p.is_dir() and not p.name.startswith(".")
    }
    redone = {k for k in after if after[k] != before.get(k)}
    assert redone == {"scan03", "scan05"}  # touched scan07: same hash, skipped
    byname = {Path(r["file"]).stem: r for r in rows}
    old = {Path(r["file"]).stem: r for r in rows0}
    assert byname["scan03"]["rms_height_m"] != old["scan03"]["rms_height_m"]
    # a 64 x 64 scan's fitted band may be under half a decade: H is then no headline (hurst
    # empty) but its fit is kept in summary.json's hurst_fit
    s03 = json.loads((out / "scan03" / "summary.json").read_text())
    assert abs(s03["hurst_fit"] - 0.5) < 0.15
    for k in ("scan00", "scan05", "scan07", "scan19"):
        assert byname[k]["hurst"] == old[k]["hurst"] and byname[k]["status"] == "ok"
    # options changed: nothing is skipped
    rc = main(campaign["args"] + ["--resume", "--no-friction"])
    again = {
        p.name: (p / "summary.json").stat().st_mtime_ns
        for p in out.iterdir()
        if p.is_dir() and not p.name.startswith(".")
    }
    assert all(again[k] != after[k] for k in after)
    assert not (out / "scan00" / "mu.csv").exists()


def test_atomic_folder_keeps_old_outputs_on_failure(tmp_path):
    target = tmp_path / "scan"
    with atomic_folder(target) as tmp:
        (tmp / "summary.json").write_text("first")
    for exc in (RuntimeError, KeyboardInterrupt):
        with pytest.raises(exc):
            with atomic_folder(target) as tmp:
                (tmp / "summary.json").write_text("half")
                raise exc()
        assert (target / "summary.json").read_text() == "first"
    with atomic_folder(target) as tmp:
        (tmp / "psd.csv").write_text("second")
    assert sorted(p.name for p in target.iterdir()) == ["psd.csv"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scan"]


def test_manifest_labels_chainage_and_bad_rows(tmp_path):
    d = tmp_path / "survey"
    (d / "cores").mkdir(parents=True)
    for i in range(3):
        np.save(d / "cores" / f"c{i}.npy", fourier_surface(64, DX, 0.8, 2e-4, seed=40 + i))
    (d / "manifest.csv").write_text(
        "file,chainage_m,label\ncores/c2.npy,250,lane 1 wheel path\ncores/c0.npy,0,start\n"
        "cores/c1.npy,ten,oops\ncores/c0.npy,500,again\n"
    )
    out = tmp_path / "out"
    rc = main(
        [
            "batch",
            str(d / "manifest.csv"),
            "--spacing",
            str(DX),
            "--out",
            str(out),
            "--workers",
            "1",
            "--no-friction",
            "--figures",
        ]
    )
    assert rc == 2
    _head, rows = _read_campaign(out / "campaign.csv")
    # --figures: the PNGs analyse makes for an area scan (no mu.png without friction)
    assert {"heightmap.png", "psd.png", "psd2d.png"} <= {p.name for p in (out / "c2").iterdir()}
    assert [r["label"] for r in rows] == ["lane 1 wheel path", "start", "oops", "again"]
    assert [r["chainage_m"] for r in rows] == ["250.0", "0.0", "", "500.0"]
    assert [r["status"] for r in rows] == ["ok", "ok", "error", "ok"]
    assert "chainage_m 'ten'" in rows[2]["error"]
    # the repeated stem gets its own folder, numbered in input order as analyse does
    assert (out / "c0" / "summary.json").exists() and (out / "c0_2" / "summary.json").exists()
    assert rows[1]["hurst"] == rows[3]["hurst"]
    assert "Along chainage" in (out / "report.html").read_text()


def test_bad_options_are_one_line_errors(tmp_path, capsys):
    f = tmp_path / "a.npy"
    np.save(f, np.zeros((8, 8)))
    assert main(["batch", str(f), "--out", str(tmp_path / "o"), "--workers", "0"]) == 2
    assert main(["batch", str(f), "--out", str(tmp_path / "o"), "--section-length", "-1"]) == 2
    assert main(["batch", str(f), "--out", str(tmp_path / "o"), "--window-alpha", "3"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 3 and all(e.startswith("roadscan batch: error:") for e in err)
    assert "--workers" in err[0] and "--section-length" in err[1] and "--window-alpha" in err[2]


def test_quiet_when_not_a_terminal(tmp_path):
    f = tmp_path / "a.npy"
    np.save(f, fourier_surface(64, DX, 0.8, 2e-4, seed=1))
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "pipelines.cli",
            "batch",
            str(f),
            str(tmp_path / "nope.npy"),
            "--spacing",
            str(DX),
            "--out",
            str(tmp_path / "o"),
            "--workers",
            "1",
            "--no-friction",
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert r.returncode == 2
    (line,) = r.stdout.splitlines()  # the one summary line (issue 22)
    assert re.fullmatch(
        rf"roadscan batch: 1 done, 0 skipped, 1 failed, [01] with warnings -> "
        rf"{re.escape(str(tmp_path / 'o' / 'campaign.csv'))}, "
        rf"{re.escape(str(tmp_path / 'o' / 'report.html'))}",
        line,
    ), line
    assert r.stderr.strip().splitlines() == [f"roadscan batch: error: {tmp_path / 'nope.npy'}: no such file"]


def test_ctrl_c_keeps_finished_scans_and_resume_completes(tmp_path):
    import signal
    import time

    src = tmp_path / "scans"
    src.mkdir()
    n = 30
    for i in range(n):
        np.save(src / f"k{i:02d}.npy", fourier_surface(128, DX, 0.8, 2e-4, seed=200 + i))
    out = tmp_path / "out"
    cmd = [
        sys.executable,
        "-m",
        "pipelines.cli",
        "batch",
        str(src / "*.npy"),
        "--spacing",
        str(DX),
        "--out",
        str(out),
        "--workers",
        "1",
    ]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    p = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    t0 = time.time()
    while time.time() - t0 < 120:
        if out.exists() and len(list(out.glob("k*/summary.json"))) >= 2:
            break
        time.sleep(0.05)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=120)
    if p.returncode == 0:
        pytest.skip("the campaign finished before Ctrl-C arrived")
    assert p.returncode == 130, err
    assert "interrupted" in err and "Traceback" not in err
    finished = [d for d in out.iterdir() if d.is_dir() and not d.name.startswith(".")]
    assert 2 <= len(finished) < n
    for d in finished:  # every folder present is complete
        assert {"summary.json", "psd.csv", "mu.csv", SIDECAR} <= {f.name for f in d.iterdir()}
        json.loads((d / "summary.json").read_text())
    _head, rows = _read_campaign(out / "campaign.csv")
    assert len(rows) == n
    ok = {Path(r["file"]).stem for r in rows if r["status"] == "ok"}
    assert ok == {d.name for d in finished}
    assert all("interrupted" in r["error"] for r in rows if r["status"] != "ok")
    before = {d.name: (d / "summary.json").stat().st_mtime_ns for d in finished}
    assert main(cmd[3:-2] + ["--workers", "2", "--resume"]) == 0
    assert all((out / k / "summary.json").stat().st_mtime_ns == t for k, t in before.items())
    assert len([d for d in out.iterdir() if d.is_dir() and not d.name.startswith(".")]) == n
    assert not [d for d in out.iterdir() if "tmp-" in d.name]


def test_progress_bar_on_a_terminal_without_tqdm(tmp_path):
    """stderr a terminal (a pty): a progress bar, the built-in one when tqdm is not installed
    (tqdm is no dependency), ending at n/n; stdout holds the one summary line."""
    import pty

    f = tmp_path / "a.npy"
    np.save(f, fourier_surface(64, DX, 0.8, 2e-4, seed=1))
    block = tmp_path / "block" / "tqdm"
    block.mkdir(parents=True)
    (block / "__init__.py").write_text("raise ImportError('tqdm hidden by the test')\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(block.parent), str(ROOT)]))
    master, slave = pty.openpty()
    r = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "pipelines.cli",
            "batch",
            str(f),
            str(f),
            "--spacing",
            str(DX),
            "--out",
            str(tmp_path / "o"),
            "--workers",
            "1",
            "--no-friction",
        ],
        stdout=subprocess.PIPE,
        stderr=slave,
        env=env,
    )
    os.close(slave)
    chunks = []
    while True:
        try:
            b = os.read(master, 4096)
        except OSError:
            break
        if not b:
            break
        chunks.append(b)
    out, _ = r.communicate(timeout=120)
    os.close(master)
    text = b"".join(chunks).decode(errors="replace")
    assert r.returncode == 0 and out.decode().count("\n") == 1
    assert "0/2 scans" in text and "2/2 scans" in text and "Traceback" not in text
    assert "2 done, 0 skipped, 0 failed" in out.decode()


def test_local_workers_keep_glibc_dynamic_mmap_threshold(monkeypatch):
    """Dask's nanny sets MALLOC_TRIM_THRESHOLD_ in its workers, which makes every array above
    128 KiB a fresh mmap (run_job measured 2.3x slower per 1024^2 scan); the local cluster's
    workers start without it, unless the user set it."""
    from pipelines.campaign.runner import _TRIM_ENV, _client

    monkeypatch.delenv(_TRIM_ENV, raising=False)
    with _client(workers=1) as client:
        seen = list(client.run(os.environ.get, _TRIM_ENV).values())
    assert seen == [None]
    assert _TRIM_ENV not in os.environ  # nor leaked into this process by the nanny


def test_event_loop_errors_are_not_printed_during_a_campaign(capfd):
    """Dask logs errors of its own event-loop callbacks on 'tornado.application' (a NameError
    traceback from distributed's sync cancel path on Ctrl-C at the wrong moment); a campaign
    keeps them off stderr, and the level is restored afterwards."""
    import logging

    import distributed  # noqa: F401 - sets up Dask's logging (tornado.application: error)

    from pipelines.campaign.runner import _quiet_event_loop

    log = logging.getLogger("tornado.application")
    before = log.level
    with _quiet_event_loop():
        log.error("Exception in callback: Traceback (most recent call last): NameError")
    assert "NameError" not in capfd.readouterr().err
    assert log.level == before
