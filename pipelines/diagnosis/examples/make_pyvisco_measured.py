"""Make ``pyvisco_measured_mu.csv``: a self-made "measured" friction curve on a real rubber.

The rubber is NREL pyvisco's measured master curve (``sample_scans/rubbers/pyvisco_master_wlf.toml``,
BSD-3, see ``sample_scans/rubbers/SOURCE.md``), the surface the sample asphalt's spectrum
(``sample_scans/asphalt_psd.csv``). The log says T0 = 20 C, but the sample was at 28 C (a warmed
tread: the hidden effect is a temperature offset of +8 K); 12 speeds from 1e-4 to 1 m/s, 3 %
multiplicative noise, seed 11. Run from the repository root:

    python pipelines/diagnosis/examples/make_pyvisco_measured.py [OUT.csv]

(default OUT: the shipped ``pyvisco_measured_mu.csv`` beside this script).
"""

import sys
from pathlib import Path

import numpy as np

import friction

ROOT = Path(__file__).resolve().parents[3]
HERE = Path(__file__).resolve().parent


def main(out=None):
    from pipelines.diagnosis.inputs import read_psd_csv
    from pipelines.output.report import write_csv
    from pipelines.settings.rubber_file import load_rubber

    rubber = load_rubber(ROOT / "sample_scans" / "rubbers" / "pyvisco_master_wlf.toml")
    psd = read_psd_csv(ROOT / "sample_scans" / "asphalt_psd.csv")
    v = np.logspace(-4, 0, 12)
    mu = friction.mu_isothermal(psd, rubber, v, sigma0_Pa=0.2e6, T0_C=28.0).mu
    mu = mu * np.exp(0.03 * np.random.default_rng(11).standard_normal(v.size))
    out = Path(out) if out else HERE / "pyvisco_measured_mu.csv"
    out.parent.mkdir(parents=True, exist_ok=True)
    write_csv(out, ["v_m_per_s", "mu", "T0_C"], [v, mu, np.full(v.size, 20.0)])


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
