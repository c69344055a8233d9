"""Make ``measured_mu_example.csv``: a stand-in "measurement" for the diagnose example.

The sample asphalt's spectrum (``roadscan analyse sample_scans/asphalt.x3p``) drives the friction
engine with flash heating (which the default, isothermal model lacks); 30 speeds from 1e-4 to
10 m/s, 3 % multiplicative log-normal noise, fixed seed. Run from the repository root:
python sample_scans/make_measured_example.py
"""

from pathlib import Path

import numpy as np

import friction
from pipelines.chain.surface import analyse_surface, surface_psd
from pipelines.output.report import write_csv
from pipelines.settings.scan_input import load_scan

HERE = Path(__file__).resolve().parent


def main():
    an = analyse_surface(load_scan(HERE / "asphalt.x3p"))
    write_csv(HERE / "asphalt_psd.csv", ["q_per_m", "C_m4"], [an.spectrum.q_per_m, an.spectrum.C_m4])
    psd = surface_psd(an.spectrum, an.fit)
    v = np.logspace(-4, 1, 30)
    mu = friction.mu_flash(psd, friction.thesis_rubber(), v, sigma0_Pa=0.2e6).mu
    rng = np.random.default_rng(2008)
    write_csv(
        HERE / "measured_mu_example.csv", ["v_m_per_s", "mu"], [v, mu * np.exp(rng.normal(0, 0.03, v.size))]
    )


if __name__ == "__main__":
    main()
