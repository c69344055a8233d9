"""Warnings belong to their run: :func:`warn` records one line in the collector of the innermost
:func:`collecting` scope (a :mod:`contextvars` variable, so each thread, task and nested run has
its own); jobs store a run's list in their result (``.warnings``) and in ``summary.json`` under
``"warnings"``. :mod:`pipelines.checks.validate` re-exports every name.

How a new line is said depends on who runs the job (:func:`say_warnings`):

- ``"warn"`` (the library's default): issued once through :func:`warnings.warn` as a
  :class:`roadscan.RoadscanWarning`, so that a notebook can filter, record or silence it; the
  library never prints.
- ``"print"`` (the ``roadscan`` command): one line ``PREFIX: warning: ...`` on stderr, as the
  command has always printed it.
- ``"quiet"`` (a campaign's worker): recorded only; the campaign reports them.
"""

from __future__ import annotations

import contextlib
import contextvars
import logging
import sys
import warnings as _py_warnings

from roadscan.errors import RoadscanWarning

__all__ = [
    "Warnings",
    "collecting",
    "current_warnings",
    "reset_warnings",
    "warn",
    "warnings_list",
    "say_warnings",
    "note",
    "LOGGER",
]

#: the logger of roadscan's notes (progress, what a run chose and why); the command line shows
#: its INFO lines on stderr, a Python caller sees them once it configures logging
LOGGER = logging.getLogger("roadscan")

_MODES = ("warn", "print", "quiet")
_MODE = ["warn"]


def say_warnings(mode: str) -> str:
    """How new warning lines are said in this process: ``"warn"`` (Python's :mod:`warnings`,
    category :class:`roadscan.RoadscanWarning`; the library's default), ``"print"`` (stderr,
    the command line) or ``"quiet"`` (recorded only). Returns the previous mode."""
    if mode not in _MODES:
        raise ValueError(f"say_warnings({mode!r}): one of {_MODES}")
    old, _MODE[0] = _MODE[0], mode
    return old


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

    def add(self, line, echo=True, issue=True):
        """Record ``line`` (once) and say it as :func:`say_warnings` decides: a
        :class:`roadscan.RoadscanWarning` (``issue``), or, on the command line, ``PREFIX:
        warning: line`` on stderr (``echo`` and the collector's own ``echo``). A line handed
        over from a nested scope is neither issued nor printed again (``issue=False``)."""
        if line in self.lines:
            return False
        self.lines.append(line)
        if not issue:
            return True
        if _MODE[0] == "warn":
            _py_warnings.warn(line, RoadscanWarning, stacklevel=3)
        elif _MODE[0] == "print" and echo and self.echo:
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
                parent.add(line, echo=False, issue=False)


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
    """Record one warning line in this run's collector and say it (:func:`say_warnings`).

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


def note(message: str) -> None:
    """Say one note (not a warning: what a run chose and why, e.g. a spectrum extended beyond
    its last point) through the ``roadscan`` logger at INFO level; the command line prints it
    on stderr as it always has.

    Parameters
    ----------
    message : str
        One line.
    """
    LOGGER.info("%s", message)
