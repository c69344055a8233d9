"""The texture set in campaign tables: columns picked by --columns, MPD validity shown."""

import contextlib
import csv
import io
from pathlib import Path

import pytest
from conftest import _shared_dir

from pipelines.campaign.table import FIXED_COLUMNS, parse_columns, pick_columns
from pipelines.cli.app import main
from roadscan.errors import InputError

CAPTIF = (_shared_dir() or Path("/nonexistent")) / "data" / "profiles" / "captif"


def test_pick_columns_patterns_keep_order_and_fixed_columns():
    cols = list(FIXED_COLUMNS) + [
        "hurst",
        "mpd_m",
        "mpd_valid",
        "etd_m",
        "roughness.Sq_m",
        "roughness.Sk_m",
        "roughness.Spk_m",
        "filters.form",
    ]
    keep, unused = pick_columns(cols, ["roughness.S?k_m", "mpd_*", "nope"])
    assert keep == list(FIXED_COLUMNS) + ["mpd_m", "mpd_valid", "roughness.Spk_m"]
    assert unused == ["nope"]
    assert pick_columns(cols, None) == (cols, [])
    assert parse_columns(" mpd_m , roughness.S* ") == ["mpd_m", "roughness.S*"]
    assert parse_columns(None) is None
    with pytest.raises(InputError):
        parse_columns(" , ")


@pytest.mark.skipif(not CAPTIF.is_dir(), reason="CAPTIF profiles not available")
def test_batch_columns_and_validity(tmp_path):
    files = [str(CAPTIF / f"20211011_aylesbury_dec_station_{k}.dat") for k in (0, 1)]
    out = tmp_path / "c"
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
        rc = main(
            [
                "batch",
                *files,
                "--workers",
                "1",
                "--no-friction",
                "--columns",
                "mpd_m,mpd_valid,etd_m,roughness.R?k_m",
                "--out",
                str(out),
            ]
        )
    assert rc == 0, buf.getvalue()
    with open(out / "campaign.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
        head = list(rows[0])
    assert head == list(FIXED_COLUMNS) + ["roughness.Rpk_m", "roughness.Rvk_m", "mpd_m", "mpd_valid", "etd_m"]
    s0, s1 = sorted(rows, key=lambda r: r["file"])
    assert s0["mpd_valid"] == "true" and float(s0["etd_m"]) > 0
    assert s1["mpd_valid"] == "false" and s1["etd_m"] == "" and float(s1["mpd_m"]) > 0
    assert "not valid (ISO 13473-1)" in (out / "report.html").read_text()
