"""Plausible-but-wrong inputs to the readers (issue 22): decimal-comma text, calibration
overrides, multi-page and palette TIFFs, hostile X3P zips, .npy 3.0, detection by content.

Every refusal is one line naming the file; every accepted file equals the array it was written
from (an independent writer: numpy's own formatting, tifffile, zipfile)."""

from __future__ import annotations

import numpy as np
import pytest

from roadscan.errors import InputError
from roadscan.io import read

RNG = np.random.default_rng(22)
H = RNG.normal(size=(6, 5)) * 1e-4  # heights [m], 17 significant digits in the text


def _comma(v):
    return repr(float(v)).replace(".", ",")


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


@pytest.mark.parametrize("sep", [";", "\t", " ", "; "])
def test_decimal_comma_matrix_read_as_decimals(tmp_path, sep):
    p = _write(tmp_path, "dc.csv", "\n".join(sep.join(_comma(v) for v in r) for r in H) + "\n")
    m = read(p, spacing=1e-4)
    assert m.heights_m.shape == H.shape
    np.testing.assert_array_equal(m.heights_m, H)
    assert m.meta["decimal_mark"] == ","


@pytest.mark.parametrize("sep", [",", ", "])
def test_dot_decimal_csv_unchanged(tmp_path, sep):
    p = _write(tmp_path, "d.csv", "\n".join(sep.join(repr(float(v)) for v in r) for r in H))
    m = read(p, spacing=1e-4)
    np.testing.assert_array_equal(m.heights_m, H)
    assert "decimal_mark" not in m.meta


def test_decimal_comma_xz_profile_semicolon(tmp_path):
    x = np.arange(40) * 0.5e-3
    z = RNG.normal(size=40) * 1e-4
    text = "x (m); z (m)\n" + "\n".join(f"{_comma(a)};{_comma(b)}" for a, b in zip(x, z))
    p = _write(tmp_path, "prof.txt", text)
    prof = read(p)
    np.testing.assert_allclose(prof.heights_m, z, rtol=0, atol=0)
    assert prof.dx_m == pytest.approx(0.5e-3, rel=1e-9)


def test_gwyddion_header_with_decimal_comma(tmp_path):
    text = "# Width: 5,00 mm\n# Height: 6,00 mm\n# Value units: m\n" + "\n".join(
        "\t".join(_comma(v) for v in r) for r in H
    )
    m = read(_write(tmp_path, "g.txt", text))
    assert (m.dx_m, m.dy_m) == (pytest.approx(1e-3), pytest.approx(1e-3))
    np.testing.assert_array_equal(m.heights_m, H)


@pytest.mark.parametrize(
    "line, word",
    [
        ("1.234,5;2;3;4;5", "thousands"),
        ("1,234,567;2;3;4;5", "thousands"),
        ("1,234.5 2 3 4 5", "thousands"),
        ("1 234,5;2;3;4;5", "thousands"),
        ("1,5;2.5;3;4;5", "both '.' and ','"),
        ("1,5, 2,5, 3,5, 4,5", "ambiguous"),
    ],
)
def test_thousands_and_ambiguous_commas_refused(tmp_path, line, word):
    p = _write(tmp_path, "bad.csv", (line + "\n") * 6)
    with pytest.raises(InputError) as ei:
        read(p, spacing=1e-4)
    msg = str(ei.value)
    assert word in msg and "bad.csv" in msg and "\n" not in msg


# ---------------------------------------------------------------- calibration never overridden
def _x3p(tmp_path, name="s.x3p", dx=2e-5):
    from roadscan.heightmap import HeightMap
    from roadscan.io import write

    h = RNG.normal(size=(48, 48)) * 2e-4
    return write(tmp_path / name, HeightMap(h, dx, dx)), h


def test_spacing_on_x3p_refused_in_one_line(tmp_path, capsys):
    from pipelines.cli.app import main

    p, _ = _x3p(tmp_path)
    for flag in (["--spacing", "1e-4"], ["--units", "mm"]):
        capsys.readouterr()
        assert (
            main(["analyse", str(p), "--out", str(tmp_path / "o"), "--no-friction", "--no-figures", *flag])
            == 2
        )
        err = capsys.readouterr().err.strip()
        assert "s.x3p" in err and "--override-calibration" in err and "\n" not in err
        assert not (tmp_path / "o").exists()


def test_override_calibration_recorded_in_summary(tmp_path):
    import json

    from pipelines.cli.app import main

    p, _h = _x3p(tmp_path)
    out = tmp_path / "o"
    assert (
        main(
            [
                "analyse",
                str(p),
                "--out",
                str(out),
                "--no-friction",
                "--no-figures",
                "--spacing",
                "1e-4",
                "--override-calibration",
            ]
        )
        == 0
    )
    s = json.loads(next(out.rglob("summary.json")).read_text())
    assert s["spacing_m"] == [1e-4, 1e-4]
    assert s["calibration_override"]["spacing"] == {"file": [2e-5, 2e-5], "flag": [1e-4, 1e-4]}


def test_units_override_rescales_from_the_files_unit(tmp_path):
    p, h = _x3p(tmp_path)
    m = read(p, units="mm", calibration="override")  # the file says m, the user says mm
    np.testing.assert_allclose(m.heights_m, h * 1e-3, rtol=1e-15)
    assert m.meta["calibration_override"]["units"] == {"file": "m", "flag": "mm"}


def test_flag_equal_to_the_files_calibration_is_accepted(tmp_path):
    p, _h = _x3p(tmp_path)
    m = read(p, spacing="2e-5", units="m")
    assert m.dx_m == 2e-5 and "calibration_override" not in m.meta


def test_npy_without_spacing_still_takes_the_flag(tmp_path):
    np.save(tmp_path / "a.npy", H)
    m = read(tmp_path / "a.npy", spacing="1e-4", units="mm")
    np.testing.assert_array_equal(m.heights_m, H * 1e-3)
    assert "calibration_override" not in m.meta


def test_mixed_batch_keeps_x3p_calibration(tmp_path):
    """--spacing in a batch fills in for files without one and never replaces an X3P's."""
    import json

    from pipelines.cli.app import main

    p, _h = _x3p(tmp_path, "a.x3p")
    np.save(tmp_path / "b.npy", np.random.default_rng(5).normal(size=(40, 40)) * 1e-4)
    out = tmp_path / "camp"
    rc = main(
        [
            "batch",
            str(p),
            str(tmp_path / "b.npy"),
            "--out",
            str(out),
            "--no-friction",
            "--spacing",
            "1e-4",
            "--workers",
            "1",
        ]
    )
    assert rc == 0
    sums = {f.parent.name: json.loads(f.read_text()) for f in out.rglob("summary.json")}
    a = next(v for k, v in sums.items() if k.startswith("a"))
    b = next(v for k, v in sums.items() if k.startswith("b"))
    assert a["spacing_m"] == [2e-5, 2e-5] and b["spacing_m"] == [1e-4, 1e-4]
    assert a["calibration_ignored"]["spacing"]["flag"] == [1e-4, 1e-4]
    assert any("ignored" in w for w in a["warnings"])


# ---------------------------------------------------------------- TIFF pages, samples, palettes
@pytest.fixture()
def tiffs(tmp_path):
    tifffile = pytest.importorskip("tifffile")
    rng = np.random.default_rng(3)
    stack = (rng.normal(size=(3, 20, 30)) * 1e-4).astype(np.float32)
    rgb = (rng.random((20, 30, 3)) * 255).astype(np.uint8)
    pal = (rng.random((20, 30)) * 255).astype(np.uint8)
    cmap = np.tile(np.arange(256, dtype=np.uint16) * 256, (3, 1))
    tifffile.imwrite(tmp_path / "stack.tif", stack, photometric="minisblack")
    tifffile.imwrite(tmp_path / "rgb.tif", rgb, photometric="rgb")
    tifffile.imwrite(
        tmp_path / "planar.tif", np.moveaxis(rgb, 2, 0).copy(), photometric="rgb", planarconfig="separate"
    )
    tifffile.imwrite(tmp_path / "pal.tif", pal, photometric="palette", colormap=cmap)
    return tmp_path, {"stack": stack, "rgb": rgb, "pal": pal}


@pytest.mark.parametrize(
    "name, word",
    [
        ("stack", "3 images"),
        ("rgb", "3 samples per pixel"),
        ("planar", "3 samples per pixel"),
        ("pal", "palette"),
    ],
)
def test_ambiguous_tiffs_refused_without_channel(tiffs, name, word):
    d, _ = tiffs
    with pytest.raises(InputError) as ei:
        read(d / f"{name}.tif", spacing=1e-4)
    msg = str(ei.value)
    assert word in msg and "'channel'" in msg and f"{name}.tif" in msg and "\n" not in msg


def test_tiff_channel_chooses_page_sample_or_indices(tiffs):
    d, src = tiffs
    for k in range(3):
        m = read(d / "stack.tif", spacing=1e-4, channel=k)
        np.testing.assert_array_equal(m.heights_m, src["stack"][k].astype(np.float64))
        assert m.meta["channel"] == k and m.meta["channel_note"] == f"page {k} of 3"
    for name in ("rgb", "planar"):
        for ch, k in ((0, 0), ("g", 1), ("b", 2)):
            m = read(d / f"{name}.tif", spacing=1e-4, channel=ch)
            np.testing.assert_array_equal(m.heights_m, src["rgb"][..., k].astype(np.float64))
    m = read(d / "pal.tif", spacing=1e-4, channel="index")
    np.testing.assert_array_equal(m.heights_m, src["pal"].astype(np.float64))
    for bad in (3, "x"):
        with pytest.raises(InputError, match="'channel'"):
            read(d / "stack.tif", spacing=1e-4, channel=bad)


def test_channel_on_single_channel_formats_refused(tmp_path):
    np.save(tmp_path / "a.npy", H)
    with pytest.raises(InputError, match=r"a.npy: 'channel' 1: a .npy file holds one"):
        read(tmp_path / "a.npy", spacing=1e-4, channel="1")


def test_channel_recorded_in_summary(tiffs):
    import json

    from pipelines.cli.app import main

    d, _src = tiffs
    out = d / "o"
    assert (
        main(
            [
                "analyse",
                str(d / "stack.tif"),
                "--spacing",
                "1e-4",
                "--channel",
                "1",
                "--out",
                str(out),
                "--no-friction",
                "--no-figures",
            ]
        )
        == 0
    )
    s = json.loads(next(out.rglob("summary.json")).read_text())
    assert s["channel"] == 1
    m = read(d / "stack.tif", spacing=1e-4, channel=1)
    assert s["shape"] == list(m.heights_m.shape)


def test_vendor_channel_by_index_or_name():
    from types import SimpleNamespace

    from roadscan.io.vendor_channel import _pick_channel

    a = SimpleNamespace(name="Phase", is_height_channel=False)
    b = SimpleNamespace(name="Height", is_height_channel=True)
    c = SimpleNamespace(name="Height retrace", is_height_channel=True)
    reader = SimpleNamespace(channels=[a, b, c], default_channel=b)
    assert _pick_channel(reader, "f", 2)[0] is c
    assert _pick_channel(reader, "f", "height RETRACE")[0] is c
    with pytest.raises(InputError, match="does not hold heights"):
        _pick_channel(reader, "f", "phase")
    with pytest.raises(InputError, match=r"holds 3 channels \(0..2"):
        _pick_channel(reader, "f", 3)
    with pytest.raises(InputError, match="no such channel"):
        _pick_channel(reader, "f", "amplitude")


def test_vendor_file_summary_names_its_channel(formats_dir, tmp_path):
    import json

    from pipelines.cli.app import main

    f = formats_dir / "opd-1.opd"
    out = tmp_path / "o"
    assert main(["analyse", str(f), "--out", str(out), "--no-friction", "--no-figures"]) == 0
    s = json.loads(next(out.rglob("summary.json")).read_text())
    assert s["channel"] == read(f).meta["channel"] and s["channel"]


# ---------------------------------------------------------------- hostile X3P archives
def _rezip(src, dst, edit):
    """Copy the X3P ``src`` to ``dst`` member by member, ``edit(name, data) -> [(name, data)]``."""
    import warnings
    import zipfile

    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w") as zout:
        for info in zin.infolist():
            for name, data in edit(info.filename, zin.read(info)):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # zipfile: "Duplicate name"
                    zout.writestr(name, data)
    return dst


def test_x3p_duplicate_member_refused(tmp_path):
    p, _ = _x3p(tmp_path)
    other, _ = _x3p(tmp_path, "other.x3p")
    import zipfile

    second = zipfile.ZipFile(other).read("main.xml").replace(b"48", b"24")
    dup = _rezip(p, tmp_path / "dup.x3p", lambda n, d: [(n, d), (n, second)] if n == "main.xml" else [(n, d)])
    with pytest.raises(InputError) as ei:
        read(dup)
    msg = str(ei.value)
    assert "dup.x3p" in msg and "'main.xml'" in msg and "several members" in msg
    assert "\n" not in msg


def test_x3p_checksum_note_is_a_warning_in_the_outputs(tmp_path, capsys):
    import json

    from pipelines.cli.app import main

    p, h = _x3p(tmp_path)
    bad = _rezip(
        p,
        tmp_path / "sum.x3p",
        lambda n, d: [(n, b"0" * 32 + b" *main.xml\n" if n == "md5checksum.hex" else d)],
    )
    m = read(bad)
    np.testing.assert_array_equal(m.heights_m, h)
    assert any("md5checksum.hex" in w for w in m.meta["read_warnings"])
    out = tmp_path / "o"
    capsys.readouterr()
    assert main(["analyse", str(bad), "--out", str(out), "--no-friction", "--no-figures"]) == 0
    err = capsys.readouterr().err
    s = json.loads(next(out.rglob("summary.json")).read_text())
    assert any("md5checksum.hex" in w and "sum.x3p" in w for w in s["warnings"])
    assert "md5checksum.hex" in err


# ---------------------------------------------------------------- .npy format 3.0
def test_npy_format_3_read(tmp_path):
    for version in ((1, 0), (2, 0), (3, 0)):
        p = tmp_path / f"v{version[0]}.npy"
        with open(p, "wb") as f:
            np.lib.format.write_array(f, H, version=version)
        with open(p, "rb") as f:
            assert np.lib.format.read_magic(f) == version
        m = read(p, spacing=1e-4)
        np.testing.assert_array_equal(m.heights_m, H)
    np.savez(tmp_path / "z.npz", heights=H, dx=1e-4, dy=1e-4)  # members through the same header
    np.testing.assert_array_equal(read(tmp_path / "z.npz").heights_m, H)


def test_npy_unknown_format_version_refused(tmp_path):
    p = tmp_path / "v9.npy"
    with open(p, "wb") as f:
        np.lib.format.write_array(f, H, version=(2, 0))
    raw = bytearray(p.read_bytes())
    raw[6] = 9  # major version byte
    p.write_bytes(bytes(raw))
    with pytest.raises(InputError, match=r"v9.npy: not a readable NumPy file"):
        read(p, spacing=1e-4)


# ---------------------------------------------------------------- detection by content
def test_unknown_extension_read_by_content(tmp_path):
    import shutil

    p, h = _x3p(tmp_path)
    shutil.copy(p, tmp_path / "scan.bin")
    m = read(tmp_path / "scan.bin")
    np.testing.assert_array_equal(m.heights_m, h)
    assert m.meta["detected_by_content"] == "x3p"
    np.save(tmp_path / "a.npy", H)
    shutil.copy(tmp_path / "a.npy", tmp_path / "a.raw")
    m = read(tmp_path / "a.raw", spacing=1e-4)
    np.testing.assert_array_equal(m.heights_m, H)
    assert m.meta["detected_by_content"] == "npy"
    (tmp_path / "t.export").write_text("\n".join(";".join(_comma(v) for v in r) for r in H))
    np.testing.assert_array_equal(read(tmp_path / "t.export", spacing=1e-4).heights_m, H)


def test_unknown_binary_refused_in_one_line(tmp_path):
    pytest.importorskip("SurfaceTopography")
    p = tmp_path / "noise.zzz"
    p.write_bytes(bytes(np.random.default_rng(1).integers(0, 256, 5000, dtype=np.uint8)))
    with pytest.raises(InputError) as ei:
        read(p)
    msg = str(ei.value)
    assert "noise.zzz" in msg and "'.zzz'" in msg and "\n" not in msg


@pytest.mark.parametrize("name", ["plu-1.plu", "opd-1.opd", "sur-2.sur", "al3d-1.al3d"])
def test_instrument_files_renamed_di_read_by_content(formats_dir, tmp_path, name):
    """As Bruker's .di scans: an extension no reader lists; SurfaceTopography tells by content."""
    import shutil

    shutil.copy(formats_dir / name, tmp_path / "scan.di")
    a, b = read(formats_dir / name), read(tmp_path / "scan.di")
    np.testing.assert_array_equal(a.heights_m, b.heights_m)
    assert (a.dx_m, a.dy_m) == (b.dx_m, b.dy_m)
    assert b.meta["detected_by_content"] == a.meta["format"]


# ---------------------------------------------------------------- lateral size vs instrument
def _nms(path, nx, ny, dx_header, z=(-2.0, 3.0), seed=0):
    """A NanoFocus .nms as SurfaceTopography's reader lays it out: 3468-byte header, z range
    (2 doubles) at 16, nx, ny (uint32) and the grid spacing (2 doubles) at 1368, then uint16."""
    import struct

    raw = np.random.default_rng(seed).integers(0, 2**16 - 1, size=(ny, nx), dtype=np.uint16)
    head = bytearray(3468)
    head[16:32] = struct.pack("<dd", *z)
    head[1368:1392] = struct.pack("<IIdd", nx, ny, dx_header, dx_header)
    path.write_bytes(bytes(head) + raw.astype("<u2").tobytes())
    return raw.astype(np.float64) / (2**16 - 2) * (z[1] - z[0]) + z[0]  # um, rows along y


def test_nanofocus_spacing_in_nanometres(tmp_path):
    pytest.importorskip("SurfaceTopography")
    z_um = _nms(tmp_path / "a.nms", 64, 48, 312.5)  # 312.5 nm pixels
    m = read(tmp_path / "a.nms")
    assert (m.dx_m, m.dy_m) == (pytest.approx(312.5e-9), pytest.approx(312.5e-9))
    np.testing.assert_allclose(m.heights_m, z_um * 1e-6, rtol=1e-12)
    assert any("nanometres" in w for w in m.meta["read_warnings"])
    _nms(tmp_path / "b.nms", 64, 48, 0.0003125)  # a header in mm stays as read
    m = read(tmp_path / "b.nms")
    assert m.dx_m == pytest.approx(312.5e-9) and "read_warnings" not in m.meta


def test_implausible_lateral_size_refused(tmp_path):
    pytest.importorskip("SurfaceTopography")
    _nms(tmp_path / "c.nms", 64, 48, 3e9)  # 3 m pixels even in nm
    with pytest.raises(InputError) as ei:
        read(tmp_path / "c.nms")
    msg = str(ei.value)
    assert "c.nms" in msg and "implausible" in msg and "'override_calibration'" in msg
    m = read(tmp_path / "c.nms", spacing="1e-6", calibration="override")
    assert m.dx_m == 1e-6


def test_lateral_ranges_by_kind():
    from roadscan.io.instrument_kind import check_lateral

    check_lateral("f", "di", "DI", 1e-8, 1e-8, 512, 512)  # AFM: 5 um field
    check_lateral("f", "hgt", "SRTM", 30.0, 30.0, 3601, 3601)  # any scale: not checked
    with pytest.raises(InputError, match="scanning-probe"):
        check_lateral("f", "di", "DI", 1e-5, 1e-5, 512, 512)  # a 5 mm AFM field
    with pytest.raises(InputError, match="optical"):
        check_lateral("f", "plu", "PLU", 1e-10, 1e-10, 512, 512)  # 0.1 nm optical pixels


def test_gwy_channel_by_number_or_title(tmp_path):
    pytest.importorskip("gwyfile")
    from gwyfile.objects import GwyContainer, GwyDataField

    a, b = H, H[::-1] * 2
    c = GwyContainer()
    for k, (h, title) in enumerate(((a, "Height"), (b, "Height retrace"))):
        c[f"/{k}/data"] = GwyDataField(h, xreal=5e-4, yreal=6e-4, si_unit_xy="m", si_unit_z="m")
        c[f"/{k}/data/title"] = title
    c.tofile(str(tmp_path / "two.gwy"))
    m = read(tmp_path / "two.gwy")
    np.testing.assert_array_equal(m.heights_m, a)
    assert m.meta["channels"] == ["0: Height", "1: Height retrace"]
    for ch in (1, "1", "height retrace"):
        np.testing.assert_array_equal(read(tmp_path / "two.gwy", channel=ch).heights_m, b)
    with pytest.raises(InputError, match=r"'channel' 7: no such channel \(channels: 0 \(Height\)"):
        read(tmp_path / "two.gwy", channel=7)


def test_text_header_over_binary_goes_to_surfacetopography(tmp_path):
    """A Bruker Nanoscope file starts with a long text header (``\\*File list``); it must reach
    SurfaceTopography's detection, not the text reader (a broken one: refused in one line)."""
    pytest.importorskip("SurfaceTopography")
    from roadscan.io.detect import sniff_extension

    p = tmp_path / "afm.di"
    p.write_bytes(
        b"\\*File list\r\n\\Version: 0x05120000\r\n"
        + b"\\x: 1\r\n" * 800
        + b"\\*File list end\r\n"
        + bytes(range(256)) * 8
    )
    assert sniff_extension(p) == "vendor"
    with pytest.raises(InputError) as ei:
        read(p)
    assert "afm.di" in str(ei.value) and "'.di'" in str(ei.value) and "\n" not in str(ei.value)
    q = tmp_path / "hdr.bin"
    q.write_bytes(b"instrument export\r\n" * 300 + b"\x00\x01" * 500)
    with pytest.raises(InputError, match=r"hdr.bin"):
        read(q)


def test_rain_fill_summary_records_channel_and_override(tiffs, tmp_path):
    import json

    from pipelines.cli.app import main

    d, _ = tiffs
    out = tmp_path / "rain"
    assert (
        main(["rain-fill", str(d / "stack.tif"), "--spacing", "1e-4", "--channel", "2", "--out", str(out)])
        == 0
    )
    s = json.loads((out / "rainfill.json").read_text())
    assert s["channel"] == 2
    p, _ = _x3p(tmp_path)
    out2 = tmp_path / "rain2"
    assert main(["rain-fill", str(p), "--spacing", "1e-4", "--override-calibration", "--out", str(out2)]) == 0
    s = json.loads((out2 / "rainfill.json").read_text())
    assert s["calibration_override"]["spacing"]["flag"] == [1e-4, 1e-4] and s["dx_m"] == 1e-4
