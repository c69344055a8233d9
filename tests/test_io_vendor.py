"""Vendor formats through the optional surfalize extra, tested with files surfalize writes."""
from __future__ import annotations

import builtins
import sys
import warnings

import numpy as np
import pytest

from roadscan.errors import InputError
from roadscan.io import read


def test_missing_extra_gives_clear_error(tmp_path, monkeypatch):
    (tmp_path / "scan.plux").write_bytes(b"PK\x03\x04 not really")
    real_import = builtins.__import__

    def no_surfalize(name, *args, **kwargs):
        if name == "surfalize" or name.startswith("surfalize."):
            raise ImportError("No module named 'surfalize'")
        return real_import(name, *args, **kwargs)

    for mod in [m for m in sys.modules if m == "surfalize" or m.startswith("surfalize.")]:
        monkeypatch.delitem(sys.modules, mod)
    monkeypatch.setattr(builtins, "__import__", no_surfalize)
    with pytest.raises(InputError) as ei:
        read(tmp_path / "scan.plux")
    assert str(ei.value) == (f"{tmp_path / 'scan.plux'}: reading .plux needs the optional extra: "
                             "pip install 'roadscan[vendor]'")


surfalize = pytest.importorskip("surfalize")


def _surface(ny=24, nx=31, seed=0):
    rng = np.random.default_rng(seed)
    h_um = rng.normal(scale=50.0, size=(ny, nx))
    h_um[5, 7] = np.nan
    return h_um


@pytest.mark.parametrize("ext", [".sur", ".sdf", ".sflz", ".tmd", ".al3d"])
def test_files_written_by_surfalize(tmp_path, ext):
    h_um = _surface()
    step_um = 2.5
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        surfalize.Surface(h_um, step_um, step_um).save(tmp_path / f"s{ext}")
    m = read(tmp_path / f"s{ext}", units="mm")  # the file has units: `units` is ignored
    assert m.dx_m == pytest.approx(2.5e-6, rel=1e-9) and m.dy_m == pytest.approx(2.5e-6, rel=1e-9)
    assert m.shape == h_um.shape
    np.testing.assert_array_equal(m.unmeasured, np.isnan(h_um))
    # integer-coded formats quantise: 1e-6 of the range is far below anything that matters
    scale = np.nanmax(np.abs(h_um)) * 1e-6
    np.testing.assert_allclose(m.heights_m, h_um * 1e-6, rtol=0, atol=1e-6 * scale, equal_nan=True)
    assert m.meta["reader"] == "surfalize" and m.meta["units_ignored"] == "mm"


def test_unsupported_vendor_extension_and_garbage(tmp_path):
    (tmp_path / "z.datx").write_bytes(b"\x89HDF garbage")
    with pytest.raises(InputError, match=r"z\.datx: surfalize .*cannot read \.datx"):
        read(tmp_path / "z.datx")
    (tmp_path / "g.plu").write_bytes(b"garbage" * 10)
    with pytest.raises(InputError, match=r"g\.plu: cannot read"):
        read(tmp_path / "g.plu")
    # a .dat without the CAPTIF marker goes to surfalize, which refuses it with a clear error
    (tmp_path / "o.dat").write_text("1 2 3\n4 5 6\n")
    with pytest.raises(InputError, match=r"o\.dat"):
        read(tmp_path / "o.dat")
