"""
A scan to a spectrum to friction with ``pipelines.analyse``
===========================================================

One call runs the whole chain of ``roadscan analyse`` on the shipped sample scan (a synthetic
asphalt-like surface, 54 x 60 mm at 55.4 µm): levelling, dropout filling, the angular-averaged
power spectrum :math:`C(q)`, its reliable band, the self-affine fit, and Persson's
:math:`\\mu(v)` for the default rubber.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import pipelines

ROOT = Path(pipelines.__file__).resolve().parents[1]
result = pipelines.analyse(ROOT / "sample_scans" / "asphalt.x3p")

# %%
# What came back
# --------------
# ``result.summary`` is exactly the ``summary.json`` the command writes; ``result.warnings``
# lists this run's warnings (none on this scan). The fitted Hurst exponent, the measured rms
# height (ISO 25178-2 Sq) and the reliable band:
s = result.summary
print(f"H = {s['hurst']:.3f} +- {s['hurst_stderr']:.3f}")
print(f"Sq = {s['rms_height_m'] * 1e3:.3g} mm")
lo, hi = result.reliable_band_per_m
print(f"reliable band: {lo:.3g} to {hi:.3g} 1/m ({s['reliable_band_reasons']})")
print("warnings:", result.warnings)

# %%
# The spectrum and friction
# -------------------------
# The spectrum is in Persson's normalisation, :math:`\langle h^2\rangle = 2\pi\int qC\,dq`.
# Grey: outside the reliable band, which the fit and the friction integral do not use.
fit = result.fit
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
ax1.loglog(result.q_per_m, result.C_m4, "o", ms=3, label="measured C(q)")
ax1.axvspan(result.q_per_m[0], lo, color="0.9")
ax1.axvspan(hi, result.q_per_m[-1], color="0.9")
q = np.geomspace(*fit.fit_band_per_m, 20)
ax1.loglog(
    q,
    fit.C_at_q0_m4 * (q / fit.q0_per_m) ** (-2 * (1 + fit.hurst)),
    "r-",
    label=f"self-affine fit, H = {fit.hurst:.2f}",
)
ax1.set_xlabel("q [1/m]")
ax1.set_ylabel("C(q) [m$^4$]")
ax1.legend()
ax2.semilogx(result.v_m_per_s, result.mu, "k-")
ax2.set_xlabel("sliding speed v [m/s]")
ax2.set_ylabel("friction coefficient $\\mu$")
ax2.set_title("thesis rubber (illustrative), 0.2 MPa, isothermal")
fig.tight_layout()

# %%
# Writing the command's files
# ---------------------------
# ``result.write(out_dir)`` writes ``summary.json``, ``psd.csv``, ``mu.csv``, the figures and
# ``report.html``, as ``roadscan analyse sample_scans/asphalt.x3p --out out_dir`` does.
import tempfile

with tempfile.TemporaryDirectory() as tmp:
    result.write(tmp)
    print(sorted(p.name for p in Path(tmp).rglob("*") if p.is_file())[:8])
