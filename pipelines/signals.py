"""SIGTERM and SIGHUP behave like Ctrl-C.

``timeout``, systemd, docker and SLURM stop a program with SIGTERM; closing a terminal sends
SIGHUP. Both raise :class:`Terminated` (a :class:`KeyboardInterrupt`) in the main thread, so
every ``except BaseException`` clean-up of :mod:`roadscan.io.atomic` runs exactly as on Ctrl-C:
the hidden temporary output is deleted and the earlier output stays. The command then exits
with the shell's convention ``128 + signal number`` (130 for SIGINT, 143 for SIGTERM, 129 for
SIGHUP) after one line on stderr.

Once the interruption has been reported (:func:`after_interrupt`), a further signal ends the
process at once with the same code (``os._exit``): nothing is half-written at that point (a
killed run's hidden folders are removed by the next run on the same target), and no library
shutting down (a Dask cluster, the figure helper) can print a traceback or turn the exit into 0.
"""
from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading

__all__ = ["Terminated", "signals_as_interrupt", "exit_code", "signal_name", "after_interrupt"]

#: signals turned into :class:`Terminated` (SIGINT keeps Python's KeyboardInterrupt)
CAUGHT = tuple(getattr(signal, n) for n in ("SIGTERM", "SIGHUP") if hasattr(signal, n))


class Terminated(KeyboardInterrupt):
    """A stop request by signal; ``signum`` is the signal's number."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = int(signum)


def _raise(signum, frame):
    raise Terminated(signum)


def exit_code(exc):
    """``128 + n`` for the signal behind ``exc`` (SIGINT for a plain KeyboardInterrupt)."""
    return 128 + int(getattr(exc, "signum", signal.SIGINT))


def signal_name(exc):
    n = int(getattr(exc, "signum", signal.SIGINT))
    try:
        return signal.Signals(n).name
    except ValueError:
        return f"signal {n}"


@contextlib.contextmanager
def signals_as_interrupt():
    """Inside the block, SIGTERM and SIGHUP raise :class:`Terminated` in the main thread and
    SIGINT raises KeyboardInterrupt (whatever handler a library installed before). Outside the
    main thread this does nothing (Python allows handlers only there)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {}
    for sig in CAUGHT + (signal.SIGINT,):
        try:
            previous[sig] = signal.signal(sig, _raise if sig != signal.SIGINT else signal.default_int_handler)
        except (OSError, ValueError):
            pass
    try:
        yield
    finally:
        for sig, old in previous.items():
            with contextlib.suppress(OSError, ValueError, TypeError):
                signal.signal(sig, old if old is not None else signal.SIG_DFL)


def after_interrupt(code):
    """After an interruption was reported: any further SIGINT/SIGTERM/SIGHUP exits with
    ``code`` at once (no traceback from a library shutting down). Call from the main thread."""
    def _now(signum, frame):
        with contextlib.suppress(Exception):
            sys.stderr.flush()
        os._exit(code)

    if threading.current_thread() is not threading.main_thread():
        return
    for sig in CAUGHT + (signal.SIGINT,):
        with contextlib.suppress(OSError, ValueError):
            signal.signal(sig, _now)
