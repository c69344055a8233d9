"""
Dry vs wet: rain fill and its effect on friction
================================================

Water fills the road's cavities up to their spill level; a sliding tyre seals them and feels
the filled surface. The wet surface has less short-wavelength roughness where the water
stands, so its spectrum and :math:`\\mu(v)` drop.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import pipelines
from roadscan.io import read
from roadscan.level import level
from roadscan.rain import rain_fill

ROOT = Path(pipelines.__file__).resolve().parents[1]
scan = level(read(ROOT / "sample_scans" / "asphalt.x3p"))
wet = rain_fill(scan)  # 4-connected, unlimited water: every depression full
print(f"wetted fraction {wet.wetted_fraction:.1%}, water {wet.water_volume_m3_per_m2 * 1e3:.3g} mm")

# %%
# The same chain on both surfaces
# -------------------------------
# ``pipelines.analyse`` accepts a height map in memory; the wet map is analysed exactly like
# the dry one (same band, same rubber).
dry_result = pipelines.analyse(scan)
wet_result = pipelines.analyse(wet.wet)

fig, ax = plt.subplots(figsize=(6, 5))
im = ax.imshow(
    wet.depth_m * 1e3,
    origin="lower",
    cmap="Blues",
    extent=[0, scan.heights_m.shape[1] * scan.dx_m * 1e3, 0, scan.heights_m.shape[0] * scan.dy_m * 1e3],
)
fig.colorbar(im, ax=ax, label="water depth [mm]")
ax.set_xlabel("x [mm]")
ax.set_ylabel("y [mm]")
ax.set_title("where the water stands")
fig.tight_layout()

# %%
# Spectra and friction, dry and wet
# ---------------------------------
# Filling the cavities removes roughness at every wavelength shorter than the water pools, so
# the wet spectrum lies below the dry one and the wet :math:`\mu(v)` follows it.
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
for r, label in ((dry_result, "dry"), (wet_result, "wet")):
    ax1.loglog(r.q_per_m, r.C_m4, label=label)
    if r.mu is not None:
        ax2.semilogx(r.v_m_per_s, r.mu, label=label)
ax1.set_xlabel("q [1/m]")
ax1.set_ylabel("C(q) [m$^4$]")
ax1.legend()
ax2.set_xlabel("v [m/s]")
ax2.set_ylabel("$\\mu$")
ax2.legend()
fig.tight_layout()

# %%
# The ratio across speed
# ----------------------
if dry_result.mu is not None and wet_result.mu is not None:
    ratio = np.interp(dry_result.v_m_per_s, wet_result.v_m_per_s, wet_result.mu) / dry_result.mu
    for v, r in zip(dry_result.v_m_per_s[::20], ratio[::20]):
        print(f"v = {v:8.2g} m/s   mu_wet / mu_dry = {r:.3f}")
