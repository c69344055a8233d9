"""Fault suite, adversarial-user findings of the issue-22 QA pass (plausible-but-wrong inputs
that went through, or went wrong, after the issue-22 work). Each case: exit 2, one line naming
the file and the problem, no traceback, inputs unchanged, nothing hidden left."""

from __future__ import annotations

import numpy as np
from conftest import fourier_surface
from fault_tools import assert_one_line_error, digest, disk_full_for, hidden_leftovers, run_cli


def test_decimal_commas_that_also_separate_fields_are_refused(tmp_path, capsys):
    """A mm map written with decimal commas AND commas between fields (``0,1609,-0,0056``) has
    no '.' anywhere: read as twice the columns it gave a 40 x 80 map and exit 0 with --units um.
    The fields '-0' and '0056' (no integer writer makes them) show the commas are decimal."""
    z = fourier_surface(40, 1e-4, 0.8, 2e-4, seed=1) * 1e3
    f = tmp_path / "dc_comma.csv"
    f.write_text("\n".join(",".join(f"{v:.4f}".replace(".", ",") for v in row) for row in z) + "\n")
    before = digest(f)
    rc, err = run_cli(
        capsys,
        [
            "analyse",
            f,
            "--spacing",
            "1e-4",
            "--units",
            "um",
            "--no-figures",
            "--no-friction",
            "--out",
            tmp_path / "o",
        ],
    )
    assert_one_line_error(rc, err, words=[str(f), "decimal comma"])
    assert digest(f) == before and not (tmp_path / "o").exists() and hidden_leftovers(tmp_path) == []


def test_integer_comma_table_still_reads(tmp_path, capsys):
    """The refusal above does not touch a comma-separated integer map (nm), which has no '.'."""
    z = np.rint(fourier_surface(32, 1e-4, 0.8, 2e-4, seed=2) * 1e9).astype(np.int64)
    f = tmp_path / "int_nm.csv"
    f.write_text("\n".join(",".join(str(v) for v in row) for row in z) + "\n")
    from roadscan.io import read

    s = read(f, spacing=1e-4, units="nm")
    assert s.heights_m.shape == (32, 32)
    assert np.allclose(s.heights_m, z * 1e-9)


def test_small_csv_with_decimal_commas_and_comma_separators_is_refused(tmp_path, capsys):
    """psd.csv exported with decimal commas ('110,103893,5,687e-15' under 'q_per_m,C_m4') was
    read as q = 110, C = 103893 and refused only as 'mu reaches 1e12 ... check the PSD', naming
    no file; the same rows under a measured mu(v) header were 'not positive'. Now a data row with
    more values than the header names is one line naming the file."""
    from conftest import ROOT

    text = (ROOT / "sample_scans" / "asphalt_psd.csv").read_text()
    f = tmp_path / "psd.csv"
    f.write_text(
        "\n".join(
            line if k == 0 else line.replace(",", ";").replace(".", ",").replace(";", ",")
            for k, line in enumerate(text.splitlines())
        )
        + "\n"
    )
    before = digest(f)
    rc, err = run_cli(
        capsys, ["friction", "--psd", f, "--velocities", "1e-2,1", "--out", tmp_path / "mu.csv"]
    )
    assert_one_line_error(rc, err, words=[str(f), "decimal commas", "header names 2"])
    assert digest(f) == before and not (tmp_path / "mu.csv").exists() and hidden_leftovers(tmp_path) == []
    # a trailing comma (an empty last field) is not a stray value: still read
    f.write_text("\n".join(line + "," for line in text.splitlines()) + "\n")
    rc, err = run_cli(
        capsys, ["friction", "--psd", f, "--velocities", "1e-2,1", "--out", tmp_path / "mu.csv"]
    )
    assert rc == 0, err


def test_full_disk_in_a_file_set_names_the_file_not_a_folder_of_its_name(tmp_path, capsys, monkeypatch):
    """friction --out mu.csv writes mu.csv and its summary through a hidden folder named after
    mu.csv; a full disk was reported as 'mu.csv/mu.csv: No space left on device' (and rubber
    master's as 'r.toml/r_master.csv'), a path that never exists. Now the file's real place."""
    from conftest import ROOT

    out = tmp_path / "mu.csv"
    with disk_full_for(monkeypatch, ".csv"):
        rc, err = run_cli(
            capsys,
            [
                "friction",
                "--psd",
                ROOT / "sample_scans" / "asphalt_psd.csv",
                "--velocities",
                "1e-2,1",
                "--out",
                out,
            ],
        )
    assert_one_line_error(rc, err, words=["No space left on device", f"{out}:"])
    assert f"{out}/" not in err
    assert list(tmp_path.iterdir()) == []


def test_integers_grouped_by_one_thousands_separator_are_refused(tmp_path, capsys):
    """A nm map written as grouped integers ('160,878' beside '-715', tab-separated; or
    '160.878' with ';') was read as decimals: rms 0.198 um instead of 0.198 mm, exit 0, and the
    units check passed (0.2 um at 100 um spacing is plausible). Now one line naming the file."""
    z = fourier_surface(40, 1e-4, 0.8, 2e-4, seed=1) * 1e9
    for name, sep, group in (("tab.txt", "\t", ","), ("semi.csv", ";", "."), ("space.txt", " ", ",")):
        f = tmp_path / name
        f.write_text("\n".join(sep.join(f"{v:,.0f}".replace(",", group) for v in row) for row in z) + "\n")
        rc, err = run_cli(
            capsys,
            [
                "analyse",
                f,
                "--spacing",
                "1e-4",
                "--units",
                "nm",
                "--no-figures",
                "--no-friction",
                "--out",
                tmp_path / "o",
            ],
        )
        assert_one_line_error(rc, err, words=[str(f), "thousands"])
    assert not (tmp_path / "o").exists() and hidden_leftovers(tmp_path) == []


def test_three_decimal_exports_still_read(tmp_path):
    """Not refused: '%.3f' decimal-comma and dot maps (every field marked), and x;y;z points whose
    integer coordinates sit in their own columns beside 3-decimal heights above 1 mm."""
    from roadscan.io import read

    z = fourier_surface(32, 1e-4, 0.8, 2e-4, seed=3) * 1e3 + 45.0  # mm, all above 1
    f = tmp_path / "dc.csv"
    f.write_text("\n".join(";".join(f"{v:.3f}".replace(".", ",") for v in row) for row in z) + "\n")
    assert np.allclose(
        read(f, spacing=1e-4, units="mm").heights_m, z * 1e-3, rtol=0, atol=6e-7
    )  # 3 decimals of mm
    f = tmp_path / "xyz.txt"
    f.write_text(
        "\n".join(f"{i};{j};{z[j, i]:.3f}".replace(".", ",") for j in range(32) for i in range(32)) + "\n"
    )
    s = read(f, units="mm")
    assert s.heights_m.shape == (32, 32)


def test_channel_choice_recorded_by_compare_dry_vs_wet_and_combine(tmp_path, capsys):
    """--channel K on a multi-page TIFF was recorded by analyse, batch and rain-fill only;
    compare's and dry-vs-wet's comparison.json and combine's combine.json did not say which page
    was read. Checked against the page's own heights (page 1 is 3x page 0's texture)."""
    import json

    import tifffile

    z = fourier_surface(48, 1e-4, 0.8, 2e-4, seed=1)
    tifffile.imwrite(tmp_path / "p.tif", np.stack([z, 3 * z]).astype(np.float32))
    tifffile.imwrite(tmp_path / "q.tif", np.stack([z, 3 * z]).astype(np.float32))
    base = ["--spacing", "1e-4", "--channel", "1"]
    for argv, js in (
        (["compare", tmp_path / "p.tif", tmp_path / "q.tif", *base, "--no-friction"], "comparison.json"),
        (["dry-vs-wet", tmp_path / "p.tif", *base, "--no-friction"], "comparison.json"),
        (["combine", tmp_path / "p.tif", *base, "--no-figures"], "combine.json"),
    ):
        out = tmp_path / argv[0]
        rc, err = run_cli(capsys, [*argv, "--out", out])
        assert rc == 0, err
        data = json.loads((out / js).read_text())
        entries = {
            "compare": lambda d: list(d.values()),
            "dry-vs-wet": lambda d: [d],
            "combine": lambda d: d["inputs"],
        }[argv[0]](data)
        assert entries and all(e["channel"] == 1 for e in entries), (argv[0], entries)
    a = json.loads((tmp_path / "compare" / "comparison.json").read_text())["p"]
    assert a["rms_height_m"] > 2 * float(np.std(z))  # page 1 read, not page 0


def test_npz_spacing_member_that_is_not_one_number_is_named(tmp_path, capsys):
    """An .npz whose dx is text said 'heights are not numbers'; dx = [1e-4, 1e-4] was dropped
    silently (then --spacing was asked for, or used instead). Each now names the member."""
    z = fourier_surface(32, 1e-4, 0.8, 2e-4, seed=1)
    for name, dx, word in (
        ("s.npz", "abc", "'dx' are not numbers"),
        ("two.npz", [1e-4, 1e-4], "'dx' must be one number"),
        ("c.npz", 1e-4 + 0j, "'dx' are complex"),
    ):
        np.savez(tmp_path / name, heights=z, dx=dx, dy=1e-4)
        rc, err = run_cli(capsys, ["convert", tmp_path / name, tmp_path / "o.npy", "--spacing", "1e-4"])
        assert_one_line_error(rc, err, words=[str(tmp_path / name), word])
    assert not (tmp_path / "o.npy").exists() and hidden_leftovers(tmp_path) == []


def test_batch_into_a_users_folder_replaces_nothing(tmp_path, capsys):
    """batch --out into an existing folder that is no campaign (a project folder holding the
    user's report.html, campaign.csv and a folder named like a scan) replaced all three, exit 0.
    Now refused like every other command's output folder; an earlier campaign is still reused."""
    from fault_tools import small_scan, snapshot

    scan = small_scan(tmp_path / "a.npy")
    proj = tmp_path / "proj"
    (proj / "a").mkdir(parents=True)
    (proj / "report.html").write_text("my report")
    (proj / "campaign.csv").write_text("my,table\n")
    (proj / "a" / "summary.json").write_text("{}")
    before = snapshot(tmp_path)
    argv = ["batch", scan, "--spacing", "1e-4", "--no-friction", "--workers", "1"]
    rc, err = run_cli(capsys, [*argv, "--out", proj])
    assert_one_line_error(rc, err, words=[str(proj), "not empty"])
    assert snapshot(tmp_path) == before and hidden_leftovers(tmp_path) == []


def test_dry_vs_wet_output_error_names_the_output_not_the_scan(tmp_path, capsys, monkeypatch):
    """A read-only --out gave 'dry-vs-wet: error: SCAN: --out OUT: cannot write there': the
    line blamed the scan first. Now the output alone; a scan problem still names the scan."""
    import errno
    import os

    from fault_tools import small_scan

    scan = small_scan(tmp_path / "a.npy")

    def ro(*a, **k):
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr(os, "mkdir", ro)  # the hidden output folder cannot be made
    rc, err = run_cli(
        capsys, ["dry-vs-wet", scan, "--spacing", "1e-4", "--no-friction", "--out", tmp_path / "o"]
    )
    monkeypatch.undo()
    assert_one_line_error(rc, err, words=["--out", "Read-only"])
    assert str(scan) not in err
    np.save(tmp_path / "p.npy", fourier_surface(64, 1e-4, 0.8, 2e-4, seed=1)[0])
    rc, err = run_cli(
        capsys, ["dry-vs-wet", tmp_path / "p.npy", "--spacing", "1e-4", "--out", tmp_path / "o"]
    )
    assert_one_line_error(rc, err, words=[str(tmp_path / "p.npy"), "area scan"])


def test_psd_csv_in_other_units_is_refused_as_units(tmp_path, capsys):
    """psd.csv with C in mm^4 (or q per mm) read as SI gave 'mu reaches 1.9e+06 ... check the
    PSD' naming no file, or (q per mm) exit 0 with mu 4e-14. Now 'units?' naming the file, from
    the table's rms height h = sqrt(2 pi int q C dq) against the wavelengths it spans; the SI
    table still runs."""
    from conftest import ROOT

    d = np.loadtxt(ROOT / "sample_scans" / "asphalt_psd.csv", delimiter=",", skiprows=1)
    for name, q, C in (
        ("C_mm4.csv", d[:, 0], d[:, 1] * 1e12),
        ("q_per_mm.csv", d[:, 0] * 1e-3, d[:, 1]),
        ("si.csv", d[:, 0], d[:, 1]),
    ):
        f = tmp_path / name
        f.write_text("q_per_m,C_m4\n" + "\n".join(f"{a:.9g},{b:.9g}" for a, b in zip(q, C)) + "\n")
        rc, err = run_cli(
            capsys, ["friction", "--psd", f, "--velocities", "1e-2,1", "--out", tmp_path / f"mu_{name}"]
        )
        if name == "si.csv":
            assert rc == 0, err
            h = np.sqrt(2 * np.pi * np.trapezoid(q * C, q))
            assert 1e-5 * 2 * np.pi / q.max() < h < np.pi / q.min()  # the bounds hold for SI
        else:
            assert_one_line_error(rc, err, words=[str(f), "units?"])
            assert not (tmp_path / f"mu_{name}").exists()
    assert hidden_leftovers(tmp_path) == []


def test_rubber_toml_with_a_byte_order_mark_reads(tmp_path, capsys):
    """A rubber TOML saved with a UTF-8 byte-order mark (Windows editors) was 'invalid TOML
    (Invalid statement at line 1, column 1)'; the CSVs beside it were read with the mark. Now
    the same mu(v) as the file without it."""
    from conftest import ROOT

    src = ROOT / "sample_scans" / "rubbers" / "thesis_sls.toml"
    (tmp_path / "bom.toml").write_bytes(b"\xef\xbb\xbf" + src.read_bytes().replace(b"\n", b"\r\n"))
    psd = ROOT / "sample_scans" / "asphalt_psd.csv"
    mus = []
    for toml in (src, tmp_path / "bom.toml"):
        out = tmp_path / f"mu_{toml.stem}.csv"
        rc, err = run_cli(
            capsys, ["friction", "--psd", psd, "--rubber", toml, "--velocities", "1e-2,1", "--out", out]
        )
        assert rc == 0, err
        mus.append(np.loadtxt(out, delimiter=",", skiprows=1)[:, 1])
    assert np.array_equal(mus[0], mus[1])


def test_damaged_tiff_gives_one_line_not_the_tiff_libraries_log(tmp_path, capsys):
    """A TIFF header over garbage printed tifffile's own log line ('<tifffile.TiffPages @...>
    invalid offset to first page') before the error, which said only 'IndexError: 0'; a TIFF
    whose size tags were edited printed two such lines. Now one roadscan line naming the file
    and tifffile's reason."""
    import os

    import tifffile

    f = tmp_path / "garbage.tif"
    f.write_bytes(b"II*\x00" + os.urandom(2000))
    rc, err = run_cli(
        capsys, ["analyse", f, "--spacing", "1e-4", "--no-figures", "--no-friction", "--out", tmp_path / "o"]
    )
    assert_one_line_error(rc, err, words=[str(f), "not a readable TIFF", "offset"])
    g = tmp_path / "good.tif"
    tifffile.imwrite(g, fourier_surface(64, 1e-4, 0.8, 2e-4, seed=1).astype(np.float32))
    rc, err = run_cli(capsys, ["convert", g, tmp_path / "g.npy", "--spacing", "1e-4"])
    assert rc == 0 and err == "", err
    assert hidden_leftovers(tmp_path) == []


def test_error_lines_carry_no_terminal_control_bytes(tmp_path, capsys):
    """A vendor reader's refusal quoted the file's binary bytes (a random .plu: 'ParserError:
    Unknown string format: <junk>'), so ESC, BEL or NUL from a file could reach the terminal.
    Error lines now show them as '?'; the line stays one line naming the file."""
    from pipelines.cli.app import one_line
    from roadscan.io.vendor_meta import one_line as vendor_line

    assert one_line("a\x1b[2Jb\x07c\x00d") == "a?[2Jb?c?d"
    assert vendor_line(ValueError("x\x1b]0;title\x07y")) == "ValueError: x?]0;title?y"
    f = tmp_path / "scan\x1b[2J.npy"
    rc, err = run_cli(capsys, ["analyse", f, "--spacing", "1e-4", "--out", tmp_path / "o"])
    assert_one_line_error(rc, err, words=["scan?[2J.npy", "no such file"])
    assert "\x1b" not in err


def test_rubber_toml_modulus_in_the_wrong_units_is_refused(tmp_path, capsys):
    """The thesis SLS with E1_Pa = 1000 (MPa numbers under a Pa key) gave mu 4e-5 and exit 0
    (a warning blaming 'the rubber model or the band'); E1_Pa = 1e15 (stiffer than diamond)
    ran without a word. Both now 'units?' naming the TOML; the shipped rubbers still run."""
    from conftest import ROOT

    rubbers = ROOT / "sample_scans" / "rubbers"
    psd = ROOT / "sample_scans" / "asphalt_psd.csv"
    text = (rubbers / "thesis_sls.toml").read_text()
    assert "E1_Pa = 1e9" in text
    for value in ("1000", "1e15"):
        f = tmp_path / f"sls_{value}.toml"
        f.write_text(text.replace("E1_Pa = 1e9", f"E1_Pa = {value}"))
        rc, err = run_cli(
            capsys,
            ["friction", "--psd", psd, "--rubber", f, "--velocities", "1e-2,1", "--out", tmp_path / "mu.csv"],
        )
        assert_one_line_error(rc, err, words=[str(f), "units?"])
        assert not (tmp_path / "mu.csv").exists()
    for toml in sorted(rubbers.glob("*.toml")):
        rc, err = run_cli(
            capsys,
            [
                "friction",
                "--psd",
                psd,
                "--rubber",
                toml,
                "--velocities",
                "1e-2,1",
                "--out",
                tmp_path / "ok.csv",
            ],
        )
        assert rc == 0, (toml, err)
