"""Every warning a command prints also lands in its outputs (issue 20): summary.json
(``warnings``), summary.csv and campaign.csv (``warnings`` column), the HTML reports, and the
campaign's headline counts the scans with warnings."""

import csv
import html
import json
import re
import subprocess
import sys

import numpy as np
from conftest import ROOT, fourier_surface

DX = 5e-5


def _stderr_warnings(text):
    return [ln.split(": warning: ", 1)[1] for ln in text.splitlines() if ": warning: " in ln]


def _scans(tmp_path):
    """A scan that warns (so small that its reliable band is under a factor 2) and one that
    does not."""
    small, big = tmp_path / "small.npy", tmp_path / "big.npy"
    np.save(small, fourier_surface(48, DX, 0.8, 2e-4, seed=3))
    np.save(big, fourier_surface(256, DX, 0.8, 2e-4, seed=4))
    return small, big


def _run(*args):
    env = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}
    return subprocess.run(
        [sys.executable, "-m", "pipelines.cli", *map(str, args)],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )


def test_analyse_warnings_in_json_csv_and_reports(tmp_path):
    small, big = _scans(tmp_path)
    out = tmp_path / "a"
    r = _run("analyse", small, big, "--spacing", DX, "--out", out, "--no-friction")
    assert r.returncode == 0, r.stderr
    printed = _stderr_warnings(r.stderr)
    assert any("small" in w and "narrower than a factor 2" in w for w in printed)
    with open(out / "summary.csv", newline="") as fh:
        rows = {row["scan"]: row for row in csv.DictReader(fh)}
    every = []
    for name in ("small", "big"):
        s = json.loads((out / name / "summary.json").read_text())
        own = [w for w in printed if name in w]
        assert set(own) <= set(s["warnings"])
        cell = rows[name]["warnings"]
        assert all(w in cell for w in own)
        page = html.unescape((out / name / "report.html").read_text())
        assert all(w in page for w in own)
        every += own
    assert rows["big"]["warnings"] == "" or "small" not in rows["big"]["warnings"]
    assert set(every) == set(printed)  # each printed warning is somewhere
    index = html.unescape((out / "report.html").read_text())
    assert all(w in index for w in printed)


def test_campaign_warnings_column_report_and_headline(tmp_path):
    small, big = _scans(tmp_path)
    out = tmp_path / "c"
    r = _run("batch", small, big, "--spacing", DX, "--out", out, "--workers", "1", "--no-friction")
    assert r.returncode == 0, r.stderr
    with open(out / "campaign.csv", newline="") as fh:
        rows = {row["file"].rsplit("/", 1)[-1]: row for row in csv.DictReader(fh)}
    assert "narrower than a factor 2" in rows["small.npy"]["warnings"]
    s = json.loads((out / "small" / "summary.json").read_text())
    assert rows["small.npy"]["warnings"] == " | ".join(s["warnings"])
    n_warned = sum(bool(row["warnings"]) for row in rows.values())
    assert re.search(rf"\b{n_warned} with warnings\b", r.stdout)
    page = html.unescape((out / "report.html").read_text())
    assert f"({n_warned} with warnings)" in page
    assert all(w in page for w in s["warnings"])
