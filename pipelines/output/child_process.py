"""Processes forked from the command: the figure helper (:mod:`pipelines.output.figure_process`)
and the diagnosis's fitting workers (:mod:`pipelines.diagnosis.fit.parallel`).

A fork copies the command's signal handlers (:mod:`pipelines.cli.signals` turns SIGTERM and
SIGHUP into an exception). A signal in the window between the fork and the child's own set-up
would run them in the child, so the stop signals are blocked across the fork
(:func:`block_stop_signals`), and the child gives them a fresh interpreter's dispositions
before it unblocks them (:func:`as_fresh_child`): SIGINT ignored, since a terminal's Ctrl-C
reaches the whole group and stopping the child is the parent's business; SIGTERM and SIGHUP end
it. On Linux the child also ends with its parent, however that ends. :func:`stop_pool` stops a
pool of such children at once.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from typing import Any

__all__ = [
    "STOP_SIGNALS",
    "stop_signals",
    "block_stop_signals",
    "restore_mask",
    "as_fresh_child",
    "stop_pool",
]

#: signals the command turns into an interruption (:mod:`pipelines.cli.signals`)
STOP_SIGNALS = ("SIGINT", "SIGTERM", "SIGHUP")


def stop_signals() -> list[signal.Signals]:
    """The stop signals this platform has.

    Returns
    -------
    list of signal.Signals
        Those of :data:`STOP_SIGNALS` the platform defines (SIGHUP is missing on Windows).
    """
    return [getattr(signal, n) for n in STOP_SIGNALS if hasattr(signal, n)]


def block_stop_signals() -> Any:
    """Block the stop signals in this thread, around a fork.

    Returns
    -------
    set of signal.Signals or None
        The previous mask, for :func:`restore_mask`; None where the platform cannot block
        signals (no ``pthread_sigmask``).
    """
    if not hasattr(signal, "pthread_sigmask"):
        return None
    return signal.pthread_sigmask(signal.SIG_BLOCK, stop_signals())


def restore_mask(previous: Any) -> None:
    """Put back the signal mask :func:`block_stop_signals` returned.

    Parameters
    ----------
    previous : set of signal.Signals or None
        The mask to restore; None: nothing was blocked, nothing to do.
    """
    if previous is not None:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _die_with_parent(parent_pid: int) -> None:
    """On Linux the kernel sends this process SIGKILL when its parent dies
    (``prctl(PR_SET_PDEATHSIG)``, see prctl(2)); a parent already gone ends it now. Without
    this, a forked child holds the write end of its own task queue and waits for work forever
    once the parent is killed (SIGKILL, the OOM killer)."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        ctypes.CDLL(None).prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG = 1
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent_pid:  # died before the request took effect
        os._exit(0)


def as_fresh_child(parent_pid: int | None) -> None:
    """A child's first step (a pool's ``initializer``): see the module docstring.

    Parameters
    ----------
    parent_pid : int or None
        The process the child ends with (on Linux, prctl PR_SET_PDEATHSIG; a parent already
        gone ends the child at once); None: not asked. SIGINT is then ignored, SIGTERM and
        SIGHUP take their defaults, and the stop signals are unblocked.
    """
    if parent_pid is not None:
        _die_with_parent(parent_pid)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for sig in stop_signals():
        if sig != signal.SIGINT:
            signal.signal(sig, signal.SIG_DFL)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, stop_signals())


def stop_pool(pool: Any, processes: list[Any] | None = None) -> None:
    """Stop a :class:`concurrent.futures.ProcessPoolExecutor` at once.

    Queued work is cancelled, the workers are killed where alive (concurrent.futures has no
    public call for that before Python 3.14), and the pool's manager thread is joined (at most
    5 s), so that it never closes its wake-up pipe while the interpreter's exit hook of
    concurrent.futures writes to it (a race that printed "OSError: [Errno 9] Bad file
    descriptor" after a command's one-line error).

    Parameters
    ----------
    pool : concurrent.futures.ProcessPoolExecutor
        The pool.
    processes : list of multiprocessing.Process, optional
        The workers to kill (None entries skipped); default: every worker the pool has.
    """
    if processes is None:
        processes = list((getattr(pool, "_processes", None) or {}).values())
    manager = getattr(pool, "_executor_manager_thread", None)
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in processes:
        if proc is not None and proc.is_alive():
            proc.kill()
    if manager is not None and manager is not threading.current_thread():
        manager.join(timeout=5.0)
