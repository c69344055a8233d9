"""Start-up of the ``roadscan`` command (issue 13): ``roadscan --help`` and ``roadscan CMD --help``
must take at most 0.15 s. Each case runs in a fresh interpreter (the installed entry point's
code: ``from pipelines.cli.app import main``), interleaved with a bare ``python -c pass`` and a
``python -c 'import numpy'`` baseline so that background load hits them alike; best of N wall
times, and CPU times (user + system of the child), which background load inflates much less.
Every command ``roadscan --help`` lists is timed (read from the parser).

Run: PYTHONPATH=. .venv/bin/python benchmarks/bench_startup.py [N]
"""

import os
import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GOAL_S = 0.15
NUMPY = "python -c 'import numpy' (reference)"
ENTRY = "import sys\nfrom pipelines.cli.app import main\nsys.argv[0] = 'roadscan'\nsys.exit(main({}))"


def commands():
    """Every command ``roadscan --help`` lists (read from the parser itself, so that a new
    command is timed without editing this file)."""
    sys.path.insert(0, str(ROOT))
    from pipelines.cli.app import _load_commands

    return [m.NAME for m in _load_commands()]


def cases():
    yield "python -c pass (interpreter floor)", "pass"
    yield NUMPY, "import numpy"
    yield "roadscan --help", ENTRY.format("['--help']")
    for cmd in commands():
        yield f"roadscan {cmd} --help", ENTRY.format(f"['{cmd}', '--help']")
    yield "import roadscan", "import roadscan"
    yield "import friction", "import friction"


def run_once(code, env):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    p = subprocess.run([sys.executable, "-c", code], env=env, cwd=ROOT, capture_output=True)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, p.returncode


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    # as on a user's machine, compiled modules are cached (__pycache__): a shell that sets
    # PYTHONDONTWRITEBYTECODE would otherwise recompile every roadscan module on each run
    # (52 modules, about 0.15 s of a 1 s command, measured)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    todo = list(cases())
    times = {name: [] for name, _ in todo}
    cpus = {name: [] for name, _ in todo}
    load0 = os.getloadavg()[0]
    for _ in range(n):
        for name, code in todo:
            dt, cpu, rc = run_once(code, env)
            if rc == 0:
                times[name].append(dt)
                cpus[name].append(cpu)
    floor = min(times["python -c pass (interpreter floor)"])
    print(f"best of {n} wall times, fresh interpreter each ({sys.executable})")
    print(f"{'case':44s} {'best s':>8s} {'minus floor':>12s} {'cpu s':>7s}  verdict")
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
        print(f"{name:44s} {best:8.3f} {best - floor:12.3f} {min(cpus[name]):7.3f}  {verdict}")
    print(
        f"slowest roadscan ... --help: {worst:.3f} s (goal <= {GOAL_S} s); "
        f"ratio to 'import numpy': {worst / min(times[NUMPY]):.2f}"
    )
    n_cmd = sum(1 for name in times if name.startswith("roadscan ")) - 1
    print(
        f"RATIO | slowest of roadscan --help and its {n_cmd} commands' --help, wall / goal | "
        f"{worst / GOAL_S:.2f} | <= 1 ({GOAL_S} s) | {'PASS' if worst <= GOAL_S else 'FAIL'} | "
        f"{worst:.3f} s; 'import numpy' takes {min(times[NUMPY]):.3f} s, load "
        f"{max(load0, os.getloadavg()[0]):.1f} on {os.cpu_count()} CPUs"
    )


if __name__ == "__main__":
    main()
