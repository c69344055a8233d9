"""roadscan friction: only an InputError is bad input (exit 2); a ValueError from inside the
friction numerics is a bug and surfaces as exit 1, "internal error" (pipelines.cli.app policy)."""

from __future__ import annotations

import json

import pytest

import friction
from pipelines.cli.app import main

SA = "H=0.8,h0=1e-4,q0=2e3,q1=1e6"


@pytest.mark.parametrize("flash", [False, True])
def test_a_valueerror_in_the_numerics_is_an_internal_error(monkeypatch, capsys, tmp_path, flash):
    def boom(*args, **kwargs):
        raise ValueError("a bug in the engine")

    monkeypatch.setattr(friction, "mu_flash" if flash else "mu_isothermal", boom)
    rc = main(
        [
            "friction",
            "--self-affine",
            SA,
            "--velocities",
            "1e-2:1:3",
            *(["--flash"] if flash else []),
            "--out",
            str(tmp_path / "mu.csv"),
        ]
    )
    err = capsys.readouterr().err
    assert rc == 1 and "internal error (ValueError: a bug in the engine)" in err and ": error:" not in err
    assert not (tmp_path / "mu.csv").exists()


@pytest.mark.parametrize(
    "spec, words",
    [
        ("H=1.7,h0=1e-4,q0=2e3,q1=1e6", "H=1.7"),
        ("H=0.8,h0=-1e-4,q0=2e3,q1=1e6", "h0=-0.0001"),
        ("H=0.8,h0=1e-4,q0=2e6,q1=1e6", "q0=2e+06 must be below q1"),
        ("H=0.8,h0=1e-4,q0=2e3,q1=1e6,qroll=5e3", "qroll=5000"),
    ],
)
def test_self_affine_model_conditions_are_bad_input(capsys, tmp_path, spec, words):
    rc = main(["friction", "--self-affine", spec, "--out", str(tmp_path / "mu.csv")])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and words in err and "--self-affine" in err and "\n" not in err


def test_q1_below_the_model_q0_is_bad_input(capsys, tmp_path):
    rc = main(["friction", "--self-affine", SA, "--q1", "1e3", "--out", str(tmp_path / "mu.csv")])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and "--q1 1000 1/m" in err and "\n" not in err


@pytest.mark.parametrize("side", ["{not json", json.dumps({"fit": {"hurst": 0.8}}), json.dumps([1, 2])])
def test_a_malformed_band_sidecar_is_bad_input_naming_it(capsys, tmp_path, side):
    psd = tmp_path / "psd.csv"
    psd.write_text("q_per_m,C_m4\n1e3,1e-20\n3e3,4e-22\n1e4,1e-23\n3e4,4e-25\n1e5,1e-26\n")
    (tmp_path / "psd_band.json").write_text(side)
    rc = main(["friction", "--psd", str(psd), "--out", str(tmp_path / "mu.csv")])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and "psd_band.json" in err and "cannot read the band of psd.csv" in err and "\n" not in err
