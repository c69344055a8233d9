"""Warnings belong to their run, and the measurement (not the rubber) judges a band's fine end."""

import json
import re
from pathlib import Path

import pytest

from pipelines.cli.app import main

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "sample_scans" / "asphalt.x3p"
RUBBER = ROOT / "sample_scans" / "rubbers" / "pyvisco_master_wlf.toml"


def _captif(shared_data):
    files = sorted((shared_data / "profiles" / "captif").glob("*.dat"))
    if len(files) < 3:
        pytest.skip("CAPTIF profiles not available")
    return files[:3]


def test_many_files_in_one_call_each_carry_their_own(shared_data, tmp_path):
    files = _captif(shared_data) + [SAMPLE]
    assert main(["analyse", *map(str, files), "--no-figures", "--out", str(tmp_path / "o")]) == 0
    names = [f.stem for f in files]
    for f in files:
        s = json.loads((tmp_path / "o" / f.stem / "summary.json").read_text())
        for w in s["warnings"]:
            others = [n for n in names if n != f.stem and re.search(rf"(?<!\w){n}(?!\w)", w)]
            assert not others, (f.stem, w)
        # the same file alone gives the same warnings (nothing carried from the files before)
        assert main(["analyse", str(f), "--no-figures", "--out", str(tmp_path / f"one_{f.stem}")]) == 0
        alone = json.loads((tmp_path / f"one_{f.stem}" / "summary.json").read_text())
        assert alone["warnings"] == s["warnings"]
    csv = (tmp_path / "o" / "summary.csv").read_text().splitlines()
    assert len(csv) == len(files) + 1


def test_two_api_calls_never_share_a_warning(shared_data):
    import pipelines

    first = _captif(shared_data)[0]
    a = pipelines.analyse(first)
    b = pipelines.analyse(SAMPLE)
    again = pipelines.analyse(first)
    assert a.warnings, "the CAPTIF band's fine end is warned about"
    assert not set(a.warnings) & set(b.warnings)
    assert again.warnings == a.warnings  # not swallowed as 'already said'
    assert a.summary["warnings"] == a.warnings


@pytest.mark.parametrize("k", [0, 1, 2])
def test_captif_band_judged_alike_with_either_rubber(shared_data, k):
    """Same band and the same judgement of its fine end with the default and a measured rubber."""
    import pipelines

    f = _captif(shared_data)[k]
    d = pipelines.analyse(f)
    m = pipelines.analyse(f, rubber=str(RUBBER))
    assert d.summary["reliable_band_per_m"] == m.summary["reliable_band_per_m"]

    def fine_end(r):
        return [w.split("(rms slope")[0] for w in r.warnings if "short end" in w]

    assert fine_end(d) == fine_end(m)
    assert ("refused" in d.summary["friction"]) == ("refused" in m.summary["friction"])
    if "refused" not in d.summary["friction"]:
        assert d.summary["friction"]["q1_per_m"] == m.summary["friction"]["q1_per_m"]
