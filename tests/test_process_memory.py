"""The command's allocator policy: glibc's mmap threshold fixed, so that freed band arrays
go back to the system (peak memory of big scans), unless the user set it."""
from __future__ import annotations

import subprocess
import sys

import pytest

CODE = """
import sys
from pipelines.process_memory import return_freed_memory
print(return_freed_memory())
"""


def _run(env_extra):
    import os

    env = {k: v for k, v in os.environ.items() if k != "MALLOC_MMAP_THRESHOLD_"}
    env.update(env_extra)
    out = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True, env=env,
                         check=True)
    return out.stdout.strip()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's mallopt")
def test_threshold_set_on_glibc_unless_the_user_chose_one():
    import platform

    if platform.libc_ver()[0] != "glibc":
        pytest.skip("not glibc")
    assert _run({}) == "True"
    assert _run({"MALLOC_MMAP_THRESHOLD_": "65536"}) == "False"   # the user's choice is kept


def test_freed_band_arrays_are_returned_to_the_system():
    """After the policy, a run of freed 2 MiB blocks (a band's size) leaves resident memory
    where it was; without it glibc's rising threshold keeps them in its heap."""
    import platform

    if not sys.platform.startswith("linux") or platform.libc_ver()[0] != "glibc":
        pytest.skip("glibc only")
    code = r'''
import sys
import numpy as np
if sys.argv[1] == "policy":
    from pipelines.process_memory import return_freed_memory
    return_freed_memory()
def rss():
    return [int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmRSS:")][0]
big = np.ones(1 << 21); del big                  # a mapped 16 MiB block freed: glibc raises its threshold
before = rss()
keep, pins = [], []
for _ in range(64):                              # 64 blocks of 2 MiB, each followed by a
    keep.append(np.ones(1 << 18))                # small live allocation (as a chain leaves
    pins.append(bytearray(4096))                 # results behind), then the blocks freed
del keep
print(rss() - before)
'''
    grown = {}
    for mode in ("policy", "default"):
        out = subprocess.run([sys.executable, "-c", code, mode], capture_output=True, text=True,
                             check=True)
        grown[mode] = int(out.stdout.strip())          # kB
    assert grown["policy"] < 16 * 1024, grown           # returned (a few pages of bookkeeping)
    assert grown["default"] > 64 * 1024, grown          # kept in the heap: what the policy avoids
