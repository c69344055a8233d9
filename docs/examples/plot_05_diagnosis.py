"""
Reading a sim-to-real gap diagnosis, step by step
=================================================

A "measured" :math:`\\mu(v)` (made from the sample asphalt's spectrum by the flash-temperature
model with 3 % noise, ``sample_scans/measured_mu_example.csv``) is compared with the
isothermal engine. :func:`pipelines.diagnose` (the ``roadscan diagnose`` command as one call)
answers: where do they disagree, which unmodelled effect explains it, and how much of the
held-out gap does it close? It writes ``diagnosis.json`` and ``report.html`` into ``out`` and
returns the ``diagnosis.json`` dict.
"""

import csv
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import pipelines

ROOT = Path(pipelines.__file__).resolve().parents[1]
measured = ROOT / "sample_scans" / "measured_mu_example.csv"
out = Path(tempfile.mkdtemp()) / "diag"
d = pipelines.diagnose(out, measured=measured, psd=ROOT / "sample_scans" / "asphalt_psd.csv")
print("written:", sorted(p.name for p in out.iterdir()), "| verdict:", d["verdict"]["effect"])

# %%
# Step 1: is there a gap, and where?
# ----------------------------------
# The gap is the rms of :math:`\log_{10}(\mu_\mathrm{real}/\mu_\mathrm{sim})`; the noise is
# estimated from the measurement itself. ``where`` splits it by speed decade with a p-value.
print(f"baseline gap {d['baseline_gap']:.3g} (noise {d['noise']:.3g}, source: {d['noise_source']})")
for w in d["where"]:
    print(
        f"  {w['v_min_m_per_s']:.0e}..{w['v_max_m_per_s']:.0e} m/s: gap {w['gap']:.3f}"
        f"{'  significant' if w['significant'] else ''}"
    )

# %%
# Step 2: which length scales carry friction?
# -------------------------------------------
# ``band_map``: for each speed band, the wave vectors that carry :math:`\mu` and
# :math:`d\ln\mu/d\ln q_1`. Above 0.3 friction depends on the spectrum's cut-off, so the
# diagnosis treats :math:`q_1` as uncertain (the "calibration" candidates below).
for b in d["band_map"]:
    print(
        f"  {b['v_min_m_per_s']:.0e}..{b['v_max_m_per_s']:.0e} m/s: "
        f"q {b['q_min_per_m']:.2g}..{b['q_max_per_m']:.2g} 1/m, "
        f"dln mu/dln q1 = {b['dlnmu_dlnq1']:.2f}, carried by cut-off: {b['carried_by_cutoff']}"
    )

# %%
# Step 3: the candidates, scored on held-out points
# -------------------------------------------------
# Every effect is fitted on the training speeds and scored on the speeds it never saw
# (``heldout``); ``shrink`` is the fraction of the held-out gap it closes.
print("held out:", d["heldout"])
effects = d["effects"]
names = [e["name"] for e in effects]
shrinks = [e["shrink"] for e in effects]
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
ax1.barh(names[::-1], shrinks[::-1], color="C2")
ax1.axvline(0.25, color="k", ls="--", lw=0.8)
ax1.set_xlabel("held-out shrink (dashed: minimum to be named)")
with open(measured) as fh:
    rows = list(csv.DictReader(fh))
v = np.array([float(r["v_m_per_s"]) for r in rows])
mu = np.array([float(r["mu"]) for r in rows])
ax2.semilogx(v, mu, "ko", ms=3, label="measured")
gap_v = [np.sqrt(w["v_min_m_per_s"] * w["v_max_m_per_s"]) for w in d["where"]]
ax3 = ax2.twinx()
ax3.semilogx(gap_v, [w["gap"] for w in d["where"]], "r-s", label="gap per decade")
ax2.set_xlabel("v [m/s]")
ax2.set_ylabel("measured $\\mu$")
ax3.set_ylabel("gap, rms log10 ratio", color="r")
fig.tight_layout()

# %%
# Step 4: the verdict, and how sure it is
# ---------------------------------------
# An effect is named only when it closes at least 25 % of the held-out gap with a bootstrap
# interval above zero. A parameter on a bound of its physical range (``at_bound``) lowers the
# confidence: a flash model whose heat scale sits on its bound explains the data, but
# its strength is not pinned down by them.
v_ = d["verdict"]


def pct(x):
    return "-" if x is None else f"{x:.0%}"


lo, hi = v_.get("shrink_interval") or (None, None)
print(
    f"verdict: {v_['effect']}, shrink {pct(v_.get('shrink'))} (5-95 %: {pct(lo)} to {pct(hi)}), "
    f"confidence {v_.get('confidence')}, at bound: {v_.get('at_bound')}"
)
print("reason:", v_["reason"])
print("inputs assumed rather than given:", d["inputs"].get("assumed"))
