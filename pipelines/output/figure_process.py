"""Figures drawn by a helper process while the numbers are computed.

A one-scan ``roadscan analyse`` spends about as long importing matplotlib and drawing its four
PNGs (0.35 s + 0.5 s, measured on the sample) as on the whole metrology chain, and the two are
independent: on a machine with two cores or more, :class:`FigureProcess` starts a Python
process that imports matplotlib while the scan is read and analysed, then draws each figure
as soon as its data exist (the height map right after levelling, while the spectrum is being
computed). Only small arrays travel to it: the display image of the height map (block means,
:func:`pipelines.output.report.heightmap_picture`), the central part of the 2D spectrum, the curves.

The PNGs are the same as drawn in-process (the same functions draw them). If the helper cannot
start, dies, or a figure fails in it, that figure is drawn in this process instead, so a
failure is reported exactly as without the helper. :class:`InProcess` is the same interface
without a helper (``roadscan batch`` workers, library use, one core, or
``ROADSCAN_FIGURE_PROCESS=0``).

The helper is a :class:`concurrent.futures.ProcessPoolExecutor` with one worker, started as
soon as the drawer is made; its initializer imports matplotlib. On Linux, when this process runs
no other thread (the command: nothing holds a lock while it forks), the worker is forked: it
starts with numpy and the readers already imported, and no resource-tracker process is started
(0.1 to 0.15 s less CPU time before it can draw, measured on the sample). The stop signals are
blocked across the fork and the worker puts them back as a fresh interpreter has them (SIGTERM
and SIGHUP end it, SIGINT is ignored) before it unblocks them: it never runs this process's
handlers. Elsewhere (macOS, Windows, a program with threads) it is started with ``spawn``, a
fresh interpreter that inherits none of this process's open files, locks or threads.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import sys
import threading
import types
import warnings
from typing import Any

from pipelines.output.child_process import as_fresh_child, block_stop_signals, restore_mask, stop_pool

__all__ = ["InProcess", "FigureProcess", "figure_drawer"]

ENV_SWITCH = "ROADSCAN_FIGURE_PROCESS"


class InProcess:
    """Draw each figure when it is submitted; :meth:`collect` returns the results in order.

    Attributes
    ----------
    None
        It holds only the figures submitted.
    """

    def __init__(self):
        self._done = []

    def submit(self, fn, *args, **kwargs):
        self._done.append(fn(*args, **kwargs))

    def collect(self):
        done, self._done = self._done, []
        return done

    def discard(self):
        """Forget what was drawn (or is being drawn) and not collected; nothing is redrawn."""
        self._done = []

    def close(self):
        self._done = []

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


class FigureProcess(InProcess):
    """Figures drawn by a helper process (see the module docstring).

    Attributes
    ----------
    None
        It holds the helper process and the figures submitted.
    """

    def __init__(self):
        super().__init__()
        self._pending = []  # (future, fn, args, kwargs) submitted, not yet collected
        self._sending = False  # a hand-over to the helper began and did not finish
        self._pool = self._proc = None
        try:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            method = _start_method()
            self._pool = ProcessPoolExecutor(
                max_workers=1,
                initializer=_warm_up,
                initargs=(os.getpid(),),
                mp_context=multiprocessing.get_context(method),
            )
            main = sys.modules.get("__main__")
            # the spawned worker would import the caller's script again (as __mp_main__): a
            # script without an ``if __name__ == "__main__"`` guard would run a second time
            sys.modules["__main__"] = types.ModuleType("__main__")
            blocked = block_stop_signals() if method == "fork" else None
            try:
                self._pool.submit(os.getpid)  # starts the worker now (it imports matplotlib)
                self._proc = next(iter(getattr(self._pool, "_processes", {}).values()), None)
            finally:
                sys.modules["__main__"] = main
                restore_mask(blocked)
        except (OSError, RuntimeError, ValueError, ImportError):
            self._stop()
        except BaseException:  # a stop signal (delivered once unblocked): no helper left
            self._stop()
            raise

    def submit(self, fn, *args, **kwargs):
        if self._pool is not None:
            try:
                self._sending = True  # still True if a signal interrupts the hand-over
                self._pending.append((self._pool.submit(fn, *args, **kwargs), fn, args, kwargs))
                self._sending = False
                return
            except RuntimeError:  # BrokenProcessPool included: the helper is gone
                self._stop()
        self._flush_locally()
        super().submit(fn, *args, **kwargs)

    def collect(self):
        # each figure leaves the pending list only once it is done: a signal raised while
        # waiting (pipelines.cli.signals) leaves the rest pending, so that :meth:`discard` waits for
        # them before the temporary output folder is removed (no PNG written into it after)
        while self._pending:
            future, fn, args, kwargs = self._pending[0]
            try:
                done = future.result()
            except Exception:  # noqa: BLE001 - failed or died in the helper: drawn (or failing) here
                done = fn(*args, **kwargs)
            self._pending.pop(0)
            self._done.append(done)
        return super().collect()

    def discard(self):
        pending, self._pending = self._pending, []
        for future, *_ in pending:  # wait: no figure is still being written after this
            future.exception()
        if self._sending and self._pool is not None:
            # a figure handed over while a signal came may be queued without its future: the
            # one worker runs its queue in order, so a no-op sent now returns after it
            with contextlib.suppress(Exception):
                self._pool.submit(int).result()
        self._sending = False
        super().discard()

    def _flush_locally(self):
        pending, self._pending = self._pending, []
        for future, fn, args, kwargs in pending:
            try:
                self._done.append(future.result())
            except Exception:  # noqa: BLE001
                self._done.append(fn(*args, **kwargs))

    def _stop(self):
        pool, self._pool = self._pool, None
        proc, self._proc = self._proc, None
        if pool is None:
            return
        # the worker, idle or importing, is killed (not waited for at exit) and the manager
        # thread joined: the race this avoided printed "OSError: [Errno 9] Bad file descriptor"
        # after the one-line error of a command that failed early, about once in 60 fuzz runs
        stop_pool(pool, [proc])

    def close(self):
        self._pending = []
        self._stop()
        super().close()


_started: list[Any] = []  # helpers started by this process


def figure_drawer(figures=True):
    """A :class:`FigureProcess` where it pays, else :class:`InProcess`.

    It pays for a one-shot command: figures wanted, two cores or more, matplotlib not yet
    imported here, no helper started before by this process (a program that runs ``roadscan``
    commands one after another through :func:`pipelines.cli.app.main` pays matplotlib's import once,
    on its second command, instead of a new helper each time), and not switched off by
    ``ROADSCAN_FIGURE_PROCESS=0``.

    Parameters
    ----------
    figures : bool, optional
        Figures wanted.

    Returns
    -------
    FigureProcess or InProcess
    """
    if (
        figures
        and (os.cpu_count() or 1) >= 2
        and "matplotlib.pyplot" not in sys.modules
        and not _started
        and os.environ.get(ENV_SWITCH, "1") != "0"
    ):
        _started.append(os.getpid())
        return FigureProcess()
    return InProcess()


def _start_method():
    """``"fork"`` on Linux when this process runs no other Python thread, else ``"spawn"``."""

    if (
        sys.platform.startswith("linux")
        and threading.active_count() == 1
        and "fork" in multiprocessing.get_all_start_methods()
        and hasattr(signal, "pthread_sigmask")
    ):
        return "fork"
    return "spawn"


def _warm_up(parent_pid=None):
    """The helper's initializer: matplotlib imported while the parent computes; warnings off.

    It ends with its parent, and the stop signals get a fresh interpreter's dispositions (a
    forked helper inherits the command's handlers, and the signals blocked) before they are
    unblocked (:func:`pipelines.output.child_process.as_fresh_child`)."""
    as_fresh_child(parent_pid)
    warnings.simplefilter("ignore")
    sys.stdout = sys.stderr  # a stray print never mixes into the command's output
    # no 3D projection here (0.03-0.04 s of matplotlib's import, the analyse figures are 2D):
    # matplotlib registers it only when mpl_toolkits.mplot3d imports; a 3D figure handed to
    # the helper would fail there and be drawn in the parent process (see the module docstring)
    sys.modules.setdefault("mpl_toolkits.mplot3d", None)
    from pipelines.output import report

    report.pyplot()
