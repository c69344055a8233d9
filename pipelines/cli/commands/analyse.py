"""``roadscan analyse FILE... --out DIR``."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from pipelines.settings.analyse import add_analysis_options, analysis_kwargs
from pipelines.settings.analyse import unique_stems as _unique_dirs
from pipelines.settings.friction import settings_from_args
from pipelines.settings.scan_input import load_scan
from roadscan.errors import InputError

NAME = "analyse"
HELP = "PSD, self-affine fit, roughness figures and friction mu(v) of height files"


def add_arguments(p):
    p.add_argument("files", nargs="+", metavar="FILE", help="height files (area scans or line profiles)")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument(
        "--no-figures",
        action="store_true",
        help="skip the PNG figures (every CSV/JSON output is the same; report.html keeps its tables)",
    )
    add_analysis_options(p)


def run(args):
    kw = analysis_kwargs(args)
    settings = settings_from_args(args)
    from pipelines.cli.signals import work_finished
    from pipelines.output.figure_process import figure_drawer
    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    out = Path(args.out)
    check_output_dir(out, inputs=args.files)
    _no_collection_at_exit()
    # matplotlib is imported by a helper process while the scans are read and analysed
    with figure_drawer(not getattr(args, "no_figures", False)) as drawer:
        scans = [_load(f, args) for f in args.files]  # every input is checked before any output
        many = len(scans) > 1
        with atomic_output_dir(out, inputs=args.files) as tmp:  # all outputs or none
            rows = _analyse_all(args, scans, tmp, out, many, settings, kw, drawer)
        work_finished()  # every output in place: a stop request now has nothing left to stop
    for _, said in scans:  # said once the outputs that carry them are in place
        said.print_all()
    if many:
        print(f"analysed {len(rows)} scans -> {out / 'summary.csv'}, {out / 'report.html'}")
    return 0


_AT_EXIT: list[Any] = []


def _no_collection_at_exit():
    """At interpreter exit, the garbage collector skips the objects alive then
    (:func:`gc.freeze` from an :mod:`atexit` hook): the interpreter's own collections while
    it shuts down cost 30-45 ms after the sample's ``roadscan analyse`` (55-73 ms exit instead
    of 24-27 ms, measured), longer than all its files take to write. Nothing is left
    unwritten: every output is written and closed (atomically) before the command returns, and
    objects alive at exit are not guaranteed a finaliser by Python anyway. Registered once a
    process, and only at exit: a program that calls the command keeps its collector until then."""
    if not _AT_EXIT:
        import atexit
        import gc

        atexit.register(gc.freeze)
        _AT_EXIT.append(True)


def _load(path, args):
    """(scan, its own :class:`pipelines.checks.validate.Warnings`): what reading it warned."""
    from pipelines.checks.validate import Warnings, collecting, current_warnings

    w = Warnings(current_warnings().prefix, echo=False)  # printed after the outputs exist
    with collecting(into=w):
        return load_scan(path, args), w


def _analyse_all(args, scans, out, final, many, settings, kw, drawer=None):
    from pipelines.checks.validate import collecting
    from pipelines.jobs.analyse.job import run_analysis
    from pipelines.output.units import length

    rows, own = [], []
    for i, (path, (scan, said), sub) in enumerate(zip(args.files, scans, _unique_dirs(args.files))):
        if many:
            print(f"[{i + 1}/{len(scans)}] {path}", file=sys.stderr, flush=True)
        try:
            with collecting(into=said):  # this scan's warnings only, reading included
                summary = run_analysis(
                    scan,
                    out / sub if many else out,
                    settings,
                    figures=not getattr(args, "no_figures", False),
                    drawer=drawer,
                    **kw,
                )
        except InputError as exc:  # keep the options it names (rendered as flags)
            raise (exc.reworded(path) if exc.file is None else exc) from None
        rows.append((sub, summary))
        own.append(list(said.lines))
        if not many:
            from pipelines.output.headline import friction_headline, hurst_text

            fr = friction_headline(summary)  # mu's peak, which q1 and why
            print(
                f"{path}: H = {hurst_text(summary)}, "
                f"rms height = {length(summary['rms_height_m'])}{', ' + fr if fr else ''} "
                f"-> {final / 'report.html'}"
            )
    if many:  # summary.csv and the summary report.html
        from pipelines.jobs.analyse.outputs import write_many_summary

        write_many_summary(out, rows, own)
    return rows
