"""``roadscan batch INPUTS... --out DIR``: a campaign of ``analyse`` runs on a Dask cluster.

See :mod:`pipelines.campaign` and the documentation's "Campaigns on Dask". Exit code 0 when every input
succeeded, 2 when any failed (every good one is still written), 130 on Ctrl-C (finished scans
and a ``campaign.csv`` of what finished are kept).
"""

from __future__ import annotations

from pipelines.settings.analyse import add_analysis_options
from pipelines.settings.scan_input import add_inputs_and_out

NAME = "batch"
HELP = "analyse many scans (files, globs, manifest CSV) on a local or existing Dask cluster"


def add_arguments(p):
    add_inputs_and_out(
        p,
        "height files, glob patterns (quote them) or a manifest CSV with header "
        "file[,chainage_m][,label] (paths relative to the manifest)",
        "campaign folder: DIR/<stem>/ per input, DIR/campaign.csv, DIR/report.html",
    )
    add_analysis_options(p)  # the very options of analyse, friction included
    g = p.add_argument_group("campaign")
    g.add_argument("--figures", action="store_true", help="also write each scan's PNG figures")
    g.add_argument(
        "--workers",
        type=int,
        default=None,
        metavar="N",
        help="local Dask cluster of N worker processes, one thread each (default: one per core)",
    )
    g.add_argument(
        "--scheduler",
        default=None,
        metavar="tcp://HOST:PORT",
        help="run on an existing dask.distributed cluster instead (files must be "
        "readable, and DIR writable, under the same paths on every worker)",
    )
    g.add_argument(
        "--resume",
        action="store_true",
        help="skip inputs whose outputs exist and whose input and options are unchanged",
    )
    g.add_argument(
        "--section-length",
        type=float,
        default=None,
        metavar="M",
        help="cut long line profiles into sections of M metres along chainage, one "
        "row each (MPD per ISO 13473-1, PSD, H, rms per section)",
    )
    g.add_argument(
        "--columns",
        default=None,
        metavar="LIST",
        help="columns of campaign.csv after file,label,chainage_m,status,error: names "
        "or patterns, comma separated (e.g. 'mpd_m,mpd_valid,roughness.S*'; "
        "default all)",
    )


def run(args):
    import sys

    from pipelines.campaign.api import batch
    from pipelines.settings.keywords import keywords_of

    r = batch(args.inputs, args.out, **keywords_of(args, batch))
    for rec in r["records"]:
        if rec["status"] != "ok":
            print(f"roadscan batch: error: {rec['error']}", file=sys.stderr)
    print(r["summary"])
    return 2 if r["failed"] else 0
