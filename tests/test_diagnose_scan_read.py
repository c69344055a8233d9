"""diagnose --scan records how the scan was read (issue 22: a flag that overrides a file's own
calibration, or the channel chosen, is recorded in every command's outputs)."""

import json
from pathlib import Path

from pipelines.cli.app import main

ROOT = Path(__file__).resolve().parents[1]


def test_diagnosis_json_records_the_calibration_override(tmp_path):
    """The record is about the scan, not the fit: six of the sample's 30 measured speeds (every
    fifth) keep the diagnosis short (few-point regime, about half the time)."""
    rows = (ROOT / "sample_scans" / "measured_mu_example.csv").read_text().splitlines()
    measured = tmp_path / "mu.csv"
    measured.write_text("\n".join([rows[0], *rows[1::5]]) + "\n")
    out = tmp_path / "dg"
    rc = main(
        [
            "diagnose",
            "--measured",
            str(measured),
            "--scan",
            str(ROOT / "sample_scans" / "asphalt.x3p"),
            "--spacing",
            "6e-5",
            "--override-calibration",
            "--out",
            str(out),
        ]
    )
    assert rc == 0
    read = json.loads((out / "diagnosis.json").read_text())["inputs"]["scan_read"]
    spacing = read["calibration_override"]["spacing"]
    assert spacing["flag"] == [6e-5, 6e-5] and spacing["file"] != spacing["flag"]
