"""The long fuzz run (issue 14): tests/test_fuzz.py's strategies with many more, random examples.

    PYTHONPATH=. python benchmarks/fuzz_long.py [--scale 20] [--figures] [--batch] [-k EXPR]

Runs ``pytest tests/test_fuzz.py`` with ``ROADSCAN_FUZZ_SCALE`` (examples x scale, random seed,
no shrinking), ``ROADSCAN_FUZZ_COLLECT=1`` (every failing case is recorded and the run goes
on) and, with ``--figures``, every figure drawn. Prints, per group, the cases tried, how they
ended (exit 0 / exit 2), the cases with a numpy warning line and the failures, then each
failure (the command line or file and the problems: traceback, exit code, multi-line error,
NaN in an output, leftovers, time limit). Exit code 1 when any case failed.

``--batch`` adds ``roadscan batch`` runs (each starts a Dask cluster: ~20 s a case).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scale", type=float, default=20.0, help="examples per test x SCALE (CI: 1)")
    ap.add_argument("--figures", action="store_true", help="draw every figure (slower)")
    ap.add_argument("--batch", action="store_true", help="include roadscan batch (Dask) runs")
    ap.add_argument("-k", default=None, help="pytest -k expression (a subset of the tests)")
    ap.add_argument("--report", default=None, help="also keep the JSON report here")
    args = ap.parse_args(argv)

    report = Path(args.report or tempfile.mkstemp(prefix="fuzz_long_", suffix=".json")[1])
    env = {
        **os.environ,
        "PYTHONPATH": str(ROOT),
        "MPLBACKEND": "Agg",
        "ROADSCAN_FUZZ_SCALE": str(args.scale),
        "ROADSCAN_FUZZ_COLLECT": "1",
        "ROADSCAN_FUZZ_REPORT": str(report),
    }
    if args.figures:
        env["ROADSCAN_FUZZ_FIGURES"] = "1"
    cmd = [
        sys.executable,
        "-m",
        "pytest",
        "-q",
        "-p",
        "no:cacheprovider",
        str(ROOT / "tests" / "test_fuzz.py"),
    ]
    if not args.batch:
        cmd += ["--deselect", "tests/test_fuzz.py::test_batch_subprocess"]
    if args.k:
        cmd += ["-k", args.k]
    t0 = time.monotonic()
    proc = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    wall = time.monotonic() - t0
    if not report.exists() or report.stat().st_size == 0:
        print(proc.stdout[-3000:], proc.stderr[-3000:], sep="\n")
        print("no report written: the run failed before the fuzz tests")
        return 1
    data = json.loads(report.read_text())
    stats, failures = data["stats"], data["failures"]
    keys = ["cases", "exit0", "exit2", "numpy_warning", "failures"]
    print(f"fuzz_long: scale {args.scale:g}, figures {'drawn' if args.figures else 'stubbed'}, {wall:.0f} s")
    print(f"{'group':<16}" + "".join(f"{k:>14}" for k in keys))
    total = {k: 0 for k in keys}
    for g in sorted(stats):
        row = [stats[g].get(k, 0) for k in keys]
        for k, v in zip(keys, row):
            total[k] += v
        print(f"{g:<16}" + "".join(f"{v:>14}" for v in row))
    print(f"{'total':<16}" + "".join(f"{total[k]:>14}" for k in keys))
    broken = [
        ln
        for ln in proc.stdout.splitlines()
        if ln.startswith(("FAILED ", "ERROR ")) and "test_cases_were_counted" not in ln
    ]
    for ln in broken:  # a test that stopped for another reason than a judged case
        print(f"pytest: {ln}")
    for f in failures:
        print(
            f"\nFAILED {f['group']}: {'; '.join(f['problems'])}\n  case: {f['case'][:600]}\n"
            f"  stderr: {f['stderr_tail'][-400:]}"
        )
    if not args.report:
        report.unlink()
    return 1 if failures or broken else 0


if __name__ == "__main__":
    sys.exit(main())
