"""Big scans (issue 14): time and peak memory of ``roadscan analyse`` from 1024^2 to 8192^2.

For each size N a scan is made in a child process (self-affine, H = 0.86, 55.4 um spacing, rms
0.5 mm, a tilt, and 2.3 % unmeasured points in clusters of radius 2 to 6, like an optical
profiler's dropouts) and saved as ``.npy``; then a fresh interpreter runs the whole command,
``roadscan analyse scan.npy --spacing 55.4e-6 --out DIR`` (figures, report and friction with the
default rubber included), through ``pipelines.cli.app.main``.

How memory is measured (Linux): the child first imports everything the command will use
(numpy, scipy, scikit-image, matplotlib, friction, roadscan, pipelines), so that library code is
part of the interpreter's baseline and not of the scan's cost; it then reads its resident set
(VmRSS) just before the command starts, resets the kernel's peak-RSS mark (``echo 5 >
/proc/self/clear_refs``) and reads the peak (VmHWM) when the command has finished. The figure
is

    peak above the baseline = VmHWM - VmRSS before reading the scan,

and its ratio to the float64 array of the scan (8 N^2 bytes: 512 MiB at 8192^2). It includes
the reader, every step, the figures and the output files. Goal: at most 6x (3 GiB at 8192^2),
judged from 4096^2 up (below, the run's fixed costs of some 50 MiB dominate the ratio).
If the peak mark cannot be reset, VmHWM over the child's whole life is used (an upper bound).

Time: wall time of the command (the scan generation and the imports excluded). It should grow
no faster than N^2 log N (the FFT): the benchmark prints t / (N^2 log2 N^2) per size, relative
to the largest size, and checks the growth from the second-largest to the largest size against
N^2 log N, with 25 % allowance for a shared machine.

``--steps`` adds, for the largest size, the peak of each step of the chain (read, level,
roughness, MPD, fill, PSD, fit, anisotropy, friction, figures) above the memory held when it
starts, and of rain fill (``roadscan rainfill``'s step, not part of analyse) on the same scan.

Run: PYTHONPATH=. .venv/bin/python benchmarks/bench_scale.py [--sizes 1024,2048,4096,8192]
[--steps]   (8192^2 needs about 4 GB of free memory and 3 to 5 minutes on 2 cores)
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SPACING = 55.4e-6
GOAL = 6.0
GOAL_FROM = 4096  # the memory goal is judged on big scans (issue 14: 8192^2)
TIME_SLACK = 1.25

GENERATE = r"""
import sys
import numpy as np
from roadscan.synth import self_affine_surface
n, path = int(sys.argv[1]), sys.argv[2]
h = self_affine_surface(n, dx_m={spacing}, hurst=0.86, rms_height_m=0.5e-3, seed=0).heights_m
h += 1e-4 * np.linspace(0.0, 1.0, n)[None, :]              # a tilt
rng = np.random.default_rng(1)
yy, xx = np.ogrid[-6:7, -6:7]
nd = int(0.025 * n * n / 60)                               # about 2.3 % of the points
for y, x, r in zip(rng.integers(6, n - 7, nd), rng.integers(6, n - 7, nd), rng.integers(2, 7, nd)):
    h[y - 6:y + 7, x - 6:x + 7][xx ** 2 + yy ** 2 <= r * r] = np.nan
np.save(path, h)
print(float(np.isnan(h).mean()))
"""

PREIMPORT = """
import numpy, scipy.fft, scipy.ndimage, scipy.sparse.linalg, scipy.special
import skimage.restoration
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot
import friction
import roadscan.level, roadscan.inpaint, roadscan.spectrum, roadscan.roughness, roadscan.fit
import roadscan.io, roadscan.trim
import pipelines.cli.app, pipelines.jobs.analyse.job, pipelines.output.report, pipelines.chain.surface
import pipelines.checks.validate, pipelines.settings.friction, pipelines.settings.scan_input
"""

MEASURE = (
    PREIMPORT
    + r"""
import json, sys, time
from pipelines.cli.app import main

def status(key):
    with open("/proc/self/status") as f:
        return [int(l.split()[1]) * 1024 for l in f if l.startswith(key)][0]

scan, out = sys.argv[1], sys.argv[2]
base = status("VmRSS:")
try:
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")                     # the peak mark (VmHWM) restarts from the current RSS
    reset = True
except OSError:
    reset = False
t = time.perf_counter()
rc = main(["analyse", scan, "--spacing", "{spacing}", "--out", out])
dt = time.perf_counter() - t
print(json.dumps({{"rc": rc, "seconds": dt, "base": base, "peak": status("VmHWM:"), "reset": reset}}))
"""
)

STEPS = (
    PREIMPORT
    + r"""
import functools, json, sys, time
import numpy as np
from roadscan import fit, inpaint, level, rain, roughness, spectrum
import pipelines.jobs.analyse.job as PA
from pipelines.output import report
from pipelines.settings.scan_input import load_scan

def status(key):
    with open("/proc/self/status") as f:
        return [int(l.split()[1]) * 1024 for l in f if l.startswith(key)][0]

def reset():
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")

rows, depth = [], [0]

def measured(label, f):
    @functools.wraps(f)
    def g(*a, **k):
        if depth[0]:
            return f(*a, **k)
        depth[0] += 1
        r0 = status("VmRSS:")
        reset()
        t = time.perf_counter()
        try:
            return f(*a, **k)
        finally:
            rows.append((label, time.perf_counter() - t, status("VmHWM:") - r0,
                         status("VmHWM:") - base, status("VmRSS:") - base))
            depth[0] -= 1
    return g

for mod, name, label in [(level, "level", "level (plane)"),
                         (roughness, "area_parameters", "roughness figures"),
                         (roughness, "mean_profile_depth_area", "MPD (ISO 13473-1)"),
                         (inpaint, "unmeasured_fill", "fill unmeasured"),
                         (spectrum, "psd_area", "psd_area"),
                         (fit, "fit_self_affine", "self-affine fit"),
                         (spectrum, "anisotropy", "anisotropy"),
                         (PA, "friction_curve", "friction mu(v)"),
                         (PA, "_figures", "figures (PNG)"),
                         (report, "write_html", "report.html")]:
    setattr(mod, name, measured(label, getattr(mod, name)))

class Args:
    spacing = "{spacing}"
    units = None

scan, out = sys.argv[1], sys.argv[2]
base = status("VmRSS:")
hm = measured("read (npy + checks)", load_scan)(scan, Args)
PA.run_analysis(hm, out, PA.FrictionSettings())
del hm
depth[0] += 1                            # rain fill on its own: the wrappers stay silent
r0 = status("VmRSS:")
scan_map = level.level(load_scan(scan, Args))
base2 = status("VmRSS:")
reset()
t = time.perf_counter()
rain.rain_fill(scan_map)
rows.append(("rain fill (not in analyse)", time.perf_counter() - t, status("VmHWM:") - base2,
             status("VmHWM:") - base2 + (base2 - r0), None))
print(json.dumps(rows))
"""
)


def child(code, *args):
    env = dict(
        os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""), MPLBACKEND="Agg"
    )
    res = subprocess.run(
        [sys.executable, "-c", code, *map(str, args)], capture_output=True, text=True, cwd=ROOT, env=env
    )
    if res.returncode != 0:
        raise SystemExit(f"child failed:\n{res.stderr[-3000:]}")
    return res.stdout.strip().splitlines()[-1]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="1024,2048,4096,8192")
    ap.add_argument("--steps", action="store_true", help="per-step peaks at the largest size")
    args = ap.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",")]
    if not Path("/proc/self/status").exists():
        print("bench_scale needs Linux's /proc to read the resident set; skipped")
        return
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_scale_") as tmp:
        tmp = Path(tmp)
        print(
            f"roadscan analyse on N x N scans (spacing {SPACING * 1e6:g} um, 2.3 % unmeasured); "
            "peak RSS above the RSS before reading, libraries pre-imported"
        )
        print(
            f"{'N':>6} {'float64 MiB':>11} {'time s':>7} {'peak MiB':>9} {'peak/array':>10} "
            f"{'t/(N^2 log N^2), rel.':>22}"
        )
        for n in sizes:
            scan = tmp / f"scan_{n}.npy"
            child(GENERATE.format(spacing=SPACING), n, scan)
            r = json.loads(child(MEASURE.format(spacing=SPACING), scan, tmp / f"out_{n}"))
            if r["rc"] != 0:
                raise SystemExit(f"analyse returned {r['rc']} at {n}^2")
            array = 8 * n * n
            rows.append(
                (
                    n,
                    r["seconds"],
                    (r["peak"] - r["base"]) / 2**20,
                    (r["peak"] - r["base"]) / array,
                    r["reset"],
                )
            )
            if n != sizes[-1]:
                scan.unlink()
        norm = [t / (n * n * math.log2(n * n)) for n, t, *_ in rows]
        for (n, t, peak, ratio, reset), v in zip(rows, norm):
            print(
                f"{n:>6} {8 * n * n / 2**20:11.0f} {t:7.2f} {peak:9.0f} {ratio:10.2f} "
                f"{v / norm[-1]:22.2f}" + ("" if reset else "  (peak over the whole life)")
            )
        if any(n < GOAL_FROM for n, *_ in rows):
            print(
                f"(below {GOAL_FROM}^2 the fixed costs of a run, about 50 MiB for the figures' "
                "canvases, the friction tables and the allocator, dominate the ratio)"
            )
        for n, t, peak, ratio, _ in rows:
            if n < GOAL_FROM:
                continue
            print(
                f"RATIO | analyse peak memory / float64 array, {n}^2 | {ratio:.2f} | <= {GOAL:g} | "
                f"{'PASS' if ratio <= GOAL else 'FAIL'} | {peak:.0f} MiB above the baseline, {t:.1f} s"
            )
        if len(rows) >= 2:
            (n1, t1, *_), (n2, t2, *_) = rows[-2], rows[-1]
            growth = (t2 / t1) / ((n2 * n2 * math.log2(n2 * n2)) / (n1 * n1 * math.log2(n1 * n1)))
            print(
                f"RATIO | analyse time growth {n1}^2 -> {n2}^2 / N^2 log N growth | {growth:.2f} | "
                f"<= {TIME_SLACK:g} | {'PASS' if growth <= TIME_SLACK else 'FAIL'} | "
                f"{t1:.1f} s -> {t2:.1f} s"
            )
        if args.steps:
            n = sizes[-1]
            steps = json.loads(
                child(STEPS.format(spacing=SPACING), tmp / f"scan_{n}.npy", tmp / f"steps_{n}")
            )
            array = 8 * n * n
            print(f"\nper step at {n}^2, in units of the float64 array ({array / 2**20:.0f} MiB):")
            print(
                f"{'step':28s} {'time s':>7} {'peak above start':>16} {'peak above base':>15} "
                f"{'held after':>10}"
            )
            for label, t, above_start, above_base, held in steps:
                held_s = "" if held is None else f"{held / array:10.2f}"
                print(f"{label:28s} {t:7.2f} {above_start / array:16.2f} {above_base / array:15.2f} {held_s}")


if __name__ == "__main__":
    main()
