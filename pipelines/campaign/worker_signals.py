"""Dask preload of a local campaign's worker processes: Ctrl-C is the parent's business.

A terminal's Ctrl-C goes to every process of the foreground group, so each local worker got
SIGINT too and printed its own KeyboardInterrupt traceback after the parent's one-line
"interrupted". The workers ignore SIGINT; the parent cancels their scans and closes
the cluster, which stops them. Loaded through ``distributed.worker.preload`` by
:func:`pipelines.campaign.runner._client` (local clusters only; an existing cluster's workers
are left as their owner started them).
"""

from __future__ import annotations

import contextlib
import signal
import threading


def dask_setup(worker=None):
    """Ignore SIGINT in this worker process (Dask calls this once at worker start)."""
    if threading.current_thread() is threading.main_thread():
        with contextlib.suppress(OSError, ValueError):
            signal.signal(signal.SIGINT, signal.SIG_IGN)
