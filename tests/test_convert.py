"""``roadscan convert IN OUT`` (issue 9): real instrument files to .x3p, .npz, .tif and .npy,
read back bit for bit (heights, NaN positions, spacing), with the instrument's metadata in the
X3P record; bad requests refused in one line with nothing written."""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
import pytest

from pipelines.cli.app import main
from roadscan.io import read

ROOT = Path(__file__).resolve().parents[1]
IN_CI = os.environ.get("CI", "").lower() == "true"
FILES = ["plu-1.plu", "opd-1.opd", "sur-2.sur", "al3d-1.al3d"]


@pytest.fixture(scope="module")
def originals(formats_dir):
    return {name: read(formats_dir / name) for name in FILES}


def _same(a, b):
    np.testing.assert_array_equal(a.unmeasured, b.unmeasured)
    assert np.array_equal(a.heights_m, b.heights_m, equal_nan=True)
    assert a.heights_m.tobytes() == b.heights_m.tobytes()  # bit for bit, NaN included
    assert (a.dx_m, a.dy_m) == (b.dx_m, b.dy_m)


@pytest.mark.parametrize("name", FILES)
def test_real_files_round_trip_through_x3p(name, formats_dir, originals, tmp_path, capsys):
    out = tmp_path / (Path(name).stem + ".x3p")
    assert main(["convert", str(formats_dir / name), str(out)]) == 0
    back = read(out)
    _same(originals[name], back)
    line = capsys.readouterr().out
    assert line.count("\n") == 1 and f"{int(originals[name].unmeasured.sum())} unmeasured" in line
    inst = back.meta["instrument"]
    src = originals[name].meta["instrument"]
    assert f"converted by roadscan from {name}" in inst["comment"]
    assert src["reader"] in inst["comment"]
    for key in ("vendor", "name", "software"):
        if key in src:
            assert inst[key] == src[key]
    if "acquired" in src:  # same wall-clock time (x3p adds the zone)
        assert inst["acquired"].startswith(src["acquired"])
    else:
        assert "acquired" not in inst and "acquisition date unknown" in inst["comment"]
    assert inst["undefined_points"] == src["undefined_points"]


def test_x3p_record_of_the_sensofar_file(formats_dir, tmp_path):
    import x3pio

    out = tmp_path / "p.x3p"
    assert main(["convert", str(formats_dir / "plu-1.plu"), str(out)]) == 0
    md = x3pio.read(str(out)).metadata
    assert (md.instrument.manufacturer, md.instrument.model) == ("Sensofar", "PLu neox")
    assert md.date.replace(tzinfo=None).isoformat() == "2023-03-10T16:35:59"
    assert md.probing_system.type == x3pio.ProbingType.NON_CONTACTING
    assert md.probing_system.identification == "Nikon CFI Plan Interferential 10X"


@pytest.mark.parametrize("ext", [".npz", ".tif"])
@pytest.mark.parametrize("name", ["opd-1.opd", "sur-2.sur"])  # both with undefined points
def test_npz_and_tif_round_trips(name, ext, formats_dir, originals, tmp_path):
    out = tmp_path / (Path(name).stem + ext)
    assert main(["convert", str(formats_dir / name), str(out)]) == 0
    _same(originals[name], read(out))


def test_npy_keeps_heights_and_asks_for_spacing(formats_dir, originals, tmp_path, capsys):
    out = tmp_path / "a.npy"
    assert main(["convert", str(formats_dir / "al3d-1.al3d"), str(out)]) == 0
    assert "spacing not stored" in capsys.readouterr().out
    o = originals["al3d-1.al3d"]
    _same(o, read(out, spacing=(o.dx_m, o.dy_m)))


def test_float32_and_spacing_options(formats_dir, originals, tmp_path):
    out = tmp_path / "f.x3p"
    assert (
        main(
            [
                "convert",
                str(formats_dir / "opd-1.opd"),
                str(out),
                "--float32",
                "--spacing",
                "2e-7,3e-7",
                "--override-calibration",
            ]
        )
        == 0
    )
    back, o = read(out), originals["opd-1.opd"]
    assert (back.dx_m, back.dy_m) == (2e-7, 3e-7)
    np.testing.assert_array_equal(back.heights_m, o.heights_m.astype(np.float32).astype(np.float64))


def test_refusals_are_one_line_and_write_nothing(formats_dir, tmp_path, capsys):
    plu = str(formats_dir / "plu-1.plu")
    captif = sorted((formats_dir.parent / "profiles" / "captif").glob("*.dat"))
    cases = [
        ([plu, str(tmp_path / "o.txt")], r"cannot write '\.txt'"),
        ([plu, str(tmp_path / "missing" / "o.x3p")], r"folder .*missing does not exist"),
        ([plu, str(tmp_path)], r"is a folder"),
        ([str(tmp_path / "none.plu"), str(tmp_path / "o.x3p")], r"no such file"),
        ([plu, str(tmp_path / "o.x3p"), "--max-pixels", "1000"], r"declares 576 x 768"),
        ([plu, str(tmp_path / "o.x3p"), "--spacing", "-1"], r"spacing"),
    ]
    if captif:
        cases.append(([str(captif[0]), str(tmp_path / "o.tif")], r"line profile: TIFF holds area"))
    for argv, pattern in cases:
        capsys.readouterr()
        assert main(["convert", *argv]) == 2, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("roadscan convert: error: "), err
        assert re.search(pattern, err), (pattern, err)
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_output_equal_to_input_is_refused(tmp_path, capsys):
    h = np.arange(20.0).reshape(4, 5) * 1e-6
    np.savez(tmp_path / "s.npz", heights=h, dx=1e-6, dy=1e-6)
    before = (tmp_path / "s.npz").read_bytes()
    assert main(["convert", str(tmp_path / "s.npz"), str(tmp_path / "s.npz")]) == 2
    assert "is the input file" in capsys.readouterr().err
    assert (tmp_path / "s.npz").read_bytes() == before


def test_failed_write_leaves_no_file(tmp_path, monkeypatch, capsys):
    """Atomic: a writer dying half-way leaves neither OUT nor a temporary file."""
    import x3pio

    h = np.arange(20.0).reshape(4, 5) * 1e-6
    np.savez(tmp_path / "s.npz", heights=h, dx=1e-6, dy=1e-6)

    def dies(path, *a, **k):
        Path(path).write_bytes(b"PK\x03\x04 half")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(x3pio, "write", dies)
    assert main(["convert", str(tmp_path / "s.npz"), str(tmp_path / "o.x3p")]) == 2
    assert "No space left" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.npz"]


def test_profile_to_x3p_and_npz(tmp_path):
    z = np.sin(np.arange(64) / 5.0) * 1e-4
    z[7] = np.nan
    np.save(tmp_path / "p.npy", z)
    for ext in (".x3p", ".npz"):
        out = tmp_path / ("p" + ext)
        assert main(["convert", str(tmp_path / "p.npy"), str(out), "--spacing", "5e-5"]) == 0
        back = read(out)
        assert back.dx_m == 5e-5 and np.array_equal(back.heights_m, z, equal_nan=True)
