"""The Python door: real signatures, SI numbers, rubber objects, warnings through ``warnings``
(never printed), short reprs, and every option the same as the command's flag."""

from __future__ import annotations

import contextlib
import inspect
import io
import warnings

import numpy as np
import pytest
from conftest import fourier_surface

import friction
import pipelines
from pipelines.settings.analyse import _parser, add_compare_options
from pipelines.settings.keywords import job_parameters
from pipelines.settings.water import add_dry_vs_wet_options, add_rain_fill_options
from roadscan import RoadscanWarning
from roadscan.heightmap import HeightMap

JOBS = ["analyse", "compare", "dry_vs_wet", "rain_fill", "friction", "combine", "diagnose", "batch"]


def _flags(add_options):
    """``{dest: default}`` of a command's option definitions (public argparse API only)."""
    return vars(_parser(add_options).parse_known_args([])[0])


@pytest.mark.parametrize("name", JOBS)
def test_every_job_has_a_real_signature(name):
    job = getattr(pipelines, name)
    sig = inspect.signature(job)
    kinds = [p.kind for p in sig.parameters.values()]
    assert inspect.Parameter.VAR_KEYWORD not in kinds and inspect.Parameter.VAR_POSITIONAL not in kinds
    opts = job_parameters(job)
    assert len(opts) >= 3
    for p in opts.values():
        assert p.default is not inspect.Parameter.empty, (name, p.name)
        assert p.annotation is not inspect.Parameter.empty, (name, p.name)
    assert "Parameters" in (job.__doc__ or "")
    for pname in opts:  # help() lists every option
        assert f"\n    {pname} :" in job.__doc__, (name, pname)


def _equivalent(name, flag_default, api_default):
    if name == "sigma0" and flag_default is not None:
        from pipelines.settings.friction import parse_pressure

        return parse_pressure(flag_default) == parse_pressure(api_default)
    return flag_default == api_default


@pytest.mark.parametrize(
    "name, add_options, extra",
    [
        ("analyse", None, {"out"}),
        ("compare", add_compare_options, set()),
        ("dry_vs_wet", add_dry_vs_wet_options, set()),
        ("rain_fill", add_rain_fill_options, set()),
    ],
)
def test_options_are_the_command_flags(name, add_options, extra):
    # names are the long flags with underscores; defaults mean the same (a test, so that the
    # two doors cannot drift apart)
    flags = _flags(add_options)
    opts = job_parameters(getattr(pipelines, name))
    assert set(flags) <= set(opts), set(flags) - set(opts)
    for dest, default in flags.items():
        assert _equivalent(dest, default, opts[dest].default), dest


@pytest.fixture(scope="module")
def small_scan():
    # 64^2 at 0.1 mm: its reliable band is narrow, so the chain warns
    return HeightMap(fourier_surface(64, 1e-4, 0.8, 2e-4, seed=3), 1e-4, 1e-4)


@pytest.fixture(scope="module")
def scan():
    return HeightMap(fourier_surface(128, 5e-5, 0.8, 2e-4, seed=11), 5e-5, 5e-5)


def test_numbers_in_si_equal_text_with_units(scan):
    v = np.logspace(-2, 1, 5)
    a = pipelines.analyse(scan, sigma0=2.5e5, velocities=v, no_figures=True)
    b = pipelines.analyse(scan, sigma0="0.25MPa", velocities="0.01:10:5", no_figures=True)
    assert a.summary == b.summary
    c = pipelines.analyse(scan, sigma0=4e5, velocities=v, no_figures=True)
    assert not np.allclose(a.mu, c.mu)  # the pressure reached the engine


def test_a_rubber_object_is_a_rubber(scan):
    v = np.logspace(-2, 1, 5)
    default = pipelines.analyse(scan, velocities=v, no_figures=True)
    given = pipelines.analyse(scan, velocities=v, rubber=friction.thesis_rubber(), no_figures=True)
    np.testing.assert_allclose(given.mu, default.mu, rtol=1e-12)  # the thesis rubber is the default
    from roadscan.errors import InputError

    with pytest.raises(InputError, match="rubber"):
        pipelines.analyse(scan, rubber=object(), no_figures=True)


def test_wrong_kinds_are_refused_naming_the_option(scan):
    from roadscan.errors import InputError

    with pytest.raises(InputError, match="--units"):
        pipelines.analyse(scan, units="inch")
    with pytest.raises(InputError, match="--nu"):
        pipelines.analyse(scan, nu="soft")
    with pytest.raises(TypeError):
        pipelines.analyse(scan, poisson=0.4)


def test_the_library_never_prints_and_warns_as_python_does(small_scan, tmp_path):
    err, out = io.StringIO(), io.StringIO()
    with (
        warnings.catch_warnings(record=True) as caught,
        contextlib.redirect_stderr(err),
        contextlib.redirect_stdout(out),
    ):
        warnings.simplefilter("always")
        r = pipelines.analyse(small_scan, no_figures=True)
        d = pipelines.rain_fill(small_scan, tmp_path / "rain")
    assert err.getvalue() == "" and out.getvalue() == ""
    ours = [str(w.message) for w in caught if issubclass(w.category, RoadscanWarning)]
    assert r.warnings, "this scan's narrow band is a warning"
    assert set(r.warnings) <= set(ours)
    assert isinstance(d, dict)
    # silenced as a group
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.simplefilter("ignore", RoadscanWarning)
        r2 = pipelines.analyse(small_scan, no_figures=True)
    assert not [w for w in caught if issubclass(w.category, RoadscanWarning)]
    assert r2.warnings == r.warnings  # still carried in the result


def test_notes_go_to_the_roadscan_logger(caplog):
    import logging

    from pipelines.checks.run_warnings import note

    with caplog.at_level(logging.INFO, logger="roadscan"):
        note("note: a choice the run made")
    assert [r.getMessage() for r in caplog.records] == ["note: a choice the run made"]


def test_a_result_shows_a_short_repr():
    scan = HeightMap(fourier_surface(256, 5e-5, 0.8, 2e-4, seed=5), 5e-5, 5e-5)
    r = pipelines.analyse(scan, no_figures=True, velocities=np.logspace(-2, 1, 5))
    text = repr(r)
    assert len(text) < 500 and "H=" in text and "mu_max" in text
    assert r.summary["hurst"] == pytest.approx(float(text.split("H=")[1].split(",")[0]), rel=2e-3)


def _silently(call):
    """(result, this call's RoadscanWarning texts) with stdout and stderr captured: both empty."""
    err, out = io.StringIO(), io.StringIO()
    with (
        warnings.catch_warnings(record=True) as caught,
        contextlib.redirect_stderr(err),
        contextlib.redirect_stdout(out),
    ):
        warnings.simplefilter("always")
        result = call()
    assert err.getvalue() == "" and out.getvalue() == "", (err.getvalue(), out.getvalue())
    return result, [str(w.message) for w in caught if issubclass(w.category, RoadscanWarning)]


def test_every_job_is_silent_carries_its_warnings_and_shows_a_short_repr(small_scan, tmp_path):
    from pipelines.diagnosis.cases import make_case
    from pipelines.diagnosis.inputs import write_psd_csv
    from pipelines.output.report import write_csv

    np.save(tmp_path / "s.npy", small_scan.heights_m)
    scan_file = tmp_path / "s.npy"
    psd_file = tmp_path / "psd.csv"
    c = make_case(11, "temperature_offset", scan=False)
    q = np.geomspace(c.psd.q_min_per_m, c.psd.q1_per_m, 60)
    write_psd_csv(psd_file, q, c.psd.C(q))
    # 8 of the case's speeds: silence, warnings and repr do not depend on the count, the time does
    keep = np.unique(np.linspace(0, c.curve.v_m_per_s.size - 1, 8).round().astype(int))
    mu_file = write_csv(tmp_path / "mu.csv", ["v_m_per_s", "mu"], [c.curve.v_m_per_s[keep], c.curve.mu[keep]])
    v = np.logspace(-2, 1, 4)
    calls = {
        "compare": lambda: pipelines.compare([small_scan, small_scan], tmp_path / "c", velocities=v),
        "dry_vs_wet": lambda: pipelines.dry_vs_wet(small_scan, tmp_path / "w", velocities=v),
        "rain_fill": lambda: pipelines.rain_fill(small_scan, tmp_path / "r"),
        "friction": lambda: pipelines.friction(tmp_path / "f" / "mu.csv", psd=psd_file, velocities=v),
        "combine": lambda: pipelines.combine([scan_file], tmp_path / "m", spacing=1e-4, no_figures=True),
        "diagnose": lambda: pipelines.diagnose(
            tmp_path / "d", measured=mu_file, psd=psd_file, noise=0.02, uncertain="q1=known"
        ),
        "batch": lambda: pipelines.batch(
            [scan_file], tmp_path / "b", spacing=1e-4, no_friction=True, workers=1
        ),
    }
    for name, call in calls.items():
        result, issued = _silently(call)
        assert isinstance(result, dict) and result.job == name
        assert len(repr(result)) < 500, (name, repr(result))
        assert set(result.warnings) <= set(issued), name  # each also a RoadscanWarning
        if name in ("compare", "dry_vs_wet", "combine"):
            assert result.warnings, f"{name}: the small scan's narrow band is a warning"
