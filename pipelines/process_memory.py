"""Freed memory goes back to the system at once in a ``roadscan`` process (glibc only).

glibc's ``malloc`` serves a block of at least ``M_MMAP_THRESHOLD`` bytes by a private mapping,
returned to the system when freed; smaller blocks come from heaps (one per thread) that keep
freed memory for reuse. The threshold starts at 128 KiB but rises, after each mapped block is
freed, to that block's size (up to 32 MiB on 64-bit systems): a command that frees band-sized
arrays of a few MiB (the chain's row bands) then keeps them in its heaps, and two threads
working side by side (the texture figures beside the spectrum) each keep their own. On a
4096 x 4096 scan that is about 1.1 times the scan's float64 array of peak memory for nothing.
:func:`return_freed_memory` fixes the threshold at 1 MiB (a fixed value also stops the
rise), as ``MALLOC_MMAP_THRESHOLD_=1048576`` in the environment would.

Only :func:`pipelines.cli.main` calls it (the ``roadscan`` command, or a program running
commands through it); a program using the library's functions keeps its allocator as it is.
Elsewhere than on glibc it does nothing.

References
----------
The GNU C Library manual, "Malloc Tunable Parameters" (``mallopt``, ``M_MMAP_THRESHOLD``).
"""
from __future__ import annotations

import os
import sys

__all__ = ["return_freed_memory", "MMAP_THRESHOLD_BYTES"]

#: blocks of at least this size are mapped, and unmapped when freed [bytes]
MMAP_THRESHOLD_BYTES = 1 << 20
_M_MMAP_THRESHOLD = -3           # glibc's malloc.h


def return_freed_memory():
    """Fix glibc's mmap threshold at :data:`MMAP_THRESHOLD_BYTES` (unless the environment sets
    ``MALLOC_MMAP_THRESHOLD_``); True when done.

    Returns
    -------
    bool
        Whether the threshold was set (False off glibc or when the user chose one).

    Parameters
    ----------
    None
    """
    if not sys.platform.startswith("linux") or "MALLOC_MMAP_THRESHOLD_" in os.environ:
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None)
        mallopt = getattr(libc, "mallopt", None)
        if mallopt is None or not hasattr(libc, "gnu_get_libc_version"):
            return False
        mallopt.argtypes, mallopt.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
        return bool(mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES))
    except (OSError, AttributeError):
        return False
