"""The client side of a campaign: a local Dask cluster or an existing one, progress, Ctrl-C.

Work is submitted as one task per input (:func:`.worker.run_job`); each returns a few small
records. Workers read the files and write the outputs themselves, so the files must be
reachable under the same paths from every worker (one machine, or a shared file system).

One scan per worker at a time: the local cluster has one thread per worker process; on an
existing cluster start the workers with ``--nthreads 1``, or give them the resource ``scan=1``
(``dask worker ... --resources scan=1``): when every worker has it, each task asks for one.
"""

from __future__ import annotations

import contextlib
import logging
import os
import sys

from pipelines.campaign.folder import read_sidecar, same_input
from pipelines.campaign.records import error_record
from pipelines.campaign.worker import run_job
from roadscan.errors import InputError

__all__ = ["default_workers", "resumed_records", "run_campaign", "Interrupted"]


class Interrupted(Exception):
    """Ctrl-C during a campaign; ``records`` holds what finished (others marked).

    Parameters
    ----------
    records : list
        What finished.
    """

    def __init__(self, records):
        super().__init__("interrupted")
        self.records = records


def default_workers():
    """One worker per core available to this process.

    Parameters
    ----------
    None

    Returns
    -------
    int
    """
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def resumed_records(job):
    """The records of a finished scan when its outputs exist, the options are the same and the
    input is unchanged (size and mtime, or SHA-256); else None.

    Parameters
    ----------
    job : dict
        The job.

    Returns
    -------
    list of dict or None
    """
    from pathlib import Path

    folder = Path(job["out"]) / job["subdir"]
    side = read_sidecar(folder)
    if not side or side.get("options") != job.get("fingerprint"):
        return None
    recs = side.get("records") or []
    if not recs or any(r.get("status") != "ok" for r in recs):
        return None
    if not same_input(job.get("path") or job["file"], side.get("input") or {}):
        return None
    if not (folder / "summary.json").exists() and not (folder / "sections.csv").exists():
        return None
    base = job.get("chainage_m")
    for r in recs:  # manifest label/chainage may have been edited since: take today's
        r["file"], r["label"] = job["file"], job.get("label") or ""
        start = r.get("values", {}).get("section_start_m")
        r["chainage_m"] = base if start is None else (base or 0.0) + start
    return recs


def _finished_on_worker(job):
    try:
        return resumed_records(job)
    except Exception:  # noqa: BLE001 - a half-visible folder is simply not finished
        return None


#: Dask's nannies start workers with MALLOC_TRIM_THRESHOLD_=65536 (``distributed.nanny.
#: pre-spawn-environ``). Setting it turns off glibc's dynamic mmap threshold, so every array
#: above 128 KiB is a fresh mmap, page-faulted in and unmapped again: measured on 1024^2
#: scans, run_job took 0.23 s per scan with it and 0.10 s without (the same in one process).
#: A local cluster's workers are started without it (a value the user set is kept); the
#: memory a worker holds stays bounded by one scan's peak, arrays above 32 MiB are always
#: returned to the system. Workers of an existing cluster (``--scheduler``) keep their own.
_TRIM_ENV = "MALLOC_TRIM_THRESHOLD_"
_TRIM_KEY = "distributed.nanny.pre-spawn-environ." + _TRIM_ENV
#: local workers log critical records only: their INFO records ("Received 'close-stream'...")
#: reached the terminal after the one-line "interrupted" of a stopped campaign, and so did, under
#: load, an ERROR with its traceback ("Failed to communicate with scheduler during heartbeat":
#: the scheduler already gone); a scan's failure reaches us through its future
_WORKER_LOG_KEY = "distributed.nanny.pre-spawn-environ.DASK_LOGGING__DISTRIBUTED"


@contextlib.contextmanager
def _quiet_event_loop():
    """Errors that Dask's event loop logs from its own callbacks (``tornado.application``) are
    not printed while a campaign runs: every scan's failure reaches us through its future, and
    Ctrl-C at the wrong moment made distributed 2026.x log a NameError traceback from its
    ``sync`` cancel path before our one-line "interrupted"."""
    log = logging.getLogger("tornado.application")
    level = log.level
    log.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        log.setLevel(level)


@contextlib.contextmanager
def _client(workers=None, scheduler=None):
    import dask
    from distributed import Client, LocalCluster

    if scheduler:
        _check_reachable(scheduler)
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise InputError(None, f"--scheduler {scheduler}: cannot connect ({exc})") from None
        try:
            yield client
        finally:
            client.close()
        return
    n = workers or default_workers()
    box = []
    trim = dask.config.set({_TRIM_KEY: None}) if _TRIM_ENV not in os.environ else contextlib.nullcontext()
    try:
        with (
            trim,
            dask.config.set(
                {
                    _WORKER_LOG_KEY: "critical",
                    "distributed.worker.preload": ["pipelines.campaign.worker_signals"],
                }
            ),
            _sigint_blocked(),
        ):
            box.append(
                LocalCluster(
                    n_workers=n,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                    silence_logs=logging.ERROR,
                )
            )
    except Exception as exc:  # noqa: BLE001 - e.g. a script without the __main__ guard
        raise InputError(
            None, f"--workers {n}: cannot start a local Dask cluster ({type(exc).__name__}: {exc})"
        ) from None
    except KeyboardInterrupt:  # Ctrl-C held while the workers started: arrives here
        for cluster in box:
            with contextlib.suppress(Exception):
                cluster.close()
        raise
    cluster = box[0]
    client = Client(cluster)
    try:
        yield client
    finally:
        with contextlib.suppress(Exception):
            client.close()
        with contextlib.suppress(Exception):
            cluster.close()


@contextlib.contextmanager
def _sigint_blocked():
    """SIGINT blocked in this (the main) thread while a local cluster starts: the cluster's
    event-loop thread, started now, inherits the mask, and so do the worker processes it spawns
    (a signal mask survives ``exec``), so a terminal's Ctrl-C, sent to the whole process group,
    never reaches a worker that is still importing, before its preload ignores SIGINT
    (:mod:`pipelines.campaign.worker_signals`): it printed a KeyboardInterrupt traceback from
    the import machinery. A Ctrl-C meanwhile stays pending and stops the campaign as soon as
    the cluster is up (a second or two); SIGTERM and SIGHUP are not held."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "pthread_sigmask"):
        yield
        return
    _start_resource_tracker()
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _start_resource_tracker():
    """multiprocessing's resource tracker started now with SIGHUP blocked (the mask survives
    its ``exec``; it ignores SIGINT and SIGTERM itself, not SIGHUP). A SIGHUP to the whole
    process group (a closed terminal) killed it; multiprocessing started a new one, and each
    semaphore the closing cluster released then printed a ``KeyError`` traceback from it (an
    unregister of a name the new tracker never saw). Does nothing when one runs already."""
    import signal

    hup = getattr(signal, "SIGHUP", None)
    if hup is None:
        return
    from multiprocessing import resource_tracker

    old = signal.pthread_sigmask(signal.SIG_BLOCK, {hup})
    try:
        resource_tracker.ensure_running()
    except Exception:  # noqa: BLE001 - no tracker: multiprocessing starts its own when needed
        pass
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _check_reachable(address):
    """Fail fast (one line) when a ``tcp://HOST:PORT`` scheduler refuses the connection."""
    import socket
    from urllib.parse import urlsplit

    if not address.startswith("tcp://"):
        return
    try:
        u = urlsplit(address)
        host, port = u.hostname, u.port
    except ValueError:
        raise InputError(None, f"--scheduler {address}: expected tcp://HOST:PORT") from None
    if not host or not port:
        raise InputError(None, f"--scheduler {address}: expected tcp://HOST:PORT")
    try:
        socket.create_connection((host, port), timeout=5).close()
    except OSError as exc:
        raise InputError(None, f"--scheduler {address}: cannot connect ({exc.strerror or exc})") from None


def _scan_resources(client):
    info = client.scheduler_info().get("workers", {})
    if info and all("scan" in (w.get("resources") or {}) for w in info.values()):
        return {"scan": 1}
    return None


class _TextBar:
    """A one-line progress bar on stderr for terminals without tqdm (not a dependency)."""

    def __init__(self, total, stream=None, width=30):
        self.total, self.n, self.width = max(int(total), 1), 0, width
        self.stream = stream or sys.stderr
        self._draw()

    def _draw(self):
        k = int(round(self.width * self.n / self.total))
        self.stream.write(f"\r[{'#' * k}{'.' * (self.width - k)}] {self.n}/{self.total} scans")
        self.stream.flush()

    def update(self, n=1):
        self.n = min(self.total, self.n + n)
        self._draw()

    def close(self):
        self.stream.write("\n")
        self.stream.flush()


def _progress(total, enabled):
    """tqdm's bar when tqdm is installed, else :class:`_TextBar`; None when not ``enabled``."""
    if not enabled:
        return None
    try:
        from tqdm import tqdm
    except ImportError:
        return _TextBar(total)
    return tqdm(total=total, unit="scan", file=sys.stderr, dynamic_ncols=True)


def run_campaign(jobs, workers=None, scheduler=None, progress=None):
    """Run ``jobs`` (dicts for :func:`.worker.run_job`) -> list (per job, input order) of lists
    of records. Jobs may carry ``"records"`` already (resumed): those are not submitted.

    ``progress`` None: a bar when stderr is a terminal. Raises :class:`Interrupted` on Ctrl-C.

    Parameters
    ----------
    jobs : list of dict
        The jobs.
    workers : int, optional
        Local worker processes.
    scheduler : str, optional
        Address of an existing Dask scheduler.
    progress : bool, optional
        Show a progress bar.

    Returns
    -------
    list of list of dict
    """
    from distributed import as_completed

    results = [job.get("records") for job in jobs]
    todo = [i for i, r in enumerate(results) if r is None]
    if progress is None:
        progress = sys.stderr.isatty()
    bar = _progress(len(jobs), progress)
    if bar is not None:
        bar.update(len(jobs) - len(todo))
    if not todo:
        if bar is not None:
            bar.close()
        return results
    try:
        if not scheduler:  # no idle processes: at most one worker per input to run
            workers = min(workers or default_workers(), len(todo))
        with _quiet_event_loop(), _client(workers, scheduler) as client:
            res = _scan_resources(client)
            futures = {}
            for i in todo:
                job = {k: v for k, v in jobs[i].items() if k != "records"}
                fut = client.submit(
                    run_job,
                    job,
                    pure=False,
                    resources=res,
                    key=f"roadscan-batch-{i}-{os.getpid()}-{id(jobs)}",
                )
                futures[fut] = i
            try:
                for fut in as_completed(futures):
                    i = futures[fut]
                    try:
                        results[i] = fut.result()
                    except Exception as exc:  # noqa: BLE001 - a worker died on this input
                        results[i] = [
                            error_record(
                                jobs[i], f"{jobs[i]['file']}: worker failed: {type(exc).__name__}: {exc}"
                            )
                        ]
                    fut.release()
                    if bar is not None:
                        bar.update(1)
            except KeyboardInterrupt:
                for fut in futures:
                    fut.cancel()
                raise
    except KeyboardInterrupt:
        # a scan whose folder a worker completed before its result arrived still counts
        done = [
            r
            if r is not None
            else (
                _finished_on_worker(job)
                or [error_record(job, f"{job['file']}: interrupted before it finished")]
            )
            for r, job in zip(results, jobs)
        ]
        raise Interrupted(done) from None
    finally:
        if bar is not None:
            bar.close()
    return results
