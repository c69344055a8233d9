"""Independent candidate fits on several cores.

The diagnosis fits its candidates in stages (every effect alone, the calibration, every effect
with the calibration...); within a stage the fits share nothing: each starts from its own starts
and a fresh evaluation cache. :func:`fit_map` runs one stage's fits in worker processes forked
from this one (copy-on-write: the context, the measured curve and the effects are not copied or
pickled; only each fitted candidate comes back). The most expensive fits are handed out first
(longest processing time first, Graham 1969, doi:10.1137/0117039), and the results are returned
in the order of the items, so the diagnosis is the same to the last bit as the serial loop; only
the wall time changes. That holds because every model evaluation is a function of its inputs
alone, whatever the process computed before (the friction engine's interpolation tables
included, :func:`friction.grids.phi_table`). Python warnings a fit raises in a worker are raised
again in this process, in item order. A stop request (Ctrl-C, SIGTERM) or a failed fit cancels
the queued fits and kills the running ones; the workers are set up as the figure helper's are
(:mod:`pipelines.output.child_process`: the stop signals blocked across the fork, Ctrl-C
ignored in them, and on Linux they die with this process).

A fitted candidate travels without its effects (their model functions are closures that do not
pickle): :func:`portable` replaces each by its position among the effects the fit was given, and
for an effect narrowed to its physical ranges (:meth:`effects.Effect.restricted`) also its new
bounds; :func:`restore` puts the same effects back from this process's own copies.

How many workers: :func:`workers` (a scope set by the job, ``roadscan diagnose --workers N``);
by default one per core available to the process. One worker, a single item, a daemon process
(a worker of some other pool, which may not have children) or a platform without ``fork`` runs
the loop in this process.
"""

from __future__ import annotations

import contextlib
import contextvars
import multiprocessing
import os
import warnings
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from typing import Any

from pipelines.output.child_process import as_fresh_child, block_stop_signals, restore_mask, stop_pool

__all__ = ["default_workers", "fit_map", "workers", "use_workers", "portable", "restore"]

_WORKERS: contextvars.ContextVar[int | None] = contextvars.ContextVar("diagnosis_workers", default=None)
#: the warnings re-raised here so far (warnings.warn_explicit's registry: the "default" action
#: shows one per text and line, as the serial loop's own registry would)
_SHOWN: dict[Any, Any] = {}
#: the stage a forked worker runs: (function, items); set only while a pool is open
_STAGE: tuple[Callable[[Any], Any], Sequence[Any]] | None = None


def default_workers() -> int:
    """One worker per core available to this process.

    Returns
    -------
    int
        The cores of this process's CPU affinity (Linux), else the machine's, at least 1.
    """
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def workers() -> int:
    """The number of worker processes a stage may use in the current scope.

    Returns
    -------
    int
        The number :func:`use_workers` set, else :func:`default_workers` (at least 1 either way;
        1 fits in this process).
    """
    n = _WORKERS.get()
    return default_workers() if n is None else n


@contextlib.contextmanager
def use_workers(n: int | None) -> Iterator[None]:
    """Fit with ``n`` worker processes inside the ``with`` block.

    Parameters
    ----------
    n : int or None
        Worker processes; None: one per core (:func:`default_workers`); 1: in this process.

    Yields
    ------
    None
        The scope; the previous number is back when it ends.

    Raises
    ------
    ValueError
        ``n`` below 1.
    """
    if n is not None and int(n) < 1:
        raise ValueError(f"workers must be at least 1, got {n}")
    token = _WORKERS.set(None if n is None else int(n))
    try:
        yield
    finally:
        _WORKERS.reset(token)


def _run(i: int) -> tuple[Any, list[tuple[str, type[Warning], str, int]]]:
    """Worker side: item ``i`` of the stage, with the warnings it raised (under the filters this
    process had when it was forked, so a warning configured to raise still raises)."""
    assert _STAGE is not None
    fn, items = _STAGE
    with warnings.catch_warnings(record=True) as caught:
        out = fn(items[i])
    return out, [(str(w.message), w.category, w.filename, w.lineno) for w in caught]


def fit_map(
    fn: Callable[[Any], Any], items: Sequence[Any], *, cost: Callable[[Any], float] | None = None
) -> list[Any]:
    """``[fn(x) for x in items]`` on :func:`workers` processes, the results in item order.

    Parameters
    ----------
    fn : callable
        One fit: a deterministic function of its item (closures are fine: the workers are forks).
        Its result must pickle.
    items : sequence
        One argument of ``fn`` per fit (e.g. the stage's effects); the forked workers inherit them
        and receive only an index, so they need not pickle.
    cost : callable, optional
        Relative cost of an item; the costliest are started first (default: item order).

    Returns
    -------
    list
        ``fn(item)`` for every item, in the order of ``items``. An exception in a fit is raised
        here, as the serial loop would.
    """
    global _STAGE
    items = list(items)
    n = min(workers(), len(items))
    if (
        n <= 1
        or _STAGE is not None  # already a worker
        or multiprocessing.current_process().daemon  # a daemon (a pool's worker) has no children
        or "fork" not in multiprocessing.get_all_start_methods()
    ):
        return [fn(x) for x in items]
    order = sorted(range(len(items)), key=lambda i: -cost(items[i])) if cost else list(range(len(items)))
    _STAGE = (fn, items)
    try:
        ex = ProcessPoolExecutor(
            n,
            mp_context=multiprocessing.get_context("fork"),
            initializer=as_fresh_child,
            initargs=(os.getpid(),),
        )
        try:
            blocked = block_stop_signals()  # the first submit forks every worker
            try:
                futures = {i: ex.submit(_run, i) for i in order}
            finally:
                restore_mask(blocked)
            done = [futures[i].result() for i in range(len(items))]
        except BaseException:  # a stop request (Ctrl-C, SIGTERM) or a failed fit: no fit left running
            stop_pool(ex)
            raise
        ex.shutdown(wait=True)
    finally:
        _STAGE = None
    out = []
    for result, caught in done:
        for message, category, filename, lineno in caught:
            warnings.warn_explicit(message, category, filename, lineno, registry=_SHOWN)
        out.append(result)
    return out


def portable(c: Any, effects: Sequence[Any]) -> Any:
    """Worker side: a fitted candidate made picklable (see the module docstring).

    Parameters
    ----------
    c : fitting.Candidate
        A candidate fitted with ``effects`` in order, some of them possibly narrowed to their
        physical ranges (:meth:`effects.Effect.restricted`).
    effects : sequence of Effect
        The effects the fit was given.

    Returns
    -------
    fitting.Candidate
        A shallow copy whose ``effects`` are tokens: ``(i,)`` for ``effects[i]`` itself,
        ``(i, params, null_kept)`` for its narrowed copy; every other attribute as in ``c``.
    """
    import copy

    tokens: list[tuple[Any, ...]] = []
    for i, e in enumerate(c.effects):
        given = effects[i]
        if e is given:
            tokens.append((i,))
        else:  # a narrowed copy: dataclasses.replace(given, params=..., null=...)
            tokens.append((i, e.params, e.null is given.null))
    out = copy.copy(c)  # keeps what the fit set besides the dataclass fields (evidence, ...)
    out.effects = tuple(tokens)
    return out


def restore(c: Any, effects: Sequence[Any]) -> Any:
    """This side: the candidate :func:`portable` sent, with its effects put back.

    Parameters
    ----------
    c : fitting.Candidate
        As :func:`portable` returned it.
    effects : sequence of Effect
        This process's copies of the effects the fit was given (the same order).

    Returns
    -------
    fitting.Candidate
        A shallow copy with ``effects[i]`` for each ``(i,)`` and a narrowed copy of it
        (``dataclasses.replace`` with the sent bounds and null point) for each longer token.
    """
    import copy
    from dataclasses import replace

    out = []
    for t in c.effects:
        given = effects[t[0]]
        out.append(given if len(t) == 1 else replace(given, params=t[1], null=given.null if t[2] else None))
    c = copy.copy(c)
    c.effects = tuple(out)
    return c
