"""Fault suite, hostile-container family (issue 22): archives built to hurt a reader (a member
declaring 4e10 points, a deflate bomb, duplicate members in .npz and .x3p, a member named
``../../heights.npy``, a truncated archive, a pickled object array). Every case through the
CLI: exit code 2, one line naming the file, no traceback, nothing written outside the temporary
folder (no output folder, nothing extracted)."""

from __future__ import annotations

import io
import warnings
import zipfile

import numpy as np
import pytest
from fault_tools import assert_one_line_error, run_cli, snapshot


def _npy(arr):
    b = io.BytesIO()
    np.save(b, arr)
    return b.getvalue()


def _npz(path, members):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # zipfile: "Duplicate name"
        with zipfile.ZipFile(path, "w") as z:
            for name, data in members:
                z.writestr(name, data)
    return path


def _cases(d):
    h = np.random.default_rng(0).normal(size=(32, 32)) * 1e-4
    sp = [("dx.npy", _npy(np.float64(1e-4))), ("dy.npy", _npy(np.float64(1e-4)))]
    hdr = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        hdr, {"descr": "<f8", "fortran_order": False, "shape": (200000, 200000)}
    )
    cases = {
        "declared.npz": _npz(d / "declared.npz", [("heights.npy", hdr.getvalue() + b"\0" * 64)] + sp),
        "dup.npz": _npz(d / "dup.npz", [("heights.npy", _npy(h)), ("heights.npy", _npy(h[:16]))] + sp),
        "travel.npz": _npz(d / "travel.npz", [("../../heights.npy", _npy(h))] + sp),
    }
    np.savez_compressed(
        d / "deflate.npz", heights=np.zeros((2000, 2000)), dx=1e-4, dy=1e-4
    )  # 32 MB in ~40 kB
    cases["deflate.npz"] = d / "deflate.npz"
    np.save(d / "pickled.npy", np.array([{"a": 1}], dtype=object), allow_pickle=True)
    cases["pickled.npy"] = d / "pickled.npy"
    from roadscan.heightmap import HeightMap
    from roadscan.io import write

    write(d / "ok.x3p", HeightMap(h, 1e-4, 1e-4))
    with zipfile.ZipFile(d / "ok.x3p") as z:
        members = [(n, z.read(n)) for n in z.namelist()]
    cases["dup.x3p"] = _npz(d / "dup.x3p", members + [("main.xml", dict(members)["main.xml"])])
    (d / "truncated.x3p").write_bytes((d / "ok.x3p").read_bytes()[:300])
    cases["truncated.x3p"] = d / "truncated.x3p"
    (d / "ok.x3p").unlink()
    return cases


@pytest.mark.parametrize("command", ["analyse", "convert"])
def test_hostile_archives_are_one_line_input_errors(tmp_path, capsys, command):
    src = tmp_path / "in"
    src.mkdir()
    cases = _cases(src)
    before = snapshot(tmp_path)
    for name, path in cases.items():
        out = tmp_path / f"out_{name}"
        argv = (
            [command, path, "--max-pixels", 1_000_000, "--no-figures", "--no-friction", "--out", out]
            if command == "analyse"
            else [command, path, tmp_path / "c.x3p", "--max-pixels", 1_000_000]
        )
        rc, err = run_cli(capsys, argv)
        assert_one_line_error(rc, err, words=[name])
        assert snapshot(tmp_path) == before, name  # nothing written, nothing extracted
    assert not (tmp_path.parent / "heights.npy").exists()
