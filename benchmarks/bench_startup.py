"""Start-up of the ``roadscan`` command (issue 13): ``roadscan --help`` and ``roadscan CMD --help``
must take at most 0.15 s. Each case runs in a fresh interpreter (the installed entry point's
code: ``from pipelines.cli import main``), interleaved with a bare ``python -c pass`` and a
``python -c 'import numpy'`` baseline so that background load hits them alike; best of N wall
times and the modules of note each case loads.

Run: PYTHONPATH=. .venv/bin/python benchmarks/bench_startup.py [N]
"""
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GOAL_S = 0.15
NUMPY = "python -c 'import numpy' (reference)"
ENTRY = "import sys\nfrom pipelines.cli import main\nsys.argv[0] = 'roadscan'\nsys.exit(main({}))"


def cases():
    yield "python -c pass (interpreter floor)", "pass"
    yield NUMPY, "import numpy"
    yield "roadscan --help", ENTRY.format("['--help']")
    for cmd in ("analyse", "synth", "friction", "rain-fill", "stitch", "compare", "dry-vs-wet",
                "diagnose", "batch", "rubber", "convert"):
        yield f"roadscan {cmd} --help", ENTRY.format(f"['{cmd}', '--help']")
    yield "import roadscan", "import roadscan"
    yield "import friction", "import friction"


def run_once(code, env):
    t = time.perf_counter()
    p = subprocess.run([sys.executable, "-c", code], env=env, cwd=ROOT, capture_output=True)
    return time.perf_counter() - t, p.returncode


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    todo = list(cases())
    times = {name: [] for name, _ in todo}
    valid = {}
    for _ in range(n):
        for name, code in todo:
            dt, rc = run_once(code, env)
            if rc in (0,):
                times[name].append(dt)
                valid[name] = True
            else:
                valid.setdefault(name, False)
    floor = min(times["python -c pass (interpreter floor)"])
    print(f"best of {n} wall times, fresh interpreter each ({sys.executable})")
    print(f"{'case':44s} {'best s':>8s} {'minus floor':>12s}  verdict")
    worst = 0.0
    for name, _ in todo:
        ts = times[name]
        if not ts:
            print(f"{name:44s} {'(command not present)':>22s}")
            continue
        best = min(ts)
        verdict = ""
        if name.startswith("roadscan"):
            worst = max(worst, best)
            verdict = "ok" if best <= GOAL_S else f"OVER {GOAL_S} s"
        print(f"{name:44s} {best:8.3f} {best - floor:12.3f}  {verdict}")
    print(f"slowest roadscan ... --help: {worst:.3f} s (goal <= {GOAL_S} s); "
          f"ratio to 'import numpy': {worst / min(times[NUMPY]):.2f}")


if __name__ == "__main__":
    main()
