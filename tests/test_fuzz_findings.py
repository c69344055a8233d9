"""Regression tests for what the fuzz suite (tests/test_fuzz.py, benchmarks/fuzz_long.py) found,
each the smallest case of its class (issue 14)."""

import signal

import numpy as np
import pytest
from conftest import fourier_surface

from pipelines.cli.app import main
from roadscan.errors import InputError


@pytest.fixture
def no_hang():
    """Fail (instead of hanging the suite) if a call takes over 20 s."""

    def boom(signum, frame):
        raise TimeoutError("hung")

    old = signal.signal(signal.SIGALRM, boom)
    signal.alarm(20)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


def _gwy_bytes(tmp_path):
    from gwyfile.objects import GwyContainer, GwyDataField

    c = GwyContainer()
    c["/0/data"] = GwyDataField(
        np.arange(12.0).reshape(3, 4) * 1e-6, xreal=4e-4, yreal=3e-4, si_unit_xy="m", si_unit_z="m"
    )
    c["/0/data/title"] = "Height"
    p = tmp_path / "ok.gwy"
    c.tofile(str(p))
    return p.read_bytes()


@pytest.mark.parametrize("cut", ["flip_last", "truncate", "huge_size", "nested_size"])
def test_corrupt_gwy_refused_not_hanging(tmp_path, no_hang, cut):
    """gwyfile loops forever on a string whose NUL terminator is lost (a .gwy with its last
    byte flipped hung the reader); the serialisation is now checked first."""
    from roadscan.io import read

    data = bytearray(_gwy_bytes(tmp_path))
    if cut == "flip_last":
        data[-1] ^= 1
    elif cut == "truncate":
        data = data[: len(data) - 9]
    elif cut == "huge_size":  # the top object's size field (after "GWYP" + "GwyContainer\0")
        i = data.index(b"\0", 4) + 1
        data[i : i + 4] = (2**31).to_bytes(4, "little")
    else:  # the data field's size field
        i = data.index(b"GwyDataField\0") + len(b"GwyDataField\0")
        data[i : i + 4] = (len(data)).to_bytes(4, "little")
    p = tmp_path / "bad.gwy"
    p.write_bytes(bytes(data))
    with pytest.raises(InputError, match=r"bad.gwy: not a readable Gwyddion file \(corrupt: "):
        read(p, spacing=1e-4)


def test_valid_gwy_passes_the_structure_check(tmp_path):
    from roadscan.io import read
    from roadscan.io.gwy import check_gwy_structure

    p = tmp_path / "ok.gwy"
    p.write_bytes(_gwy_bytes(tmp_path))
    check_gwy_structure(p)
    hm = read(p)
    assert hm.shape == (3, 4) and hm.dx_m == pytest.approx(1e-4)
    assert np.array_equal(hm.heights_m, np.arange(12.0).reshape(3, 4) * 1e-6)


def _one_line_refusal(capsys, argv, *needles):
    capsys.readouterr()
    rc = main([str(a) for a in argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "error:" in err[0], err
    for n in needles:
        assert n in err[0], (n, err[0])


@pytest.mark.parametrize(
    "extra, needles",
    [
        (["--rms", "1e300"], ["--rms 1e+300 m"]),  # was OverflowError through the last resort
        (["--rms", "1e-300"], ["--rms 1e-300 m"]),  # wrote a grid of zeros, exit 0
        (["--spacing", "1e300"], ["--spacing 1e+300 m"]),  # was accepted
        (["--seed", "-1"], ["--seed -1"]),  # numpy's "expected non-negative integer"
        (["--nx", "4000", "--max-pixels", "1000000"], ["--nx/--ny", "4000 x 4000", "--max-pixels"]),
    ],
)
def test_synth_numbers_checked(capsys, tmp_path, extra, needles):
    out = tmp_path / "s.npy"
    _one_line_refusal(capsys, ["synth", "--nx", "32", "--out", out, *extra], *needles)
    assert list(tmp_path.iterdir()) == []


def test_stitch_negative_max_shift_refused(capsys, tmp_path):
    """--max-shift -1 reached numpy as a broadcast ValueError (the CLI's last resort)."""
    wide = fourier_surface(96, 5e-5, 0.8, 3e-4, seed=3)[:40]
    np.save(tmp_path / "a.npy", wide[:, :56])
    np.save(tmp_path / "b.npy", wide[:, 40:])
    _one_line_refusal(
        capsys,
        [
            "stitch",
            tmp_path / "a.npy",
            tmp_path / "b.npy",
            "--grid",
            "1x2",
            "--overlap",
            "0.286",
            "--spacing",
            "5e-5",
            "--max-shift",
            "-1",
            "--out",
            tmp_path / "st.npy",
        ],
        "--max-shift -1",
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.npy", "b.npy"]


def test_atomic_file_set_all_or_none(tmp_path):
    """The sibling-file sets (friction's mu.csv + summary + plot, stitch's map + overlaps,
    rubber master's TOML + data) appear together or not at all."""
    from roadscan.io.atomic import atomic_file_set

    target = tmp_path / "new" / "deeper" / "mu.csv"
    with pytest.raises(RuntimeError):
        with atomic_file_set(target) as d:
            (d / "mu.csv").write_text("1\n")
            raise RuntimeError("plot failed")
    assert list(tmp_path.iterdir()) == []  # created folders removed too
    (tmp_path / "keep.txt").write_text("other\n")
    (tmp_path / "mu.csv").write_text("old\n")
    with atomic_file_set(tmp_path / "mu.csv") as d:
        (d / "mu.csv").write_text("new\n")
        (d / "mu.png").write_bytes(b"png")
        assert sorted(p.name for p in tmp_path.iterdir() if not p.name.startswith(".")) == [
            "keep.txt",
            "mu.csv",
        ]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.txt", "mu.csv", "mu.png"]
    assert (tmp_path / "mu.csv").read_text() == "new\n"
    (tmp_path / "box").mkdir()
    with pytest.raises(InputError, match="is a folder"):
        with atomic_file_set(tmp_path / "box"):
            pass
    with pytest.raises(InputError, match="below the file"):
        with atomic_file_set(tmp_path / "keep.txt" / "mu.csv"):
            pass


def test_friction_failure_after_first_file_leaves_nothing(monkeypatch, capsys, tmp_path):
    """Fuzz finding: friction wrote mu.csv and mu_summary.json, then failed drawing the plot and
    left them behind (exit 1 with a partial set)."""
    from conftest import ROOT

    from pipelines.output import report

    def broken(*a, **k):
        raise RuntimeError("plot failed")

    monkeypatch.setattr(report, "plot_mu", broken)
    rc = main(
        [
            "friction",
            "--psd",
            str(ROOT / "sample_scans" / "asphalt_psd.csv"),
            "--velocities",
            "1e-3:1:3",
            "--out",
            str(tmp_path / "sub" / "mu.csv"),
        ]
    )
    assert rc == 1 and "internal error" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("ext", [".npy", ".npz", ".x3p", ".tif"])
def test_float32_overflow_refused(capsys, tmp_path, ext):
    """Fuzz finding: convert --float32 of a height beyond float32's range wrote infinity (read
    back as an unmeasured point) with only a numpy warning line."""
    a = fourier_surface(16, 5e-5, 0.8, 3e-4, seed=1)
    a[3, 3] = 1e300
    np.save(tmp_path / "big.npy", a)
    _one_line_refusal(
        capsys,
        ["convert", tmp_path / "big.npy", tmp_path / f"o{ext}", "--spacing", "5e-5", "--float32"],
        "does not fit float32",
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.npy"]
    assert main(["convert", str(tmp_path / "big.npy"), str(tmp_path / f"o{ext}"), "--spacing", "5e-5"]) == 0


@pytest.mark.parametrize(
    "where, needle",
    [
        ("flag", "--temperature -400"),  # was OverflowError through the last resort
        ("row", "measured.csv: T0_C -400"),
        ("pole", "WLF pole"),
        ("pressure", "measured.csv: sigma0_Pa 1e+300 Pa"),
    ],
)
def test_diagnose_conditions_checked(capsys, tmp_path, where, needle):
    from conftest import ROOT

    v = np.geomspace(1e-4, 1e1, 12)
    mu = 0.3 + 0.5 * np.exp(-(np.log10(v / 1e-2) ** 2))
    T = {"row": -400.0, "pole": -81.5}.get(where, 20.0)
    s = 1e300 if where == "pressure" else 2e5
    p = tmp_path / "measured.csv"
    p.write_text("v_m_per_s,mu,T0_C,sigma0_Pa\n" + "".join(f"{a},{b},{T},{s}\n" for a, b in zip(v, mu)))
    extra = ["--temperature", "-400"] if where == "flag" else []
    _one_line_refusal(
        capsys,
        [
            "diagnose",
            "--measured",
            p,
            "--psd",
            ROOT / "sample_scans" / "asphalt_psd.csv",
            "--out",
            tmp_path / "out",
            *extra,
        ],
        needle,
    )
    assert sorted(q.name for q in tmp_path.iterdir()) == ["measured.csv"]


def test_synth_tiny_roll_off_without_numpy_warning(capsys, tmp_path):
    """--q-roll 1e-300 overflowed 1e-300^-3.6 at q = 0 (a point set to zero anyway): a numpy
    warning line on a correct result."""
    assert (
        main(
            ["synth", "--nx", "32", "--q-roll", "1e-300", "--q0", "1e-300", "--out", str(tmp_path / "s.npy")]
        )
        == 0
    )
    assert "warning" not in capsys.readouterr().err
    assert np.all(np.isfinite(np.load(tmp_path / "s.npy")))


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["analyse", "{scan}", "--spacing", "5e-5", "--q1", "1e300", "--flash"], "--q1 1e+300 1/m"),
        (["dry-vs-wet", "{scan}", "--spacing", "5e-5", "--q1", "1e30"], "--q1 1e+30 1/m"),
        (["friction", "--self-affine", "H=0.8,h0=1e-4,q0=1e3,q1=1e30"], "--self-affine q1=1e+30 1/m"),
        (["friction", "--self-affine", "H=0.8,h0=1e-4,q0=1e3,q1=1e6", "--q1", "1e12"], "--q1 1e+12 1/m"),
    ],
)
def test_wave_vectors_beyond_the_atomic_scale_refused(capsys, tmp_path, argv, needle):
    """Fuzz finding: --q1 1e300 went to the flash solver (FlashConvergenceError as an internal
    error, exit 1); 1e30 1/m gave a number. Wave vectors above 1e11 1/m are refused."""
    scan = tmp_path / "g.npy"
    np.save(scan, fourier_surface(32, 5e-5, 0.8, 3e-4, seed=1))
    argv = [str(scan) if a == "{scan}" else a for a in argv]
    _one_line_refusal(capsys, [*argv, "--velocities", "1e-3:1:3", "--out", tmp_path / "out"], needle)


def test_flash_failure_in_analyse_is_an_input_error(monkeypatch, capsys, tmp_path):
    """A flash solution that truly cannot be found is one error line with exit 2 in analyse
    (as in friction), not an internal error."""
    import friction
    from friction.flash import FlashConvergenceError

    def fails(*a, **k):
        raise FlashConvergenceError("flash temperature: the heat balance is not finite at v = 1 m/s")

    monkeypatch.setattr(friction, "mu_flash", fails)
    scan = tmp_path / "g.npy"
    np.save(scan, fourier_surface(32, 5e-5, 0.8, 3e-4, seed=1))
    _one_line_refusal(
        capsys,
        [
            "analyse",
            scan,
            "--spacing",
            "5e-5",
            "--flash",
            "--velocities",
            "1e-3:1:3",
            "--out",
            tmp_path / "out",
        ],
        "friction: flash temperature",
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.npy"]


def test_reference_temperature_checked(capsys, tmp_path):
    """--reference-temperature 1e300 was an OverflowError through the last resort."""
    from conftest import ROOT

    r = ROOT / "sample_scans" / "rubbers"
    _one_line_refusal(
        capsys,
        [
            "friction",
            "--psd",
            ROOT / "sample_scans" / "asphalt_psd.csv",
            "--master-curve",
            r / "freq_user_master.csv",
            "--shift-table",
            r / "freq_user_master__shift_factors.csv",
            "--reference-temperature",
            "1e300",
            "--velocities",
            "1e-3:1:3",
            "--out",
            tmp_path / "mu.csv",
        ],
        "--reference-temperature 1e+300 C",
    )
    assert list(tmp_path.iterdir()) == []


def test_diagnosis_never_prefers_unusable_parameters():
    """Fuzz finding: with T0 5.5 K above the thesis rubber's WLF pole the baseline misfit is
    over 10 decades, and the fit preferred temperature offsets past the pole (NaN model, cost
    10 decades a point) to the no-effect point: gaps NaN, written as null. A NaN model now
    costs 1e3 decades a point, so the fit keeps a finite one."""
    from pipelines.diagnosis.effects import all_effects
    from pipelines.diagnosis.measured import MeasuredCurve

    v = np.geomspace(1e-4, 1e1, 8)
    mu = 0.3 + 0.5 * np.exp(-(np.log10(v / 1e-2) ** 2))
    curve = MeasuredCurve(
        v, mu, np.full(v.size, -76.0), np.full(v.size, 2e5), np.zeros(v.size, bool), False, "t"
    )
    import friction
    from pipelines.diagnosis.inputs import build_context
    from pipelines.diagnosis.verdict.search import diagnose_friction

    ctx = build_context(curve, friction.SelfAffinePSD(0.8, 5e-4, 2000.0, 2e5))
    eff = [e for e in all_effects("friction") if e.name == "temperature_offset"]
    d = diagnose_friction(ctx, mu, noise=0.01, effects=eff, pairs=False)
    c = d.candidates[0]
    assert np.isfinite(c.gap_train) and np.isfinite(c.gap_heldout) and np.all(np.isfinite(c.pred))
    assert c.gap_train <= d.baseline_gap_train + 1e-9


def test_wave_vectors_far_below_any_surface_refused(tmp_path, capsys):
    """fuzz_long finding: --self-affine q0=2.2e-308 was an OverflowError in the flash grid;
    wave vectors below 1e-4 1/m (wavelengths above 63 km) are refused, in flags and PSD rows."""
    from pipelines.cli.app import main

    rc = main(
        [
            "friction",
            "--self-affine",
            "H=0.5,h0=1e-5,q0=2.2e-308,q1=1e7",
            "--flash",
            "--velocities",
            "1e-3:1:3",
            "--out",
            str(tmp_path / "mu.csv"),
        ]
    )
    err = capsys.readouterr().err.strip()
    assert rc == 2 and "q0=2.2e-308 1/m" in err and "\n" not in err
    psd = tmp_path / "psd.csv"
    psd.write_text("q_per_m,C_m4\n1e-9,1e-10\n1e3,1e-20\n1e4,1e-23\n")
    rc = main(["friction", "--psd", str(psd), "--out", str(tmp_path / "mu2.csv")])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and "data row 1" in err and "\n" not in err
    assert not (tmp_path / "mu.csv").exists() and not (tmp_path / "mu2.csv").exists()


def test_raw_sweep_temperatures_must_be_physical(tmp_path, capsys):
    """fuzz_long finding: a raw DMA file with a sweep at 6.7e16 C was accepted (numpy overflow
    warnings in the WLF fit); temperatures outside (-273.15, 1000] C are refused by row."""
    from pipelines.cli.app import main

    rows = ["f_Hz,E_stor_Pa,E_loss_Pa,T_C"]
    for T in (0.0, 20.0, 6.7e16):
        rows += [f"{f:g},{1e6 * (1 + f):g},{1e5 * (1 + f):g},{T:g}" for f in (0.1, 0.3, 1, 3, 10)]
    raw = tmp_path / "raw.csv"
    raw.write_text("\n".join(rows) + "\n")
    rc = main(
        ["rubber", "master", str(raw), "--reference-temperature", "20", "--out", str(tmp_path / "r.toml")]
    )
    err = capsys.readouterr().err.strip()
    assert rc == 2 and "data row 11" in err and "6.7e+16 C" in err and "\n" not in err
    assert not (tmp_path / "r.toml").exists()
