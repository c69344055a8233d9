"""Does measuring where ``next_measurement`` says tell the top two explanations apart? (issue 27)

Worlds: the few-point offset worlds of ``bench_diagnose_blind_offsets.py`` (5 to 10 measured
speeds, unknown offsets of q1, sigma0 and the spectrum's level, ``--uncertain`` ranges that
contain the truth). For every world whose diagnosis carries a ``next_measurement`` (inconclusive
or low verdicts), the hidden truth is "measured" once more at each proposed speed (with the
world's own noise), as many times as the proposal's ``repeats`` (at most 5), and the diagnosis is
rerun on the points plus the new ones. The same is done with as many new points at random
speeds over the same range (the control).

Separated: in the second diagnosis, one of the two explanations the proposal named is at least
``ODDS`` (10) times as probable as the other (posteriors of ``verdict.evidence.models``; an
explanation missing there counts as probability 0).

Usage::

    .venv/bin/python benchmarks/bench_diagnose_next.py [--seed 1000] [--cases 10] [--nulls 5] [--jobs 2]
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np
from bench_diagnose_blind_cases import true_mu, write_mu_csv
from bench_diagnose_blind_offsets import make_offset_case, offset_specs
from bench_diagnose_blind_run import run_diagnose

import friction as F

ODDS = 10.0
MAX_REPEATS = 5


def _posteriors(diag):
    ev = ((diag.get("verdict") or {}).get("evidence") or {}).get("models") or []
    return {m["name"]: m["posterior"] for m in ev}


def _separated(diag, a, b):
    p = _posteriors(diag)
    pa, pb = p.get(a, 0.0), p.get(b, 0.0)
    hi, lo = max(pa, pb), min(pa, pb)
    return hi > 0 and (lo == 0 or hi / lo >= ODDS)


def _truth_at(case, v):
    effect, p, surf, s0 = case.info["truth"]
    if effect:
        return true_mu(effect, p, surf, v, sigma0_Pa=s0)
    return F.mu_isothermal(surf.psd, F.thesis_rubber(), v, sigma0_Pa=s0).mu


def _rerun(case, v_new, tag, rng):
    mu_new = _truth_at(case, v_new) * np.exp(case.noise_rel * rng.standard_normal(v_new.size))
    v = np.concatenate([case.v, v_new])
    mu = np.concatenate([case.mu_meas, mu_new])
    o = np.argsort(v)
    d = case.dir / tag
    d.mkdir(parents=True, exist_ok=True)
    write_mu_csv(d / "mu.csv", v[o], mu[o])
    diag, _ = run_diagnose(
        replace(case, dir=d), extra=["--uncertain", case.info["uncertain"]], validate=False
    )
    return diag


def run_case(case):
    diag, dt = run_diagnose(case, extra=["--uncertain", case.info["uncertain"]], validate=False)
    nxt = diag.get("next_measurement") if "error" not in diag else None
    row = dict(
        seed=case.seed,
        effect=case.effect or "null",
        n=case.v.size,
        seconds=dt,
        verdict=(diag.get("verdict") or {}).get("effect"),
        next=nxt,
    )
    if not nxt or not nxt.get("speeds_m_per_s"):  # no speed separates them: another quantity is proposed
        return row
    a, b = nxt["between"]
    rng = np.random.default_rng(case.seed + 7)
    reps = min(int(nxt.get("repeats", 1)), MAX_REPEATS)
    v_prop = np.repeat(np.asarray(nxt["speeds_m_per_s"], float), reps)
    lo, hi = np.log10(case.v.min()) - 0.5, np.log10(case.v.max()) + 0.5
    v_rand = 10 ** rng.uniform(max(lo, -7), min(hi, np.log10(30.0)), v_prop.size)
    d1 = _rerun(case, v_prop, "proposed", np.random.default_rng(case.seed + 11))
    d2 = _rerun(case, v_rand, "random", np.random.default_rng(case.seed + 11))
    row.update(
        between=[a, b],
        separated_before=_separated(diag, a, b),
        separated_proposed=_separated(d1, a, b) if "error" not in d1 else None,
        separated_random=_separated(d2, a, b) if "error" not in d2 else None,
        expected_sigma=nxt["separation_sigma"],
        new_points=int(v_prop.size),
    )
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=1000)
    ap.add_argument("--cases", type=int, default=10, help="effect worlds (default 10)")
    ap.add_argument("--nulls", type=int, default=5, help="worlds without an effect (default 5)")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args(argv)
    root = Path(tempfile.mkdtemp(prefix="diag_next_"))
    t0 = time.perf_counter()
    cases = [
        make_offset_case(s, e, root / f"{s}_{e or 'null'}", few=True)
        for s, e in offset_specs(a.seed, a.cases, a.nulls)
    ]
    with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        rows = list(ex.map(run_case, cases))
    shutil.rmtree(root, ignore_errors=True)
    with_next = [r for r in rows if r.get("between")]
    for r in with_next:
        print(
            f"  seed {r['seed']} {r['effect']:20s} n={r['n']:2d} "
            f"{r['between'][0]} vs {r['between'][1]}: expected "
            + ", ".join(f"{x:.2g}" for x in r["expected_sigma"])
            + f" sigma, {r['new_points']} new points; separated before "
            f"{r['separated_before']}, proposed {r['separated_proposed']}, random {r['separated_random']}"
        )
    sp = sum(bool(r["separated_proposed"]) for r in with_next)
    sr = sum(bool(r["separated_random"]) for r in with_next)
    print(
        f"\n{len(with_next)} of {len(rows)} worlds carry next_measurement; measuring at the proposed speeds "
        f"separates the top two (odds >= {ODDS:g}) in "
        f"{sp}/{len(with_next)}, the same number of random speeds "
        f"in {sr}/{len(with_next)}"
    )
    open_ = [r for r in with_next if not r["separated_before"]]
    print(
        f"of them {len(open_)} not yet separated before the "
        "new points: separated after measuring as proposed "
        f"{sum(bool(r['separated_proposed']) for r in open_)}/{len(open_)}, at random speeds "
        f"{sum(bool(r['separated_random']) for r in open_)}/{len(open_)}"
    )
    print(f"total wall time {time.perf_counter() - t0:.0f} s ({a.jobs} jobs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
