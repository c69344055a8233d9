"""Figures drawn by a helper process while the numbers are computed.

A one-scan ``roadscan analyse`` spends about as long importing matplotlib and drawing its four
PNGs (0.35 s + 0.5 s, measured on the sample) as on the whole metrology chain, and the two are
independent: on a machine with two cores or more, :class:`FigureProcess` starts a Python
process that imports matplotlib while the scan is read and analysed, then draws each figure
as soon as its data exist (the height map right after levelling, while the spectrum is being
computed). Only small arrays travel to it: the display image of the height map (block means,
:func:`pipelines.report.heightmap_picture`), the central part of the 2D spectrum, the curves.

The PNGs are the same as drawn in-process (the same functions draw them). If the helper cannot
start, dies, or a figure fails in it, that figure is drawn in this process instead, so a
failure is reported exactly as without the helper. :class:`InProcess` is the same interface
without a helper (``roadscan batch`` workers, library use, one core, or
``ROADSCAN_FIGURE_PROCESS=0``).

Protocol: pickled ``(module, function name, args, kwargs)`` on the helper's stdin, one pickled
``("ok", result)`` or ``("error", message)`` back on a private copy of its stdout (the helper's
own ``sys.stdout`` goes to its stderr, so a stray print cannot corrupt the stream).
"""
from __future__ import annotations

import os
import pickle
import subprocess
import sys
from pathlib import Path

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
    """Figures drawn by a helper Python process (see the module docstring).

    Attributes
    ----------
    None
        It holds the helper process and the figures submitted.
    """

    def __init__(self):
        super().__init__()
        root = str(Path(__file__).resolve().parents[1])
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(
            [root, *[p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]]))
        self._pending = []            # (fn, args, kwargs) sent and not yet answered
        try:
            self._proc = subprocess.Popen([sys.executable, "-m", "pipelines.figure_process"],
                                          stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                          stderr=subprocess.DEVNULL, env=env)
        except OSError:
            self._proc = None

    def submit(self, fn, *args, **kwargs):
        if self._proc is not None:
            try:
                pickle.dump((fn.__module__, fn.__name__, args, kwargs), self._proc.stdin,
                            protocol=pickle.HIGHEST_PROTOCOL)
                self._proc.stdin.flush()
                self._pending.append((fn, args, kwargs))
                return
            except (OSError, pickle.PicklingError, AttributeError, TypeError):
                self._stop()
        self._flush_locally()
        super().submit(fn, *args, **kwargs)

    def collect(self):
        while self._pending:
            fn, args, kwargs = self._pending[0]
            reply = None
            if self._proc is not None:
                try:
                    reply = pickle.load(self._proc.stdout)
                except Exception:  # noqa: BLE001 - the helper died: draw the rest here
                    self._stop()
            self._pending.pop(0)
            if reply is not None and reply[0] == "ok":
                self._done.append(reply[1])
            else:                   # a figure that failed in the helper fails here, as usual
                self._done.append(fn(*args, **kwargs))
        return super().collect()

    def discard(self):
        while self._pending and self._proc is not None:
            self._pending.pop(0)
            try:
                pickle.load(self._proc.stdout)
            except Exception:  # noqa: BLE001
                self._stop()
        self._pending = []
        super().discard()

    def _flush_locally(self):
        pending, self._pending = self._pending, []
        for fn, args, kwargs in pending:
            self._done.append(fn(*args, **kwargs))

    def _stop(self, wait=True):
        proc, self._proc = self._proc, None
        if proc is None:
            return
        for f in (proc.stdin, proc.stdout):
            try:
                f.close()
            except OSError:
                pass
        if not wait:       # it ends on the closed stdin; subprocess reaps it later (no zombie
            return         # is waited for: its interpreter's shutdown took 0.1 s of the command)
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()

    def close(self):
        self._pending = []
        self._stop(wait=False)
        super().close()


_started = []       # helpers started by this process


def figure_drawer(figures=True):
    """A :class:`FigureProcess` where it pays, else :class:`InProcess`.

    It pays for a one-shot command: figures wanted, two cores or more, matplotlib not yet
    imported here, no helper started before by this process (a program that runs ``roadscan``
    commands one after another through :func:`pipelines.cli.main` pays matplotlib's import once,
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
    if (figures and (os.cpu_count() or 1) >= 2 and "matplotlib.pyplot" not in sys.modules
            and not _started and os.environ.get(ENV_SWITCH, "1") != "0"):
        _started.append(os.getpid())
        return FigureProcess()
    return InProcess()


def _serve():
    import importlib
    import warnings

    out = os.fdopen(os.dup(sys.stdout.fileno()), "wb")
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())   # prints go to stderr, not the replies
    warnings.simplefilter("ignore")
    from . import report

    report.pyplot()                      # import matplotlib now, while the parent computes
    inp = sys.stdin.buffer
    while True:
        try:
            module, name, args, kwargs = pickle.load(inp)
        except (EOFError, OSError, ValueError, pickle.UnpicklingError):
            return
        try:
            fn = getattr(importlib.import_module(module), name)
            reply = ("ok", fn(*args, **kwargs))
        except Exception as exc:  # noqa: BLE001 - the parent draws this figure itself
            reply = ("error", f"{type(exc).__name__}: {exc}")
        try:
            pickle.dump(reply, out, protocol=pickle.HIGHEST_PROTOCOL)
            out.flush()
        except (OSError, pickle.PicklingError):
            return


if __name__ == "__main__":
    try:
        _serve()
    except KeyboardInterrupt:
        pass
