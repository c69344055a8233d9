"""Units of every column of a text input are known or refused (x,z profiles and x,y,z lists
without a unit line): a mm profile read as metres is refused naming --units mm; --units
converts coordinates and heights; --spacing replaces the step inferred from the x column."""

import json
import re

import numpy as np
import pytest
from fault_tools import assert_one_line_error, run_cli

from roadscan.errors import InputError
from roadscan.io import read
from roadscan.io.text_units import line_rms, plausible_reading

DX_MM = 0.0375  # a CAPTIF-like laser profile: 0.0375 mm steps, 150 mm, heights of a mm


def _names_units_mm(msg):
    """The flag (``--units`` on the CLI, ``units`` in the library's wording) and mm."""
    return re.search(r"(--units|'units') mm", msg) is not None


def _mm_profile(tmp_path, n=4000, rms_mm=0.73, name="mm_profile.csv", seed=3):
    rng = np.random.default_rng(seed)
    x = np.arange(n) * DX_MM
    z = np.cumsum(rng.normal(size=n))
    z -= np.polyval(np.polyfit(x, z, 1), x)
    z *= rms_mm / z.std()
    p = tmp_path / name
    np.savetxt(p, np.column_stack([x, z]), fmt="%.5f", delimiter=",")
    return p, z


def test_mm_profile_without_unit_line_refused_naming_units_mm(tmp_path):
    p, _ = _mm_profile(tmp_path)
    with pytest.raises(InputError) as e:
        read(p)
    msg = str(e.value)
    assert "\n" not in msg and str(p) in msg
    assert _names_units_mm(msg) and "look like mm" in msg


def test_mm_profile_refused_by_the_cli_in_one_line(tmp_path, capsys):
    p, _ = _mm_profile(tmp_path)
    rc, err = run_cli(capsys, ["analyse", p, "--out", tmp_path / "out", "--no-friction"])
    assert_one_line_error(rc, err, words=[str(p), "--units mm"])
    assert not (tmp_path / "out" / "summary.json").exists()


def test_units_mm_converts_spacing_and_heights(tmp_path):
    p, z = _mm_profile(tmp_path)
    prof = read(p, units="mm")
    assert prof.dx_m == pytest.approx(DX_MM * 1e-3, rel=1e-6)
    assert prof.length_m == pytest.approx(4000 * DX_MM * 1e-3, rel=1e-3)
    # heights: the file's numbers (rounded to 1e-5 mm) times 1e-3, independent of the reader
    np.testing.assert_allclose(prof.heights_m, np.round(z, 5) * 1e-3, atol=1e-11)
    assert prof.meta["coordinate_unit"] == "mm"


def test_units_mm_through_analyse_gives_mm_texture(tmp_path, capsys):
    p, z = _mm_profile(tmp_path)
    out = tmp_path / "out"
    rc, err = run_cli(capsys, ["analyse", p, "--out", out, "--units", "mm", "--no-friction", "--no-figures"])
    assert rc == 0, err
    s = json.loads((out / "summary.json").read_text())
    assert s["spacing_m"] == [pytest.approx(DX_MM * 1e-3, rel=1e-6)]
    # rms height of the levelled profile against a line fit of the raw numbers (independent)
    assert s["rms_height_m"] == pytest.approx(np.std(z) * 1e-3, rel=0.05)


def test_spacing_replaces_the_inferred_step_with_a_note(tmp_path):
    p, _z = _mm_profile(tmp_path)
    prof = read(p, spacing=2e-5, units="mm")  # not the file's 0.0375 mm: a note, no refusal
    assert prof.dx_m == pytest.approx(2e-5)
    notes = [str(w) for w in prof.meta.get("read_warnings", [])]
    assert any("replaces the spacing inferred from the x column" in w for w in notes), notes
    same = read(p, spacing=DX_MM * 1e-3, units="mm")  # the same spacing: nothing to say
    assert not same.meta.get("read_warnings")


def test_spacing_note_reaches_summary_warnings(tmp_path, capsys):
    p, _ = _mm_profile(tmp_path)
    out = tmp_path / "out"
    rc, err = run_cli(
        capsys,
        ["analyse", p, "--out", out, "--units", "mm", "--spacing", "2e-5", "--no-friction", "--no-figures"],
    )
    assert rc == 0, err
    s = json.loads((out / "summary.json").read_text())
    assert s["spacing_m"] == [pytest.approx(2e-5)]
    assert any("x column" in w for w in s["warnings"]), s["warnings"]


def test_metre_profile_still_read_as_metres(tmp_path):
    """A real road texture profile in metres (0.5 mm steps, 0.4 mm rms) is plausible as is."""
    rng = np.random.default_rng(1)
    x = np.arange(3000) * 5e-4
    z = np.cumsum(rng.normal(size=x.size))
    z *= 4e-4 / z.std()
    np.savetxt(tmp_path / "m.txt", np.column_stack([x, z]), fmt="%.9g")
    prof = read(tmp_path / "m.txt")
    assert prof.dx_m == pytest.approx(5e-4, rel=1e-6)
    assert prof.meta["coordinate_unit"] == "m"


def test_explicit_units_m_accepts_a_long_unevenness_profile(tmp_path):
    """Metres stated by the user are taken: a 150 m profile with 0.7 m rms is their call."""
    p, _z = _mm_profile(tmp_path)
    prof = read(p, units="m")
    assert prof.dx_m == pytest.approx(DX_MM, rel=1e-6)


def test_units_on_metre_coordinates_read_as_metres_with_a_warning(tmp_path):
    """x in metres, heights in mm, --units mm (the older convention): read in mm the x column
    would give a 10 um profile with 660 um heights, impossible; metres is the one plausible
    reading: taken, with a warning naming --x-units."""
    x = np.arange(200) * 0.05e-3
    z = np.sin(np.arange(200) * 0.05)
    np.savetxt(tmp_path / "p.txt", np.column_stack([x, z]), fmt="%.6e %.9f")
    prof = read(tmp_path / "p.txt", units="mm")
    assert prof.dx_m == pytest.approx(0.05e-3, rel=1e-6)
    np.testing.assert_allclose(prof.heights_m, np.round(z, 9) * 1e-3, atol=1e-12)
    notes = [str(w) for w in prof.meta["read_warnings"]]
    assert len(notes) == 1 and "x read as metres" in notes[0] and "'x_units' m" in notes[0]
    assert prof.meta["coordinate_unit"] == "m"
    given = read(tmp_path / "p.txt", units="mm", x_units="m")  # stated: no warning
    assert given.dx_m == prof.dx_m and not given.meta.get("read_warnings")
    with open(tmp_path / "t.txt", "w") as f:  # or a title line
        f.write("x (m), z (mm)\n")
        for a, b in zip(x, z):
            f.write(f"{a:.6e}, {b:.9f}\n")
    titled = read(tmp_path / "t.txt")
    assert titled.dx_m == pytest.approx(0.05e-3, rel=1e-6)
    np.testing.assert_allclose(titled.heights_m, prof.heights_m, atol=1e-12)


def test_units_on_coordinates_in_another_unit_refused(tmp_path):
    """x in um, heights in mm (5 nm rms, a microscope's), --units mm: read in mm x gives a 2 m
    profile at 1 mm with heights 1e-5 of its spacing, below any instrument; in um it is a
    microscope's field. Not the older metre convention: refused naming --x-units um."""
    rng = np.random.default_rng(5)
    x = np.arange(2000) * 1.0  # um
    z = rng.normal(size=x.size) * 5e-6  # mm
    np.savetxt(tmp_path / "u.txt", np.column_stack([x, z]), fmt="%.6f %.9f")
    with pytest.raises(InputError) as e:
        read(tmp_path / "u.txt", units="mm")
    msg = str(e.value)
    assert "\n" not in msg and "'x_units' um" in msg and "x (um), z (mm)" in msg


def test_xyz_in_mm_without_titles_refused_then_read_with_units(tmp_path):
    rng = np.random.default_rng(2)
    ny, nx = 40, 50
    h = rng.normal(size=(ny, nx)) * 0.5  # mm
    yy, xx = np.mgrid[0:ny, 0:nx]
    pts = np.column_stack([xx.ravel() * 0.05, yy.ravel() * 0.05, h.ravel()])  # 0.05 mm grid
    np.savetxt(tmp_path / "s.xyz", pts, fmt="%.6f")
    with pytest.raises(InputError) as e:
        read(tmp_path / "s.xyz")
    assert _names_units_mm(str(e.value)) and "x, y and heights" in str(e.value)
    m = read(tmp_path / "s.xyz", units="mm")
    assert (m.dx_m, m.dy_m) == pytest.approx((5e-5, 5e-5), rel=1e-6)
    np.testing.assert_allclose(m.heights_m, np.round(h, 6) * 1e-3, atol=1e-12)


def test_plausible_reading_bounds():
    assert plausible_reading(5e-5, 0.1, 5e-4)  # road texture
    assert plausible_reading(1e-7, 1e-4, 1e-8)  # microscope
    assert not plausible_reading(0.0375, 150.0, 0.73)  # the mm file read as metres
    assert not plausible_reading(5e-4, 1.0, 0.2)  # 20 cm rms: no texture
    assert not plausible_reading(1e-12, 1e-9, 1e-13)  # below a nanometre spacing


def test_line_rms_removes_a_line_and_a_plane():
    x = np.arange(1000.0)
    z = 3.0 + 0.2 * x + np.sin(x)
    assert line_rms(z) == pytest.approx(np.sqrt(0.5), rel=0.05)
    yy, xx = np.mgrid[0:60, 0:70].astype(float)
    zz = 1.0 + 0.5 * xx - 0.3 * yy + np.cos(xx + yy)
    assert line_rms(zz) == pytest.approx(np.sqrt(0.5), rel=0.05)


def test_x_units_refused_where_it_means_nothing(tmp_path):
    np.save(tmp_path / "a.npy", np.zeros((16, 16)))
    with pytest.raises(InputError, match="x_units"):
        read(tmp_path / "a.npy", spacing=1e-4, x_units="mm")
    with open(tmp_path / "t.txt", "w") as f:  # titles state x in mm
        f.write("x (mm), z (mm)\n" + "".join(f"{0.05 * k:.3f}, {np.sin(k):.6f}\n" for k in range(100)))
    with pytest.raises(InputError, match="title line states the coordinates in mm"):
        read(tmp_path / "t.txt", x_units="m")
    assert read(tmp_path / "t.txt", x_units="mm").dx_m == pytest.approx(5e-5, rel=1e-6)


def test_cli_x_units_reads_metre_coordinates_with_mm_heights(tmp_path, capsys):
    rng = np.random.default_rng(4)
    x = np.arange(4000) * 5e-5  # metres
    z = np.cumsum(rng.normal(size=x.size)) * 0.01  # mm
    np.savetxt(tmp_path / "p.csv", np.column_stack([x, z]), fmt="%.8g", delimiter=",")
    out = tmp_path / "out"
    rc, err = run_cli(
        capsys,
        ["analyse", tmp_path / "p.csv", "--out", out, "--units", "mm", "--no-friction", "--no-figures"],
    )
    assert rc == 0 and "--x-units m" in err, err  # read so, with a warning
    s = json.loads((out / "summary.json").read_text())
    assert s["spacing_m"] == [pytest.approx(5e-5, rel=1e-6)]
    assert any("x read as metres" in w for w in s["warnings"])
    out = tmp_path / "out2"
    rc, err = run_cli(
        capsys,
        [
            "analyse",
            tmp_path / "p.csv",
            "--out",
            out,
            "--units",
            "mm",
            "--x-units",
            "m",
            "--no-friction",
            "--no-figures",
        ],
    )
    assert rc == 0, err
    s = json.loads((out / "summary.json").read_text())
    assert s["spacing_m"] == [pytest.approx(5e-5, rel=1e-6)]
