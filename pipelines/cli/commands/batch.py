"""``roadscan batch INPUTS... --out DIR``: a campaign of ``analyse`` runs on a Dask cluster.

See :mod:`pipelines.campaign` and the documentation's "Campaigns on Dask". Exit code 0 when every input
succeeded, 2 when any failed (every good one is still written), 130 on Ctrl-C (finished scans
and a ``campaign.csv`` of what finished are kept).
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

from roadscan.errors import InputError

from pipelines.settings.friction import settings_from_args
from pipelines.settings.scan_input import add_inputs_and_out
from pipelines.settings.analyse import add_analysis_options, analysis_kwargs

NAME = "batch"
HELP = "analyse many scans (files, globs, manifest CSV) on a local or existing Dask cluster"


def add_arguments(p):
    add_inputs_and_out(p, "height files, glob patterns (quote them) or a manifest CSV with header "
                          "file[,chainage_m][,label] (paths relative to the manifest)",
                       "campaign folder: DIR/<stem>/ per input, DIR/campaign.csv, DIR/report.html")
    add_analysis_options(p)   # the very options of analyse, friction included
    g = p.add_argument_group("campaign")
    g.add_argument("--figures", action="store_true", help="also write each scan's PNG figures")
    g.add_argument("--workers", type=int, default=None, metavar="N",
                   help="local Dask cluster of N worker processes, one thread each "
                        "(default: one per core)")
    g.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                   help="run on an existing dask.distributed cluster instead (files must be "
                        "readable, and DIR writable, under the same paths on every worker)")
    g.add_argument("--resume", action="store_true",
                   help="skip inputs whose outputs exist and whose input and options are unchanged")
    g.add_argument("--section-length", type=float, default=None, metavar="M",
                   help="cut long line profiles into sections of M metres along chainage, one "
                        "row each (MPD per ISO 13473-1, PSD, H, rms per section)")
    g.add_argument("--columns", default=None, metavar="LIST",
                   help="columns of campaign.csv after file,label,chainage_m,status,error: names "
                        "or patterns, comma separated (e.g. 'mpd_m,mpd_valid,roughness.S*'; "
                        "default all)")


def _rubber_identity(path):
    if not path:
        return None
    from pipelines.campaign.folder import sha256_of

    try:
        return sha256_of(path)
    except OSError:
        return str(path)


_NOT_OPTIONS = {"inputs", "out", "workers", "scheduler", "resume", "command", "_run", "debug",
                "columns"}    # --columns shapes campaign.csv only, not a scan's outputs


def _fingerprint(args, kw):
    """Hash of every option that changes a scan's outputs (all of analyse's, --figures,
    --section-length; the rubber file by content)."""
    from pipelines.campaign.folder import options_fingerprint

    opts = {k: v for k, v in vars(args).items() if k not in _NOT_OPTIONS and not k.startswith("_")}
    opts.update(kw)
    opts["rubber"] = _rubber_identity(getattr(args, "rubber", None))
    return options_fingerprint(opts)


def _say(text, tty):
    if tty:
        print(text, file=sys.stderr, flush=True)


def run(args):
    from pipelines.campaign.inputs import expand_inputs
    from pipelines.campaign.records import REPORT_SPEEDS_M_PER_S
    from pipelines.campaign.report import write_campaign_report
    from pipelines.campaign.runner import Interrupted, resumed_records, run_campaign
    from pipelines.campaign.table import parse_columns, write_campaign_csv, write_campaign_parquet

    kw = analysis_kwargs(args)
    settings = settings_from_args(args)
    if args.workers is not None and args.workers < 1:
        raise InputError(None, f"--workers {args.workers}: need at least 1")
    if args.workers is not None and args.scheduler:
        raise InputError(None, "--workers and --scheduler exclude each other (the cluster has its own workers)")
    if args.section_length is not None and not args.section_length > 0:
        raise InputError(None, f"--section-length {args.section_length}: must be positive (metres)")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError(out, "--out exists and is not a folder")
    if out.is_dir() and any(out.iterdir()) and not _earlier_campaign(out):   # a user's folder
        raise InputError(None, f"--out {out}: folder exists, is not empty and holds no earlier "
                               f"batch campaign (its campaign.csv, report.html or scan folders would "
                               f"replace files there); name a new folder")
    if out.is_dir():          # what a killed campaign left (hidden folders, temporary files)
        from pipelines.campaign.folder import recover_campaign

        recover_campaign(out)
    tty = sys.stderr.isatty()

    fingerprint = _fingerprint(args, kw)
    jobs = []
    for j in expand_inputs(args.inputs):
        job = {"file": j.file, "path": os.path.abspath(j.file), "label": j.label,
               "chainage_m": j.chainage_m, "error": j.error, "subdir": j.subdir,
               "out": str(out.resolve()), "spacing": args.spacing, "units": args.units,
               # shared flags fill in what a file lacks, never replace what it carries
               "calibration": "override" if getattr(args, "override_calibration", False) else "default",
               "channel": getattr(args, "channel", None),
               "settings": settings, "analysis": kw, "figures": args.figures,
               "section_length_m": args.section_length, "fingerprint": fingerprint}
        if args.resume and not j.error:
            recs = resumed_records(job)
            if recs is not None:
                job["records"] = recs
        jobs.append(job)
    _refuse_overwrite(out, jobs, args.inputs)
    out.mkdir(parents=True, exist_ok=True)
    skipped = sum("records" in j for j in jobs)
    if skipped:
        _say(f"--resume: {skipped} of {len(jobs)} inputs unchanged, skipped", tty)

    interrupted = False
    try:
        results = run_campaign(jobs, workers=args.workers, scheduler=args.scheduler, progress=tty)
    except Interrupted as exc:
        results, interrupted = exc.records, True
        _clean_after_stop(out, jobs)
    records = [r for recs in results for r in recs]
    write_campaign_csv(out / "campaign.csv", records, parse_columns(getattr(args, "columns", None)))
    write_campaign_parquet(out / "campaign.parquet", records)
    write_campaign_report(out, records, REPORT_SPEEDS_M_PER_S)
    failed = [r for r in records if r["status"] != "ok"]
    if interrupted:
        raise KeyboardInterrupt
    for r in failed:
        print(f"roadscan batch: error: {r['error']}", file=sys.stderr)
    print(summary_line(jobs, results, out))
    return 2 if failed else 0


def summary_line(jobs, results, out):
    """The one line a campaign ends with (stdout): inputs done now, skipped by ``--resume``
    (unchanged), failed; where the table and report are."""
    skipped = sum("records" in j for j in jobs)
    failed = sum(any(r["status"] != "ok" for r in recs) for recs in results)
    done = len(jobs) - skipped - failed
    warned = sum(any(r["status"] == "ok" and r["values"].get("warnings") for r in recs)
                 for recs in results)          # scans with warnings
    return (f"roadscan batch: {done} done, {skipped} skipped, {failed} failed, "
            f"{warned} with warnings -> "
            f"{out / 'campaign.csv'}, {out / 'report.html'}")


def _clean_after_stop(out, jobs):
    """Hidden temporary folders of scans whose worker was stopped mid-write (a signal to the
    whole process group, a cluster closed under them): removed unless still locked by a live
    writer (:func:`roadscan.io.atomic.recover_output_dir`)."""
    from roadscan.io.atomic import recover_output_dir

    for j in jobs:
        if j.get("subdir"):
            try:
                recover_output_dir(out / j["subdir"])
            except OSError:
                pass


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
    refuse_overwrite(outputs, [j["path"] for j in jobs if not j.get("error")] +
                     [g for g in given if os.path.isfile(g)])   # a manifest too
