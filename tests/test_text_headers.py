"""Text files as people write them: units from every common header form, missing-value markers
as dropouts, decimal commas, a preamble of key: value lines; what cannot be known is refused in
one line naming the option that decides. Expected values come from the numbers written here
(metres = file number x unit), never from the reader."""

import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from roadscan.errors import InputError
from roadscan.io import read
from roadscan.io.text_table import column_units

M_PER = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "nm": 1e-9, "cm": 1e-2}
N = 300
DX_M = 5e-5  # 0.05 mm


def _truth():
    x = np.arange(N) * DX_M
    z = 3e-4 * np.sin(np.arange(N) * 0.37) + 1e-4 * np.cos(np.arange(N) * 1.3)
    return x, z


def _write(
    path, head, x_unit, z_unit, sep=",", decimal=".", missing=None, at=(7, 150), preamble=(), encoding="utf-8"
):
    x, z = _truth()
    xs, zs = x / M_PER[x_unit], z / M_PER[z_unit]
    lines = list(preamble) + ([head] if head is not None else [])
    for i in range(N):
        a, b = f"{xs[i]:.9g}", f"{zs[i]:.9g}"
        if decimal == ",":
            a, b = a.replace(".", ","), b.replace(".", ",")
        if missing is not None and i in at:
            b = missing
        lines.append(a + sep + b)
    path.write_text("\n".join(lines) + "\n", encoding=encoding)
    return path


# header form -> (x unit, z unit) it states
FORMS = [
    ("x_mm,z_mm", "mm", "mm"),
    ("x [mm],z [mm]", "mm", "mm"),
    ("x (mm),z (mm)", "mm", "mm"),
    ("x/mm,z/mm", "mm", "mm"),
    ("x_mm,Height (µm)", "mm", "um"),
    ("x_mm,z_um", "mm", "um"),
    ("x (mm),height[nm]", "mm", "nm"),
    ("x [m],z [mm]", "m", "mm"),
    ("x in mm,z in mm", "mm", "mm"),
    ("x (mm),z (μm)", "mm", "um"),
    ("x (mm),z (um)", "mm", "um"),
    ("distance (mm),z_um", "mm", "um"),
    ("X [MM],Z [UM]", "mm", "um"),
    ("x (micron),z (micron)", "um", "um"),
    ("x_mm,z_nm", "mm", "nm"),
    ("x (millimetres),z (micrometres)", "mm", "um"),
    ("x mm,z um", "mm", "um"),
    ("x (cm),z (mm)", "cm", "mm"),
    ('"x_mm","z_mm"', "mm", "mm"),
    ("x-mm,z-um", "mm", "um"),
    ("x [mm],z {um}", "mm", "um"),
]


@pytest.mark.parametrize("head, xu, zu", FORMS)
def test_header_forms_give_each_column_its_unit(tmp_path, head, xu, zu):
    _x, z = _truth()
    p = read(_write(tmp_path / "p.csv", head, xu, zu))
    assert p.dx_m == pytest.approx(DX_M, rel=1e-6)
    np.testing.assert_allclose(p.heights_m, z, rtol=1e-6, atol=1e-15)


@pytest.mark.parametrize(
    "sep, head",
    [
        (";", "x [mm];z [um]"),
        ("\t", "x (mm)\tz (um)"),
        (" ", "x (mm) z (um)"),
        (" ", "x_mm  z_um"),
        (" ", "x in mm z in um"),
    ],
)
def test_header_forms_with_other_separators(tmp_path, sep, head):
    _x, z = _truth()
    p = read(_write(tmp_path / "p.txt", head, "mm", "um", sep=sep))
    assert p.dx_m == pytest.approx(DX_M, rel=1e-6)
    np.testing.assert_allclose(p.heights_m, z, rtol=1e-6, atol=1e-15)


MARKERS = ["", "NaN", "nan", "NA", "N/A", "n/a", "-", "null", "NULL", "#N/A", "None", "--", "***", " "]


@pytest.mark.parametrize("marker", MARKERS)
@pytest.mark.parametrize("sep, decimal", [(",", "."), (";", ","), ("\t", ","), ("\t", ".")])
def test_missing_value_markers_are_dropouts(tmp_path, marker, sep, decimal):
    _x, z = _truth()
    head = sep.join(["x (mm)", "z (mm)"])
    p = read(
        _write(
            tmp_path / "p.csv",
            head,
            "mm",
            "mm",
            sep=sep,
            decimal=decimal,
            missing=marker,
            at=(0, 7, 150, N - 1),
        )
    )
    assert p.n == N
    assert list(np.flatnonzero(p.unmeasured)) == [0, 7, 150, N - 1]
    keep = ~p.unmeasured
    np.testing.assert_allclose(p.heights_m[keep], z[keep], rtol=1e-6, atol=1e-15)


def test_empty_field_in_a_matrix_is_a_dropout(tmp_path):
    (tmp_path / "hole.csv").write_text("1,2,3,4\n5,,7,8\n9,10,11,12\n")
    m = read(tmp_path / "hole.csv", spacing=1e-4, units="um")
    assert m.unmeasured.sum() == 1 and m.unmeasured[1, 1]
    assert m.heights_m[2, 3] == pytest.approx(12e-6)


def test_sentinels_far_from_the_heights_are_dropouts_with_a_warning(tmp_path):
    _x, _z = _truth()
    for s in ("-9999", "9999.0", "-99999", "1.70141e38"):
        p = read(_write(tmp_path / "p.csv", "x_mm,z_mm", "mm", "mm", missing=s))
        assert list(np.flatnonzero(p.unmeasured)) == [7, 150], s
        notes = [str(w) for w in p.meta["read_warnings"]]
        assert any("read as dropouts" in w for w in notes), notes


def test_a_sentinel_value_within_reach_of_the_heights_is_a_height(tmp_path):
    """Heights in nm spanning +-4000: -9999 nm is 1.25 spreads away, a real (deep) point."""
    _x, _z = _truth()
    p = _write(tmp_path / "p.csv", "x_mm,z_nm", "mm", "nm", missing="-9999")
    prof = read(p)
    assert not prof.unmeasured.any()
    assert prof.heights_m[7] == pytest.approx(-9999e-9)


def test_declared_nodata_in_a_preamble(tmp_path):
    _x, _z = _truth()
    p = _write(
        tmp_path / "p.txt",
        "x (mm);z (um)",
        "mm",
        "um",
        sep=";",
        decimal=",",
        missing="-1",
        preamble=["Instrument: LS-40", "NoData = -1"],
    )
    prof = read(p)
    assert list(np.flatnonzero(prof.unmeasured)) == [7, 150]
    assert prof.meta["preamble"]["Instrument"] == "LS-40"


def test_preamble_states_units_and_spacing_of_a_heights_column(tmp_path):
    _x, z = _truth()
    text = "Operator: A. Smith\nSpacing: 0.05 mm\nUnits: um\n" + "\n".join(f"{v * 1e6:.6f}" for v in z)
    (tmp_path / "h.txt").write_text(text)
    prof = read(tmp_path / "h.txt")
    assert prof.dx_m == pytest.approx(DX_M)
    np.testing.assert_allclose(prof.heights_m, z, atol=1e-12)
    # the spacing's unit in the key, heights unit for the heights only, decimal commas
    text = "Step (mm) = 0,05\nHeight unit: nm\n" + "\n".join(
        f"{v * 1e9:.3f}".replace(".", ",") + ";" for v in z
    )
    (tmp_path / "k.csv").write_text(text)
    prof = read(tmp_path / "k.csv")
    assert prof.dx_m == pytest.approx(DX_M)
    np.testing.assert_allclose(prof.heights_m, z, atol=1e-12)


def test_matrix_with_preamble_and_single_title(tmp_path):
    h = np.random.default_rng(2).normal(size=(12, 9)) * 1e-4
    rows = "\n".join(";".join(f"{v * 1e6:.4f}".replace(".", ",") for v in r) for r in h)
    (tmp_path / "m.csv").write_text("Pitch: 0,1 mm\nHeight (µm)\n" + rows + "\n")
    m = read(tmp_path / "m.csv")
    assert (m.dx_m, m.dy_m) == pytest.approx((1e-4, 1e-4))
    np.testing.assert_allclose(m.heights_m, h, atol=1e-10)


def test_xyz_map_with_units_in_different_forms_and_dropouts(tmp_path):
    rng = np.random.default_rng(4)
    h = rng.normal(size=(20, 25)) * 2e-4
    yy, xx = np.mgrid[0:20, 0:25]
    lines = ["x/mm;y [mm];z_um"]
    for i, (a, b, c) in enumerate(zip(xx.ravel() * 0.1, yy.ravel() * 0.2, h.ravel() * 1e6)):
        lines.append(f"{a:.3f};{b:.3f};" + ("NA" if i in (3, 40) else f"{c:.4f}"))
    (tmp_path / "p.csv").write_text("\n".join(lines).replace(".", ",") + "\n")
    m = read(tmp_path / "p.csv")
    assert (m.dx_m, m.dy_m) == pytest.approx((1e-4, 2e-4))
    assert m.unmeasured.ravel()[[3, 40]].all() and m.unmeasured.sum() == 2
    ok = ~m.unmeasured
    np.testing.assert_allclose(m.heights_m[ok], h[ok], atol=1e-9)


def test_pandas_index_column_and_units_row(tmp_path):
    x, z = _truth()
    lines = [",x_mm,z_um"] + [f"{i},{a * 1e3:.6f},{b * 1e6:.4f}" for i, (a, b) in enumerate(zip(x, z))]
    (tmp_path / "pd.csv").write_text("\n".join(lines) + "\n")
    p = read(tmp_path / "pd.csv")
    assert p.dx_m == pytest.approx(DX_M) and p.meta["index_column_dropped"] == "(untitled)"
    np.testing.assert_allclose(p.heights_m, z, atol=1e-10)
    lines = ["distance\theight", "mm\tum"] + [f"{a * 1e3:.6f}\t{b * 1e6:.4f}" for a, b in zip(x, z)]
    (tmp_path / "ur.txt").write_text("\n".join(lines) + "\n")
    p = read(tmp_path / "ur.txt")
    assert p.dx_m == pytest.approx(DX_M)
    np.testing.assert_allclose(p.heights_m, z, atol=1e-10)


def test_utf16_spreadsheet_text(tmp_path):
    _x, z = _truth()
    p = _write(tmp_path / "u.txt", "x (mm)\tz (µm)", "mm", "um", sep="\t", decimal=",", encoding="utf-16")
    prof = read(p)
    np.testing.assert_allclose(prof.heights_m, z, rtol=1e-6, atol=1e-15)


# refusals: (header, preamble, what the message must name)
REFUSED = [
    ("x (mm),z (a.u.)", [], "'units'"),  # a token that is no length unit
    ("x_mm,z [counts]", [], "'units'"),
    ("x_mm,z_in", [], "'units'"),  # inches: not converted, not guessed
    ("x (mm),z", [], "'units'"),  # heights' unit not stated
    ("x,z (mm)", [], "'x_units'"),  # coordinates' unit not stated
    ("x (px),z (mm)", [], "'x_units'"),
    ("x (mm),z (mm)", ["Units: um"], "preamble"),  # title and preamble disagree
    ("x (mm),z (mm)", ["Z scale: 0.001"], "scale"),  # a scale roadscan does not apply
    ("x (mm),z (mm)", ["Spacing: 0.1 mm"], "preamble"),  # the x column steps 0.05 mm
]


@pytest.mark.parametrize("head, preamble, word", REFUSED)
def test_what_cannot_be_known_is_refused_naming_what_decides(tmp_path, head, preamble, word):
    p = _write(tmp_path / "p.csv", head, "mm", "mm", preamble=preamble)
    with pytest.raises(InputError) as e:
        read(p)
    msg = str(e.value)
    assert "\n" not in msg and str(p) in msg and word in msg, msg
    if "'units'" in word or "x_units" in word:
        assert head in msg, msg  # what was found is quoted


def test_unknown_token_decided_by_the_flag(tmp_path):
    _x, z = _truth()
    p = _write(tmp_path / "p.csv", "x (mm),z (a.u.)", "mm", "um")
    prof = read(p, units="um")
    np.testing.assert_allclose(prof.heights_m, z, rtol=1e-6, atol=1e-15)
    assert prof.meta["title_unit_ignored"] == {"z (a.u.)": "a.u."}


def test_unitless_titles_are_quoted_in_the_refusal(tmp_path):
    p = _write(tmp_path / "p.csv", "distance,height", "mm", "mm")
    with pytest.raises(InputError, match=r"title line 'distance,height' states no units.*'units' mm"):
        read(p)
    prof = read(p, units="mm")
    assert prof.dx_m == pytest.approx(DX_M, rel=1e-6)


def test_cli_names_the_flag(tmp_path, capsys):
    from fault_tools import assert_one_line_error, run_cli

    p = _write(tmp_path / "p.csv", "x (mm),z", "mm", "mm")
    rc, err = run_cli(capsys, ["analyse", p, "--out", tmp_path / "out", "--no-friction", "--no-figures"])
    assert_one_line_error(rc, err, words=[str(p), "--units", "x (mm),z"])


def test_column_units_reads_the_new_forms():
    assert column_units("x_mm,z_um") == ["mm", "um"]
    assert column_units("x [m]; height[nm]") == ["m", "nm"]
    assert column_units("x,z") is None and column_units("x (mm),z") is None


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    form=st.sampled_from(["{n}_{u}", "{n} [{u}]", "{n} ({u})", "{n}/{u}", "{n} in {u}", "{n}[{u}]"]),
    xu=st.sampled_from(["m", "mm", "um"]),
    zu=st.sampled_from(["mm", "um", "nm", "µm", "μm"]),
    marker=st.sampled_from(["", "NaN", "NA", "N/A", "-", "null", "#N/A", "nan"]),
    sep_dec=st.sampled_from([(",", "."), (";", ","), ("\t", "."), ("\t", ","), (";", ".")]),
    seed=st.integers(0, 10_000),
)
def test_round_trip_in_random_forms(tmp_path, form, xu, zu, marker, sep_dec, seed):
    """A profile written in a random header form, units, marker and separator reads back in
    metres: spacing, heights and the dropouts where they were written."""
    sep, decimal = sep_dec
    rng = np.random.default_rng(seed)
    n = int(rng.integers(50, 400))
    dx = float(rng.choice([1e-5, 5e-5, 2.5e-4]))
    z = rng.normal(size=n) * float(rng.choice([1e-6, 1e-4, 1e-3]))
    holes = set(rng.choice(n, size=3, replace=False).tolist())
    key = {"µm": "um", "μm": "um"}.get(zu, zu)
    head = sep.join([form.format(n="x", u=xu), form.format(n="z", u=zu)])
    lines = [head]
    for i in range(n):
        a, b = f"{i * dx / M_PER[xu]:.10g}", f"{z[i] / M_PER[key]:.10g}"
        if decimal == ",":
            a, b = a.replace(".", ","), b.replace(".", ",")
        lines.append(a + sep + (marker if i in holes else b))
    path = tmp_path / f"r{seed}.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    p = read(path)
    assert p.dx_m == pytest.approx(dx, rel=1e-6)
    assert set(np.flatnonzero(p.unmeasured).tolist()) == holes
    ok = ~p.unmeasured
    np.testing.assert_allclose(p.heights_m[ok], z[ok], rtol=1e-8, atol=1e-18)
    assert re.fullmatch(r"[a-z]+,[a-z]+", p.meta["units"])
