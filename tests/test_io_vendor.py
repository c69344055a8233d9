"""Instrument files through SurfaceTopography (issue 9), tested on real files.

The four files in ``shared/data/formats/`` were written by the instruments themselves (Sensofar
confocal ``.plu``, Wyko white-light interferometer ``.opd``, Digital Surf ``.sur``, Alicona
focus variation ``.al3d``); ``expected.json`` beside them holds what SurfaceTopography 1.27's
own tests pin for each: shape [rows along y, columns along x], spacing, undefined fraction, rms
about the mean of the defined points, and 25 samples [row, col, height in m or null].

In CI (``CI=true``) nothing here may skip: the CI installs the ``vendor`` extra and the shared
data sit beside the checkout.
"""

from __future__ import annotations

import builtins
import json
import os
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from conftest import need_vendor

from roadscan.errors import InputError
from roadscan.io import read

ROOT = Path(__file__).resolve().parents[1]
IN_CI = os.environ.get("CI", "").lower() == "true"
FILES = ["plu-1.plu", "opd-1.opd", "sur-2.sur", "al3d-1.al3d"]


@pytest.fixture(scope="module")
def expected(formats_dir):
    return json.loads((formats_dir / "expected.json").read_text())


@pytest.fixture(scope="module")
def maps(formats_dir):
    return {name: read(formats_dir / name) for name in FILES}


@pytest.mark.parametrize("name", FILES)
def test_real_file_matches_expected(name, maps, expected):
    m, e = maps[name], expected[name]
    h = m.heights_m
    assert list(h.shape) == e["shape"]  # [rows along y, cols along x]
    assert m.dx_m == pytest.approx(e["dx_m"], rel=1e-6)
    assert m.dy_m == pytest.approx(e["dy_m"], rel=1e-6)
    assert abs(m.unmeasured.mean() - e["undefined_fraction"]) <= 1e-3
    np.testing.assert_array_equal(np.isnan(h), m.unmeasured)
    defined = h[~m.unmeasured]
    rms = np.sqrt(np.mean((defined - defined.mean()) ** 2))
    assert rms == pytest.approx(e["rms_m"], rel=1e-3)
    span = defined.max() - defined.min()
    for row, col, value in e["samples"]:
        if value is None:
            assert m.unmeasured[row, col], (row, col)
        else:
            assert abs(h[row, col] - value) <= 1e-6 * span, (row, col, h[row, col], value)


def test_orientation_agrees_with_an_independent_array(tmp_path):
    """SurfaceTopography indexes heights [x, y]; roadscan [y, x]. A non-square masked array
    written by SurfaceTopography as NetCDF (read through it) and as X3P (read by roadscan's own
    x3pio reader, despite the checksum SurfaceTopography's writer puts in the wrong place) comes
    back as its transpose, in metres, with the masked point unmeasured."""
    need_vendor()
    from SurfaceTopography import Topography

    a = np.random.default_rng(0).normal(size=(7, 5))  # [x, y]: nx = 7, ny = 5
    am = np.ma.masked_array(a, mask=np.zeros(a.shape, bool))
    am.mask[2, 3] = True
    t = Topography(
        am,
        physical_sizes=(7 * 0.5, 5 * 0.25),
        unit="nm",
        info={"instrument": {"name": "Foo", "vendor": "Bar"}},
    )
    want = np.where(am.mask, np.nan, a).T * 1e-9
    t.to_netcdf(str(tmp_path / "s.nc"))
    t.to_x3p(str(tmp_path / "s.x3p"))
    for name in ("s.nc", "s.x3p"):
        m = read(tmp_path / name)
        assert m.shape == (5, 7) and m.unmeasured[3, 2] and m.unmeasured.sum() == 1
        np.testing.assert_allclose(m.heights_m, want, rtol=1e-12, atol=0)
        assert (m.dx_m, m.dy_m) == pytest.approx((0.5e-9, 0.25e-9), rel=1e-12)
    nc = read(tmp_path / "s.nc").meta["instrument"]
    assert (nc["name"], nc["vendor"], nc["units"]) == ("Foo", "Bar", "nm")
    assert "checksum_note" in read(tmp_path / "s.x3p").meta


def test_metadata_of_real_files(maps):
    plu = maps["plu-1.plu"].meta
    inst = plu["instrument"]
    assert inst["vendor"] == "Sensofar" and inst["name"] == "PLu neox"
    assert inst["acquired"] == "2023-03-10T16:35:59"
    assert inst["objective"] == "Nikon CFI Plan Interferential 10X"
    assert inst["units"] == "µm" and inst["undefined_points"] == 0
    assert inst["reader"].startswith("SurfaceTopography 1.") and "PLUReader" in inst["reader"]
    assert plu["format"] == "plu" and plu["undefined_points"] == 0
    opd = maps["opd-1.opd"].meta["instrument"]
    assert opd["acquired"] == "2015-07-07T16:19:48" and opd["units"] == "mm"
    assert opd["undefined_points"] == int(maps["opd-1.opd"].unmeasured.sum()) == 116
    assert opd["magnification"] == pytest.approx(50.322, rel=1e-4)
    assert maps["sur-2.sur"].meta["instrument"]["undefined_points"] == 117
    al3d = maps["al3d-1.al3d"].meta["instrument"]
    assert al3d["vendor"] == "Alicona Imaging" and al3d["software"] == "MeasureSuite 5.3.6"
    for m in maps.values():
        json.dumps(m.meta)  # JSON-safe as it is


def test_issue9_plu_regression(maps):
    """The Sensofar file once read shifted by two samples with denormal garbage first: the
    first values are now ordinary heights, none denormal."""
    h = maps["plu-1.plu"].heights_m
    assert abs(h[0, 0] - (-1.112265625e-4)) < 1e-12
    a = np.abs(h[np.isfinite(h)])
    assert a.min() > 1e-5


def test_spacing_and_units_options(formats_dir, maps):
    """A flag never silently overrides the file's calibration (issue 22): refused by default,
    used and recorded under the override policy, set aside (and recorded) in a batch."""
    with pytest.raises(InputError, match=r"carries its own spacing.*'override_calibration'"):
        read(formats_dir / "plu-1.plu", spacing="2e-6,3e-6")
    with pytest.raises(InputError, match=r"heights in .*'units' mm would override"):
        read(formats_dir / "plu-1.plu", units="mm")
    m = read(formats_dir / "plu-1.plu", spacing="2e-6,3e-6", units="mm", calibration="override")
    assert (m.dx_m, m.dy_m) == (2e-6, 3e-6)
    f = {"m": 1.0, "mm": 1e-3, "µm": 1e-6, "um": 1e-6}[maps["plu-1.plu"].meta["units"]]
    np.testing.assert_allclose(m.heights_m, maps["plu-1.plu"].heights_m * 1e-3 / f, rtol=1e-12)
    over = m.meta["calibration_override"]
    assert over["spacing"]["file"] == pytest.approx([1.66e-6, 1.66e-6], rel=1e-6)
    assert over["spacing"]["flag"] == [2e-6, 3e-6] and over["units"]["flag"] == "mm"
    kept = read(formats_dir / "plu-1.plu", spacing="2e-6,3e-6", units="mm", calibration="default")
    np.testing.assert_array_equal(kept.heights_m, maps["plu-1.plu"].heights_m)
    assert kept.dx_m == maps["plu-1.plu"].dx_m and kept.meta["units_ignored"] == "mm"
    assert set(kept.meta["calibration_ignored"]) == {"spacing", "units"}


def test_size_limit_refuses_before_reading(formats_dir, monkeypatch):
    from roadscan.io import _size_limits, vendor_channel

    monkeypatch.setattr(_size_limits, "_MAX_PIXELS", 1000)
    called = []
    monkeypatch.setattr(vendor_channel, "_check_values", lambda *a: called.append(a))
    with pytest.raises(InputError, match=r"declares 576 x 768 = .*'max_pixels'") as ei:
        read(formats_dir / "plu-1.plu")
    assert "\n" not in str(ei.value) and not called


def test_extension_table_matches_installed_package():
    """Every extension SurfaceTopography reads is routed to it, except roadscan's own."""
    need_vendor()
    import SurfaceTopography.IO as stio

    from roadscan.io import READERS, vendor

    st_exts = {}
    for cls in stio.readers:
        for e in cls.file_extensions():
            st_exts.setdefault("." + e.lower(), []).append(cls.format())
    assert set(vendor.VENDOR_EXTENSIONS) | set(vendor.OWN_EXTENSIONS) == set(st_exts)
    assert not set(vendor.VENDOR_EXTENSIONS) & set(vendor.OWN_EXTENSIONS)
    for ext, fmt in vendor.VENDOR_FORMATS.items():
        assert fmt in st_exts[ext], ext
        assert READERS[ext] is vendor.read_vendor
    for ext in vendor.OWN_EXTENSIONS:
        assert READERS[ext] is not vendor.read_vendor


def _loaded(code):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    probe = code + "\nimport sys\nprint(int('SurfaceTopography' in sys.modules))"
    out = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, env=env, cwd=ROOT, timeout=120
    )
    assert out.returncode == 0, out.stderr
    return out.stdout.strip().splitlines()[-1] == "1"


def test_imported_only_when_a_vendor_file_is_read(formats_dir, tmp_path):
    assert not _loaded("import roadscan, roadscan.io")
    np.save(tmp_path / "a.npy", np.zeros((4, 4)))
    assert not _loaded(f"import roadscan.io as io\nio.read({str(tmp_path / 'a.npy')!r}, spacing=1e-6)")
    assert _loaded(f"import roadscan.io as io\nio.read({str(formats_dir / 'al3d-1.al3d')!r})")


def test_missing_extra_gives_clear_error(tmp_path, monkeypatch):
    (tmp_path / "scan.plux").write_bytes(b"PK\x03\x04 not really")
    real_import = builtins.__import__

    def hide(name, *args, **kwargs):
        if name == "SurfaceTopography" or name.startswith("SurfaceTopography."):
            raise ImportError("No module named 'SurfaceTopography'")
        return real_import(name, *args, **kwargs)

    for mod in [m for m in sys.modules if m.split(".")[0] == "SurfaceTopography"]:
        monkeypatch.delitem(sys.modules, mod)
    monkeypatch.setattr(builtins, "__import__", hide)
    with pytest.raises(InputError) as ei:
        read(tmp_path / "scan.plux")
    assert str(ei.value) == (
        f"{tmp_path / 'scan.plux'}: reading .plux files needs the optional "
        "extra: pip install 'roadscan[vendor]' (SurfaceTopography)"
    )


def _text_dat(path, rows):
    path.write_text("\n".join(" ".join(str(v) for v in r) for r in rows) + "\n")
    return path


def test_text_dat_through_the_plain_text_reader(tmp_path):
    """A non-CAPTIF ``.dat`` goes to SurfaceTopography; a text matrix states no unit nor size,
    so both are asked for, then rows are y and columns x as in the file."""
    need_vendor()
    rows = [[1, 2, 3, 4, 5], [6, 7, 8, 9, 10], [11, 12, 13, 14, 15]]
    p = _text_dat(tmp_path / "m.dat", rows)
    with pytest.raises(InputError, match=r"states no length unit: pass 'units'"):
        read(p, spacing=1e-6)
    with pytest.raises(InputError, match=r"states no lateral size: pass 'spacing'"):
        read(p, units="um")
    m = read(p, spacing="1e-6,2e-6", units="um")
    np.testing.assert_array_equal(m.heights_m, np.array(rows, dtype=float) * 1e-6)
    assert (m.dx_m, m.dy_m) == (1e-6, 2e-6)
    assert m.meta["format"] == "asc" and m.meta["instrument"]["units"] == "µm"


@pytest.mark.parametrize(
    "bad, message",
    [
        ("1e-320", r"1 heights are denormal"),
        ("3e15", r"heights reach 3e\+15 m: an unmasked invalid-point marker"),
    ],
)
def test_values_no_instrument_writes_are_refused(tmp_path, bad, message):
    need_vendor()
    p = _text_dat(tmp_path / "v.dat", [[1, 2, 3, 4], [5, bad, 7, 8], [9, 10, 11, 12]])
    with pytest.raises(InputError, match=message) as ei:
        read(p, spacing=1e-6, units="m")
    assert "\n" not in str(ei.value)


def test_nan_in_text_is_undefined(tmp_path):
    need_vendor()
    p = _text_dat(tmp_path / "n.dat", [[1, 2, 3, 4], [5, "nan", 7, 8], [9, 10, 11, 12]])
    m = read(p, spacing=1e-6, units="nm")
    assert m.unmeasured.sum() == 1 and m.unmeasured[1, 1]
    assert m.meta["undefined_points"] == 1


def test_garbage_files_one_line(tmp_path):
    need_vendor()
    cases = {
        "g.plu": b"garbage" * 40,
        "z.datx": b"\x89HDF garbage" * 10,
        "k.vk4": b"\x00" * 300,
        "s.sur": b"DIGITAL SURF" + b"\xff" * 600,
        "o.opd": b"\x01\x00" * 200,
    }
    for name, data in cases.items():
        (tmp_path / name).write_bytes(data)
        with pytest.raises(InputError) as ei:
            read(tmp_path / name)
        msg = str(ei.value)
        assert msg.startswith(str(tmp_path / name)) and "\n" not in msg, msg


def test_truncated_real_file_is_refused(formats_dir, tmp_path):
    """Half a real file: the declared grid no longer fits the data; never half a map."""
    for name in FILES:
        data = (formats_dir / name).read_bytes()
        p = tmp_path / name
        p.write_bytes(data[: len(data) // 2])
        with pytest.raises(InputError) as ei:
            read(p)
        assert "\n" not in str(ei.value)


def test_park_systems_tiff_is_not_read_as_a_picture(tmp_path):
    """A TIFF with Park Systems' magic tag goes to SurfaceTopography's reader, which refuses
    this fake one, instead of the preview image being read as heights."""
    need_vendor()
    import tifffile

    p = tmp_path / "park.tif"
    tifffile.imwrite(
        p, np.arange(64, dtype=np.uint8).reshape(8, 8), extratags=[(50432, "I", 1, 0x0E031301, False)]
    )
    with pytest.raises(InputError, match=r"park\.tif: cannot read \(Park Systems"):
        read(p, spacing=1e-6)


def test_channel_choice():
    """Default channel when it holds heights, else the first height channel."""
    from roadscan.io.vendor_channel import _pick_channel

    a = SimpleNamespace(name="phase", is_height_channel=False)
    b = SimpleNamespace(name="height", is_height_channel=True)
    c = SimpleNamespace(name="height2", is_height_channel=True)
    reader = SimpleNamespace(channels=[a, b, c], default_channel=a)
    assert _pick_channel(reader, "f")[0] is b
    reader = SimpleNamespace(channels=[a, b, c], default_channel=c)
    assert _pick_channel(reader, "f")[0] is c
    with pytest.raises(InputError, match="no height channel"):
        _pick_channel(SimpleNamespace(channels=[a], default_channel=a), "f")


def test_line_scan_and_nonuniform_channels_are_refused():
    from roadscan.io.vendor_channel import _declared_grid

    line = SimpleNamespace(name="p", dim=1, nb_grid_pts=(500,), is_uniform=True)
    with pytest.raises(InputError, match=r"is a line scan of 500 points"):
        _declared_grid(line, "f")
    scattered = SimpleNamespace(name="p", dim=2, nb_grid_pts=None, is_uniform=False)
    with pytest.raises(InputError, match=r"non-uniform"):
        _declared_grid(scattered, "f")
    ok = SimpleNamespace(name="p", dim=2, nb_grid_pts=(768, 576), is_uniform=True)
    assert _declared_grid(ok, "f") == (576, 768)  # (ny, nx) from [x, y] counts


def test_instrument_block_units_and_json():
    from datetime import datetime

    from roadscan.io.vendor import instrument_block

    info = {
        "acquisition_time": datetime(2020, 1, 2, 3, 4, 5),
        "instrument": {
            "name": "X\x00",
            "vendor": " V ",
            "parameters": {
                "resolution": {"value": 0.5, "unit": "µm"},
                "tip_radius": {"value": 20, "unit": "nm"},
            },
        },
        "raw_metadata": {"a": {"Objective": "50x", "Comment": "(None)"}},
    }
    b = instrument_block(info, units="nm", undefined_points=3, reader="R", channel="c")
    assert b == {
        "name": "X",
        "vendor": "V",
        "acquired": "2020-01-02T03:04:05",
        "objective": "50x",
        "lateral_resolution_m": pytest.approx(5e-7),
        "tip_radius_m": pytest.approx(2e-8),
        "units": "nm",
        "undefined_points": 3,
        "reader": "R",
        "channel": "c",
    }
    json.dumps(b)


def _plane_rms(m):
    """rms of the defined heights about their least-squares plane (independent of roadscan)."""
    yy, xx = np.nonzero(~m.unmeasured)
    a = np.column_stack([np.ones(xx.size), xx * m.dx_m, yy * m.dy_m])
    z = m.heights_m[yy, xx]
    coef, *_ = np.linalg.lstsq(a, z, rcond=None)
    r = z - a @ coef
    return float(np.sqrt(np.mean(r**2)))


@pytest.mark.parametrize("name", FILES)
def test_analyse_end_to_end(name, formats_dir, maps, tmp_path, capsys):
    """``roadscan analyse`` on each real file: H, rms, PSD, report; the rms in summary.json is
    the file's levelled rms, the instrument block reaches summary.json and the report header."""
    from pipelines.cli.app import main

    out = tmp_path / "out"
    assert main(["analyse", str(formats_dir / name), "--no-friction", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    m = maps[name]
    assert s["shape"] == list(m.shape) and s["spacing_m"] == [m.dx_m, m.dy_m]
    assert s["rms_height_m"] == pytest.approx(_plane_rms(m), rel=1e-6)
    # H is a headline only over half a decade within [0, 1]; the fit itself is always kept
    assert np.isfinite(s["hurst_fit"]) and (s["hurst"] is None) == (s["hurst_note"] is not None)
    assert s["filled_fraction"] == pytest.approx(m.unmeasured.mean())
    assert s["instrument"] == m.meta["instrument"]
    psd = np.loadtxt(out / "psd.csv", delimiter=",", skiprows=1)
    assert psd.shape[0] > 10 and (psd[:, 0] > 0).all() and (psd[:, 1] > 0).all()
    report = (out / "report.html").read_text()
    assert "<b>Instrument</b>" in report and m.meta["instrument"]["reader"] in report
    if "vendor" in m.meta["instrument"]:
        assert m.meta["instrument"]["vendor"] in report


def test_x3p_with_misplaced_checksum_but_damaged_data_is_refused(tmp_path):
    """The tolerance above holds only while the point data match their own checksum."""
    need_vendor()
    import zipfile

    from SurfaceTopography import Topography

    Topography(np.arange(35.0).reshape(7, 5), physical_sizes=(1.0, 1.0), unit="µm").to_x3p(
        str(tmp_path / "a.x3p")
    )
    with zipfile.ZipFile(tmp_path / "a.x3p") as src, zipfile.ZipFile(tmp_path / "b.x3p", "w") as dst:
        for info in src.infolist():
            data = src.read(info)
            if info.filename == "bindata/data.bin":
                data = data[:-8] + np.float64(1.0).tobytes()
            dst.writestr(info, data)
    assert read(tmp_path / "a.x3p").heights_m[0, 1] == pytest.approx(5e-6)  # a[x=1, y=0]
    with pytest.raises(InputError, match=r"b\.x3p: not a readable X3P file \(X3pChecksumError"):
        read(tmp_path / "b.x3p")
