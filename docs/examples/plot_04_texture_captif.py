"""
Texture levels and MPD on a real CAPTIF laser profile
=====================================================

A 0.6 m excerpt of a stationary laser profiler reading of the CAPTIF test track's chip seal
(New Zealand, 2021; MIT licence, CAPTIF Road Research Centre, shipped as
``sample_scans/captif_station_1_excerpt.dat``). Road authorities report its macrotexture as the
mean profile depth (ISO 13473-1) and as third-octave texture levels (ISO 13473-4).
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import pipelines
from roadscan.io import read
from roadscan.roughness import mean_profile_depth
from roadscan.texture_depth import estimated_texture_depth, ifi_speed_constant
from roadscan.texture_spectrum import texture_spectrum

ROOT = Path(pipelines.__file__).resolve().parents[1]
profile = read(ROOT / "sample_scans" / "captif_station_1_excerpt.dat")
x_m = np.arange(profile.heights_m.size) * profile.dx_m
print(
    f"{profile.heights_m.size} points at {profile.dx_m * 1e6:.1f} um, "
    f"{profile.unmeasured.mean():.1%} dropouts"
)

# %%
# Mean profile depth
# ------------------
# Each 100 mm segment is resampled to 0.5 mm, spikes are replaced, a 2.4 mm low-pass and a
# least-squares line are applied; the segment depth is the mean of the two halves' peaks minus
# the mean level. The standard's spike criterion (alpha = 3) flags the steep stone edges of a
# chip seal as spikes; CAPTIF uses alpha = 6 for this surface.
for alpha in (3.0, 6.0):
    mpd, note = mean_profile_depth(profile, spike_alpha=alpha)
    print(f"alpha = {alpha:g}: MPD = {None if mpd is None else round(mpd * 1e3, 2)} mm; {note}")
mpd, _ = mean_profile_depth(profile, spike_alpha=6.0)
print(
    f"ETD = {estimated_texture_depth(mpd) * 1e3:.2f} mm (ISO 13473-1), "
    f"IFI speed constant Sp = {ifi_speed_constant(mpd):.0f} km/h (ASTM E1960)"
)

# %%
# Texture levels
# --------------
# :math:`L = 20\log_{10}(a / 1\,\mu\mathrm{m})` dB, ``a`` the rms amplitude of the profile in
# each third-octave band of wavelength; only bands the profile resolves are given.
ts = texture_spectrum(profile)
fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 6))
ax1.plot(x_m * 1e3, profile.heights_m * 1e3, lw=0.5)
ax1.set_xlabel("distance [mm]")
ax1.set_ylabel("height [mm]")
ax1.set_title(f"CAPTIF station 1 (excerpt), MPD = {mpd * 1e3:.2f} mm")
labels = [f"{n:g}" for n in ts.nominal_mm]
ax2.bar(range(len(ts.level_dB)), ts.level_dB, color="C1")
ax2.set_xticks(range(len(ts.level_dB)), labels, rotation=90)
ax2.set_xlabel("third-octave band, centre wavelength [mm]")
ax2.set_ylabel("texture level [dB re 1 µm]")
fig.tight_layout()
