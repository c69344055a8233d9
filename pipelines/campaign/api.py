"""``pipelines.batch``: a campaign of ``analyse`` runs on a Dask cluster, from Python exactly as
``roadscan batch`` runs it (:func:`batch`): one folder per input, ``campaign.csv`` (and
``campaign.parquet`` with pyarrow), ``report.html``; ``resume=True`` skips inputs whose outputs
exist and whose input and options are unchanged.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from pipelines.checks.run_warnings import note
from pipelines.output.job_result import returns_job_result
from pipelines.settings.option_docs import document_options
from roadscan.errors import InputError

if TYPE_CHECKING:  # numpy's typing only for checkers: the command's --help stays light
    from numpy.typing import ArrayLike

    from friction.rubber import Rubber

__all__ = ["batch", "summary_line"]


@returns_job_result("batch")
@document_options()
def batch(
    inputs: Any,
    out: str | os.PathLike[str],
    *,
    spacing: float | str | tuple[float, float] | None = None,
    units: Literal["m", "mm", "um", "nm"] | None = None,
    x_units: Literal["m", "mm", "um", "nm"] | None = None,
    override_calibration: bool = False,
    channel: int | str | None = None,
    window_alpha: float = 0.25,
    fit_band: tuple[float, float] | str | None = None,
    despike: bool = False,
    mpd_spike_alpha: float | None = None,
    resolution: float | None = None,
    direction: Literal["x", "y"] = "x",
    friction_measurement: str | None = None,
    ifi_constants: str | None = None,
    form: Literal["plane", "poly2", "poly3"] = "plane",
    s_filter: float | None = None,
    l_filter: float | None = None,
    rubber: str | os.PathLike[str] | Rubber | None = None,
    sigma0: float | str = 200000.0,
    temperature: float | None = None,
    flash: bool = False,
    velocities: ArrayLike | str | None = None,
    q0: float | None = None,
    q1: float | None = None,
    contact_gamma: float | None = None,
    nu: float = 0.5,
    extrapolate: Literal["powerlaw", "hold"] = "powerlaw",
    no_friction: bool = False,
    figures: bool = False,
    workers: int | None = None,
    scheduler: str | None = None,
    resume: bool = False,
    section_length: float | None = None,
    columns: str | None = None,
) -> dict[str, Any]:
    """``roadscan batch`` as one call: every input analysed as :func:`pipelines.analyse` would
    analyse it, on a local Dask cluster (one single-threaded worker process per core) or an
    existing one, written into ``out``.

    Parameters
    ----------
    inputs : sequence of str or os.PathLike
        Height files, glob patterns, or a manifest CSV with header
        ``file[,chainage_m][,label]`` (paths relative to the manifest).
    out : str or os.PathLike
        The campaign folder: ``out/<stem>/`` per input, ``out/campaign.csv``,
        ``out/report.html``.
    {options}

    figures : bool, default False
        ``--figures``: also write each scan's PNG figures.
    workers : int or None, default None
        ``--workers``: a local Dask cluster of this many worker processes, one thread each
        (default: one per core).
    scheduler : str or None, default None
        ``--scheduler``: address ``tcp://HOST:PORT`` of an existing dask.distributed cluster
        (files must be readable, and ``out`` writable, under the same paths on every worker).
    resume : bool, default False
        ``--resume``: skip inputs whose outputs exist and whose input and options are unchanged.
    section_length : float or None, default None
        ``--section-length``: cut long line profiles into sections of this length [m] along
        chainage, one row each (MPD per ISO 13473-1, PSD, H, rms per section).
    columns : str or None, default None
        ``--columns``: the columns of campaign.csv after ``file,label,chainage_m,status,error``,
        names or patterns, comma separated (e.g. ``"mpd_m,mpd_valid,roughness.S*"``; default all).

    Returns
    -------
    dict
        ``records`` (one dict per scan or section: ``file``, ``status``, ``error``,
        ``values``), ``done``, ``skipped``, ``failed`` (counts), ``campaign_csv`` and
        ``report`` (paths) and ``summary`` (the line the command prints).

    Raises
    ------
    roadscan.InputError
        An option out of range or an output folder that is not a campaign's (one line).
    KeyboardInterrupt
        The campaign was stopped; finished scans and a ``campaign.csv`` of them are kept.
    """
    from pipelines.campaign.inputs import expand_inputs
    from pipelines.campaign.records import REPORT_SPEEDS_M_PER_S
    from pipelines.campaign.report import write_campaign_report
    from pipelines.campaign.runner import Interrupted, resumed_records, run_campaign
    from pipelines.campaign.table import parse_columns, write_campaign_csv, write_campaign_parquet
    from pipelines.settings.analyse import analysis_kwargs
    from pipelines.settings.friction import settings_from_args
    from pipelines.settings.keywords import options_of

    args = options_of(batch, locals())
    args.inputs = [os.fspath(i) for i in ([inputs] if isinstance(inputs, (str, os.PathLike)) else inputs)]
    args.out = os.fspath(out)
    kw = analysis_kwargs(args)
    settings = settings_from_args(args)
    if args.workers is not None and args.workers < 1:
        raise InputError(None, f"--workers {args.workers}: need at least 1")
    if args.workers is not None and args.scheduler:
        raise InputError(
            None, "--workers and --scheduler exclude each other (the cluster has its own workers)"
        )
    if args.section_length is not None and not args.section_length > 0:
        raise InputError(None, f"--section-length {args.section_length}: must be positive (metres)")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError(out, "--out exists and is not a folder")
    if out.is_dir() and any(out.iterdir()) and not _earlier_campaign(out):  # a user's folder
        raise InputError(
            None,
            f"--out {out}: folder exists, is not empty and holds no earlier "
            f"batch campaign (its campaign.csv, report.html or scan folders would "
            f"replace files there); name a new folder",
        )
    if out.is_dir():  # what a killed campaign left (hidden folders, temporary files)
        from pipelines.campaign.folder import recover_campaign

        recover_campaign(out)

    fingerprint = _fingerprint(args, kw, settings)
    jobs = []
    for j in expand_inputs(args.inputs):
        job = {
            "file": j.file,
            "path": os.path.abspath(j.file),
            "label": j.label,
            "chainage_m": j.chainage_m,
            "error": j.error,
            "subdir": j.subdir,
            "out": str(out.resolve()),
            "spacing": args.spacing,
            "units": args.units,
            # shared flags fill in what a file lacks, never replace what it carries
            "calibration": "override" if getattr(args, "override_calibration", False) else "default",
            "channel": getattr(args, "channel", None),
            "settings": settings,
            "analysis": kw,
            "figures": args.figures,
            "section_length_m": args.section_length,
            "fingerprint": fingerprint,
        }
        if args.resume and not j.error:
            recs = resumed_records(job)
            if recs is not None:
                job["records"] = recs
        jobs.append(job)
    _refuse_overwrite(out, jobs, args.inputs)
    out.mkdir(parents=True, exist_ok=True)
    skipped = sum("records" in j for j in jobs)
    if skipped:
        note(f"--resume: {skipped} of {len(jobs)} inputs unchanged, skipped")

    interrupted = False
    try:
        results = run_campaign(
            jobs, workers=args.workers, scheduler=args.scheduler, progress=_progress_wanted()
        )
    except Interrupted as exc:
        results, interrupted = exc.records, True
        _clean_after_stop(out, jobs)
    records = [r for recs in results for r in recs]
    write_campaign_csv(out / "campaign.csv", records, parse_columns(getattr(args, "columns", None)))
    write_campaign_parquet(out / "campaign.parquet", records)
    write_campaign_report(out, records, REPORT_SPEEDS_M_PER_S)
    if interrupted:
        raise KeyboardInterrupt
    failed = sum(any(r["status"] != "ok" for r in recs) for recs in results)
    return {
        "records": records,
        "done": len(jobs) - skipped - failed,
        "skipped": skipped,
        "failed": failed,
        "campaign_csv": str(out / "campaign.csv"),
        "report": str(out / "report.html"),
        "summary": summary_line(jobs, results, out),
    }


def _progress_wanted():
    """A progress bar only where someone watches: the command on a terminal
    (:func:`pipelines.campaign.runner.run_campaign` draws it on stderr)."""
    import sys

    from pipelines.checks.run_warnings import _MODE

    return _MODE[0] == "print" and sys.stderr.isatty()


def _rubber_identity(path):
    if not path:
        return None
    from pipelines.campaign.folder import sha256_of

    try:
        return sha256_of(path)
    except OSError:
        return str(path)


_NOT_OPTIONS = {
    "inputs",
    "out",
    "workers",
    "scheduler",
    "resume",
    "command",
    "_run",
    "debug",
    "columns",
}  # --columns shapes campaign.csv only, not a scan's outputs


def _fingerprint(args, kw, settings):
    """Hash of every option that changes a scan's outputs (all of analyse's, --figures,
    --section-length; the rubber file by content), by value: ``sigma0=2e5`` and ``"0.2MPa"``,
    speeds as text or as numbers, hash the same."""
    from pipelines.campaign.folder import options_fingerprint

    opts = {k: v for k, v in vars(args).items() if k not in _NOT_OPTIONS and not k.startswith("_")}
    opts.update(kw)
    opts["sigma0"] = float(settings.sigma0_Pa)
    v = settings.v_m_per_s
    opts["velocities"] = None if v is None else [float(x) for x in v]
    if isinstance(opts.get("fit_band"), tuple):
        opts["fit_band"] = list(opts["fit_band"])
    opts["rubber"] = _rubber_identity(getattr(args, "rubber", None))
    return options_fingerprint(opts)


def summary_line(jobs, results, out):
    """The one line a campaign ends with (stdout): inputs done now, skipped by ``--resume``
    (unchanged), failed; where the table and report are."""
    skipped = sum("records" in j for j in jobs)
    failed = sum(any(r["status"] != "ok" for r in recs) for recs in results)
    done = len(jobs) - skipped - failed
    warned = sum(
        any(r["status"] == "ok" and r["values"].get("warnings") for r in recs) for recs in results
    )  # scans with warnings
    return (
        f"roadscan batch: {done} done, {skipped} skipped, {failed} failed, "
        f"{warned} with warnings -> "
        f"{out / 'campaign.csv'}, {out / 'report.html'}"
    )


def _clean_after_stop(out, jobs, wait_s=5.0):
    """What a stopped campaign's workers left in ``out`` removed (:func:`pipelines.campaign.
    folder.recover_campaign`: hidden temporary scan folders, a set-aside folder put back). A
    folder a worker still holds (``flock``: the cluster was closed, the worker process is still
    dying, as happens under load) is waited for, up to ``wait_s`` seconds, then removed: the
    stopped campaign leaves nothing half-written behind it."""
    import time

    from pipelines.campaign.folder import campaign_leftovers, recover_campaign

    scans = {j["subdir"] for j in jobs if j.get("subdir")}
    deadline = time.monotonic() + wait_s
    while True:
        recover_campaign(out)
        left = [p for p in campaign_leftovers(out) if any(p.name.startswith(f".{s}.") for s in scans)]
        if not left or time.monotonic() > deadline:
            return
        time.sleep(0.05)


def _earlier_campaign(out):
    """True when ``out`` holds an earlier campaign, finished or killed
    (:func:`pipelines.campaign.folder.earlier_campaign`)."""
    from pipelines.campaign.folder import earlier_campaign

    return earlier_campaign(out)


def _refuse_overwrite(out, jobs, given):
    """No campaign output (campaign.csv/.parquet, report.html, a scan's folder) replaces an
    input file or the manifest."""
    from roadscan.io.overwrite_guard import refuse_overwrite

    outputs = [out / n for n in ("campaign.csv", "campaign.parquet", "report.html")]
    outputs += [(out / j["subdir"], True) for j in jobs if j.get("subdir")]
    refuse_overwrite(
        outputs, [j["path"] for j in jobs if not j.get("error")] + [g for g in given if os.path.isfile(g)]
    )  # a manifest too
