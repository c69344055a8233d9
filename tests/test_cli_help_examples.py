"""Help that teaches (issue 37): every parser of the ``roadscan`` command (every subcommand and
sub-action) ends its ``--help`` with example commands, every option has help text, and every
example is a command the parser accepts."""

from __future__ import annotations

import argparse
import shlex

import pytest

from pipelines.cli.app import build_parser, main


def _walk(parser, path):
    yield path, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _walk(sub, [*path, name])


PARSERS = list(_walk(build_parser(), ["roadscan"]))


def _examples(parser):
    lines = (parser.epilog or "").splitlines()
    return [ln.strip() for ln in lines[1:] if ln.strip().startswith("roadscan")]


def test_every_command_is_walked():
    names = {" ".join(p) for p, _ in PARSERS}
    for cmd in ("analyse", "compare", "dry-vs-wet", "friction", "rubber master", "batch", "convert"):
        assert f"roadscan {cmd}" in names


@pytest.mark.parametrize("path,parser", PARSERS, ids=[" ".join(p) for p, _ in PARSERS])
def test_every_action_has_help(path, parser):
    bare = [
        a.option_strings or [a.dest]
        for a in parser._actions
        if not isinstance(a, argparse._SubParsersAction) and not (a.help or "").strip()
    ]
    assert not bare, (" ".join(path), bare)


@pytest.mark.parametrize("path,parser", PARSERS, ids=[" ".join(p) for p, _ in PARSERS])
def test_every_parser_ends_with_examples_that_parse(path, parser):
    ex = _examples(parser)
    assert 1 <= len(ex) <= 2, (" ".join(path), parser.epilog)
    assert parser.epilog.splitlines()[0] in ("example:", "examples:")
    for line in ex:
        argv = shlex.split(line, comments=True)[1:]
        if "--help" in argv:
            continue
        args = build_parser().parse_args(argv)  # exits (SystemExit) on an unknown flag
        assert args.command == path[1] if len(path) > 1 else args.command
        if len(path) > 1:
            assert argv[0] == path[1], (path, line)  # the example runs its own command


@pytest.mark.parametrize("cmd", ["compare", "dry-vs-wet", "analyse"])
def test_help_output_ends_with_the_examples(cmd, capsys):
    with pytest.raises(SystemExit) as e:
        main([cmd, "--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out.rstrip().splitlines()
    sub = next(p for path, p in PARSERS if path == ["roadscan", cmd])
    ex = _examples(sub)
    assert [ln.strip() for ln in out[-len(ex) :]] == ex  # verbatim, not re-wrapped
    assert any(ln.lstrip().startswith("--out") for ln in out)
    out_help = next(a.help for a in sub._actions if "--out" in a.option_strings)
    assert "output" in out_help
