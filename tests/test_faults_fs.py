"""Fault suite, file-system family (issue 22): read-only and file-occupied outputs, a full disk,
symbolic-link loops and links as outputs, folders and unreadable files as inputs. Every case:
exit code 2 (or 0 where the run is legitimate), one line on stderr naming the file, no
traceback, no hidden temporary left, the input's bytes unchanged."""

from __future__ import annotations

import builtins
import errno
import os
import tempfile

import numpy as np
import pytest
from fault_tools import (
    DX,
    assert_one_line_error,
    digest,
    disk_full_for,
    hidden_leftovers,
    run_cli,
    small_scan,
    snapshot,
)

FAST = ["--spacing", DX, "--no-figures", "--no-friction"]


@pytest.fixture
def scan(tmp_path):
    return small_scan(tmp_path / "scan.npy")


def _deny(monkeypatch, exc_errno, where):
    """Make creating anything inside ``where`` fail as a read-only or full file system would
    (the tests may run as root, for whom chmod does not deny)."""
    where = os.path.realpath(where)
    real_mkdtemp, real_mkstemp, real_mkdir = tempfile.mkdtemp, tempfile.mkstemp, os.mkdir

    def inside(d):
        return os.path.realpath(d or ".").startswith(where)

    def mkdtemp(*a, dir=None, **k):
        if inside(dir):
            raise OSError(exc_errno, os.strerror(exc_errno), dir)
        return real_mkdtemp(*a, dir=dir, **k)

    def mkstemp(*a, dir=None, **k):
        if inside(dir):
            raise OSError(exc_errno, os.strerror(exc_errno), dir)
        return real_mkstemp(*a, dir=dir, **k)

    def mkdir(p, *a, **k):
        if inside(os.path.dirname(os.fspath(p))):
            raise OSError(exc_errno, os.strerror(exc_errno), os.fspath(p))
        return real_mkdir(p, *a, **k)

    monkeypatch.setattr(tempfile, "mkdtemp", mkdtemp)
    monkeypatch.setattr(tempfile, "mkstemp", mkstemp)
    monkeypatch.setattr(os, "mkdir", mkdir)


@pytest.mark.parametrize("code", [errno.EROFS, errno.EACCES])
def test_read_only_output_folder(tmp_path, scan, capsys, monkeypatch, code):
    ro = tmp_path / "ro"
    ro.mkdir()
    before = digest(scan)
    _deny(monkeypatch, code, ro)
    for argv in (
        ["analyse", scan, "--out", ro / "a", *FAST],
        ["convert", scan, ro / "c.x3p", "--spacing", DX],
        ["synth", "--nx", 32, "--out", ro / "s.npy"],
        [
            "friction",
            "--self-affine",
            "H=0.8,h0=2e-4,q0=300,q1=3e4",
            "--velocities",
            "1e-2,1",
            "--out",
            ro / "mu.csv",
        ],
    ):
        rc, err = run_cli(capsys, argv)
        assert_one_line_error(rc, err, words=[str(ro)])
    assert list(ro.iterdir()) == [] and digest(scan) == before


def test_output_that_is_a_file(tmp_path, scan, capsys):
    taken = tmp_path / "taken"
    taken.write_text("mine\n")
    for argv in (
        ["analyse", scan, "--out", taken, *FAST],
        ["analyse", scan, "--out", taken / "below", *FAST],
        ["rain-fill", scan, "--spacing", DX, "--out", taken],
        ["batch", scan, "--spacing", DX, "--out", taken],
        [
            "stitch",
            scan,
            scan,
            "--grid",
            "1x2",
            "--overlap",
            "0.2",
            "--spacing",
            DX,
            "--out",
            taken / "m.x3p",
        ],
    ):
        rc, err = run_cli(capsys, argv)
        assert_one_line_error(rc, err, words=["taken"])
    assert taken.read_text() == "mine\n"
    assert hidden_leftovers(tmp_path) == []


def test_full_disk_names_the_file(tmp_path, scan, capsys, monkeypatch):
    """write() raising ENOSPC (no file name in the exception): the message names the output."""
    before = digest(scan)
    real_save = np.save

    def full(file, *a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(np, "save", full)
    for argv, name in (
        (["convert", scan, tmp_path / "c.npy", "--spacing", DX], "c.npy"),
        (["rain-fill", scan, "--spacing", DX, "--out", tmp_path / "rf"], "wet.npy"),
        (["synth", "--nx", 32, "--out", tmp_path / "s.npy"], "s.npy"),
    ):
        rc, err = run_cli(capsys, argv)
        assert_one_line_error(rc, err, words=["No space left on device", name])
        assert ".roadscan-tmp" not in err  # the final name, not the hidden one
    monkeypatch.setattr(np, "save", real_save)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scan.npy"]
    assert digest(scan) == before


def test_full_disk_in_a_plain_write_of_an_output_folder(tmp_path, scan, capsys, monkeypatch):
    """ENOSPC from a text write inside analyse's output folder: the folder is named, the
    temporary folder is gone."""
    with disk_full_for(monkeypatch, ".json"):
        rc, err = run_cli(capsys, ["analyse", scan, "--out", tmp_path / "out", *FAST])
    assert_one_line_error(rc, err, words=["No space left on device", "out"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scan.npy"]


def test_symlink_loop_and_dangling_link_inputs(tmp_path, capsys):
    a, b = tmp_path / "a.npy", tmp_path / "b.npy"
    os.symlink(b, a)
    os.symlink(a, b)
    gone = tmp_path / "gone.npy"
    os.symlink(tmp_path / "nowhere.npy", gone)
    psd_loop = tmp_path / "p.csv"
    os.symlink(psd_loop, psd_loop)
    for argv, word in (
        (["analyse", a, "--out", tmp_path / "o", *FAST], "loop"),
        (["convert", a, tmp_path / "c.x3p"], "loop"),
        (["rain-fill", a, "--out", tmp_path / "o"], "loop"),
        (["compare", a, gone, "--out", tmp_path / "o"], "a.npy"),
        (["analyse", gone, "--out", tmp_path / "o", *FAST], "broken"),
        (["friction", "--psd", psd_loop, "--out", tmp_path / "mu.csv"], "loop"),
        (["batch", a, "--out", tmp_path / "o"], "loop"),
    ):
        rc, err = run_cli(capsys, argv)
        assert_one_line_error(rc, err, words=[word])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.npy", "b.npy", "gone.npy", "p.csv"]


def test_symlink_loop_as_output(tmp_path, scan, capsys):
    loop = tmp_path / "loop"
    os.symlink(loop, loop)
    for argv in (
        ["analyse", scan, "--out", loop, *FAST],
        ["convert", scan, tmp_path / "loop", "--spacing", DX],
    ):
        rc, err = run_cli(capsys, argv)
        assert_one_line_error(rc, err, words=["loop"])
    assert os.path.islink(loop)


def test_output_through_a_symlink_writes_where_it_points(tmp_path, scan, capsys):
    """A link to a folder: the folder it points to gets the outputs, the link stays a link,
    nothing hidden is left (before: a hidden symlink and the link replaced by a folder)."""
    real = tmp_path / "real"
    real.mkdir()
    link = tmp_path / "link"
    os.symlink(real, link)
    for _ in range(2):  # a new set, then a replaced one
        rc, err = run_cli(capsys, ["analyse", scan, "--out", link, *FAST])
        assert rc == 0, err
        assert os.path.islink(link) and os.readlink(link) == str(real)
        assert (real / "summary.json").is_file()
        assert sorted(p.name for p in tmp_path.iterdir()) == ["link", "real", "scan.npy"]
    # a link to a file: convert writes the file it points to
    target = tmp_path / "real" / "t.npz"
    flink = tmp_path / "flink.npz"
    os.symlink(target, flink)
    rc, err = run_cli(capsys, ["convert", scan, flink, "--spacing", DX])
    assert rc == 0, err
    assert os.path.islink(flink) and target.is_file()
    got = np.load(target)
    assert np.array_equal(got["heights"], np.load(scan))
    assert hidden_leftovers(tmp_path) == []


def test_folder_given_as_input(tmp_path, capsys):
    d = tmp_path / "folder.npy"
    d.mkdir()
    for argv in (
        ["analyse", d, "--out", tmp_path / "o", *FAST],
        ["convert", d, tmp_path / "c.x3p"],
        ["rain-fill", d, "--out", tmp_path / "o"],
        ["friction", "--psd", d, "--out", tmp_path / "m.csv"],
        ["rubber", "master", d, "--reference-temperature", 20, "--out", tmp_path / "r.toml"],
    ):
        rc, err = run_cli(capsys, argv)
        assert_one_line_error(rc, err, words=["folder.npy"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["folder.npy"]


def test_unreadable_input(tmp_path, scan, capsys, monkeypatch):
    """Permission denied on the input (simulated: tests may run as root): one line, exit 2."""
    real_open = builtins.open
    denied = os.path.realpath(scan)

    def no_read(file, *a, **k):
        if isinstance(file, (str, os.PathLike)) and os.path.realpath(file) == denied:
            raise PermissionError(errno.EACCES, "Permission denied", os.fspath(file))
        return real_open(file, *a, **k)

    monkeypatch.setattr(builtins, "open", no_read)
    for argv in (
        ["analyse", scan, "--out", tmp_path / "o", *FAST],
        ["convert", scan, tmp_path / "c.x3p", "--spacing", DX],
    ):
        rc, err = run_cli(capsys, argv)
        assert_one_line_error(rc, err, words=["scan.npy"])
    monkeypatch.setattr(builtins, "open", real_open)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scan.npy"]


def test_snapshot_helper_sees_changes(tmp_path):
    """The suite's own check: a changed byte and a new hidden file are seen."""
    f = tmp_path / "x"
    f.write_bytes(b"a")
    s = snapshot(tmp_path)
    f.write_bytes(b"b")
    assert snapshot(tmp_path) != s
    (tmp_path / ".x.roadscan-tmp-1").mkdir()
    assert hidden_leftovers(tmp_path)


def test_devices_and_pipes_are_not_read(tmp_path, capsys):
    """/dev/zero never ends and a FIFO blocks until written: both refused before reading."""
    fifo = tmp_path / "pipe.npy"
    os.mkfifo(fifo)
    for src in ("/dev/zero", fifo):
        for argv in (
            ["analyse", src, "--out", tmp_path / "o", *FAST],
            ["convert", src, tmp_path / "c.x3p"],
            ["friction", "--psd", src, "--out", tmp_path / "mu.csv"],
            ["rubber", "master", src, "--reference-temperature", 20, "--out", tmp_path / "r.toml"],
        ):
            rc, err = run_cli(capsys, argv)
            assert_one_line_error(rc, err, words=[str(src), "not a file"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe.npy"]


def test_full_disk_outside_the_atomic_writers_names_the_output(tmp_path, scan, capsys, monkeypatch):
    """An ENOSPC without a file name raised anywhere (here the writer itself): the one line
    names the command's output."""
    import roadscan.io

    def full(*a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(roadscan.io, "write", full)
    rc, err = run_cli(capsys, ["convert", scan, tmp_path / "c.x3p", "--spacing", DX])
    assert_one_line_error(rc, err, words=["No space left on device", "c.x3p"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scan.npy"]


def test_earlier_output_folder_with_a_users_file_is_not_replaced(tmp_path, scan, capsys):
    """An earlier run's folder where the user put notes: replacing the folder as a whole would
    lose them, so it is refused; without them the folder is replaced."""
    out = tmp_path / "out"
    assert run_cli(capsys, ["analyse", scan, "--out", out, *FAST])[0] == 0
    (out / "notes.txt").write_text("field log\n")
    before = snapshot(tmp_path)
    rc, err = run_cli(capsys, ["analyse", scan, "--out", out, *FAST])
    assert_one_line_error(rc, err, words=["notes.txt"])
    assert snapshot(tmp_path) == before
    (out / "notes.txt").unlink()
    assert run_cli(capsys, ["analyse", scan, "--out", out, *FAST])[0] == 0
