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

__all__ = [
    "Terminated",
    "signals_as_interrupt",
    "received",
    "exit_code",
    "signal_name",
    "after_interrupt",
    "exit_early_on_signals",
    "own_the_process",
    "work_finished",
]

#: signals turned into :class:`Terminated` (SIGINT keeps Python's KeyboardInterrupt)
CAUGHT = tuple(getattr(signal, n) for n in ("SIGTERM", "SIGHUP") if hasattr(signal, n))


class Terminated(KeyboardInterrupt):
    """A stop request by signal; ``signum`` is the signal's number.

    Parameters
    ----------
    signum : int
        Signal number.
    """

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = int(signum)


#: the last signal :func:`signals_as_interrupt` turned into an exception (code that catches
#: the interruption and raises a plain KeyboardInterrupt again keeps its exit code this way)
_LAST = {"signum": None}


def _quiet():
    """From the first stop request on, libraries winding down (a Dask cluster closing while its
    workers start: asyncio's "Task exception was never retrieved", "Exception ignored in ...")
    print nothing: the command's one line says what happened."""
    import logging

    logging.disable(logging.CRITICAL)
    sys.unraisablehook = lambda unraisable: None
    threading.excepthook = lambda args: None  # a helper thread stopped mid-import


def _raise(signum, frame):
    _LAST["signum"] = int(signum)
    _quiet()
    raise Terminated(signum)


def _int(signum, frame):
    _LAST["signum"] = int(signum)
    _quiet()
    raise KeyboardInterrupt


def _signum(exc):
    return int(getattr(exc, "signum", None) or _LAST["signum"] or signal.SIGINT)


def received():
    """The signal number a stop request arrived with inside :func:`signals_as_interrupt`
    (None when none did): a library that swallowed the exception cannot turn it into exit 0.

    Parameters
    ----------
    None

    Returns
    -------
    int or None
    """
    return _LAST["signum"]


def exit_code(exc):
    """``128 + n`` for the signal behind ``exc`` (SIGINT for a plain KeyboardInterrupt).

    Parameters
    ----------
    exc : BaseException
        The interruption.

    Returns
    -------
    int
    """
    return 128 + _signum(exc)


def signal_name(exc):
    """The name of the signal behind ``exc`` (``"SIGTERM"``), or ``"signal N"``.

    Parameters
    ----------
    exc : BaseException
        The interruption.

    Returns
    -------
    str
    """
    n = _signum(exc)
    try:
        return signal.Signals(n).name
    except ValueError:
        return f"signal {n}"


@contextlib.contextmanager
def signals_as_interrupt(restore=True):
    """Inside the block, SIGTERM and SIGHUP raise :class:`Terminated` in the main thread and
    SIGINT raises KeyboardInterrupt (whatever handler a library installed before). A signal the
    parent set to be ignored stays ignored (``nohup`` ignores SIGHUP). Outside the main thread
    this does nothing (Python allows handlers only there). With ``restore`` the handlers, the
    logging switch, ``sys.unraisablehook`` and ``threading.excepthook`` are as before after the block (a
    program calling ``main()``); the command line passes False (the process ends with the block).

    Parameters
    ----------
    restore : bool, optional
        Restore the handlers after the block.

    Yields
    ------
    None

    Returns
    -------
    contextlib.AbstractContextManager
        Use with ``with``.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    import logging

    _LAST["signum"] = None
    hook, disabled = sys.unraisablehook, logging.root.manager.disable
    thread_hook = threading.excepthook
    previous = {}
    for sig in CAUGHT + (signal.SIGINT,):
        try:
            if signal.getsignal(sig) == signal.SIG_IGN:  # nohup, a shell's background job
                continue
            previous[sig] = signal.signal(sig, _raise if sig != signal.SIGINT else _int)
        except (OSError, ValueError):
            pass
    try:
        yield
    finally:
        if restore:
            for sig, old in previous.items():
                with contextlib.suppress(OSError, ValueError, TypeError):
                    signal.signal(sig, old if old is not None else signal.SIG_DFL)
            sys.unraisablehook = hook
            threading.excepthook = thread_hook
            logging.disable(disabled)


def after_interrupt(code):
    """After an interruption was reported: any further SIGINT/SIGTERM/SIGHUP exits with
    ``code`` at once, and what libraries print while the interpreter shuts down (log records,
    "Exception ignored in atexit callback" of a Dask cluster that was closing when the signal
    came) is not shown: the user has the one line already. Call from the main thread.

    Parameters
    ----------
    code : int
        Exit code.

    Returns
    -------
    None
    """
    _quiet()

    def _now(signum, frame):
        with contextlib.suppress(Exception):
            sys.stderr.flush()
        os._exit(code)

    if threading.current_thread() is not threading.main_thread():
        return
    for sig in CAUGHT + (signal.SIGINT,):
        with contextlib.suppress(OSError, ValueError):
            signal.signal(sig, _now)


def exit_early_on_signals(prog="roadscan"):
    """Until :func:`signals_as_interrupt` takes over: SIGINT/SIGTERM/SIGHUP print one line and
    exit with 128 + signal at once (the program is still importing: nothing to clean up, and
    Python's own SIGINT handler would print a traceback from the import machinery). Signals the
    parent set to be ignored stay ignored.

    Parameters
    ----------
    prog : str, optional
        Program name in the line.

    Returns
    -------
    None
    """

    def _early(signum, frame):
        name = "" if signum == signal.SIGINT else f" ({signal.Signals(signum).name})"
        with contextlib.suppress(Exception):
            sys.stderr.write(f"{prog}: interrupted{name}\n")
            sys.stderr.flush()
        os._exit(128 + signum)

    _handle_stop_signals(_early)


def _handle_stop_signals(handler):
    """SIGINT, SIGTERM and SIGHUP to ``handler`` (a function, or SIG_IGN), from the main thread
    only (Python allows handlers only there); a signal the parent set to be ignored (``nohup``)
    stays ignored."""
    if threading.current_thread() is not threading.main_thread():
        return
    for sig in CAUGHT + (signal.SIGINT,):
        with contextlib.suppress(OSError, ValueError):
            if signal.getsignal(sig) != signal.SIG_IGN:
                signal.signal(sig, handler)


#: whether this process is the ``roadscan`` command itself (set by its ``main`` when it reads
#: the real command line); a program calling ``main(argv)`` keeps its own signal handling
_OWN = {"process": False}


def own_the_process():
    """Mark this process as the command line's own: :func:`work_finished` may then change how
    it answers stop signals until it exits. Also, at exit (an :mod:`atexit` hook registered
    first, so run after every library's own), stop signals are ignored: Python's shutdown puts
    the default action back for every signal that had a Python handler, and a signal in that
    last window would kill the process with -signal instead of its own exit code.

    Returns
    -------
    None
    """
    import atexit

    if not _OWN["process"]:
        _OWN["process"] = True
        atexit.register(_ignore_stop_signals)


def _ignore_stop_signals():
    _handle_stop_signals(signal.SIG_IGN)


def work_finished():
    """The command's outputs are complete and in place: from now on SIGINT, SIGTERM and SIGHUP
    are ignored, and the command ends with its own exit code after saying its warnings and
    closing its helpers (a stop request then has nothing left to stop: reporting
    "interrupted", or dying by the signal, would deny outputs that exist). Does nothing unless
    :func:`own_the_process` was called (a program calling ``main(argv)``, a test).

    Returns
    -------
    None
    """
    if _OWN["process"]:
        _ignore_stop_signals()
