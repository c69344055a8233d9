"""End-to-end time of ``roadscan analyse`` on the shipped sample (1088 x 978 points), as a user
waits for it: at most 1.2 s with its four PNGs and report.html, at most 0.7 s with
``--no-figures`` (friction with the default rubber included in both), and at most 0.5 s for
``pipelines.analyse`` of the sample without writing (case ``api``, imports included).

Each case runs the installed entry point's code (``from pipelines.cli.app import main``) in a fresh
interpreter, interleaved with a ``python -c 'import numpy'`` reference so that background load
hits them alike; printed: best wall time of N, best CPU time (user + system of the child, which
load inflates less than wall time; with figures, the figure helper process that the command
starts and does not wait for is not counted), and the machine's load average. ``--phases`` adds where the
time goes, measured in one fresh process step by step: imports, reading, the metrology chain,
friction, each figure.

Run: PYTHONPATH=. .venv/bin/python benchmarks/bench_analyse.py [N] [--phases]
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "sample_scans" / "asphalt.x3p"
GOALS = {"figures": 1.2, "no-figures": 0.7, "api": 0.5}
API = "import pipelines\npipelines.analyse({!r})"  # the computation alone: nothing written
ENTRY = "import sys\nfrom pipelines.cli.app import main\nsys.argv[0] = 'roadscan'\nsys.exit(main({}))"
#: the command's own CPU time, printed at its exit: a helper process it reaps (the figure worker
#: of concurrent.futures) is not counted, as the docstring says
OWN_CPU = (
    "import atexit, resource, sys\natexit.register(lambda: sys.stderr.write("
    "'\\nBENCH_OWN_CPU %r\\n' % sum(resource.getrusage(resource.RUSAGE_SELF)[:2])))\n"
)

PHASES = r"""
import sys, time
t0 = time.perf_counter(); c0 = time.process_time()
def mark(what):
    global t0, c0
    t, c = time.perf_counter(), time.process_time()
    print(f"  {what:44s} {t - t0:7.3f} {c - c0:7.3f}")
    t0, c0 = t, c
import numpy as np; mark("import numpy")
from pathlib import Path
from pipelines.settings.scan_input import load_scan
from pipelines.chain.surface import analyse_surface, friction_curve, surface_psd
from roadscan.io import read
mark("import roadscan, pipelines (before the steps)")
hm = read(sys.argv[1]); mark("read the X3P")
an = analyse_surface(hm); mark("metrology chain (level ... PSD, fit, roughness)")
fr = friction_curve(surface_psd(an.spectrum, an.fit)); mark("friction mu(v), default rubber")
from pipelines.jobs.analyse import job as A
from pipelines.output import report
out = Path(sys.argv[2])
report.pyplot(); mark("import matplotlib (first figure only)")
report.plot_heightmap(an.levelled, out / "heightmap.png", title="levelled heights"); mark("heightmap.png")
A.draw_psd2d_figure(A.psd2d_picture(an.spec2d), out / "psd2d.png", "x"); mark("psd2d.png")
report.plot_psd([("m", an.spectrum.q_per_m, an.spectrum.C_m4)], out / "psd.png"); mark("psd.png")
report.plot_mu([("m", fr.v_m_per_s, fr.mu)], out / "mu.png"); mark("mu.png")
"""


def run_once(code, env):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    p = subprocess.run([sys.executable, "-c", code], env=env, cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if p.returncode != 0:
        raise SystemExit(f"bench_analyse: {code!r} failed: {p.stderr.strip()[-400:]}")
    own = [ln for ln in p.stderr.splitlines() if ln.startswith("BENCH_OWN_CPU ")]
    return wall, float(own[-1].split()[1]) if own else cpu


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    n = int(next((a for a in argv if a.isdigit()), 5))
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    # as on a user's machine, compiled modules are cached (__pycache__): a shell that sets
    # PYTHONDONTWRITEBYTECODE would otherwise recompile every roadscan module on each run
    # (52 modules, about 0.15 s of a 1 s command, measured)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    load0 = os.getloadavg()
    with tempfile.TemporaryDirectory(prefix="bench_analyse_") as tmp:

        def code(name, i):
            if name == "import numpy":
                return "import numpy"
            if name == "api":
                return API.format(str(SAMPLE))
            extra = ["--no-figures"] if name == "no-figures" else []
            return OWN_CPU + ENTRY.format(["analyse", str(SAMPLE), *extra, "--out", f"{tmp}/{name}{i}"])

        names = ("import numpy", "figures", "no-figures", "api")
        times = {k: [] for k in names}
        for i in range(n):
            for name in names:
                times[name].append(run_once(code(name, i), env))
        load1 = os.getloadavg()
        print(f"roadscan analyse {SAMPLE.name} (1088 x 978), fresh interpreter each, best of {n}")
        print(
            f"machine: {os.cpu_count()} CPUs, load average {load0[0]:.2f} before, {load1[0]:.2f} after "
            f"(wall times grow with load; CPU times much less)"
        )
        print(
            "(cpu s: the command's own process; the PNGs are drawn by a helper process it does "
            "not wait for, whose CPU time is not counted)"
        )
        print(f"{'case':14s} {'wall s':>8s} {'cpu s':>8s} {'goal s':>7s}")
        for name, ts in times.items():
            wall, cpu = min(t[0] for t in ts), min(t[1] for t in ts)
            goal = GOALS.get(name)
            print(f"{name:14s} {wall:8.3f} {cpu:8.3f} {goal if goal else '':>7}")
        for name, goal in GOALS.items():
            wall, cpu = min(t[0] for t in times[name]), min(t[1] for t in times[name])
            print(
                f"RATIO | roadscan analyse sample ({name}), wall / goal | {wall / goal:.2f} | <= 1 "
                f"({goal} s) | {'PASS' if wall <= goal else 'FAIL'} | {wall:.2f} s wall, {cpu:.2f} s "
                f"CPU, load {max(load0[0], load1[0]):.1f} on {os.cpu_count()} CPUs"
            )
        if "--phases" in argv:
            print("where the time goes (one fresh process; wall s, cpu s):")
            out = subprocess.run(
                [sys.executable, "-c", PHASES, str(SAMPLE), tmp],
                env=env,
                cwd=ROOT,
                capture_output=True,
                text=True,
            )
            print(out.stdout.rstrip() or out.stderr.strip()[-400:])


if __name__ == "__main__":
    main()
