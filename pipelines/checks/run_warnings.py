"""Warnings belong to their run: :func:`warn` prints one line ``PREFIX: warning: ...`` on stderr
and records it in the collector of the innermost :func:`collecting` scope (a :mod:`contextvars`
variable, so each thread, task and nested run has its own); commands store a run's list in
``summary.json`` under ``"warnings"``. :mod:`pipelines.checks.validate` re-exports every name.
"""
from __future__ import annotations

import contextlib
import contextvars
import sys

__all__ = ["Warnings", "collecting", "current_warnings", "reset_warnings", "warn", "warnings_list"]


class Warnings:
    """The warnings of one run (one scan, one command): lines in the order first said, each
    once. :func:`warn` records into the collector of the innermost :func:`collecting` scope
    (a :mod:`contextvars` variable: each thread, task and nested run has its own), so two runs
    in one process, or many files in one call, never share a warning.

    Parameters
    ----------
    prefix : str, optional
        Program name printed before each line.
    echo : bool, optional
        Print each new line on stderr as it is said (default). A command that writes its
        outputs atomically collects with ``echo=False`` and calls :meth:`print_all` once the
        outputs are in place, so an interrupted or refused run prints no warning about
        outputs that never appeared.
    """

    def __init__(self, prefix="roadscan", echo=True):
        self.prefix = prefix
        self.lines = []
        self.echo = echo

    def add(self, line, echo=True):
        """Record ``line`` (once); ``echo`` (and the collector's own ``echo``) prints
        ``PREFIX: warning: line`` on stderr."""
        if line in self.lines:
            return False
        self.lines.append(line)
        if echo and self.echo:
            print(f"{self.prefix}: warning: {line}", file=sys.stderr)
        return True

    def print_all(self):
        """Print every line on stderr (``PREFIX: warning: line``), in the order first said.

        Returns
        -------
        None
        """
        for line in self.lines:
            print(f"{self.prefix}: warning: {line}", file=sys.stderr)

    def __iter__(self):
        return iter(list(self.lines))

    def __len__(self):
        return len(self.lines)


_CURRENT = contextvars.ContextVar("roadscan_warnings", default=None)


def current_warnings():
    """The collector :func:`warn` records into (one is started in this context if none is).

    Parameters
    ----------
    None

    Returns
    -------
    Warnings
    """
    w = _CURRENT.get()
    if w is None:
        w = Warnings()
        _CURRENT.set(w)
    return w


@contextlib.contextmanager
def collecting(into=None, prefix=None):
    """A scope of its own for warnings: ``with collecting() as w: ...`` records every
    :func:`warn` inside into ``w`` (a :class:`Warnings`; ``into`` re-enters a given one). On
    leaving, the lines are also handed to the enclosing scope (not printed again), so a
    command that runs several scans still sees them all.

    Parameters
    ----------
    into : Warnings, optional
        Collector to re-enter.
    prefix : str, optional
        Program name.

    Yields
    ------
    Warnings
        The scope's collector.

    Returns
    -------
    contextlib.AbstractContextManager
        Use with ``with``; the block receives the scope's :class:`Warnings`.
    """
    parent = _CURRENT.get()
    w = into if into is not None else Warnings(prefix or (parent.prefix if parent else "roadscan"))
    token = _CURRENT.set(w)
    try:
        yield w
    finally:
        _CURRENT.reset(token)
        if parent is not None and parent is not w:
            for line in w.lines:
                parent.add(line, echo=False)


def reset_warnings(prefix="roadscan"):
    """Start a new collector in this context (the CLI calls this at the start of every command).

    Parameters
    ----------
    prefix : str, optional
        Program name.

    Returns
    -------
    None
    """
    _CURRENT.set(Warnings(prefix))


def warn(message):
    """Print one warning line on stderr and record it in this run's collector.

    Parameters
    ----------
    message : str
        One line.

    Returns
    -------
    None
    """
    current_warnings().add(" ".join(str(message).split()))


def warnings_list():
    """The warnings of the current scope (a new list).

    Parameters
    ----------
    None

    Returns
    -------
    list of str
    """
    return list(current_warnings().lines)
