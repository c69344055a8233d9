"""
Several instruments, one spectrum
=================================

Road texture spans wavelengths from metres to micrometres; no single instrument measures all of
them. Here two simulated instruments look at the same kind of surface, one whose spectrum is
known exactly: a texture laser (0.2 mm spacing, 0.4 mm lateral resolution, a 51 mm field) and a
confocal microscope (5 µm spacing, 10 µm resolution, 0.3 µm noise, a 2.6 mm field). Each keeps
only its *reliable band* (the field of view at the low end, and below the surface's roll-off
its plateau; Nyquist, the lateral resolution and the noise floor at the high end), and the
parts are merged on a common grid, as ``roadscan combine`` does.
"""

import matplotlib.pyplot as plt
import numpy as np

from pipelines.jobs.combine.job import combine_sources
from pipelines.jobs.combine.sources import source_spectrum
from roadscan.rolloff_origin import surface_q0
from roadscan.synth import model_psd
from roadscan.synth_measure import measure_synthetic

H, K, Q_ROLL = 0.8, 1.3e-3, 1e3  # C(q) = K q^(-2(H+1)) [m^4] above the roll-off [1/m]
laser = measure_synthetic(
    256, 2e-4, H, K, q_roll_per_m=Q_ROLL, resolution_m=4e-4, seed=1, name="texture laser"
)
confocal = measure_synthetic(
    512, 5e-6, H, K, q_roll_per_m=Q_ROLL, resolution_m=1e-5, noise_rms_m=3e-7, seed=2, name="confocal"
)
sources = [
    source_spectrum(hm, hm.name, hm.name, resolution_m=r) for hm, r in ((laser, 4e-4), (confocal, 1e-5))
]
merged, fit, notes = combine_sources(sources)
for s in sources:
    lo, hi = s.band.lo_per_m, s.band.hi_per_m
    print(f"{s.label}: reliable from {lo:.3g} to {hi:.3g} 1/m ({s.band.hi_reason})")
print(
    f"merged: {merged.q_per_m[0]:.3g} to {merged.q_per_m[-1]:.3g} 1/m, fitted H = {fit['hurst']:.3f}"
    f" (true {H})"
)
# the laser's knee is the surface's roll-off (far from its field of view and its resolution):
# the plateau below it stays in the merged curve, and q0 is reported (combine.json's q0_per_m)
q0, how = surface_q0(verdicts=[s.roll_off for s in sources if s.roll_off is not None])
print(f"q0 = {q0:.3g} 1/m (true {Q_ROLL:g}): {how}" if q0 else how)

# %%
# The measured spectra, their reliable bands, and the merged spectrum
# -------------------------------------------------------------------
# Outside its band each instrument's spectrum is drawn thin: the confocal's lowest rings lie above
# the truth (its window leaks power from wavelengths longer than its 2.6 mm field), the laser's
# lowest rings scatter (few lattice points) and its shortest ones are cut by its lateral
# resolution. The merged spectrum (with its 5-95 % band) follows the known truth over more than
# two decades, across the gap between the two bands.
fig, ax = plt.subplots(figsize=(8, 5))
for s, colour in zip(sources, ("C0", "C1")):
    inside = (s.q_per_m >= s.band.lo_per_m) & (s.q_per_m <= s.band.hi_per_m)
    ax.loglog(s.q_per_m, s.C_m4, color=colour, lw=0.6, alpha=0.6)
    ax.loglog(s.q_per_m[inside], s.C_m4[inside], color=colour, lw=2, label=f"{s.label} (reliable band)")
ax.fill_between(merged.q_per_m, merged.C_lo_m4, merged.C_hi_m4, color="k", alpha=0.15)
ax.loglog(merged.q_per_m, merged.C_m4, "k.", ms=3, label="merged")
q = np.geomspace(merged.q_per_m[0] / 3, merged.q_per_m[-1] * 3, 200)
ax.loglog(q, model_psd(q, H, K, q_roll_per_m=Q_ROLL), "r--", lw=1, label="the true spectrum")
ax.set_xlabel("q [1/m]")
ax.set_ylabel("C(q) [m$^4$]")
ax.legend()
fig.tight_layout()
