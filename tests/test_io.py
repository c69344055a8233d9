"""Reading and writing height files: round trips, units, text layouts, gwy, errors."""

from __future__ import annotations

import os

import numpy as np
import pytest

from roadscan.errors import InputError
from roadscan.heightmap import HeightMap, Profile
from roadscan.io import READERS, WRITERS, parse_spacing, parse_units, read, write


def _surface(ny=37, nx=53, seed=0, holes=True, dtype=np.float64):
    rng = np.random.default_rng(seed)
    h = rng.normal(scale=3e-4, size=(ny, nx)).astype(dtype)
    if holes:
        h[rng.random((ny, nx)) < 0.05] = np.nan
    return HeightMap(h, 5.54e-5, 6.1e-5, name="s")


def _same(a, b):
    assert a.shape == b.shape
    np.testing.assert_array_equal(a.unmeasured, b.unmeasured)
    np.testing.assert_array_equal(a.heights_m, b.heights_m)  # NaN == NaN here


# ---------------------------------------------------------------- round trips


@pytest.mark.parametrize("ext", [".x3p", ".npz", ".tif", ".tiff"])
def test_round_trip_exact(tmp_path, ext):
    hm = _surface()
    out = write(tmp_path / f"s{ext}", hm)
    back = read(out)
    _same(hm, back)
    assert back.dx_m == hm.dx_m and back.dy_m == hm.dy_m
    assert back.unmeasured.sum() > 0


def test_x3p_bitwise_and_profile(tmp_path):
    hm = _surface(seed=3)
    write(tmp_path / "a.x3p", hm)
    back = read(tmp_path / "a.x3p")
    assert back.heights_m.tobytes() == hm.heights_m.tobytes()
    assert back.meta["format"] == "x3p" and back.meta["units"] == "m"
    pr = Profile(hm.heights_m[5], 3.75e-5)
    write(tmp_path / "p.x3p", pr)
    pb = read(tmp_path / "p.x3p")
    assert isinstance(pb, Profile) and pb.dx_m == pr.dx_m
    np.testing.assert_array_equal(pb.heights_m, pr.heights_m)


def test_npy_round_trip_needs_spacing(tmp_path):
    hm = _surface()
    write(tmp_path / "a.npy", hm)
    with pytest.raises(InputError, match=r"a\.npy.*no spacing: pass 'spacing' DX\[,DY\] in metres"):
        read(tmp_path / "a.npy")
    back = read(tmp_path / "a.npy", spacing=(hm.dx_m, hm.dy_m))
    _same(hm, back)
    back2 = read(tmp_path / "a.npy", spacing=f"{hm.dx_m},{hm.dy_m}")
    assert (back2.dx_m, back2.dy_m) == (hm.dx_m, hm.dy_m)
    sq = read(tmp_path / "a.npy", spacing=1e-4)
    assert sq.dx_m == sq.dy_m == 1e-4


@pytest.mark.parametrize("ext", [".tif", ".npz", ".npy", ".x3p"])
def test_float32_on_request(tmp_path, ext):
    import tifffile

    hm = _surface()
    write(tmp_path / f"a{ext}", hm, dtype="float32")
    if ext == ".tif":
        stored = tifffile.imread(tmp_path / "a.tif")
    elif ext == ".npz":
        stored = np.load(tmp_path / "a.npz")["heights"]
    elif ext == ".x3p":
        import x3pio

        f = x3pio.read(str(tmp_path / "a.x3p"))
        assert f.header.z.data_type == x3pio.DataType.FLOAT32
        stored = f.layers[0].z.astype(np.float32)
    else:
        stored = np.load(tmp_path / "a.npy")
    assert stored.dtype == np.float32
    back = read(tmp_path / f"a{ext}", spacing=None if ext != ".npy" else (hm.dx_m, hm.dy_m))
    np.testing.assert_array_equal(back.heights_m, hm.heights_m.astype(np.float32).astype(np.float64))
    np.testing.assert_array_equal(back.unmeasured, hm.unmeasured)
    with pytest.raises(ValueError):
        write(tmp_path / f"b{ext}", hm, dtype="int16")
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"a{ext}"]  # nothing half-written


def test_tiff_resolution_tags(tmp_path):
    import tifffile

    h = np.random.default_rng(1).random((8, 9))
    tifffile.imwrite(
        tmp_path / "cm.tif", h, resolution=(200.0, 100.0), resolutionunit="CENTIMETER", metadata=None
    )
    m = read(tmp_path / "cm.tif", units="um")
    assert m.dx_m == pytest.approx(5e-5) and m.dy_m == pytest.approx(1e-4)
    np.testing.assert_allclose(m.heights_m, h * 1e-6)
    # 72 dpi is an image program's default, not a physical spacing
    tifffile.imwrite(tmp_path / "dpi.tif", h, resolution=(72, 72), resolutionunit="INCH", metadata=None)
    with pytest.raises(InputError, match="no spacing"):
        read(tmp_path / "dpi.tif")
    tifffile.imwrite(tmp_path / "none.tif", h, metadata=None)
    with pytest.raises(InputError, match="no spacing"):
        read(tmp_path / "none.tif")
    assert read(tmp_path / "none.tif", spacing=2e-5).dx_m == 2e-5


def test_npz_keys_and_override(tmp_path):
    h = np.random.default_rng(2).normal(size=(6, 7))
    mask = np.zeros_like(h, bool)
    mask[2, 3] = True
    np.savez(tmp_path / "a.npz", heights=h, dx=1e-4, dy=2e-4, unmeasured=mask)
    m = read(tmp_path / "a.npz")
    assert (m.dx_m, m.dy_m) == (1e-4, 2e-4)
    assert m.unmeasured[2, 3] and np.isnan(m.heights_m[2, 3]) and m.unmeasured.sum() == 1
    with pytest.raises(InputError, match=r"a.npz: the file carries its own spacing"):
        read(tmp_path / "a.npz", spacing="3e-5")  # never silently overridden (issue 22)
    m2 = read(tmp_path / "a.npz", spacing="3e-5", calibration="override")
    assert (m2.dx_m, m2.dy_m) == (3e-5, 3e-5)
    assert m2.meta["calibration_override"]["spacing"] == {"file": [1e-4, 2e-4], "flag": [3e-5, 3e-5]}
    np.savez(tmp_path / "b.npz", heights=h)
    with pytest.raises(InputError, match=r"b.npz: no spacing"):
        read(tmp_path / "b.npz")
    np.savez(tmp_path / "c.npz", z=h)
    with pytest.raises(InputError, match=r"c.npz.*'heights'"):
        read(tmp_path / "c.npz")


def test_write_is_atomic_and_unknown_extension(tmp_path):
    hm = _surface()
    with pytest.raises(InputError, match=r"out\.png"):
        write(tmp_path / "out.png", hm)
    assert list(tmp_path.iterdir()) == []
    assert set(WRITERS) >= {".x3p", ".npy", ".npz", ".tif"}


# ---------------------------------------------------------------- units


@pytest.mark.parametrize("units,scale", [("mm", 1e3), ("um", 1e6), ("nm", 1e9), ("m", 1.0)])
def test_units_give_identical_heights(tmp_path, units, scale):
    h = np.random.default_rng(4).normal(scale=1e-4, size=(9, 11))
    np.save(tmp_path / "m.npy", h)
    np.save(tmp_path / "x.npy", h * scale)
    a = read(tmp_path / "m.npy", spacing=1e-4)
    b = read(tmp_path / "x.npy", spacing=1e-4, units=units)
    np.testing.assert_allclose(b.heights_m, a.heights_m, rtol=1e-14, atol=0)
    # text matrix too
    np.savetxt(tmp_path / "x.txt", h * scale)
    c = read(tmp_path / "x.txt", spacing=1e-4, units=units)
    np.testing.assert_allclose(c.heights_m, a.heights_m, rtol=1e-12)


def test_parse_helpers():
    assert parse_units("mm") == 1e-3 and parse_units("µm") == 1e-6 and parse_units("nm") == 1e-9
    assert parse_spacing("5e-5") == (5e-5, 5e-5)
    assert parse_spacing("5e-5,6e-5") == (5e-5, 6e-5)
    for bad in ["", "a", "1,2,3", "0", "-1e-5", "1e-5,-2", "nan", "inf"]:
        with pytest.raises(InputError):
            parse_spacing(bad)
    with pytest.raises(InputError, match="unknown units 'furlong'"):
        parse_units("furlong")


# ---------------------------------------------------------------- text layouts


def test_ascii_matrix_comma_and_whitespace(tmp_path):
    h = np.random.default_rng(5).normal(size=(5, 6))
    h[1, 2] = np.nan
    np.savetxt(tmp_path / "a.csv", h, delimiter=",")
    np.savetxt(tmp_path / "b.txt", h, delimiter="\t")
    for name in ("a.csv", "b.txt"):
        m = read(tmp_path / name, spacing="1e-4,2e-4", units="mm")
        np.testing.assert_allclose(m.heights_m, h * 1e-3, rtol=1e-15)
        assert m.unmeasured[1, 2] and m.unmeasured.sum() == 1 and m.dy_m == 2e-4


def test_esri_ascii_grid(tmp_path):
    rows = [[1, 2, 3, 4], [5, -9999, 7, 8], [9, 10, 11, 12]]
    text = "ncols 4\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 0.001\nNODATA_value -9999\n"
    text += "\n".join(" ".join(str(v) for v in r) for r in rows) + "\n"
    (tmp_path / "g.asc").write_text(text)
    m = read(tmp_path / "g.asc", units="mm")
    assert m.dx_m == m.dy_m == 0.001
    # first file row is the north edge: it becomes the last row (largest y)
    np.testing.assert_allclose(m.heights_m[-1], np.array([1, 2, 3, 4]) * 1e-3)
    assert m.unmeasured[1, 1] and m.unmeasured.sum() == 1


def test_gwyddion_ascii_export(tmp_path):
    h = np.arange(12.0).reshape(3, 4)
    text = "# Channel: Height\n# Width: 2.000 mm\n# Height: 1.500 mm\n# Value units: um\n"
    text += "\n".join("\t".join(f"{v:.6e}" for v in r) for r in h)
    (tmp_path / "g.txt").write_text(text)
    with pytest.raises(InputError, match="states its heights in um: 'units' mm"):
        read(tmp_path / "g.txt", units="mm")  # never silently overridden (issue 22)
    m = read(tmp_path / "g.txt", units="mm", calibration="default")  # batch: the file wins
    assert m.dx_m == pytest.approx(0.5e-3) and m.dy_m == pytest.approx(0.5e-3)
    np.testing.assert_allclose(m.heights_m, h * 1e-6)
    assert m.meta["units_ignored"] == "mm"


def _xyz_points(ny=7, nx=9, dx=2e-4, dy=3e-4, seed=6):
    rng = np.random.default_rng(seed)
    h = rng.normal(size=(ny, nx))
    yy, xx = np.mgrid[0:ny, 0:nx]
    pts = np.column_stack([1.0 + xx.ravel() * dx, -2.0 + yy.ravel() * dy, h.ravel()])
    return h, pts


def test_xyz_grid_shuffled_with_missing_points(tmp_path):
    h, pts = _xyz_points()
    rng = np.random.default_rng(0)
    keep = np.ones(len(pts), bool)
    keep[[3, 20, 40]] = False
    sel = pts[keep][rng.permutation(keep.sum())]
    np.savetxt(tmp_path / "p.xyz", sel, fmt="%.9f")
    m = read(tmp_path / "p.xyz")
    assert m.shape == h.shape
    assert m.dx_m == pytest.approx(2e-4, rel=1e-6) and m.dy_m == pytest.approx(3e-4, rel=1e-6)
    expect = h.copy().ravel()
    expect[[3, 20, 40]] = np.nan
    np.testing.assert_allclose(m.heights_m.ravel(), expect, atol=1e-9)
    assert m.unmeasured.sum() == 3
    # CSV with a title line naming units: x,y in mm, z in um
    with open(tmp_path / "p.csv", "w") as f:
        f.write("x (mm), y (mm), z (um)\n")
        for x, y, z in pts:
            f.write(f"{x * 1e3:.6f}, {y * 1e3:.6f}, {z:.9f}\n")
    c = read(tmp_path / "p.csv")
    assert c.dx_m == pytest.approx(2e-4, rel=1e-6)
    np.testing.assert_allclose(c.heights_m, h * 1e-6, atol=1e-15)


def test_xyz_irregular_rejected(tmp_path):
    rng = np.random.default_rng(7)
    pts = rng.random((60, 3))
    np.savetxt(tmp_path / "r.xyz", pts)
    with pytest.raises(InputError, match=r"r\.xyz.*regular grid"):
        read(tmp_path / "r.xyz")
    # two points on one node
    _, pts = _xyz_points(4, 5)
    pts = np.vstack([pts, pts[:1]])
    np.savetxt(tmp_path / "d.xyz", pts)
    with pytest.raises(InputError, match=r"d\.xyz.*regular grid"):
        read(tmp_path / "d.xyz")


def test_two_column_profile(tmp_path):
    x = np.arange(200) * 0.05  # mm
    z = np.sin(x)
    z[10] = np.nan
    keep = np.ones(200, bool)
    keep[50:53] = False  # three rows missing: become unmeasured
    # without unit titles --units applies to the coordinates and the heights alike
    np.savetxt(tmp_path / "p.txt", np.column_stack([x[keep], z[keep]]), fmt="%.6e %.9f")
    p = read(tmp_path / "p.txt", units="mm")
    assert isinstance(p, Profile) and p.n == 200
    assert p.dx_m == pytest.approx(0.05e-3, rel=1e-6)
    assert p.unmeasured.sum() == 4 and p.unmeasured[50:53].all() and p.unmeasured[10]
    np.testing.assert_allclose(p.heights_m[~p.unmeasured], z[keep & np.isfinite(z)] * 1e-3, atol=1e-12)
    with open(tmp_path / "q.csv", "w") as f:
        f.write("distance (mm),height (um)\n")
        for xi, zi in zip(x, z):
            f.write(f"{xi:.3f},{zi:.6f}\n")
    q = read(tmp_path / "q.csv")
    assert q.dx_m == pytest.approx(5e-5) and np.nanmax(np.abs(q.heights_m)) <= 1e-6


# ---------------------------------------------------------------- gwy


def test_gwy_written_by_gwyfile(tmp_path):
    from gwyfile.objects import GwyContainer, GwyDataField

    h = np.random.default_rng(8).normal(scale=1e-5, size=(12, 17))
    h[4, 5] = np.nan
    c = GwyContainer()
    c["/0/data"] = GwyDataField(h, xreal=17 * 2e-6, yreal=12 * 3e-6, si_unit_xy="m", si_unit_z="m")
    c["/0/data/title"] = "Height"
    c.tofile(str(tmp_path / "a.gwy"))
    m = read(tmp_path / "a.gwy")
    assert m.dx_m == pytest.approx(2e-6, rel=1e-12) and m.dy_m == pytest.approx(3e-6, rel=1e-12)
    np.testing.assert_array_equal(m.heights_m, h)
    assert m.unmeasured[4, 5] and m.meta["title"] == "Height"
    # a field without units: heights in `units`, spacing required
    c2 = GwyContainer()
    c2["/3/data"] = GwyDataField(h * 1e6, xreal=1.0, yreal=1.0)
    c2.tofile(str(tmp_path / "b.gwy"))
    with pytest.raises(InputError, match=r"b.gwy: no spacing"):
        read(tmp_path / "b.gwy")
    b = read(tmp_path / "b.gwy", spacing=1e-5, units="um")
    np.testing.assert_allclose(b.heights_m, h, rtol=1e-12)


def test_gwy_mask_is_unmeasured_like_surfacetopography(tmp_path):
    """An instrument export marks invalid points (filled with 0) by /0/mask: they are unmeasured,
    as SurfaceTopography (the independent reader) reads them; rows stay along y."""
    from gwyfile.objects import GwyContainer, GwyDataField

    rng = np.random.default_rng(9)
    h = rng.normal(scale=1e-6, size=(9, 14))
    bad = rng.random(h.shape) < 0.1
    h[bad] = 0.0
    c = GwyContainer()
    c["/0/data"] = GwyDataField(h, xreal=14 * 1e-6, yreal=9 * 2e-6, si_unit_xy="m", si_unit_z="m")
    c["/0/mask"] = GwyDataField(bad.astype(float), xreal=14 * 1e-6, yreal=9 * 2e-6)
    c.tofile(str(tmp_path / "m.gwy"))
    m = read(tmp_path / "m.gwy")
    np.testing.assert_array_equal(m.unmeasured, bad)
    np.testing.assert_array_equal(m.heights_m[~bad], h[~bad])
    assert m.meta["gwy_mask_fraction"] == pytest.approx(bad.mean())
    if os.environ.get("CI") != "true":
        pytest.importorskip("SurfaceTopography")
    from SurfaceTopography import open_topography

    t = open_topography(str(tmp_path / "m.gwy")).topography()
    st = np.ma.filled(t.heights().astype(float), np.nan).T  # ST indexes [x, y]
    np.testing.assert_array_equal(np.isnan(st), bad)
    np.testing.assert_allclose(st[~bad], h[~bad], rtol=1e-12)


# ---------------------------------------------------------------- errors


def test_errors_name_the_file(tmp_path):
    f = tmp_path
    cases = {}
    cases["missing.npy"] = ("no such file", None)
    (f / "empty.csv").write_text("")
    cases["empty.csv"] = ("empty file", None)
    (f / "blank.txt").write_text("\n  \n")
    cases["blank.txt"] = ("empty file", None)
    (f / "scan.xyzw").write_text("1 2 3")
    cases["scan.xyzw"] = ("unknown file extension", None)
    np.save(f / "cube.npy", np.zeros((2, 3, 4)))
    cases["cube.npy"] = ("shape", 1e-4)
    (f / "words.txt").write_text("1 2 3 4\n5 6 7 8\n9 x 11 12\n")
    cases["words.txt"] = ("non-numeric value 'x' on line 3", 1e-4)
    (f / "first.txt").write_text("1 2 abc 4\n5 6 7 8\n9 10 11 12\n")
    cases["first.txt"] = ("non-numeric value 'abc'", 1e-4)
    (f / "ragged.txt").write_text("1 2 3 4\n5 6 7 8\n9 10 11\n")
    cases["ragged.txt"] = ("ragged rows: line 3", 1e-4)
    (f / "short.csv").write_text("1,2,3,4\n5,6,7\n9,10,11,12\n")  # (an empty field is a dropout:
    cases["short.csv"] = ("ragged rows: line 2", 1e-4)  # tests/test_text_headers.py)
    np.save(f / "nan.npy", np.full((4, 4), np.nan))
    cases["nan.npy"] = ("no measured points", 1e-4)
    (f / "nan.txt").write_text("nan nan nan nan\nNaN NaN NaN NaN\n")
    cases["nan.txt"] = ("no measured points", 1e-4)
    np.save(f / "ok.npy", np.zeros((4, 4)))
    (f / "broken.x3p").write_bytes(b"not a zip file at all")
    cases["broken.x3p"] = ("not a readable X3P", None)
    (f / "broken.gwy").write_bytes(b"GWYPgarbage")
    cases["broken.gwy"] = ("not a readable Gwyddion", None)
    (f / "broken.tif").write_bytes(b"II*\x00garbage")
    cases["broken.tif"] = ("not a readable TIFF", None)
    (f / "broken.npz").write_bytes(b"PK garbage")
    cases["broken.npz"] = ("not a readable NumPy", None)
    np.save(f / "text.npy", np.array([["a", "b"], ["c", "d"]]))
    cases["text.npy"] = ("not numbers", 1e-4)
    (f / "irregular.txt").write_text("0 1\n1 2\n2.5 3\n3 4\n7.1 5\n")
    cases["irregular.txt"] = ("not on a regular grid", None)
    for name, (msg, sp) in cases.items():
        with pytest.raises(InputError) as ei:
            read(f / name, spacing=sp)
        assert name in str(ei.value), (name, str(ei.value))
        assert msg in str(ei.value), (name, str(ei.value))
        assert "\n" not in str(ei.value)
    for sp in (0, -1e-4, (1e-4, 0), "0,1e-4", "abc", float("nan")):
        with pytest.raises(InputError, match=r"ok\.npy.*spacing"):
            read(f / "ok.npy", spacing=sp)
    with pytest.raises(InputError, match=r"ok\.npy: unknown units 'inch'"):
        read(f / "ok.npy", spacing=1e-4, units="inch")
    with pytest.raises(InputError, match=r"is a directory"):
        read(f / "dir.npy" if (f / "dir.npy").mkdir() is None else None)


def test_registry_has_required_formats():
    for ext in (
        ".npy",
        ".npz",
        ".tif",
        ".tiff",
        ".txt",
        ".csv",
        ".asc",
        ".xyz",
        ".x3p",
        ".gwy",
        ".dat",
        ".plu",
        ".plux",
        ".sur",
        ".datx",
        ".vk4",
        ".opd",
        ".al3d",
    ):
        assert ext in READERS, ext


def test_geotiff_pixel_scale(tmp_path):
    import tifffile

    h = np.random.default_rng(9).random((5, 6))
    tifffile.imwrite(
        tmp_path / "geo.tif", h, metadata=None, extratags=[(33550, "d", 3, (0.002, 0.003, 0.0), True)]
    )
    m = read(tmp_path / "geo.tif")
    assert (m.dx_m, m.dy_m) == (0.002, 0.003)
    assert "ModelPixelScaleTag" in m.meta["spacing_from"]


def test_profile_in_npz_and_one_column_text(tmp_path):
    z = np.cos(np.arange(50) * 0.3)
    write(tmp_path / "p.npz", Profile(z, 1e-4))
    p = read(tmp_path / "p.npz")
    assert isinstance(p, Profile) and p.dx_m == 1e-4
    np.testing.assert_array_equal(p.heights_m, z)
    np.savetxt(tmp_path / "c.txt", z * 1e3)
    with pytest.raises(InputError, match=r"c.txt: no spacing"):
        read(tmp_path / "c.txt")
    c = read(tmp_path / "c.txt", spacing=1e-4, units="mm")
    np.testing.assert_allclose(c.heights_m, z, rtol=1e-12)


def test_xyz_units_apply_to_coordinates_and_heights(tmp_path):
    """--units names the unit of x, y and z of a point list without unit titles."""
    _h, pts = _xyz_points()
    pts = pts.copy()
    pts *= 1e6  # coordinates and heights written in um
    np.savetxt(tmp_path / "u.xyz", pts, fmt="%.9g")
    m = read(tmp_path / "u.xyz", units="um")
    np.savetxt(tmp_path / "u.xyz", pts * 1e-6, fmt="%.9g")
    ref = read(tmp_path / "u.xyz")
    assert (m.dx_m, m.dy_m) == pytest.approx((2e-4, 3e-4))
    assert (ref.dx_m, ref.dy_m) == pytest.approx((2e-4, 3e-4))
    np.testing.assert_allclose(m.heights_m, ref.heights_m, rtol=1e-8)


def test_npy_units_scaled_without_changing_the_file(tmp_path):
    """read_npy scales in place (one array, issue 14): float and integer files, any unit."""
    from roadscan.io import read

    f64 = np.arange(120.0).reshape(10, 12) - 30.5
    i16 = (np.arange(120) - 60).astype(np.int16).reshape(10, 12)
    for name, a in (("f.npy", f64), ("i.npy", i16)):
        np.save(tmp_path / name, a)
        for units, k in (("um", 1e-6), ("mm", 1e-3), ("m", 1.0)):
            hm = read(tmp_path / name, spacing=1e-5, units=units)
            assert hm.heights_m.dtype == np.float64
            np.testing.assert_array_equal(hm.heights_m, a.astype(np.float64) * k)
        np.testing.assert_array_equal(np.load(tmp_path / name), a)
