"""CAPTIF stationary laser profiler files (real data, read as they are)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from roadscan.errors import InputError
from roadscan.heightmap import Profile
from roadscan.io import read

DATA = Path("/work/shared/data/profiles/captif")
FILES = sorted(DATA.glob("*.dat")) if DATA.is_dir() else []

pytestmark = pytest.mark.skipif(not FILES, reason="shared CAPTIF data not present on this machine")


def _raw(path):
    """Independent parse with numpy: (distance mm, depth mm) rows, as in the file."""
    a = np.genfromtxt(path, skip_header=11, delimiter="\t")
    return a[:, 1], a[:, 2]


@pytest.fixture(scope="module")
def profiles():
    return {p.name: read(p) for p in FILES}


def test_three_files_present():
    assert len(FILES) == 3


def test_counts_spacing_dropouts(profiles):
    for name, prof in profiles.items():
        d, z = _raw(DATA / name)
        assert isinstance(prof, Profile)
        assert 50_000 <= prof.n <= 52_000, (name, prof.n)
        assert prof.n == d.size  # every grid node has a row in these files
        # nominal 0.0375 mm; the fitted step is 0.037489 mm (0.03 % short of nominal)
        assert prof.dx_m == pytest.approx(0.0375e-3, rel=1e-3), prof.dx_m
        assert abs(prof.dx_m * (prof.n - 1) - (d.max() - d.min()) * 1e-3) < 1e-6
        frac = 1 - prof.measured_fraction
        assert 0.0855 <= frac <= 0.1055, (name, frac)  # "8.6 to 10.5 %", rounded
        assert prof.unmeasured.sum() == np.isnan(z).sum()
        assert prof.meta["header"]["Road Name"] == "CAPTIF"
        assert prof.meta["units"] == "mm"


def test_heights_mm_to_m_in_distance_order(profiles):
    for name, prof in profiles.items():
        d, z = _raw(DATA / name)
        order = np.argsort(d, kind="stable")
        np.testing.assert_allclose(prof.heights_m, z[order] * 1e-3, rtol=0, atol=1e-12, equal_nan=True)


def test_reference_plates_read_plus_47mm(profiles):
    """Heights are positive up: the plates at both ends stand about 47 mm above the road."""
    for name, prof in profiles.items():
        x = prof.x_m()
        h = prof.heights_m
        ends = [(x < 0.1), (x > x[-1] - 0.1)]
        middle = (x > 0.2) & (x < x[-1] - 0.2)
        for sel in ends:
            top = np.nanpercentile(h[sel], 99)
            assert 0.044 < top < 0.050, (name, top)
        assert np.nanmedian(h[middle]) < 0.01
        assert np.nanmedian(h[middle]) > -0.01


def test_point_numbers_not_monotonic_but_handled(tmp_path):
    src = FILES[0].read_bytes()
    assert b"\r\n" in src  # station_0 has CRLF line endings
    prof = read(FILES[0])
    # swap two data rows and drop one: sorting restores order, the gap becomes unmeasured
    lines = src.decode().split("\r\n")
    k = next(i for i, ln in enumerate(lines) if ln.startswith("Data Point No:"))
    body = lines[k + 1 :]
    body[100], body[101] = body[101], body[100]
    del body[500]
    (tmp_path / "cut.dat").write_text("\n".join(lines[: k + 1] + body))
    cut = read(tmp_path / "cut.dat")
    assert cut.n == prof.n and cut.unmeasured[500] and not prof.unmeasured[500]
    ok = ~cut.unmeasured
    np.testing.assert_array_equal(cut.heights_m[ok], prof.heights_m[ok])


def test_captif_errors(tmp_path):
    good = FILES[1].read_text().splitlines()
    k = next(i for i, ln in enumerate(good) if ln.startswith("*****DATA*****"))
    (tmp_path / "nodata.dat").write_text("\n".join(good[: k + 2]) + "\n")
    with pytest.raises(InputError, match=r"nodata\.dat: no data rows"):
        read(tmp_path / "nodata.dat")
    bad = list(good)
    bad[k + 30] = "30.000\tabc\t1.0"
    (tmp_path / "bad.dat").write_text("\n".join(bad))
    with pytest.raises(InputError, match=r"bad\.dat: non-numeric value in data row 29"):
        read(tmp_path / "bad.dat")
    cols = list(good)
    cols[k + 1] = "a\tb\tc"
    (tmp_path / "cols.dat").write_text("\n".join(cols))
    with pytest.raises(InputError, match=r"cols\.dat: unexpected CAPTIF columns"):
        read(tmp_path / "cols.dat")
