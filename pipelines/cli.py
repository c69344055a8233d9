"""The ``roadscan`` command. Each subcommand lives in ``pipelines/commands/<name>.py`` and
provides ``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``.

Bad input raises :class:`roadscan.InputError` (or ``FileNotFoundError``/``ValueError`` from a
reader); it is reported as one line on stderr with exit code 2, never a traceback.
"""
from __future__ import annotations

import argparse
import importlib
import sys

from roadscan.errors import InputError

# subcommand modules, in the order ``roadscan --help`` lists them
COMMAND_MODULES = (
    "analyse", "batch", "synth", "friction_cmd", "rubber", "stitch", "rainfill", "dry_vs_wet", "compare",
    "diagnose", "convert",
)


def _load_commands():
    mods = []
    for name in COMMAND_MODULES:
        try:
            mods.append(importlib.import_module(f"pipelines.commands.{name}"))
        except ModuleNotFoundError as exc:  # a command not built yet
            if exc.name != f"pipelines.commands.{name}":
                raise
    return mods


def build_parser():
    parser = argparse.ArgumentParser(
        prog="roadscan",
        description="Road-surface scans to spectra, rain fill and rubber friction.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for mod in _load_commands():
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=mod.HELP)
        mod.add_arguments(p)
        p.set_defaults(_run=mod.run)
    return parser




def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)  # argparse exits with code 2 on usage errors
    try:
        return int(args._run(args) or 0)
    except InputError as exc:
        print(f"roadscan {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except (FileNotFoundError, IsADirectoryError, PermissionError) as exc:
        name = getattr(exc, "filename", None) or ""
        print(f"roadscan {args.command}: error: {name}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("roadscan: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
