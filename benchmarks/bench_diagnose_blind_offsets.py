"""Blind worlds with unknown input offsets (issue 19; see ``bench_diagnose_blind.py``).

Each world is a ``psd.csv`` case of the blind generator (its own effect implementations) whose
truth also differs from the files in what a tribologist does not know: the road's roughness is
cut at q1 = f_q x the spectrum's last wave vector, f_q ~ logU(0.3, 3) (continued by the true
self-affine law above it, truncated below), the nominal pressure is f_s x 0.2 MPa, f_s ~ U(0.7,
1.4), and the spectrum's level is f_C x the file's, f_C ~ logU(0.6, 1.6). The diagnosis runs with
``--uncertain q1=0.3q:3q,sigma0=0.14MPa:0.28MPa,psd_scale=0.6:1.6`` (ranges that contain the
truth). Hidden effects: flash_temperature, relaxation_spectrum, temperature_offset, adhesion,
contact_correction (load and fine_roughness are the uncertain sigma0 and q1 themselves), and
null worlds (offsets only).

Goals (issue 19): of the verdicts that name an effect, >= 90 % name the true one; <= 10 % of the
null worlds get a named effect ("calibration", "inconclusive" and no effect are not named
effects); >= half of all effect worlds named right. A world's effect signal is measured against
the offset truth without the effect (rms log10), and counted "strong" above 3 x the noise.
"""

from __future__ import annotations

import collections
import shutil
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np
from bench_diagnose_blind_cases import (
    K_SIGNAL,
    SIGMA0_PA,
    Case,
    _psd_surface,
    _rms,
    draw_params,
    draw_speeds,
    true_mu,
    write_mu_csv,
)
from bench_diagnose_blind_run import _label, named, run_diagnose, verdict_names

import friction as F

OFFSET_EFFECTS = (
    "flash_temperature",
    "relaxation_spectrum",
    "temperature_offset",
    "adhesion",
    "contact_correction",
)
Q1_FACTORS = (0.3, 3.0)
SIGMA0_FACTORS = (0.7, 1.4)
LEVELS = (0.6, 1.6)


def _scaled(psd, level):
    return F.TabulatedPSD(psd.q_per_m, psd.C_m4 * level, psd.q0_per_m, psd.q1_per_m)


def offset_surface(surf, q1_factor, level):
    """The true road of a world: the given spectrum times ``level`` cut at ``q1_factor`` x its
    last wave vector (the true law above it)."""
    q1 = q1_factor * surf.q_nyq_per_m
    psd = surf.extend(q1) if q1_factor > 1 else surf.psd.with_q1(q1)
    return replace(surf, psd=_scaled(psd, level), extend=lambda q: _scaled(surf.extend(q), level))


def uncertain_spec(surf):
    q1 = surf.q_nyq_per_m
    return (
        f"q1={Q1_FACTORS[0] * q1:.8g}:{Q1_FACTORS[1] * q1:.8g},"
        f"sigma0={SIGMA0_FACTORS[0] * SIGMA0_PA:.8g}Pa:{SIGMA0_FACTORS[1] * SIGMA0_PA:.8g}Pa,"
        f"psd_scale={LEVELS[0]}:{LEVELS[1]}"
    )


def few_speeds(seed):
    """The number of measured speeds of a few-point world (5 to 10, from the seed)."""
    return 5 + seed % 6


def make_offset_case(seed, effect, workdir, few=False):
    """One world in ``workdir`` (mu.csv, psd.csv); ``case.params['offsets']`` holds the truth.
    ``few``: 5 to 10 measured speeds (:func:`few_speeds`) instead of 20 to 40."""
    rng = np.random.default_rng(seed)
    d = Path(workdir)
    d.mkdir(parents=True, exist_ok=True)
    surf = _psd_surface(rng, d)
    v = draw_speeds(rng, few_speeds(seed) if few else None)
    p = draw_params(rng, effect, surf)
    fq = float(np.exp(rng.uniform(*np.log(Q1_FACTORS))))
    fs = float(rng.uniform(*SIGMA0_FACTORS))
    fc = float(np.exp(rng.uniform(*np.log(LEVELS))))
    true_surf = offset_surface(surf, fq, fc)
    s0 = SIGMA0_PA * fs
    rub = F.thesis_rubber()
    mu_model = F.mu_isothermal(surf.psd, rub, v).mu
    mu_offsets = F.mu_isothermal(true_surf.psd, rub, v, sigma0_Pa=s0).mu
    mu_clean = true_mu(effect, p, true_surf, v, sigma0_Pa=s0) if effect else mu_offsets
    noise = rng.uniform(0.02, 0.05)
    mu_meas = mu_clean * np.exp(noise * rng.standard_normal(v.size))
    write_mu_csv(d / "mu.csv", v, mu_meas)
    case = Case(
        seed,
        effect,
        dict(p, offsets=dict(q1_factor=fq, sigma0_factor=fs, level=fc)),
        surf,
        v,
        mu_model,
        mu_clean,
        mu_meas,
        noise,
        d,
    )
    case.signal_gap = _rms(np.log10(mu_clean / mu_offsets))
    case.info = dict(
        offset_gap=_rms(np.log10(mu_offsets / mu_model)),
        uncertain=uncertain_spec(surf),
        truth=(effect, p, true_surf, s0),
    )
    return case


def run_offset_case(case):
    diag, dt = run_diagnose(case, extra=["--uncertain", case.info["uncertain"]], validate=False)
    names = verdict_names(diag) if "error" not in diag else ["<error>"]
    label = _label(diag, names)
    ver = diag.get("verdict") or {}
    return dict(
        seed=case.seed,
        effect=case.effect or "null",
        called=label,
        named=named(label),
        right=(names == [case.effect]) if case.effect else not named(label),
        strong=case.effect is None or case.signal_gap > K_SIGNAL * case.noise_rel / np.log(10),
        signal_gap=case.signal_gap,
        offset_gap=case.info["offset_gap"],
        seconds=dt,
        offsets=case.params["offsets"],
        confidence=ver.get("confidence"),
        calibrated=ver.get("calibrated"),
        error=diag.get("error"),
    )


def offset_specs(seed, n_cases, n_nulls):
    """(seed, effect or None) of the worlds of a seed set."""
    specs = [(seed + 50000 + i, OFFSET_EFFECTS[i % len(OFFSET_EFFECTS)]) for i in range(n_cases)]
    return specs + [(seed + 150000 + i, None) for i in range(n_nulls)]


def run_offset_level(seed, n_cases, n_nulls, jobs, keep=None, few=False):
    """``n_cases`` effect worlds and ``n_nulls`` null worlds from ``seed``; returns the rows.
    ``few``: 5 to 10 measured speeds per world."""
    root = Path(keep) if keep else Path(tempfile.mkdtemp(prefix="blind_offsets_"))
    specs = offset_specs(seed, n_cases, n_nulls)
    t0 = time.perf_counter()
    cases = [make_offset_case(s, e, root / f"offset_{s}_{e or 'null'}", few=few) for s, e in specs]
    print(
        f"generated {len(cases)} offset worlds in {time.perf_counter() - t0:.1f} s under {root}", flush=True
    )
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as ex:
        rows = list(ex.map(run_offset_case, cases))
    if not keep:
        shutil.rmtree(root, ignore_errors=True)
    for r in rows:
        r["seed_set"] = seed
        r["n_speeds"] = next(c.v.size for c in cases if c.seed == r["seed"])
    return rows


def offset_report(rows, few=False):
    """The issue's three figures (named precision, null false positives, effect recall)."""
    eff = [r for r in rows if r["effect"] != "null"]
    nul = [r for r in rows if r["effect"] == "null"]
    out = [
        "\n== worlds with unknown offsets of q1, sigma0 and the spectrum's level (--uncertain)"
        + (", 5 to 10 measured speeds ==" if few else " ==")
    ]
    for name, sel in (("all", eff), ("strong (signal > 3 x noise)", [r for r in eff if r["strong"]])):
        nm = [r for r in sel if r["named"]]
        ok = sum(r["right"] for r in nm)
        out.append(
            f"  {name:28s} named {len(nm)}/{len(sel)}, of them right {ok}/{len(nm)} = "
            f"{100 * ok / max(1, len(nm)):.0f} % (goal >= 90 %); named right {ok}/{len(sel)} = "
            f"{100 * ok / max(1, len(sel)):.0f} % (goal >= {30 if few else 50} %)"
        )
    fp = [r for r in nul if r["named"]]
    out.append(
        f"  null worlds with a named effect {len(fp)}/{len(nul)} = {100 * len(fp) / max(1, len(nul)):.0f} % "
        f"(goal <= 10 %); answered: "
        + ", ".join(f"{k} {n}" for k, n in collections.Counter(r["called"] for r in nul).most_common())
    )
    conf = collections.defaultdict(collections.Counter)
    for r in rows:
        conf[r["effect"]][r["called"]] += 1
    for e, c in sorted(conf.items()):
        out.append(f"  {e:20s} -> " + ", ".join(f"{k}: {n}" for k, n in c.most_common()))
    for r in rows:
        if (r["named"] and not r["right"]) or r.get("error"):
            out.append(
                f"  wrong: seed {r['seed']} {r['effect']} -> {r['called']} ({r['confidence']}); signal "
                f"{r['signal_gap']:.3f}, offsets {r['offsets']}"
                + (f"; ERROR {r['error']}" if r.get("error") else "")
            )
    t = [r["seconds"] for r in rows]
    out.append(f"  run time per diagnosis: median {np.median(t):.1f} s, max {np.max(t):.1f} s")
    return "\n".join(out)
