"""Property-based fuzz of every reader and every command's numbers (issue 14).

Hypothesis makes odd files (``fuzz_files``: truncated, garbage bytes, wrong headers, huge declared
sizes, NaN/inf/denormal/constant/complex/int data, tiny and 1-row grids) for every reader (npy,
npz, tif, x3p, gwy, text/csv/asc/xyz, CAPTIF .dat; vendor extensions with garbage bytes) and odd
flag values (spacing, sigma0 with and without units, nu, temperature, q0/q1, velocities, units,
...) for every command, and runs the command line in-process (``pipelines.cli.app.main``; a few runs
as subprocesses). ``fuzz_harness.judge`` fails a case on any traceback, any exit code but 0 and 2,
a multi-line or missing error line, exit 0 with NaN/inf in a CSV/JSON output, and anything left
behind by a failed run. The counts of the cases tried are printed at the end of the module.

CI runs a fixed (derandomised) set in well under a minute; ``benchmarks/fuzz_long.py`` runs the
same strategies with many more, random examples and prints the counts of cases and failures.
Figures are stubbed in most cases (drawing is 95 % of a small run); ``test_figures_drawn``
draws them, as does the long run.
"""

from __future__ import annotations

import contextlib
import io
import shutil
import warnings

import fuzz_files as ff
import numpy as np
import pytest
from conftest import fourier_surface
from fuzz_harness import (
    FAILURES,
    STATS,
    counts_line,
    fuzz_settings,
    memory_cap,
    reader_limit,
    record,
    run_cli,
    run_subprocess,
    time_limit,
    workdir,
    write_report,
)
from hypothesis import given
from hypothesis import strategies as st

SAMPLES = ff.SAMPLES


# ------------------------------------------------------------------------------ fixtures
@pytest.fixture(scope="module")
def base(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz")


@pytest.fixture(scope="module")
def goods(tmp_path_factory):
    """Good inputs, read-only during the fuzz (watched: a command must never change them)."""
    d = tmp_path_factory.mktemp("goods")
    g = fourier_surface(48, 5e-5, 0.8, 3e-4, seed=1)
    np.save(d / "good.npy", g)
    np.save(d / "good2.npy", fourier_surface(48, 5e-5, 0.6, 2e-4, seed=2))
    wide = fourier_surface(96, 5e-5, 0.8, 3e-4, seed=3)[:40]
    np.save(d / "tile_a.npy", wide[:, :56])
    np.save(d / "tile_b.npy", wide[:, 40:])
    for name in ("asphalt_psd.csv", "measured_mu_example.csv"):
        shutil.copy(SAMPLES / name, d / name)
    for name in (
        "thesis_sls.toml",
        "freq_user_master.csv",
        "freq_user_master__shift_factors.csv",
        "freq_user_raw.csv",
    ):
        shutil.copy(SAMPLES / "rubbers" / name, d / name)
    return d


@pytest.fixture(scope="module", autouse=True)
def counts(request):
    yield
    line = counts_line()
    write_report()
    capman = request.config.pluginmanager.get_plugin("capturemanager")
    tr = request.config.pluginmanager.get_plugin("terminalreporter")
    with capman.global_and_fixture_disabled() if capman else contextlib.nullcontext():
        if tr is not None:
            tr.write_line("")
            tr.write_line(line)
        else:
            print(line)


def _flag(name, value):
    if value is None:
        return []
    if value is True:
        return [name]
    if value is False:
        return []
    return [f"{name}={value}"]


def _flags(**kw):
    out = []
    for k, v in kw.items():
        out += _flag("--" + k.replace("_", "-"), v)
    return out


# ------------------------------------------------------------------------------ flag specifications
F = ff.F
ODD_SPACING = [
    "1e-300",
    "0",
    "-5e-5",
    "5e-5,",
    ",",
    "5e-5;6e-5",
    "5e-5,5e-5,5e-5",
    "1",
    "2",
    "1e-9",
    "1e-10",
    "nan,5e-5",
    "5e-5,0",
    "1e-3",
]
ODD_PRESSURE = [
    "0.3",
    "-0.2MPa",
    "0MPa",
    "1e300Pa",
    "nanMPa",
    "infPa",
    "0.3 psi",
    "0.3MPa/m",
    "3e5%",
    "1e10Pa",
    "999",
    "1000",
    "0.3 MPa",
    "0.3mpa",
    "0.3N/mm2",
    "1e-300MPa",
    "2bar",
    "1.1GPa",
    "MPa",
]
ODD_TEMPERATURE = [
    "-400",
    "-81.5",
    "-76.5",
    "-76",
    "-273.15",
    "-273.16",
    "999",
    "1001",
    "-88.47",
    "-138.47",
    "-143.47",
    "1e300",
]
ODD_Q = ["-5", "10", "1e300", "6.3e4", "1e-300", "0", "2e3", "2.7e3"]
SPEED_LISTS = ["1e-3:1:3", "1e-3:1:3", "1e-3:1:3", "1e-6:1e2:5", "1e-8:1e4:121"]
ODD_SPEEDS = [
    "1e-3:1",
    "1:1e-3:3",
    "0:1:3",
    "-1:1:3",
    "1e-3:1:1",
    "1e-3:1:0",
    "1e-3:1:-3",
    "1e-3:1:abc",
    "1e-3:1:2.5",
    "1e-3,1,3",
    "1e-3::1:3",
    "1e-3:inf:3",
    "nan:1:3",
    "1e-300:1e300:3",
    "1e-12:1e-10:3",
    "1e4:1e6:3",
    "1e3:1e4:3",
    "5:5:3",
    "1e-3:1:1e1",
    ":",
    "",
]

#: the friction options of analyse, compare, dry-vs-wet, batch
FRICTION = {
    "sigma0": F(["0.2MPa", "0.3MPa", "300kPa", "3e5Pa", "3e5", "2bar"], ODD_PRESSURE),
    "temperature": F(["20", "60", "-20", "100", "0"], ODD_TEMPERATURE),
    "nu": F(["0.5", "0.3", "0", "0.49"], ["0.7", "-0.1", "0.5000001", "1"], 3),
    "q0": F(["3e3", "5e3", "1e4"], ODD_Q, 4),
    "q1": F(["1e4", "3e4", "5e4", "1e5", "1e6"], ODD_Q, 3),
    "contact_gamma": F(["0", "0.5", "1"], ["1.5", "-0.1"], 4),
    "extrapolate": F(["powerlaw", "hold"], ["linear", ""], 4),
    "flash": F([False, False, True], (), 0),
    "velocities": F(SPEED_LISTS, ODD_SPEEDS, 0),
}
SCAN = {
    "spacing": F(["5e-5"], ODD_SPACING, 0),
    "units": F(["m", "mm", "um", "nm"], ["µm", "M", "furlong", ""], 4),
}
ANALYSIS = {
    "window_alpha": F(["0", "0.25", "1"], (), 5),
    "fit_band": F(
        ["3e3,3e4", "1e4,5e4"],
        [
            "5e4,1e4",
            "0,1",
            "1e10,1e11",
            "nan,1e4",
            "1e4",
            "a,b",
            "3e3,3e3",
            "-1,1e4",
            "1e4,1e300",
            "1e-300,1e4",
        ],
        5,
    ),
    "mpd_spike_alpha": F(["3", "6"], ["0", "1e-300", "1e300"], 5),
    "despike": F([False, False, True], (), 0),
    "no_friction": F([False, False, False, True], (), 0),
    "max_pixels": F(["100000000", "4000"], ["0", "-1", "abc", "1e300", "1", "inf", "nan", "2.5"], 6),
}


@st.composite
def rubber_choice(draw):
    return draw(st.sampled_from([None, None, None, "good", "fuzz"]))


def _rubber_arg(choice, goods, folder, data):
    if choice == "good":
        return goods / "thesis_sls.toml"
    if choice == "fuzz":
        spec = data.draw(ff.rubber_toml_files(), label="rubber.toml")
        shutil.copy(goods / "freq_user_master.csv", folder / "master.csv")
        return spec.write(folder)
    return None


# ------------------------------------------------------------------------------ readers
SPACING_ARG = st.one_of(
    st.none(),
    st.sampled_from(
        [
            5e-5,
            1e-4,
            (5e-5, 6e-5),
            0.0,
            -1.0,
            float("nan"),
            1e-300,
            "5e-5",
            "5e-5,6e-5",
            "abc",
            "",
            (1.0, 2.0, 3.0),
            5e-324,
        ]
    ),
)


@given(
    spec=st.one_of(ff.any_height_file(), ff.analysable_height_file()),
    spacing=SPACING_ARG,
    units=st.sampled_from([None, None, "m", "mm", "um", "nm", "furlong", ""]),
)
@fuzz_settings(260)
def test_readers_never_crash(base, spec, spacing, units):
    """Every reader, on any file: a HeightMap/Profile that passes its invariants, or one
    InputError line naming the file; the plausibility checks then accept or refuse in one line."""
    from pipelines.checks.validate import check_scan
    from roadscan.errors import InputError
    from roadscan.heightmap import HeightMap, Profile
    from roadscan.io import read

    with workdir(base) as d:
        p = spec.write(d)
        problems, obj, rc = [], None, 2
        err = io.StringIO()
        with (
            warnings.catch_warnings(record=True),
            reader_limit(),
            memory_cap(),
            contextlib.redirect_stderr(err),
        ):
            warnings.simplefilter("always")
            try:
                with time_limit(30):
                    obj = read(p, spacing=spacing, units=units)
                    check_scan(obj, p)
                rc = 0
            except InputError as exc:
                msg = str(exc)
                if "\n" in msg or not msg.strip():
                    problems.append(f"InputError not one line: {msg!r}")
                if str(p) not in msg:
                    problems.append(f"InputError does not name the file: {msg!r}")
            except BaseException as exc:  # noqa: BLE001
                problems.append(f"{type(exc).__name__}: {exc}"[:300])
                rc = "exception"
        if obj is not None and rc == 0:
            h = obj.heights_m
            if not isinstance(obj, (HeightMap, Profile)):
                problems.append(f"read returned {type(obj).__name__}")
            elif h.dtype != np.float64 or h.ndim != (2 if isinstance(obj, HeightMap) else 1):
                problems.append(f"heights {h.dtype} {h.shape}")
            else:
                um = np.asarray(obj.unmeasured, bool)
                if um.shape != h.shape or not np.all(np.isfinite(h[~um])) or not np.all(np.isnan(h[um])):
                    problems.append("unmeasured mask does not match the NaN heights")
                for s in (obj.dx_m, getattr(obj, "dy_m", obj.dx_m)):
                    if not (np.isfinite(s) and s > 0):
                        problems.append(f"spacing {s}")
        record("read", f"{spec!r} spacing={spacing!r} units={units!r}", rc, problems, err.getvalue())


# ------------------------------------------------------------------------------ analyse
@given(data=st.data(), spec=st.one_of(ff.analysable_height_file(), ff.any_height_file()))
@fuzz_settings(36)
def test_analyse_odd_files(base, goods, data, spec):
    with workdir(base) as d:
        p = spec.write(d)
        sp = data.draw(st.sampled_from(["5e-5", "5e-5", None, "1e-4,5e-5"]), label="spacing")
        fr = data.draw(st.sampled_from([["--no-friction"], ["--velocities=1e-3:1:3"]]), label="friction")
        units = data.draw(ff.maybe(st.sampled_from(["m", "mm", "um", "nm"]), 3), label="units")
        despike = data.draw(st.sampled_from([False, False, True]), label="despike")
        argv = ["analyse", p, "--out", d / "out", *_flags(spacing=sp, units=units, despike=despike), *fr]
        run_cli("analyse-files", argv, d, watch=[goods], desc=repr(spec))


@given(data=st.data(), kw=ff.flagset({**SCAN, **ANALYSIS, **FRICTION}), rubber=rubber_choice())
@fuzz_settings(36)
def test_analyse_flags(base, goods, data, kw, rubber):
    with workdir(base) as d:
        rub = _rubber_arg(rubber, goods, d, data)
        scan = data.draw(st.sampled_from(["good.npy", "good.npy", "good.npy", "good2.npy"]), label="scan")
        argv = ["analyse", goods / scan, "--out", d / "out", *_flags(**kw), *_flag("--rubber", rub)]
        run_cli("analyse-flags", argv, d, watch=[goods])


# ------------------------------------------------------------------------------ friction
@st.composite
def self_affine(draw):
    kw = draw(
        ff.flagset(
            {
                "H": F(["0.8", "0.5", "0.9"], ["0", "1", "1.5", "-0.2"], 0),
                "h0": F(["1e-4", "3e-4", "1e-5"], ["0", "1e3"], 0),
                "q0": F(["1e3", "300", "1e4"], ["0", "1e7"], 0),
                "q1": F(["1e6", "1e5", "1e7"], ["1e3", "1e300"], 0),
                "qroll": F(["3e3", "1e3"], ["1e8", "1"], 4),
            }
        )
    )
    keys = [k for k, v in kw.items() if v is not None]
    if draw(st.integers(0, 6)) == 0:
        keys.remove(draw(st.sampled_from(keys)))
    if draw(st.integers(0, 8)) == 0:
        keys.append(draw(st.sampled_from(["H", "foo", "h0"])))
    text = ",".join(f"{k}={kw.get(k) or '1'}" for k in keys)
    return draw(st.sampled_from([text] * 6 + [text.replace(",", ";"), text.replace("=", ":"), "", "H=0.8"]))


FRICTION_CMD = {
    **{k: v for k, v in FRICTION.items()},
    "tol": F(["1e-3", "1e-2"], ["0", "1", "1e-300"], 4),
    "magnifications": F(["1,10,100"], ["0", "-1,2", "abc", "1e300", "nan", ",", "1,,2"], 5),
}


@given(data=st.data(), kw=ff.flagset(FRICTION_CMD))
@fuzz_settings(50)
def test_friction_flags(base, goods, data, kw):
    with workdir(base) as d:
        src = data.draw(st.sampled_from(["self", "self", "psd_good", "psd_good", "psd_fuzz"]), label="source")
        if src == "self":
            source = _flag("--self-affine", data.draw(self_affine(), label="self-affine"))
        elif src == "psd_good":
            source = ["--psd", goods / "asphalt_psd.csv"]
        else:
            source = ["--psd", data.draw(ff.psd_csv_files(), label="psd.csv").write(d)]
        rub = data.draw(
            st.sampled_from(["none", "none", "toml", "fuzz_toml", "master", "master_fuzz"]), label="rubber"
        )
        rubber = []
        if rub == "toml":
            rubber = ["--rubber", goods / "thesis_sls.toml"]
        elif rub == "fuzz_toml":
            rubber = ["--rubber", _rubber_arg("fuzz", goods, d, data)]
        elif rub in ("master", "master_fuzz"):
            mc = goods / "freq_user_master.csv"
            sh = goods / "freq_user_master__shift_factors.csv"
            if rub == "master_fuzz":
                if data.draw(st.booleans(), label="fuzz master"):
                    mc = data.draw(ff.master_curve_files(), label="master.csv").write(d)
                else:
                    sh = data.draw(ff.shift_table_files(), label="shift.csv").write(d)
            tref = data.draw(st.sampled_from([None, None, "-5", "20", "-400", "nan", "1e300"]), label="T_ref")
            rubber = [
                "--master-curve",
                mc,
                *(["--shift-table", sh] if data.draw(st.integers(0, 4)) else []),
                *_flag("--reference-temperature", tref),
            ]
        out = data.draw(st.sampled_from(["mu.csv", "mu.csv", "sub/mu.csv", "mu.txt", None]), label="out")
        argv = ["friction", *source, *rubber, *_flags(**kw), *_flag("--out", out)]
        run_cli("friction", argv, d, watch=[goods])


# ------------------------------------------------------------------------- rain-fill, dry-vs-wet, compare
WATER = {
    "connectivity": F(["4", "8"], ["6", "0"], 3),
    "max_depth": F(["1e-4", "1e-3"], ["0", "-1e-4"], 4),
    "water_film": F(["1e-5", "1e-4"], ["0", "1e3"], 5),
}


@given(
    data=st.data(),
    spec=st.one_of(ff.analysable_height_file(), ff.any_height_file(), st.none()),
    kw=ff.flagset({**SCAN, **WATER, "no_level": F([False, True], (), 0)}, odd_counts=(0, 0, 1, 1, 2)),
)
@fuzz_settings(30)
def test_rain_fill(base, goods, data, spec, kw):
    with workdir(base) as d:
        scan = spec.write(d) if spec is not None else goods / "good.npy"
        run_cli(
            "rain-fill",
            ["rain-fill", scan, "--out", d / "out", *_flags(**kw)],
            d,
            watch=[goods],
            desc=repr(spec),
        )


@given(
    data=st.data(),
    kw=ff.flagset({**SCAN, **WATER, **FRICTION, "no_friction": F([False, False, True], (), 0)}),
    spec=st.one_of(st.none(), st.none(), ff.analysable_height_file()),
    rubber=rubber_choice(),
)
@fuzz_settings(10)
def test_dry_vs_wet(base, goods, data, kw, spec, rubber):
    with workdir(base) as d:
        scan = spec.write(d) if spec is not None else goods / "good.npy"
        rub = _rubber_arg(rubber, goods, d, data)
        argv = ["dry-vs-wet", scan, "--out", d / "out", *_flags(**kw), *_flag("--rubber", rub)]
        run_cli("dry-vs-wet", argv, d, watch=[goods], desc=repr(spec))


@given(
    data=st.data(),
    kw=ff.flagset({**SCAN, **FRICTION, "no_friction": F([False, False, True], (), 0)}),
    specs=st.lists(st.one_of(ff.analysable_height_file(), ff.any_height_file()), max_size=2),
    rubber=rubber_choice(),
)
@fuzz_settings(10)
def test_compare(base, goods, data, kw, specs, rubber):
    with workdir(base) as d:
        scans = [goods / "good.npy"]
        for i, s in enumerate(specs):
            sub = d / f"in{i}"
            sub.mkdir()
            scans.append(s.write(sub))
        if len(scans) == 1 or data.draw(st.booleans(), label="good2"):
            scans.append(goods / "good2.npy")
        rub = _rubber_arg(rubber, goods, d, data)
        argv = ["compare", *scans, "--out", d / "out", *_flags(**kw), *_flag("--rubber", rub)]
        run_cli("compare", argv, d, watch=[goods], desc=repr(specs))


# ------------------------------------------------------------------------------ diagnose
DIAGNOSE = {
    "sigma0": FRICTION["sigma0"],
    "temperature": FRICTION["temperature"],
    "q0": FRICTION["q0"],
    "q1": FRICTION["q1"],
    "contact_gamma": FRICTION["contact_gamma"],
    "noise": F(["0.01", "0.05"], ["0", "-1", "1e300"], 3),
}


@given(data=st.data(), kw=ff.flagset(DIAGNOSE))
@fuzz_settings(8)
def test_diagnose(base, goods, data, kw):
    """Friction level on odd measured curves (most are refused quickly; a fit takes ~10 s) and
    the surface level on odd scans."""
    with workdir(base) as d:
        level = data.draw(st.sampled_from(["friction", "friction", "friction", "surface"]), label="level")
        if level == "friction":
            meas = data.draw(ff.measured_csv_files(), label="measured.csv").write(d)
            src = data.draw(st.sampled_from(["psd", "psd", "psd_fuzz"]), label="source")
            spec = (
                goods / "asphalt_psd.csv"
                if src == "psd"
                else data.draw(ff.psd_csv_files(), label="psd").write(d)
            )
            argv = ["diagnose", "--measured", meas, "--psd", spec]
        else:
            spec = data.draw(st.one_of(ff.analysable_height_file(), ff.any_height_file()), label="scan")
            argv = ["diagnose", "--scan", spec.write(d), "--spacing=5e-5"]
        run_cli("diagnose", [*argv, "--out", d / "out", *_flags(**kw)], d, timeout=90, watch=[goods])


# ------------------------------------------------------------------------------ stitch, synth, rubber master
STITCH = {
    "spacing": SCAN["spacing"],
    "max_shift": F(["5", "20"], ["0", "-1", "1000000", "abc", "2.5"], 3),
    "blend": F(["feather", "average"], ["max", ""], 3),
    "overlap": F(["0.286", "0.25", "0.3"], ["0", "1", "-0.1"], 0),
}


@given(data=st.data(), kw=ff.flagset(STITCH))
@fuzz_settings(24)
def test_stitch(base, goods, data, kw):
    with workdir(base) as d:
        mode = data.draw(st.sampled_from(["grid", "grid", "manifest"]), label="mode")
        tiles = [goods / "tile_a.npy", goods / "tile_b.npy"]
        if data.draw(st.integers(0, 2)) == 0:
            spec = data.draw(st.one_of(ff.analysable_height_file(), ff.npy_files()), label="odd tile")
            tiles[data.draw(st.integers(0, 1), label="which")] = spec.write(d)
        if mode == "grid":
            kw["grid"] = data.draw(
                st.sampled_from(
                    ["1x2"] * 6 + ["2x1", "0x2", "1x1", "x", "100000x100000", "-1x2", "1X2", "1x3"]
                ),
                label="grid",
            )
            inputs = tiles
        else:
            kw.pop("overlap")
            pos = data.draw(
                ff.flagset(
                    {
                        "x0": F(["0"], ["1e300", "-1"], 0),
                        "x1": F(["2e-3", "1.95e-3"], ["1e3", "0"], 0),
                        "y0": F(["0"], ["1e3"], 0),
                        "y1": F(["0", "5e-5"], ["-1e3"], 0),
                    }
                ),
                label="positions",
            )
            rows = [
                f"{t.name if t.parent == d else t},{x},{y}"
                for t, x, y in zip(tiles, (pos["x0"], pos["x1"]), (pos["y0"], pos["y1"]))
            ]
            man = d / "manifest.csv"
            man.write_text("file,x_m,y_m\n" + "\n".join(rows) + "\n")
            inputs = [man]
        out = data.draw(
            st.sampled_from(["st.npy"] * 3 + ["st.x3p", "st.npz", "st.tif", "st.txt", "st", "o/st.npy"]),
            label="out",
        )
        run_cli("stitch", ["stitch", *inputs, "--out", d / out, *_flags(**kw)], d, watch=[goods])


SYNTH = {
    "nx": F(["32", "16", "33"], ["0", "1", "2", "-5", "1e3", "100000", "3.5", "7", "65536"], 0),
    "ny": F(["32", "8", "40"], ["0", "1", "-5", "100000", "1000000"], 3),
    "spacing": F(["5e-5", "1e-4"], ["0", "1e-300", "1e300"], 2),
    "hurst": F(["0.8", "0.5", "0.99"], ["0", "1", "1.5", "-0.2"], 2),
    "rms": F(["5e-4", "1e-4"], ["0", "1e300", "1e-300"], 2),
    "q_roll": F(["3e3", "1e4"], ODD_Q, 4),
    "q0": F(["3e3", "5e3"], ODD_Q, 4),
    "q1": F(["3e4", "5e4"], ODD_Q, 4),
    "seed": F(["0", "1", "12345"], ["-1", str(2**70), "1.5"], 3),
}


@given(data=st.data(), kw=ff.flagset(SYNTH))
@fuzz_settings(30)
def test_synth(base, data, kw):
    with workdir(base) as d:
        out = data.draw(
            st.sampled_from(
                ["s.npy"] * 3 + ["s.npz", "s.x3p", "s.tif", "s.tiff", "s.txt", "s.foo", "s", "a/s.npy"]
            ),
            label="out",
        )
        run_cli("synth", ["synth", "--out", d / out, *_flags(**kw)], d)


@given(
    data=st.data(),
    kw=ff.flagset(
        {
            "reference_temperature": F(["20", "-5", "0"], ["-400", "1e300", "200"], 0),
            "prony_per_decade": F(["1.5", "1", "3"], ["0", "-1", "1e300", "1e-300", "1000"], 3),
        }
    ),
)
@fuzz_settings(10)
def test_rubber_master(base, goods, data, kw):
    with workdir(base) as d:
        raw = (
            goods / "freq_user_raw.csv"
            if data.draw(st.integers(0, 3)) == 0
            else data.draw(ff.raw_dma_files(), label="raw.csv").write(d)
        )
        out = data.draw(st.sampled_from(["r.toml", "r.toml", "sub/r.toml", "r.txt", "r"]), label="out")
        run_cli("rubber-master", ["rubber", "master", raw, "--out", d / out, *_flags(**kw)], d, watch=[goods])


@given(
    data=st.data(),
    spec=st.one_of(ff.analysable_height_file(), ff.any_height_file()),
    kw=ff.flagset(
        {
            "spacing": F(["5e-5"], ODD_SPACING, 1),
            "units": SCAN["units"],
            "float32": F([False, False, True], (), 0),
        },
        odd_counts=(0, 0, 1),
    ),
)
@fuzz_settings(24)
def test_convert(base, data, spec, kw):
    """Any height file to each writable format (float32 too: huge heights must not become inf)."""
    with workdir(base) as d:
        p = spec.write(d)
        out = data.draw(
            st.sampled_from(
                ["o.x3p", "o.npy", "o.npz", "o.tif", "o.tiff", "o.txt", "o", "sub/o.npy", p.name]
            ),
            label="out",
        )
        run_cli("convert", ["convert", p, d / out, *_flags(**kw)], d, desc=repr(spec))


# ------------------------------------------------------------------------- outputs, subprocesses, figures
@given(data=st.data())
@fuzz_settings(12)
def test_out_targets(base, goods, data):
    """--out naming an existing file, a path below a file, a foreign folder, an earlier run, the
    folder holding the input, an empty name."""
    with workdir(base) as d:
        kind = data.draw(
            st.sampled_from(
                ["file", "below_file", "foreign", "earlier", "input_dir", "empty", "nested", "dot"]
            ),
            label="out kind",
        )
        (d / "f.txt").write_text("keep\n")
        (d / "foreign").mkdir()
        (d / "foreign" / "photo.jpg").write_text("x")
        (d / "earlier").mkdir()
        (d / "earlier" / "summary.json").write_text('{"old": 1}\n')
        shutil.copy(goods / "good.npy", d / "scan.npy")
        out = {
            "file": d / "f.txt",
            "below_file": d / "f.txt" / "sub",
            "foreign": d / "foreign",
            "earlier": d / "earlier",
            "input_dir": d,
            "empty": "",
            "nested": d / "a" / "b" / "c",
            "dot": ".",
        }[kind]
        cmd = data.draw(st.sampled_from(["analyse", "rain-fill", "compare", "dry-vs-wet"]), label="command")
        scans = [d / "scan.npy"] + ([goods / "good2.npy"] if cmd == "compare" else [])
        extra = ["--no-friction"] if cmd in ("analyse", "compare", "dry-vs-wet") else []
        run_cli("out-targets", [cmd, *scans, "--spacing=5e-5", "--out", out, *extra], d, watch=[goods])


@given(data=st.data(), spec=ff.any_height_file())
@fuzz_settings(2)
def test_subprocess_analyse(base, goods, data, spec):
    """The real interpreter, real stderr (warnings filters, exit codes) on odd files."""
    with workdir(base) as d:
        p = spec.write(d)
        run_subprocess(
            "subprocess",
            ["analyse", p, "--spacing=5e-5", "--out", d / "out", "--velocities=1e-3:1:3"],
            d,
            desc=repr(spec),
        )


BATCH = {
    "workers": F(["1"], ["0", "-1", "abc"], 0),
    "section_length": F(["1"], ["0", "-1", "nan"], 3),
    "sigma0": FRICTION["sigma0"],
    "spacing": SCAN["spacing"],
}


@given(data=st.data())
@fuzz_settings(3)
def test_batch_subprocess(base, goods, data):
    """batch as a subprocess. A cluster start costs ~20 s, so CI draws cases with one odd option
    that is refused before the start; the long run draws all."""
    from fuzz_harness import SCALE

    with workdir(base) as d:
        kw = data.draw(ff.flagset(BATCH, odd_counts=(1,) if SCALE == 1 else (0, 1, 1, 2)), label="flags")
        if SCALE == 1:
            kw["workers"] = data.draw(st.sampled_from(["0", "-1", "abc"]), label="workers")
        inputs = [goods / "good.npy"]
        if data.draw(st.booleans(), label="odd input"):
            inputs.append(data.draw(ff.any_height_file(), label="file").write(d))
        run_subprocess(
            "batch", ["batch", *inputs, "--out", d / "camp", "--no-friction", *_flags(**kw)], d, timeout=240
        )


@given(data=st.data(), spec=ff.analysable_height_file())
@fuzz_settings(3)
def test_figures_drawn(base, goods, data, spec):
    """A few cases with every figure drawn (odd data can break log axes, colour scales)."""
    with workdir(base) as d:
        p = spec.write(d)
        cmd = data.draw(st.sampled_from(["analyse", "rain-fill"]), label="command")
        extra = ["--velocities=1e-3:1:3"] if cmd == "analyse" else []
        run_cli(
            "figures",
            [cmd, p, "--spacing=5e-5", "--out", d / "out", *extra],
            d,
            figures=True,
            watch=[goods],
            desc=repr(spec),
        )


def test_cases_were_counted():
    """The module's fuzz ran cases and none failed (in collect mode the failures are only
    recorded; this test then lists them)."""
    ran = sum(s["cases"] for s in STATS.values())
    if ran == 0:
        pytest.skip("no fuzz test ran before this one")
    assert not FAILURES, "\n".join(
        f"{f['group']}: {f['problems']} <- {f['case'][:300]}" for f in FAILURES[:20]
    )
