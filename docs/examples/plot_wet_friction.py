"""
Wet friction: sealing, squeeze-out and the speed constant
=========================================================

:func:`pipelines.dry_vs_wet` computes mu(v) dry and wet on a scan with Persson's picture of a
tyre on a wet road (:doc:`/wet_friction`): the water the contact seals in its pools, the film
left under a tread block after the time it takes to cross the footprint, and the adhesion water
removes. The same physics is in :mod:`friction.wet` for a spectrum you already have.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import friction
import pipelines
from friction.wet import WetConditions, wet_friction
from pipelines.settings.rubber_file import load_rubber

ROOT = Path(pipelines.__file__).resolve().parents[1]
rubber = load_rubber(ROOT / "sample_scans" / "rubbers" / "pyvisco_master_wlf.toml")  # a tread compound
speeds = [1e-3, 1e-1, 1.0, 20 / 3.6, 40 / 3.6, 60 / 3.6, 80 / 3.6, 100 / 3.6]

# %%
# A scan, dry and wet
# -------------------
# The default wet model is ``"persson"``; ``wet_model="fill"`` gives the thesis's model (every
# basin filled). The result is ``comparison.json`` as a dict.
with tempfile.TemporaryDirectory() as out:
    r = pipelines.dry_vs_wet(
        ROOT / "sample_scans" / "asphalt.x3p", Path(out) / "wet", rubber=rubber, velocities=speeds
    )
v = np.array([float(s) for s in r["mu_dry"]])
mu_dry, mu_wet = (np.array(list(r[k].values())) for k in ("mu_dry", "mu_wet"))
print(f"wet model {r['wet_model']['name']}, friction model {r['wet_model']['friction_model']}")
print(f"sealed pools: {r['sealing']['pool_count']}, {r['sealing']['sealed_fraction']:.1%} of the area")
print(f"mu_wet / mu_dry at {v[0]:g} m/s: {mu_wet[0] / mu_dry[0]:.3f}")
print(
    f"speed constant of mu_wet over 20-100 km/h: {r['speed_constant_model_kmh']} km/h; "
    f"IFI (ASTM E1960): {r['ifi_speed_constant_kmh']} ({r.get('mpd_note') or 'from the MPD'})"
)

fig, ax = plt.subplots(figsize=(6, 4))
ax.semilogx(v * 3.6, mu_dry, "o-", label="dry")
ax.semilogx(v * 3.6, mu_wet, "s--", label="wet (persson)")
ax.set_xlabel("sliding speed [km/h]")
ax.set_ylabel("$\\mu$")
ax.legend()
fig.tight_layout()

# %%
# Where water matters: a polished road and the water film
# -------------------------------------------------------
# On macrotexture the squeezed water drains through the texture channels within microseconds,
# so the film left is nil at road speeds. On a polished surface (rms 8 µm, no macrotexture)
# the film under a 25 mm tread block does not drain during the dwell time and carries part of
# the load: mu_wet falls with speed, more with more water and with colder (more viscous)
# water. ``engine`` is the dry model (here isothermal) at one pressure per speed.
psd = friction.SelfAffinePSD(0.8, 8e-6, 314, 2e4, q_roll_per_m=150)
vv = np.array([1e-3, *np.linspace(20, 100, 9) / 3.6])
dry = friction.mu_isothermal(psd, rubber, vv)


def engine(p, v_m_per_s, sigma0_Pa):
    return friction.mu_isothermal(p, rubber, v_m_per_s, sigma0_Pa=sigma0_Pa)


fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
ax1.plot(vv[1:] * 3.6, dry.mu[1:], "k-", label="dry")
for depth in (0.1e-3, 0.5e-3, 2e-3):
    wf = wet_friction(
        dry=dry, psd=psd, engine=engine, sigma0_Pa=2e5, conditions=WetConditions(water_depth_m=depth)
    )
    ax1.plot(vv[1:] * 3.6, wf.mu_wet[1:], "o-", label=f"wet, {depth * 1e3:g} mm of water")
    ax2.semilogy(vv[1:] * 3.6, np.maximum(wf.film_m[1:], 1e-9) * 1e6, "o-", label=f"{depth * 1e3:g} mm")
    print(f"{depth * 1e3:g} mm: mu_wet/mu_dry {wf.ratio[1]:.3f} at 20 km/h, {wf.ratio[-1]:.3f} at 100 km/h")
ax1.set_xlabel("sliding speed [km/h]")
ax1.set_ylabel("$\\mu$")
ax1.legend(fontsize=8)
ax2.set_xlabel("sliding speed [km/h]")
ax2.set_ylabel("film left [µm]")
ax2.legend(fontsize=8, title="water on the road")
fig.tight_layout()

# %%
# The shares of the loss
# ----------------------
# ``WetFriction.shares`` splits mu_dry - mu_wet into sealing, the squeeze-out film and the
# adhesion lost (zero here: no frictional shear stress was given, so adhesion is left out of
# both curves).
for name, share in wf.shares.items():
    print(f"{name:12s}", " ".join(f"{x:5.2f}" for x in share[1:]))
