"""Make ``compounds/``: several self-made "measured" compounds on one road, with hidden offsets of
the inputs a tribologist does not know (a tyre maker's workflow).

One spectrum (the sample asphalt's, ``sample_scans/asphalt_psd.csv``) and four rubbers of
``sample_scans/rubbers/`` (NREL pyvisco's measured master curve with its WLF fit and with its
shift table, BSD-3; the thesis's SLS and its Prony form). The truth differs from what the files
say in ways shared by every compound: the road's roughness continues to q1 = 2.5 x the
spectrum's last wave vector (``HIDDEN_Q1_FACTOR``) and the nominal pressure was 0.25 MPa, not the
assumed 0.2 MPa (``HIDDEN_SIGMA0_PA``). One compound (``sls_adhesive``) also carries an adhesive
contribution at low speed (a bell in log v, amplitude 0.12 at 1e-3 m/s, 0.8 decade wide) that the
model lacks. 24 speeds from 1e-4 to 1 m/s, 3 % multiplicative noise, seeds 21-24. Writes
``DIR/<label>.csv`` (v_m_per_s, mu, T0_C) and ``DIR/measurements.csv`` (measured, rubber, label;
paths relative to it). Run from the repository root:

    python pipelines/diagnosis/examples/make_pyvisco_compounds.py [DIR]

(default DIR: the shipped ``compounds/`` beside this script).
"""

import os
import sys
from pathlib import Path

import numpy as np

import friction

ROOT = Path(__file__).resolve().parents[3]
OUT = Path(__file__).resolve().parent / "compounds"
HIDDEN_Q1_FACTOR = 2.5
HIDDEN_SIGMA0_PA = 0.25e6
#: label, rubber TOML, T0 [C], hidden adhesion amplitude
COMPOUNDS = (
    ("pyvisco_wlf", "pyvisco_master_wlf.toml", 20.0, 0.0),
    ("pyvisco_table", "pyvisco_master_table.toml", 30.0, 0.0),
    ("sls", "thesis_sls.toml", 60.0, 0.0),
    ("sls_adhesive", "thesis_prony.toml", 50.0, 0.12),
)


def main(out=None):
    from pipelines.diagnosis.inputs import read_psd_csv
    from pipelines.output.report import write_csv
    from pipelines.settings.rubber_file import load_rubber

    out = Path(out) if out else OUT
    out.mkdir(parents=True, exist_ok=True)
    psd = read_psd_csv(ROOT / "sample_scans" / "asphalt_psd.csv")
    truth = psd.with_q1(psd.q1_per_m * HIDDEN_Q1_FACTOR)
    v = np.logspace(-4, 0, 24)
    rows = []
    for i, (label, toml, T0, amp) in enumerate(COMPOUNDS):
        rubber = load_rubber(ROOT / "sample_scans" / "rubbers" / toml)
        mu = friction.mu_isothermal(truth, rubber, v, sigma0_Pa=HIDDEN_SIGMA0_PA, T0_C=T0).mu
        mu = mu + amp * np.exp(-0.5 * (np.log10(v / 1e-3) / 0.8) ** 2)
        mu = mu * np.exp(0.03 * np.random.default_rng(21 + i).standard_normal(v.size))
        write_csv(out / f"{label}.csv", ["v_m_per_s", "mu", "T0_C"], [v, mu, np.full(v.size, T0)])
        rel = os.path.relpath(ROOT / "sample_scans" / "rubbers" / toml, out.resolve())
        rows.append((f"{label}.csv", Path(rel).as_posix(), label))
    text = "measured,rubber,label\n" + "".join(",".join(r) + "\n" for r in rows)
    (out / "measurements.csv").write_text(text)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
