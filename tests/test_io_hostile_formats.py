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
H = RNG.normal(size=(6, 5)) * 1e-4          # heights [m], 17 significant digits in the text


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
    text = ("# Width: 5,00 mm\n# Height: 6,00 mm\n# Value units: m\n"
            + "\n".join("\t".join(_comma(v) for v in r) for r in H))
    m = read(_write(tmp_path, "g.txt", text))
    assert (m.dx_m, m.dy_m) == (pytest.approx(1e-3), pytest.approx(1e-3))
    np.testing.assert_array_equal(m.heights_m, H)


@pytest.mark.parametrize("line, word", [
    ("1.234,5;2;3;4;5", "thousands"),
    ("1,234,567;2;3;4;5", "thousands"),
    ("1,234.5 2 3 4 5", "thousands"),
    ("1 234,5;2;3;4;5", "thousands"),
    ("1,5;2.5;3;4;5", "both '.' and ','"),
    ("1,5, 2,5, 3,5, 4,5", "ambiguous"),
])
def test_thousands_and_ambiguous_commas_refused(tmp_path, line, word):
    p = _write(tmp_path, "bad.csv", (line + "\n") * 6)
    with pytest.raises(InputError) as ei:
        read(p, spacing=1e-4)
    msg = str(ei.value)
    assert word in msg and "bad.csv" in msg and "\n" not in msg
