"""Issue 14: every example of bad input is one line on stderr, exit 2, no output, no traceback."""

import json
import zipfile

import numpy as np
import pytest
from conftest import fourier_surface

from pipelines.cli import app as cli
from pipelines.cli.app import main
from roadscan.io import _common


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("bad")
    g = fourier_surface(64, 5e-5, 0.8, 3e-4, seed=1)
    f = {}

    def save(name, arr):
        f[name] = d / name
        np.save(f[name], arr)

    save("good.npy", g)
    save("grid2.npy", np.array([[1.0, 2.0], [3.0, 4.0]]) * 1e-4)
    save("flat.npy", np.full((64, 64), 2e-3))
    two = np.full((128, 128), np.nan)
    two[3, 4], two[50, 60] = 1e-4, 2e-4
    save("two.npy", two)
    save("complex.npy", g.astype(complex))
    spike = g.copy()
    spike[10, 10] = 1e300
    save("spike.npy", spike)
    f["huge.npy"] = d / "huge.npy"
    with open(f["huge.npy"], "wb") as fh:
        np.lib.format.write_array_header_1_0(
            fh, {"descr": "<f8", "fortran_order": False, "shape": (200000, 200000)}
        )
        fh.write(b"\0" * 64)
    q = np.geomspace(1e3, 1e5, 30)
    f["rise.csv"] = d / "rise.csv"
    f["rise.csv"].write_text("q_per_m,C_m4\n" + "".join(f"{a},{1e-30 * a**3}\n" for a in q))
    for name, bad in (("neg.csv", "-1e-20"), ("nan.csv", "nan")):
        f[name] = d / name
        f[name].write_text(
            "q_per_m,C_m4\n" + "".join(f"{a},{1e-10 * a**-3 if i != 5 else bad}\n" for i, a in enumerate(q))
        )
    f["sls.toml"] = d / "sls.toml"
    f["sls.toml"].write_text('model = "sls"\n[sls]\nE1_Pa = 1e9\n')
    f["file.txt"] = d / "file.txt"
    f["file.txt"].write_text("not a folder\n")
    return f


def _run(capsys, argv):
    capsys.readouterr()
    rc = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return rc, cap.err


def _refused(capsys, argv, *needles):
    rc, err = _run(capsys, argv)
    lines = err.strip().splitlines()
    assert rc == 2, err
    assert len(lines) == 1, err  # one line, no traceback, no warnings first
    assert "error:" in lines[0] and "Traceback" not in err
    for n in needles:
        assert n in lines[0], (n, lines[0])
    return lines[0]


SP = ["--spacing", "5e-5"]


@pytest.mark.parametrize(
    "name, needle",
    [
        ("grid2.npy", "2 x 2"),  # was ZeroDivisionError in the Tukey window
        ("flat.npy", "equal"),  # was H = -3.75, rms 6e-20
        ("two.npy", "only 2 of 16384"),  # was H = 5.1
        ("complex.npy", "complex"),  # imaginary part was dropped
        ("spike.npy", "1e+300"),  # rain fill said 0 % wet
        ("huge.npy", "--max-pixels"),  # was MemoryError
    ],
)
def test_bad_scans_refused(files, capsys, tmp_path, name, needle):
    out = tmp_path / "o"
    line = _refused(capsys, ["analyse", files[name], *SP, "--out", out], name, needle)
    assert not out.exists() and list(tmp_path.iterdir()) == [], line


def test_spike_refused_by_rain_fill(files, capsys, tmp_path):
    _refused(capsys, ["rain-fill", files["spike.npy"], *SP, "--out", tmp_path / "o"], "spike.npy")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "extra, needle",
    [
        (["--spacing", "1e-300"], "--spacing 1e-300"),
        (["--temperature", "-400"], "--temperature -400"),
        (["--temperature", "-81.5"], "WLF pole"),  # thesis rubber: Tg - C2 = -81.5 C
        (["--q1", "-5"], "--q1 -5"),
        (["--q1", "10"], "--q1 10"),  # below the lowest measured q
        (["--q1", "nan"], "--q1"),
        (["--sigma0", "-1"], "--sigma0"),
        (["--sigma0", "0.3"], "did you mean 0.3MPa"),  # was taken as 0.3 Pa
        (["--nu", "0.7"], "--nu 0.7"),  # was accepted
    ],
)
def test_bad_numbers_refused(files, capsys, tmp_path, extra, needle):
    sp = [] if "--spacing" in extra else SP
    _refused(
        capsys,
        ["analyse", files["good.npy"], *sp, *extra, "--out", tmp_path / "o", "--velocities", "1e-3:1:3"],
        needle,
    )
    assert list(tmp_path.iterdir()) == []


def test_q1_inside_band_cuts_the_spectrum(files, capsys, tmp_path):
    """--q1 between the lowest q and Nyquist is honoured (not silently ignored): the
    integral up to q1 gives a lower mu than the whole band at the speed of the peak."""
    a, b = tmp_path / "a", tmp_path / "b"
    common = [*SP, "--velocities", "1e-2:1e1:4"]
    assert main(["analyse", str(files["good.npy"]), *common, "--out", str(a)]) == 0
    assert main(["analyse", str(files["good.npy"]), *common, "--out", str(b), "--q1", "1e4"]) == 0
    sa = json.loads((a / "summary.json").read_text())
    sb = json.loads((b / "summary.json").read_text())
    assert sb["friction"]["q1_per_m"] == pytest.approx(1e4) and sa["friction"]["q1_per_m"] > 2e4
    assert sb["friction"]["mu_peak"] < sa["friction"]["mu_peak"]


@pytest.mark.parametrize("target", ["file", "below"])
def test_out_naming_a_file_refused(files, capsys, target):
    out = files["file.txt"] if target == "file" else files["file.txt"] / "sub"
    _refused(capsys, ["analyse", files["good.npy"], *SP, "--out", out], "--out")
    assert files["file.txt"].read_text() == "not a folder\n"


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["--psd", "{rise.csv}"], "rises with q"),  # mu was up to 4e4
        (["--psd", "{neg.csv}"], "data row 6"),  # was dropped silently
        (["--psd", "{nan.csv}"], "data row 6"),
        (["--self-affine", "H=0.8,h0=inf,q0=1e3,q1=1e6"], "h0=inf"),  # mu was all NaN
        (["--self-affine", "H=0.8,h0=1e-4,q0=1e3,q1=1e6", "--rubber", "{sls.toml}"], "a1, tau_s"),
        (["--self-affine", "H=0.8,h0=1e-4,q0=1e3,q1=1e6", "--temperature", "-400"], "-400"),
        (["--self-affine", "H=0.8,h0=1e-4,q0=1e3,q1=1e6", "--temperature", "-81.5"], "WLF pole"),
        (["--self-affine", "H=0.8,h0=1e-4,q0=1e3,q1=1e6", "--nu", "0.7"], "--nu 0.7"),
    ],
)
def test_friction_inputs_refused(files, capsys, tmp_path, argv, needle):
    argv = [files[a[1:-1]] if a.startswith("{") else a for a in argv]
    out = tmp_path / "mu.csv"
    _refused(capsys, ["friction", *argv, "--out", out, "--velocities", "1e-3:1:3"], needle)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("speeds", ["1e-300:1e300:3", "1,2e7"])
def test_speeds_beyond_any_sliding_rubber_are_refused(capsys, tmp_path, speeds):
    """1e300 m/s once ran and overflowed the log speed axis (long fuzz run): a speed above
    1e6 m/s is refused in one line naming it, and nothing is written."""
    out = tmp_path / "mu.csv"
    argv = ["friction", "--self-affine", "H=0.8,h0=1e-4,q0=1e3,q1=1e6", "--velocities", speeds, "--out", out]
    line = _refused(capsys, argv, "--velocities", "no sliding speed")
    assert "e+06 m/s" in line
    assert list(tmp_path.iterdir()) == []


def test_bad_choice_is_one_line(capsys, files, tmp_path):
    capsys.readouterr()
    with pytest.raises(SystemExit) as ei:
        main(["analyse", str(files["good.npy"]), "--units", "furlong", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert ei.value.code == 2
    assert len(err.strip().splitlines()) == 1 and "--units" in err and "furlong" in err
    with pytest.raises(SystemExit) as ei:
        main(["no-such-command"])
    assert ei.value.code == 2 and len(capsys.readouterr().err.strip().splitlines()) == 1


def _replace_synth_run(monkeypatch, run):
    """Make ``roadscan synth`` call ``run(args)`` instead of its own job."""
    parser = cli.build_parser

    def patched():
        p = parser()
        for action in p._subparsers._group_actions[0].choices.values():
            if action.prog.endswith(" synth"):
                action.set_defaults(_run=run)
        return p

    monkeypatch.setattr(cli, "build_parser", patched)


def test_unexpected_error_is_one_line_and_debug_shows_traceback(monkeypatch, capsys, files, tmp_path):
    import pipelines.cli.inputs.synth as synth

    def boom(args):
        raise RuntimeError("unexpected\nsecond line")

    _replace_synth_run(monkeypatch, boom)
    rc, err = _run(capsys, ["synth", "--out", tmp_path / "x.npy"])
    assert rc == 1 and len(err.strip().splitlines()) == 1
    assert "internal error" in err and "--debug" in err and "Traceback" not in err
    rc, err = _run(capsys, ["synth", "--out", tmp_path / "x.npy", "--debug"])
    assert rc == 1 and "Traceback" in err and "RuntimeError" in err
    assert synth.NAME == "synth"


def test_numpy_warnings_become_one_named_line(monkeypatch, capsys, tmp_path):
    import pipelines.cli.inputs.synth as synth

    def noisy(args):
        np.log(np.zeros(3))
        np.sqrt(-np.ones(2))
        return 0

    _replace_synth_run(monkeypatch, noisy)
    rc, err = _run(capsys, ["synth", "--out", tmp_path / "x.npy"])
    assert rc == 0
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "warning: numpy:" in lines[0] and "+1 more" in lines[0]
    assert synth.NAME == "synth"


def test_max_pixels_flag_before_or_after_command(files, capsys, tmp_path):
    for argv in (
        ["--max-pixels", "1000", "analyse", files["good.npy"], *SP, "--out", tmp_path / "o"],
        ["analyse", files["good.npy"], *SP, "--out", tmp_path / "o", "--max-pixels", "1000"],
    ):
        _refused(capsys, argv, "64 x 64", "--max-pixels")
    assert _common.get_max_pixels() is None  # restored after the command


def _x3p_bomb(path, nx, ny, payload_mb=1):
    xml = f"""<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2"><Record1><Revision>ISO25178-72</Revision>
<FeatureType>SUR</FeatureType><Axes><CX><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-4</Increment>
</CX><CY><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-4</Increment></CY><CZ><AxisType>A</AxisType>
<DataType>D</DataType></CZ></Axes></Record1><Record3><MatrixDimension><SizeX>{nx}</SizeX><SizeY>{ny}</SizeY>
<SizeZ>1</SizeZ></MatrixDimension><DataLink><PointDataLink>bindata/data.bin</PointDataLink></DataLink></Record3>
</p:ISO5436_2>"""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("main.xml", xml)
        with z.open("bindata/data.bin", "w", force_zip64=True) as fh:
            for _ in range(payload_mb):
                fh.write(b"\0" * (1 << 20))


def test_x3p_zip_bomb_refused_before_allocating(capsys, tmp_path):
    bomb = tmp_path / "bomb.x3p"
    _x3p_bomb(bomb, 20000, 20000)  # 3.2 GB declared, 1 KB stored
    _refused(
        capsys,
        ["analyse", bomb, "--out", tmp_path / "o", "--max-pixels", "100000000"],
        "bomb.x3p",
        "20000 x 20000",
    )
    _refused(
        capsys,
        ["analyse", bomb, "--out", tmp_path / "o", "--max-pixels", "1000000000"],
        "bomb.x3p",
        "zip bomb",
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bomb.x3p"]


def test_npz_and_tiff_declared_sizes_checked(capsys, tmp_path):
    import tifffile

    g = fourier_surface(64, 5e-5, 0.8, 3e-4, seed=1)
    np.savez_compressed(tmp_path / "a.npz", heights=g, dx=5e-5)
    tifffile.imwrite(tmp_path / "a.tif", g.astype(np.float32))
    for name in ("a.npz", "a.tif"):
        _refused(
            capsys,
            ["analyse", tmp_path / name, *SP, "--out", tmp_path / "o", "--max-pixels", "4000"],
            name,
            "64 x 64",
        )
    z = np.zeros((3000, 3000))  # 72 MB of zeros compress ~1000x
    np.savez_compressed(tmp_path / "zeros.npz", heights=z, dx=5e-5)
    _refused(capsys, ["analyse", tmp_path / "zeros.npz", "--out", tmp_path / "o"], "zip bomb")


def test_text_file_size_checked(capsys, tmp_path):
    p = tmp_path / "grid.txt"
    p.write_text("\n".join(" ".join("1e-4" for _ in range(40)) for _ in range(40)))
    _refused(capsys, ["analyse", p, *SP, "--out", tmp_path / "o", "--max-pixels", "500"], "grid.txt")


def test_warnings_land_in_summary(capsys, tmp_path):
    """A scan that is still meaningful but odd: the warning is one line and in summary.json."""
    rng = np.random.default_rng(0)
    white = rng.normal(0, 1e-4, (64, 64))  # white noise: H outside [0, 1]
    p = tmp_path / "white.npy"
    np.save(p, white)
    rc, err = _run(capsys, ["analyse", p, *SP, "--out", tmp_path / "o", "--no-friction"])
    assert rc == 0
    warn = [line for line in err.splitlines() if "warning:" in line]
    assert sum("Hurst" in w for w in warn) == 1  # (a 64 x 64 scan's narrow band warns too)
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert [w.split("warning: ", 1)[1] for w in warn] == s["warnings"]  # every line, in order


def test_undefined_h0_is_null_with_a_warning_not_a_nan(monkeypatch, capsys, tmp_path):
    """Fuzz finding: a scan whose spectrum falls no faster than white noise (H <= 0) had its
    undefined h0 computed as NaN and written as null without saying so. Now h0 is None on
    purpose and the Hurst warning says that h0 is undefined."""
    from pipelines.output import report

    written = []
    orig = report.write_json
    monkeypatch.setattr(report, "write_json", lambda path, data: (written.append(data), orig(path, data))[1])
    rng = np.random.default_rng(0)
    p = tmp_path / "white.npy"
    np.save(p, rng.normal(0, 1e-4, (64, 64)))
    rc, err = _run(capsys, ["analyse", p, *SP, "--out", tmp_path / "o", "--no-friction"])
    assert rc == 0
    s = written[-1]
    assert s["hurst_fit"] < 0 and s["hurst"] is None and s["h0_m"] is None  # not float("nan")
    assert "outside [0, 1]" in s["hurst_note"]
    assert "h0 is undefined" in err and "h0 is undefined" in s["warnings"][0]


@pytest.mark.parametrize("flash", [False, True])
def test_real_master_curve_runs_without_numpy_warnings(capsys, tmp_path, flash):
    """Noise example of issue 14: friction/grids.py printed RuntimeWarnings on a real master
    curve. The measured pyvisco curve over the default 121 speeds (1e-8..1e4 m/s): no warning
    line at all, numpy's included (the CLI would print one as 'warning: numpy: ...')."""
    from conftest import ROOT

    rub = ROOT / "sample_scans" / "rubbers" / "pyvisco_master_wlf.toml"
    psd = ROOT / "sample_scans" / "asphalt_psd.csv"
    rc, err = _run(
        capsys,
        [
            "friction",
            "--psd",
            psd,
            "--rubber",
            rub,
            "--temperature",
            "20",
            "--out",
            tmp_path / "mu.csv",
            *(["--flash"] if flash else []),
        ],
    )
    # no numpy warning, nothing about the rubber; on this compound mu still rises at the default
    # speeds' end (100 m/s), which is a warning of its own since the peak lies beyond them
    said = [ln for ln in err.splitlines() if "warning" in ln]
    assert rc == 0 and all("still rising" in ln for ln in said), err


def test_undefined_slopes_are_null_with_a_warning(monkeypatch, capsys, tmp_path):
    """Fuzz finding: with every other row unmeasured no grid cell has four measured corners, so
    Sdq and Sdr are undefined; they were NaN written as null without a word. Now None on
    purpose, with one warning line that also lands in summary.json."""
    from pipelines.output import report

    written = []
    orig = report.write_json
    monkeypatch.setattr(report, "write_json", lambda path, data: (written.append(data), orig(path, data))[1])
    g = fourier_surface(64, 5e-5, 0.8, 3e-4, seed=1)
    g[::2] = np.nan
    p = tmp_path / "rows.npy"
    np.save(p, g)
    rc, err = _run(capsys, ["analyse", p, *SP, "--out", tmp_path / "o", "--no-friction"])
    assert rc == 0, err
    s = written[-1]
    assert s["roughness"]["Sdq"] is None and s["roughness"]["Sdr"] is None
    assert np.isfinite(s["roughness"]["Sq_m"])
    assert any("Sdq, Sdr undefined" in w for w in s["warnings"])
    assert "Sdq, Sdr undefined" in err


def test_check_heights_flat_and_spike_rules_without_copying():
    """The plausibility rules of check_heights (issue 14), now read band by band: a grid equal
    to 12 digits is flat; a 1.5 m spike on a grid whose heights are mostly equal is refused
    (its robust spread is 0); an ordinary rough grid passes; unmeasured points are ignored."""
    from pipelines.checks.validate import _measured_range, check_heights
    from roadscan.errors import InputError

    rng = np.random.default_rng(3)
    rough = rng.normal(0, 1e-4, (300, 200))
    check_heights(rough)
    with pytest.raises(InputError, match="flat grid"):
        check_heights(np.full((64, 64), 0.25) + 1e-15 * rng.random((64, 64)))
    spiky = np.zeros((64, 64))
    spiky[10, 10] = 1.5
    with pytest.raises(InputError, match="implausible spike"):
        check_heights(spiky)
    masked = np.zeros((64, 64), dtype=bool)
    masked[10, 10] = True
    spiky[20:30] = rng.normal(0, 1e-4, (10, 64))
    check_heights(spiky, unmeasured=masked)  # the spike is marked unmeasured
    h = rough.copy()
    h[5, 7], h[9, 9] = np.nan, 7.0
    m = np.zeros(h.shape, dtype=bool)
    m[9, 9] = True
    n, lo, hi = _measured_range(h, m, chunk_bytes=8 * 200 * 7)  # bands of 7 rows
    ref = h[np.isfinite(h) & ~m]
    assert (n, lo, hi) == (ref.size, ref.min(), ref.max())


def test_heights_near_the_float64_limit_give_their_rms_without_overflow():
    """Fuzz finding (convert of an x3p scaled to ~1e300): the plausibility rms squared the
    heights and overflowed. Heights above 2^500 are scaled by a power of two first (exact), so
    the rms comes out; ordinary heights give the plain formula's bits."""
    from roadscan.heightmap import HeightMap
    from roadscan.plausibility import detrended_rms

    rng = np.random.default_rng(5)
    plain = rng.normal(0, 1e-4, (40, 40))
    with np.errstate(all="raise"):
        huge = detrended_rms(HeightMap(plain * 1e304, 5e-5, 5e-5))
        small = detrended_rms(HeightMap(plain, 5e-5, 5e-5))
    assert huge == pytest.approx(small * 1e304, rel=1e-9)
    z = plain.ravel()  # the plain formula on the same grid (every point kept, 40^2 < the cap)
    keep = (z >= np.percentile(z, 1)) & (z <= np.percentile(z, 99))
    yy, xx = np.indices(plain.shape, dtype=float)
    a = np.column_stack([np.ones(keep.sum()), xx.ravel()[keep], yy.ravel()[keep]])
    zk = z[keep] - np.median(z[keep])
    r = zk - a @ np.linalg.lstsq(a, zk, rcond=None)[0]
    assert small == pytest.approx(float(np.sqrt(np.mean(r * r))), rel=1e-12)


def test_flash_on_a_band_shorter_than_its_macro_asperity_factor_is_refused(capsys, tmp_path):
    """Fuzz finding: --flash on a band whose end q1 lies below zeta_m q0 (the macro-asperity
    wave vector, zeta_m = 3) was an internal error (exit 1); now one line naming the band's end
    and the options."""
    argv = ["friction", "--self-affine", "H=0.8,h0=1e-4,q0=1e4,q1=2e4", "--flash", "--velocities", "1e-3:1:3"]
    line = _refused(capsys, [*argv, "--out", tmp_path / "mu.csv"], "--q1", "--flash")
    assert "macro-asperity" in line and "3e+04" in line
    assert list(tmp_path.iterdir()) == []
