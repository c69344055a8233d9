"""
A real master curve, and the flash temperature
==============================================

A measured polymer (NREL pyvisco's example DMA data, BSD-3-Clause, shipped in
``sample_scans/rubbers/``): its master curve :math:`E'(f), E''(f)` at -5 C with a measured
shift-factor table. We compute :math:`\\mu(v)` on the sample asphalt's spectrum without and
with flash heating (Persson 2006): at high speed the rubber heats at every length scale,
stiffens less, dissipates less, and :math:`\\mu` falls.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import friction
import pipelines
from pipelines.output.csv_files import read_psd_csv
from pipelines.settings.rubber_file import load_rubber

ROOT = Path(pipelines.__file__).resolve().parents[1]
rubber = load_rubber(ROOT / "sample_scans" / "rubbers" / "pyvisco_master_table.toml")
print(
    type(rubber).__name__,
    f"T_ref = {rubber.T_ref_C} C, {rubber.f_Hz.min():.2g} to {rubber.f_Hz.max():.2g} Hz",
)

# %%
# The master curve and its shift
# -------------------------------
# ``E(omega, T) = E_ref(omega aT(T) / aT(T_ref))``; :math:`\mathrm{Im}\,E > 0` for
# :math:`\omega > 0` (the loss modulus).
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
ax1.loglog(rubber.f_Hz, rubber.E_storage_Pa, label="E' (storage)")
ax1.loglog(rubber.f_Hz, rubber.E_loss_Pa, label="E'' (loss)")
ax1.set_xlabel("f [Hz]")
ax1.set_ylabel("modulus [Pa]")
ax1.set_title(f"master curve at {rubber.T_ref_C:g} C")
ax1.legend()
T = np.linspace(rubber.shift.T_C.min(), rubber.shift.T_C.max(), 50)
ax2.plot(T, rubber.shift.log10_aT(T))
ax2.plot(rubber.shift.T_C, rubber.shift.log10_aT_values, "o")
ax2.set_xlabel("T [C]")
ax2.set_ylabel("log10 aT")
fig.tight_layout()

# %%
# Friction without and with flash heating
# ---------------------------------------
# The road: the sample asphalt's spectrum as ``roadscan analyse`` wrote it (``psd.csv``,
# Persson's normalisation), continued above its last point as the fitted power law up to
# q1 = 1e6 1/m. Background temperature 20 C, nominal pressure 0.3 MPa.
psd = read_psd_csv(ROOT / "sample_scans" / "asphalt_psd.csv").with_q1(1e6)
v = np.logspace(-4, 1, 16)
cold = friction.mu_isothermal(psd, rubber, v, sigma0_Pa=0.3e6, T0_C=20.0)
hot = friction.mu_flash(psd, rubber, v, sigma0_Pa=0.3e6, T0_C=20.0)

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
ax1.semilogx(v, cold.mu, label="isothermal")
ax1.semilogx(v, hot.mu, label="flash temperature")
ax1.set_xlabel("v [m/s]")
ax1.set_ylabel("$\\mu$")
ax1.legend()
for zeta in (1, 10, 100):
    ax2.semilogx(v, hot.temperature_at(zeta), label=f"$T_q$ at q/q0 = {zeta}")
ax2.set_xlabel("v [m/s]")
ax2.set_ylabel("flash temperature [C]")
ax2.legend()
fig.tight_layout()
print(f"hottest flash temperature {np.nanmax(hot.T_q_C):.1f} C at {v[-1]:g} m/s")
