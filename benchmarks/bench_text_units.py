"""What the unit check of unitless text coordinates adds to reading a text file.

Cases: a 51,000-point x,z profile (a CAPTIF-like laser profile) and a 1000 x 1000 x,y,z point
list, both without unit titles. For each: the whole ``roadscan.io.read`` and the check alone
(:func:`roadscan.io.text_units.line_rms` on the heights, the only part that grows with the
file). Goal: the check under 5 % of the read. Printed: best of N wall times [s].

Run: PYTHONPATH=. .venv/bin/python benchmarks/bench_text_units.py [N]
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from roadscan.io import read
from roadscan.io.text_units import line_rms


def _best(fn, n):
    best = np.inf
    for _ in range(n):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def main(n=3):
    rng = np.random.default_rng(0)
    with tempfile.TemporaryDirectory() as d:
        prof = Path(d) / "profile.txt"
        z = np.cumsum(rng.normal(size=51_000)) * 1e-6
        np.savetxt(prof, np.column_stack([np.arange(z.size) * 3.75e-5, z]), fmt="%.6e")
        pts = Path(d) / "map.xyz"
        h = rng.normal(size=(1000, 1000)) * 1e-4
        yy, xx = np.mgrid[0:1000, 0:1000]
        np.savetxt(pts, np.column_stack([xx.ravel() * 5e-5, yy.ravel() * 5e-5, h.ravel()]), fmt="%.6e")
        for name, path, heights in (("x,z profile 51k", prof, z), ("x,y,z map 1 Mpx", pts, h)):
            t_read = _best(lambda path=path: read(path), n)
            t_check = _best(lambda heights=heights: line_rms(heights), n)
            share = 100 * t_check / t_read
            print(
                f"{name:18s} read {t_read:7.3f} s   unit check {t_check:7.4f} s   "
                f"{share:5.1f} %  {'ok' if share < 5 else 'ABOVE GOAL (5 %)'}"
            )


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 3)
