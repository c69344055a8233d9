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
wet = rain_fill(scan)            # 4-connected, unlimited water: every depression full
print(f"wetted fraction {wet.wetted_fraction:.1%}, water {wet.water_volume_m3_per_m2 * 1e3:.3g} mm")

# %%
# The same chain on both surfaces
# -------------------------------
# ``pipelines.analyse`` accepts a height map in memory; the wet map is analysed exactly like
# the dry one (same band, same rubber).
dry_result = pipelines.analyse(scan)
wet_result = pipelines.analyse(wet.wet)

fig, axes = plt.subplots(1, 3, figsize=(13, 4))
depth_mm = wet.depth_m * 1e3
im = axes[0].imshow(depth_mm, origin="lower", cmap="Blues",
                    extent=[0, scan.heights_m.shape[1] * scan.dx_m * 1e3,
                            0, scan.heights_m.shape[0] * scan.dy_m * 1e3])
fig.colorbar(im, ax=axes[0], label="water depth [mm]")
axes[0].set_xlabel("x [mm]")
axes[0].set_ylabel("y [mm]")
for r, label in ((dry_result, "dry"), (wet_result, "wet")):
    axes[1].loglog(r.q_per_m, r.C_m4, label=label)
    if r.mu is not None:
        axes[2].semilogx(r.v_m_per_s, r.mu, label=label)
axes[1].set_xlabel("q [1/m]")
axes[1].set_ylabel("C(q) [m$^4$]")
axes[1].legend()
axes[2].set_xlabel("v [m/s]")
axes[2].set_ylabel("$\\mu$")
axes[2].legend()
fig.tight_layout()

# %%
# The ratio across speed
# ----------------------
if dry_result.mu is not None and wet_result.mu is not None:
    ratio = np.interp(dry_result.v_m_per_s, wet_result.v_m_per_s, wet_result.mu) / dry_result.mu
    for v, r in zip(dry_result.v_m_per_s[::20], ratio[::20]):
        print(f"v = {v:8.2g} m/s   mu_wet / mu_dry = {r:.3f}")
