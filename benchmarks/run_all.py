"""Every speed figure of issue 13 in one run: runs each benchmark script of this directory in
turn (a fresh interpreter each, this checkout first on the path), shows its output, collects
its ``RATIO | figure | value | goal | PASS/FAIL | detail`` lines and prints them as one table,
with the machine (CPU model, cores, RAM, Python and library versions), the load average and the
date. ``--readme`` also writes that table into ``benchmarks/README.md`` (between its
``run_all`` markers) and the full output into ``benchmarks/last_run.txt``.

A script that prints no RATIO line but ``ratio A / B = X (goal <= Y)`` lines is read from those.
A script not present in this checkout is listed as such.

Run: PYTHONPATH=. .venv/bin/python benchmarks/run_all.py [--quick] [--readme] [--only NAME,...]
"""

from __future__ import annotations

import argparse
import datetime as _dt
import os
import platform
import re
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
README = HERE / "README.md"
BEGIN, END = "<!-- run_all:begin -->", "<!-- run_all:end -->"

#: (script, arguments, arguments with --quick, what it measures)
SCRIPTS = [
    ("bench_startup.py", ["7"], ["3"], "roadscan --help and every CMD --help, fresh interpreters"),
    (
        "bench_analyse.py",
        ["5", "--phases"],
        ["3", "--phases"],
        "roadscan analyse on the sample, with and without figures",
    ),
    ("bench_psd.py", [], [], "psd_area against the same-FFT floor and SurfaceTopography"),
    (
        "bench_scale.py",
        [],
        ["--sizes", "1024,2048,4096"],
        "roadscan analyse time and peak memory, 1024^2 to 8192^2 (issue 14)",
    ),
    (
        "bench_rainfill.py",
        [],
        ["--sizes", "1024,2048", "--repeats", "1"],
        "rain fill against scikit-image, 1024^2 to 4096^2",
    ),
    ("bench_friction.py", [], ["--quick"], "isothermal and flash engines against independent references"),
    ("bench_texture.py", ["3"], ["1"], "ISO 25178-2 texture set + MPD against height figures + MPD, 2048^2"),
]

RATIO = re.compile(r"^RATIO \| (.+?) \| (.+?) \| (.+?) \| (PASS|FAIL) \| ?(.*)$")
LOOSE = re.compile(r"ratio (.+?) = ([0-9.]+)\s*\(goal ([<>]=?)\s*([0-9.]+)\)")


def machine():
    """CPU model, cores, RAM, versions: the row under the table."""
    cpu = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    ram = ""
    try:
        kb = int(
            next(
                row.split()[1]
                for row in Path("/proc/meminfo").read_text().splitlines()
                if row.startswith("MemTotal")
            )
        )
        ram = f", {kb / 2**20:.0f} GiB RAM"
    except (OSError, StopIteration, ValueError):
        pass
    versions = [f"Python {platform.python_version()}"]
    for mod in ("numpy", "scipy", "matplotlib", "numba", "skimage"):
        try:
            versions.append(f"{mod} {__import__(mod).__version__}")
        except Exception:  # noqa: BLE001 - a missing library is just not listed
            pass
    return f"{cpu}, {os.cpu_count()} cores{ram}; {', '.join(versions)}; {platform.system()}"


def loose_ratios(text):
    rows = []
    for line in text.splitlines():
        m = LOOSE.search(line)
        if m:
            what, val, op, goal = m.group(1), float(m.group(2)), m.group(3), float(m.group(4))
            ok = {"<=": val <= goal, "<": val < goal, ">=": val >= goal, ">": val > goal}[op]
            rows.append((f"ratio {what}", f"{val:.2f}", f"{op} {goal:g}", "PASS" if ok else "FAIL", ""))
    return rows


def run(script, args, timeout):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    t = time.perf_counter()
    try:
        p = subprocess.run(
            [sys.executable, str(HERE / script), *args],
            cwd=ROOT,
            env=env,
            capture_output=True,
            text=True,
            timeout=timeout,
        )
        out, rc = p.stdout + (f"\n[stderr]\n{p.stderr.strip()}" if p.returncode else ""), p.returncode
    except subprocess.TimeoutExpired as exc:
        out, rc = (exc.stdout or b"").decode() if isinstance(exc.stdout, bytes) else (exc.stdout or ""), -1
        out += f"\n[timed out after {timeout} s]"
    return out, rc, time.perf_counter() - t


def table(rows):
    lines = ["| figure | value | goal | verdict | detail |", "|---|---|---|---|---|"]
    for r in rows:
        lines.append("| " + " | ".join(c.replace("|", "/") for c in r) + " |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description="run every issue-13 benchmark and collect the ratios")
    ap.add_argument("--quick", action="store_true", help="fewer repeats and smaller sizes")
    ap.add_argument("--readme", action="store_true", help="write the table into benchmarks/README.md")
    ap.add_argument("--only", default="", help="comma-separated script names (e.g. bench_startup)")
    ap.add_argument("--timeout", type=float, default=3600, help="seconds per script")
    a = ap.parse_args(argv)
    if a.readme and a.only:
        ap.error("--readme writes the whole table: run every script (no --only)")
    only = {s if s.endswith(".py") else s + ".py" for s in a.only.split(",") if s}
    started = _dt.datetime.now().astimezone()
    loads = [os.getloadavg()[0]]
    rows, log = [], []
    for script, args, quick_args, what in SCRIPTS:
        if only and script not in only:
            continue
        if not (HERE / script).exists():
            rows.append((f"{script}: {what}", "—", "—", "n/a", f"see {script}: not in this checkout"))
            print(f"== {script}: not in this checkout", flush=True)
            continue
        use = quick_args if a.quick else args
        print(f"== {script} {' '.join(use)}  ({what})", flush=True)
        out, rc, dt = run(script, use, a.timeout)
        loads.append(os.getloadavg()[0])
        print(out.rstrip(), flush=True)
        print(f"== {script}: {dt:.0f} s, exit {rc}\n", flush=True)
        log.append(f"== {script} {' '.join(use)} ({dt:.0f} s, exit {rc})\n{out.rstrip()}\n")
        found = [m.groups() for m in map(RATIO.match, out.splitlines()) if m]
        found = found or loose_ratios(out)
        if not found:
            found = [(f"{script}: {what}", "—", "—", "FAIL", f"no ratio printed (exit {rc})")]
        rows.extend(tuple(r) for r in found)
    mach = machine()
    stamp = (
        f"{started:%Y-%m-%d %H:%M %Z}; load average {min(loads):.1f} to {max(loads):.1f} "
        f"during the run{' (--quick)' if a.quick else ''}"
    )
    print("== every ratio")
    print(table(rows))
    print(f"\nmachine: {mach}\ndate: {stamp}")
    if a.readme:
        write_readme(table(rows), mach, stamp)
        (HERE / "last_run.txt").write_text(f"machine: {mach}\ndate: {stamp}\n\n" + "\n".join(log))
        print(f"wrote {README.relative_to(ROOT)} and benchmarks/last_run.txt")
    return 0 if all(r[3] != "FAIL" for r in rows) else 1


def write_readme(tab, mach, stamp):
    block = f"{BEGIN}\n{tab}\n\nMachine: {mach}.  \nMeasured: {stamp}.\n{END}"
    text = README.read_text() if README.exists() else f"# Benchmarks\n\n{BEGIN}\n{END}\n"
    if BEGIN not in text:
        text += f"\n{BEGIN}\n{END}\n"
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    tmp = README.with_suffix(".md.tmp")
    tmp.write_text(head + block + tail)
    tmp.replace(README)


if __name__ == "__main__":
    sys.exit(main())
