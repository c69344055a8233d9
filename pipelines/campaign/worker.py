"""What a Dask worker runs for one input of a campaign.

:func:`run_job` reads the file itself, analyses it with :func:`pipelines.jobs.analyse.job.run_analysis`
(the very function ``roadscan analyse`` runs, so the outputs are identical), writes the outputs
itself into an atomic folder ``DIR/<subdir>/`` and returns a list of small records
(:mod:`.records`): big arrays never travel through the scheduler. It never raises for a bad
input: the failure is a record with status ``error`` and a one-line message.
"""

from __future__ import annotations

import contextlib
import csv
import gc
import io
from pathlib import Path

import numpy as np

from pipelines.campaign.folder import atomic_folder, file_identity, write_sidecar
from pipelines.campaign.records import error_record, mu_at_speeds, ok_record
from roadscan.errors import InputError

__all__ = ["run_job", "SECTION_COLUMNS"]

SECTION_COLUMNS = ("section", "section_start_m", "section_length_m")


def _message(file, exc):
    if isinstance(exc, InputError):
        from pipelines.cli.hints import flag_text

        text = flag_text(exc) if exc.path else f"{file}: {flag_text(exc)}"
    elif isinstance(exc, (ValueError, OSError, MemoryError)):
        text = f"{file}: {exc}"
    else:
        text = f"{file}: {type(exc).__name__}: {exc}"
    return " ".join(text.split())


def _mu_at(folder):
    f = Path(folder) / "mu.csv"
    if not f.exists():
        return {}
    d = np.loadtxt(f, delimiter=",", skiprows=1, ndmin=2)
    return mu_at_speeds(d[:, 0], d[:, 1])


def _own_warnings():
    """A warnings scope of its own (:func:`pipelines.checks.validate.collecting`): each scan's
    ``summary.json`` lists its own warnings, as ``roadscan analyse`` on that one file does."""
    from pipelines.checks import validate
    from pipelines.checks.run_warnings import say_warnings

    say_warnings("quiet")  # a worker's warnings reach the user through the campaign's records
    return validate.collecting(prefix="roadscan batch")


def _analyse_one(job, tmp):
    from pipelines.jobs.analyse.job import run_analysis
    from pipelines.settings.scan_input import load_scan

    with _own_warnings():
        scan = load_scan(
            job.get("path") or job["file"],
            spacing=job.get("spacing"),
            units=job.get("units"),
            calibration=job.get("calibration"),
            channel=job.get("channel"),
        )
        summary = run_analysis(
            scan, tmp, job["settings"], figures=job.get("figures", False), **job["analysis"]
        )
    return [ok_record(job, summary, job["subdir"], _mu_at(tmp))]


def _analyse_sections(job, tmp):
    from pipelines.campaign.sections import iter_sections
    from pipelines.jobs.analyse.job import run_analysis

    L = job["section_length_m"]
    base = job.get("chainage_m") or 0.0
    recs = []
    for k, (start, prof) in enumerate(
        iter_sections(job.get("path") or job["file"], L, job.get("spacing"), job.get("units"))
    ):
        sub = f"section_{k:05d}"
        extra = {"section": k, "section_start_m": start, "section_length_m": prof.length_m}
        chain = base + start
        if k == 0:  # a units slip refuses the file before any section
            from roadscan.plausibility import check_plausible

            check_plausible(prof, job["file"], job.get("units"))
        try:
            with _own_warnings():
                summary = run_analysis(
                    prof, tmp / sub, job["settings"], figures=job.get("figures", False), **job["analysis"]
                )
            recs.append(ok_record(job, summary, f"{job['subdir']}/{sub}", _mu_at(tmp / sub), extra, chain))
        except (ValueError, ArithmeticError) as exc:
            recs.append(
                error_record(job, f"{job['file']}: section {k} at {start:g} m: {exc}", None, extra, chain)
            )
        del prof
    if not recs:
        raise InputError(job["file"], "no section: the profile is too short")
    _write_sections_csv(tmp / "sections.csv", recs)
    return recs


def _write_sections_csv(path, recs):
    cols = [
        "chainage_m",
        *SECTION_COLUMNS,
        "status",
        "error",
        "mpd_m",
        "mpd_valid",
        "hurst",
        "rms_height_m",
        "mpd_note",
        "etd_m",
        "texture_level_dB.80",
        "texture_level_dB.5",
    ]
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for r in recs:
            v = r["values"]
            w.writerow(
                [
                    _cell(r["chainage_m"]),
                    *(_cell(v.get(c)) for c in SECTION_COLUMNS),
                    r["status"],
                    r["error"],
                    *(_cell(v.get(c)) for c in cols[6:]),
                ]
            )


def _cell(x):
    if x is None:
        return ""
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, float):
        return repr(x)
    return str(x)


def run_job(job):
    """Analyse one input (a dict built by :mod:`.runner`) -> list of records.

    ``job`` keys: ``file``, ``label``, ``chainage_m``, ``subdir``, ``out`` (campaign folder),
    ``spacing``, ``units``, ``settings`` (FrictionSettings), ``analysis`` (run_analysis keyword
    arguments), ``figures``, ``section_length_m`` (None: whole scan), ``fingerprint``.

    Parameters
    ----------
    job : dict
        The job.

    Returns
    -------
    list of dict
        Its records.
    """
    if job.get("error"):
        return [error_record(job, job["error"])]
    target = Path(job["out"]) / job["subdir"]
    # warnings go into each summary.json / campaign.csv, not onto the worker's stderr
    with contextlib.redirect_stderr(io.StringIO()):
        return _run_job(job, target)


BIG_INPUT_BYTES = 32 << 20  # inputs above this get a full garbage collection after them


def _run_job(job, target):
    big = False
    try:
        path = Path(job.get("path") or job["file"])
        if not path.is_file():
            raise InputError(
                path, "is a directory, expected a height file" if path.is_dir() else "no such file"
            )
        ident = file_identity(path)
        big = ident["size"] > BIG_INPUT_BYTES or bool(job.get("section_length_m"))
        with atomic_folder(target) as tmp:
            if job.get("section_length_m"):
                recs = _analyse_sections(job, tmp)
            else:
                recs = _analyse_one(job, tmp)
            write_sidecar(tmp, ident, job.get("fingerprint"), recs)
        return recs
    except Exception as exc:  # noqa: BLE001 - any failure of one input is a row, not the end
        big = True  # a traceback's frames may hold the scan in a reference cycle
        return [error_record(job, _message(job["file"], exc))]
    finally:
        # One scan at a time: numpy arrays go with their last reference. A full collection
        # costs 0.1-0.3 s in a Dask worker's heap, more than analysing a small scan, so it runs
        # only where reference cycles may hold big data: figures (matplotlib), large inputs,
        # long profiles, failures.
        if big or job.get("figures"):
            gc.collect()
