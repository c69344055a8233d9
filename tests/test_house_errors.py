"""The house: structured input errors (roadscan names options, the CLI names flags), bugs not
reported as bad input, one length formatter, one resolution and its bound, HTML templates."""

import json
import pickle

import numpy as np
import pytest

from pipelines.cli.app import main
from roadscan.errors import InputError, OptionNote


def test_input_error_names_options_by_keyword_and_renders_flags():
    e = InputError(
        "a.npy",
        "no spacing: pass {spacing} DX[,DY] and {override_calibration}",
        ("spacing", "override_calibration"),
    )
    assert (e.file, e.hint_option) == ("a.npy", ("spacing", "override_calibration"))
    assert str(e) == "a.npy: no spacing: pass 'spacing' DX[,DY] and 'override_calibration'"
    assert e.what == "no spacing: pass 'spacing' DX[,DY] and 'override_calibration'"
    from pipelines.cli.hints import flag_text

    assert flag_text(e) == "a.npy: no spacing: pass --spacing DX[,DY] and --override-calibration"
    assert isinstance(e, ValueError)  # library callers catching ValueError still do


def test_input_error_keeps_its_options_across_processes_and_rewording():
    e = InputError(None, "{channel} 7: no such channel", "channel")
    back = pickle.loads(pickle.dumps(e))
    assert back.render(lambda k: "--" + k) == "--channel 7: no such channel"
    moved = e.reworded("f.tif", "read by its content: ")
    assert str(moved) == "f.tif: read by its content: 'channel' 7: no such channel"
    assert moved.hint_option == ("channel",)


def test_braces_that_are_not_options_stay():
    e = InputError("x.csv", "bad value '{a}' near {spacing}", "spacing")
    assert str(e) == "x.csv: bad value '{a}' near 'spacing'"
    plain = InputError("x.csv", "bad value '{spacing}'")  # no options: text as given
    assert str(plain) == "x.csv: bad value '{spacing}'"


def test_option_note_is_text_and_renders():
    n = OptionNote("{spacing} 5e-05 ignored", "spacing")
    assert n == "'spacing' 5e-05 ignored" and n.render(lambda k: "--" + k) == "--spacing 5e-05 ignored"
    assert pickle.loads(pickle.dumps(n)).render(lambda k: "--" + k) == "--spacing 5e-05 ignored"
    assert str(InputError("p", n)) == "p: 'spacing' 5e-05 ignored"


def test_cli_names_the_flag_a_reader_points_at(tmp_path, capsys):
    p = tmp_path / "s.npy"
    np.save(p, np.random.default_rng(0).standard_normal((32, 32)) * 1e-4)
    assert main(["analyse", str(p), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "--spacing" in err and "'spacing'" not in err


def _replace_synth_run(monkeypatch, run):
    import pipelines.cli.app as cli

    real = cli.build_parser

    def patched():
        parser = real()
        for action in parser._actions:
            if getattr(action, "choices", None) and "synth" in action.choices:
                action.choices["synth"].set_defaults(_run=run)
        return parser

    monkeypatch.setattr(cli, "build_parser", patched)


@pytest.mark.parametrize(
    "exc",
    [
        ValueError("x must be positive"),
        ZeroDivisionError("division"),
        OverflowError("big"),
        IndexError("index 3"),
    ],
)
def test_a_programming_error_is_never_bad_input(monkeypatch, capsys, tmp_path, exc):
    def boom(args):
        raise exc

    _replace_synth_run(monkeypatch, boom)
    assert main(["synth", "--out", str(tmp_path / "x.npy")]) == 1
    err = capsys.readouterr().err
    assert "internal error" in err and type(exc).__name__ in err and ": error:" not in err


def test_bad_input_and_parsing_errors_stay_exit_2(monkeypatch, capsys, tmp_path):
    def bad(args):
        raise InputError("f.csv", "{units} furlong: unknown unit", "units")

    _replace_synth_run(monkeypatch, bad)
    assert main(["synth", "--out", str(tmp_path / "x.npy")]) == 2
    assert "f.csv: --units furlong: unknown unit" in capsys.readouterr().err

    def broken_json(args):
        json.loads("{not json")

    _replace_synth_run(monkeypatch, broken_json)
    assert main(["synth", "--out", str(tmp_path / "y.npy")]) == 2
    assert "cannot parse" in capsys.readouterr().err


@pytest.mark.parametrize(
    "x, text",
    [
        (3.2755905e-3, "3.28 mm"),
        (3.974e-4, "397 µm"),
        (0.06, "60.0 mm"),
        (1.80872, "1.81 m"),
        (9.9996e-4, "1.00 mm"),
        (9.994e-4, "999 µm"),
        (1.2e-8, "12.0 nm"),
        (-2.5e-3, "-2.50 mm"),
        (0.0, "0 mm"),
        (None, "—"),
        (float("nan"), "—"),
    ],
)
def test_one_length_formatter(x, text):
    from pipelines.output.units import length as pipelines_length
    from roadscan.units import length

    assert length(x) == text == pipelines_length(x)


def test_length_formatter_against_independent_rounding():
    from roadscan.units import length

    rng = np.random.default_rng(3)
    for x in 10 ** rng.uniform(-8.5, 0.5, 300):
        value, unit = length(x).split()
        f = {"m": 1.0, "mm": 1e-3, "µm": 1e-6, "nm": 1e-9}[unit]
        assert float(value) == pytest.approx(float(f"{x / f:.3g}"), rel=1e-12)
        assert 1 <= float(value) < 1000 or unit == "nm" or (unit == "m" and x >= 1)


def test_one_resolution_and_one_bound(tmp_path):
    from roadscan.heightmap import HeightMap
    from roadscan.resolution import RESOLUTION_MAX_M, resolution_of, resolution_problem

    hm = HeightMap(np.zeros((8, 8)), 1e-4, 1e-4)
    assert resolution_of(hm) == (None, None)
    hm.meta["resolution_m"] = 2e-5  # a top-level key counts too
    assert resolution_of(hm) == (2e-5, "file metadata")
    hm.meta["instrument"] = {"lateral_resolution_m": 3e-5}  # the instrument block first
    assert resolution_of(hm) == (3e-5, "file metadata")
    assert resolution_of(hm, 1e-5) == (1e-5, "given")
    assert resolution_problem(RESOLUTION_MAX_M) is None and resolution_problem(1.5 * RESOLUTION_MAX_M)
    assert resolution_problem(0.0) and resolution_problem(float("inf")) and resolution_problem("x")
    from pipelines.jobs.combine.inputs import collect_inputs
    from pipelines.settings.analyse import check_resolution

    with pytest.raises(InputError, match="--resolution"):
        check_resolution(5.0)  # combine accepted up to 10 m
    (tmp_path / "a.npy").write_bytes(b"")
    (tmp_path / "m.csv").write_text("file,resolution_m\na.npy,5\n")
    with pytest.raises(InputError, match="resolution_m"):
        collect_inputs([tmp_path / "m.csv"])


def test_html_from_templates_escapes_what_it_is_given(tmp_path):
    from pipelines.output import report

    hostile = "<script>alert('x')</script> & \"q\""
    t = report.table_html([[hostile, 1.23456, None, [1e-3, 2.0]]], [hostile])
    assert "<script>" not in t and "&lt;script&gt;" in t and "1.23" in t and "—" in t
    li = report.list_html([hostile], links=["a b/report.html"])
    assert "<script>" not in li and "href='a b/report.html'" in li
    png = tmp_path / "f.png"
    png.write_bytes(b"\x89PNG\r\n\x1a\nfake")
    out = report.write_html(
        tmp_path / "r.html",
        hostile,
        [(hostile, [t, png, [png, png]])],
        intro=report.instrument_html({"name": hostile}),
    )
    html = out.read_text()
    assert "<script>" not in html and html.count("data:image/png;base64,") == 3
    assert html.count("<table>") == 1 and "Instrument" in html
