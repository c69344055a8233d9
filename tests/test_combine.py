"""``roadscan combine`` (issue 20): several measurements of one surface merged into one C(q)."""
import pytest

from pipelines.combine_inputs import collect_inputs, is_manifest
from roadscan.errors import InputError


def test_manifest_relative_paths_and_labels(tmp_path):
    d = tmp_path / "m"
    d.mkdir()
    (d / "a.npy").write_bytes(b"x")
    (d / "b.npy").write_bytes(b"x")
    (d / "list.csv").write_text("file,spacing_m,resolution_m,label\n"
                                "a.npy,1e-5,2e-5,laser\nb.npy,1e-6;2e-6,,\n")
    assert is_manifest(d / "list.csv")
    got = collect_inputs([d / "list.csv"], resolution_m=3e-6)
    assert [e.path for e in got] == [d / "a.npy", d / "b.npy"]
    assert [e.label for e in got] == ["laser", "b"]
    assert got[0].spacing == "1e-05" and got[1].spacing == "1e-06,2e-06"
    assert got[0].resolution_m == 2e-5 and got[1].resolution_m == 3e-6


@pytest.mark.parametrize("text, word", [
    ("file,colour\na.npy,red\n", "colour"),
    ("file,spacing_m\na.npy,-1\n", "spacing_m"),
    ("file,resolution_m\na.npy,abc\n", "resolution_m"),
    ("file,units\na.npy,inch\n", "units"),
    ("file\nmissing.npy\n", "missing.npy"),
    ("file\n", "no file"),
    ("file,label\na.npy\n", "cells"),
])
def test_bad_manifests_are_one_line_naming_the_file(tmp_path, text, word):
    (tmp_path / "a.npy").write_bytes(b"x")
    m = tmp_path / "list.csv"
    m.write_text(text)
    with pytest.raises(InputError) as e:
        collect_inputs([m])
    msg = str(e.value)
    assert "\n" not in msg and word in msg and ("list.csv" in msg or "missing.npy" in msg)
