"""The ``roadscan`` command. Each subcommand lives in ``pipelines/cli/commands/<name>.py`` and
provides ``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``.

Errors (the policy of :mod:`pipelines.checks.validate`): whatever goes wrong, the user sees **one
line** on stderr, never a traceback.

- Bad input (:class:`roadscan.InputError`, the options it points at named by their flags; a
  missing/unreadable file; a file the standard parsers refuse: ``UnicodeError``, JSON, CSV,
  TOML; ``MemoryError``: the scan is too large) -> ``roadscan CMD: error: ...``, exit code 2.
  argparse's usage errors are one line too, exit 2.
- Anything else, a plain ``ValueError`` or ``ArithmeticError`` included, is a bug (the checks
  turn bad input into an InputError before the numerics) -> ``roadscan CMD: internal error
  (Type: message); rerun with --debug for the traceback``, exit code 1.
- ``--debug`` (before or after the command name) shows the full traceback instead.
- NumPy floating-point warnings are not printed as they happen: the CLI collects them and, if
  the command succeeds, prints one named line (``warning: numpy: ...``); the checks of
  :mod:`pipelines.checks.validate` make them rare. Python ``RuntimeWarning``\\ s are treated the same.
- Ctrl-C, SIGTERM and SIGHUP at any moment: temporary outputs removed, one line
  (``interrupted``), exit code 128 + signal (130, 143, 129; :mod:`pipelines.cli.signals`).
- No output replaces an input (:mod:`pipelines.checks.overwrite`, before any work, and
  :mod:`roadscan.io.overwrite_guard` when writing): one line, exit code 2.
- A mistyped command or option gets "did you mean" (:mod:`pipelines.cli.hints`); ``--version``.
- ``--max-pixels N`` (before or after the command name) caps the size a reader accepts
  (default: :func:`roadscan.io._common.default_max_pixels`, from the available memory).
"""

from __future__ import annotations

import os
import sys

# roadscan runs its own parallel work (the texture thread of analyse, the figure process, Dask
# workers); OpenBLAS's own pool of one thread per core on top of it oversubscribes the cores and
# spins between calls (the sample's ``roadscan analyse``: 0.2 s of CPU time, 0.15 s of wall time
# on two cores). Set before numpy is first imported; a user's own setting is kept.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


# the console script itself, still importing (not a Dask worker re-importing it as __mp_main__)
def _runs_as(main_name: str) -> bool:
    """Is ``sys.modules[main_name]`` the ``roadscan`` script or ``python -m pipelines.cli``?"""
    mod = sys.modules.get(main_name)
    spec = getattr(mod, "__spec__", None)
    return os.path.basename(getattr(mod, "__file__", None) or "") == "roadscan" or getattr(
        spec, "name", None
    ) in ("pipelines.cli.__main__", "pipelines.cli.app")


if __name__ == "__main__" or _runs_as("__main__"):
    from pipelines.cli.signals import exit_early_on_signals

    exit_early_on_signals()
elif __name__ == "__mp_main__" or _runs_as("__mp_main__"):
    # a process the command spawned (a local Dask worker re-importing the script): a terminal's
    # Ctrl-C reaches the whole group, but stopping is the parent's business
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)

import argparse
import errno
import importlib
import traceback
import warnings

from pipelines.cli.hints import flag_text
from roadscan.errors import InputError

# subcommand modules, in the order ``roadscan --help`` lists them
# (``commands/`` computes from scans and spectra; ``inputs/`` prepares them)
COMMAND_MODULES = (
    "commands.analyse",
    "commands.batch",
    "inputs.synth",
    "commands.friction_cmd",
    "inputs.rubber",
    "inputs.stitch",
    "commands.rainfill",
    "commands.dry_vs_wet",
    "commands.compare",
    "commands.diagnose",
    "inputs.convert",
    "commands.combine",
)


def _parsing_errors():
    """Errors of the standard parsers reading a file's text (a broken JSON, CSV, TOML or text
    encoding): bad input even where no reader wrapped them in an InputError."""
    import csv
    import json

    found = [UnicodeError, json.JSONDecodeError, csv.Error]
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # Python 3.10: the tomli backport (a dependency there)
        import tomli as tomllib
    found.append(tomllib.TOMLDecodeError)
    return tuple(found)


def one_line(text, limit=400):
    """Collapse a message to one line (newlines -> ' | ', at most ``limit`` characters)."""
    s = " | ".join(part.strip() for part in str(text).splitlines() if part.strip())
    s = "".join(c if c.isprintable() else "?" for c in s)  # no terminal control bytes from a file
    return s if len(s) <= limit else s[: limit - 3] + "..."


class OneLineParser(argparse.ArgumentParser):
    """argparse parser whose usage errors are one line (``prog: error: msg (see prog -h)``),
    exit code 2."""

    def error(self, message):
        from pipelines.cli.hints import hint

        more = hint(self, message, _ARGV if _ARGV is not None else sys.argv[1:])
        self.exit(2, f"{self.prog}: error: {one_line(message)}{more} (see {self.prog} -h)\n")


#: the words being parsed (for "did you mean"), set by :func:`main`
_ARGV = None


def _load_commands():
    mods = []
    for name in COMMAND_MODULES:
        try:
            mods.append(importlib.import_module(f"pipelines.cli.{name}"))
        except ModuleNotFoundError as exc:  # a command not built yet
            if exc.name != f"pipelines.cli.{name}":
                raise
    return mods


def _positive_int(text):
    try:
        v = int(float(text))
    except (TypeError, ValueError, OverflowError):
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"{text!r} must be at least 1")
    return v


def _add_global_options(p, default):
    p.add_argument(
        "--debug", action="store_true", default=default, help="show the full traceback of any error"
    )
    p.add_argument(
        "--max-pixels",
        type=_positive_int,
        default=default,
        metavar="N",
        help="largest scan (points) a reader accepts before allocating (default: from the available memory)",
    )


def _nested(p):
    from pipelines.cli.hints import subparsers

    return subparsers(p).values()


class _Version(argparse.Action):
    """``--version``: the installed version, read (``importlib.metadata``, 0.03 s to import)
    only when asked."""

    def __call__(self, parser, namespace, values, option_string=None):
        from pipelines.cli.hints import package_version

        print(f"roadscan {package_version()}")
        parser.exit()


def build_parser():
    parser = OneLineParser(
        prog="roadscan",
        description="Road-surface scans to spectra, rain fill and rubber friction.",
    )
    _add_global_options(parser, None)
    parser.add_argument("--version", action=_Version, nargs=0, help="show the installed version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=OneLineParser)
    sub.required = True
    from pipelines.cli.examples import add_examples
    from pipelines.cli.hints import subparsers

    add_examples(parser, "roadscan")
    for mod in _load_commands():
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=mod.HELP)
        mod.add_arguments(p)
        add_examples(p, mod.NAME)  # --help ends with example commands
        for action, nested in subparsers(p).items():
            add_examples(nested, f"{mod.NAME} {action}")
        _add_global_options(p, argparse.SUPPRESS)  # after the command name too
        for action in list(_nested(p)):  # and after a sub-action ('rubber master')
            _add_global_options(action, argparse.SUPPRESS)
        p.set_defaults(_run=mod.run)
    return parser


def _numpy_warning_line(caught):
    seen = []
    for w in caught:
        key = (str(w.message), w.filename.rsplit("/", 1)[-1], w.lineno)
        if key not in seen:
            seen.append(key)
    msg, fname, line = seen[0]
    more = f" (+{len(seen) - 1} more)" if len(seen) > 1 else ""
    return f"numpy: {one_line(msg)} in {fname}:{line}{more}; results may be inaccurate"


def main(argv=None):
    """Run one command; SIGTERM/SIGHUP/SIGINT at any moment: one line, exit 128 + signal."""
    from pipelines.cli.signals import (
        after_interrupt,
        exit_code,
        own_the_process,
        received,
        signal_name,
        signals_as_interrupt,
        work_finished,
    )

    global _ARGV
    _ARGV = list(sys.argv[1:] if argv is None else argv)
    cmd = "roadscan"
    if argv is None:  # the real command line: this process is the command's own
        own_the_process()
    try:
        with signals_as_interrupt(restore=argv is not None):
            parser = build_parser()
            args = parser.parse_args(argv)  # one-line usage errors, exit code 2
            cmd = f"roadscan {args.command}"
            rc = _main(args, cmd)
            if received():  # a library swallowed the interruption: never exit 0
                raise KeyboardInterrupt
            work_finished()  # the real command line, its work done and its outputs in place
            return rc
    except KeyboardInterrupt as exc:  # Ctrl-C, SIGTERM, SIGHUP (pipelines.cli.signals)
        code = exit_code(exc)
        if argv is None:  # the real command line: a second signal ends at once
            after_interrupt(code)
        what = "" if code == 130 else f" ({signal_name(exc)})"
        print(f"{cmd}: interrupted{what}", file=sys.stderr, flush=True)
        return code
    finally:
        _ARGV = None


def _main(args, cmd):
    # heavy modules (numpy, the readers) only now: --help and usage errors stay fast
    from pipelines.checks import validate
    from pipelines.checks.overwrite import check_command_paths
    from pipelines.checks.run_warnings import say_warnings
    from roadscan.io import _common as io_common
    from roadscan.io.overwrite_guard import reads_tracked

    debug = bool(getattr(args, "debug", False))
    validate.reset_warnings(prefix=cmd)
    said_before = say_warnings("print")  # the command prints its warnings as lines on stderr
    notes = _print_notes()  # and its notes (the roadscan logger's INFO lines)
    previous_limit = io_common.get_max_pixels()
    if getattr(args, "max_pixels", None):
        io_common.set_max_pixels(args.max_pixels)
    try:
        with warnings.catch_warnings(record=True) as caught, reads_tracked():
            warnings.simplefilter("always", RuntimeWarning)
            check_command_paths(args)  # no output over an input, no looping link (exit 2)
            rc = int(args._run(args) or 0)
        runtime = [w for w in caught if issubclass(w.category, RuntimeWarning)]
        for w in caught:
            if w not in runtime and debug:
                print(f"{cmd}: warning: {one_line(w.message)}", file=sys.stderr)
        if runtime:
            print(f"{cmd}: warning: {_numpy_warning_line(runtime)}", file=sys.stderr)
        return rc
    except (SystemExit, KeyboardInterrupt):
        raise
    except InputError as exc:
        return _fail(cmd, debug, one_line(flag_text(exc)))
    except (
        FileNotFoundError,
        IsADirectoryError,
        NotADirectoryError,
        PermissionError,
        FileExistsError,
    ) as exc:
        name = getattr(exc, "filename", None) or ""
        return _fail(cmd, debug, one_line(f"{name}: {exc.strerror or exc}" if name else exc))
    except MemoryError as exc:
        return _fail(
            cmd,
            debug,
            one_line(
                f"out of memory ({exc or 'allocation failed'}); use a smaller scan or lower --max-pixels"
            ),
        )
    except OSError as exc:
        name = getattr(exc, "filename", None) or _output_of(args, exc)
        return _fail(cmd, debug, one_line(f"{str(name) + ': ' if name else ''}{exc.strerror or exc}"))
    except _parsing_errors() as exc:
        return _fail(cmd, debug, one_line(f"cannot parse this input ({type(exc).__name__}: {exc})"))
    except Exception as exc:  # last resort: a bug, still one line
        if _interrupted(exc):  # a stop request that a library wrapped (Python wraps an
            raise KeyboardInterrupt from exc  # exception raised while a class is made, 3.11)
        if isinstance(exc, RuntimeError) and "symlink loop" in str(exc).lower():  # pathlib, a looping link
            return _fail(cmd, debug, one_line(f"{exc}: a symbolic link loop"))
        return _fail(
            cmd,
            debug,
            one_line(f"internal error ({type(exc).__name__}: {exc}); rerun with --debug for the traceback"),
            internal=True,
        )
    finally:
        io_common.set_max_pixels(previous_limit)
        say_warnings(said_before)
        notes()


def _print_notes():
    """Print the ``roadscan`` logger's notes on stderr, each as its bare line, while the command
    runs; returns the function that undoes it (a test calls several commands in one process)."""
    import logging

    logger = logging.getLogger("roadscan")
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("%(message)s"))
    old_level, old_propagate = logger.level, logger.propagate
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
    logger.propagate = False

    def undo():
        logger.removeHandler(handler)
        logger.setLevel(old_level)
        logger.propagate = old_propagate

    return undo


def _interrupted(exc):
    """Whether ``exc`` follows a stop request: a KeyboardInterrupt (or a SIGTERM/SIGHUP turned
    into one) among its causes, or a stop signal received while the command ran."""
    from pipelines.cli.signals import received

    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return received() is not None


#: errors of writing: when the exception names no file, the message names the command's output
_WRITE_ERRNOS = {
    getattr(errno, n) for n in ("ENOSPC", "EDQUOT", "EFBIG", "EROFS", "EIO") if hasattr(errno, n)
}


def _output_of(args, exc):
    if getattr(exc, "errno", None) not in _WRITE_ERRNOS:
        return None
    out = getattr(args, "out", None) or getattr(args, "output", None)
    return f"{out} (writing the output)" if out else None


def _fail(cmd, debug, message, internal=False):
    if debug:
        traceback.print_exc()
    label = "" if internal else "error: "
    print(f"{cmd}: {label}{message}", file=sys.stderr)
    return 1 if internal else 2


if __name__ == "__main__":
    sys.exit(main())
