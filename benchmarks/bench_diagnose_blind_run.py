"""Running and scoring the blind diagnosis benchmark's friction-level cases through the command
line (see ``bench_diagnose_blind.py``): run_diagnose, scores, the per-seed report and the summary
table over seed sets."""

from __future__ import annotations

import collections
import json
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
from bench_diagnose_blind_cases import EFFECTS, K_ALT, K_SIGNAL, ROOT, make_case


# ----------------------------------------------------------------------------- running
def run_diagnose(case, extra=(), validate=True, out_name="out"):
    out = case.dir / out_name
    cmd = [
        sys.executable,
        "-m",
        "pipelines.cli",
        "diagnose",
        "--measured",
        str(case.dir / "mu.csv"),
        *case.surface.cli,
        "--out",
        str(out),
        *extra,
    ]
    if validate and case.validate:
        cmd += ["--validate", case.validate["path"]]
    t = time.perf_counter()
    pr = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    dt = time.perf_counter() - t
    if pr.returncode != 0:
        return dict(error=f"exit {pr.returncode}: {pr.stderr.strip()[-400:]}"), dt
    return json.loads((out / "diagnosis.json").read_text()), dt


def verdict_names(diag):
    e = (diag.get("verdict") or {}).get("effect")
    if e is None:
        return []
    if isinstance(e, str):
        return e.split("+")
    return list(e)


def _label(diag, names):
    """The called label: effect names, "inconclusive(a|b)" or "null" (no effect)."""
    inc = (diag.get("verdict") or {}).get("inconclusive")
    if not names and inc:
        return "inconclusive(" + "|".join(inc) + ")"
    return "+".join(names) if names else "null"


def named(label):
    """Whether a called label names an effect ("null", "calibration" and "inconclusive(...)" do not)."""
    return not (label in ("null", "calibration") or label.startswith("inconclusive("))


def score(case, diag):
    """(strict hit, lenient hit, called label). On a null case, an inconclusive verdict is a
    miss (it is not "no effect"), "calibration" is a hit (issue 19: no false positive). A
    fine_roughness case answered "calibration" with q1 fitted is a hit (q1 beyond the given
    spectrum is that effect)."""
    names = verdict_names(diag) if "error" not in diag else ["<error>"]
    label = _label(diag, names)
    if case.effect is None:
        ok = label in ("null", "calibration")
        return ok, ok, label
    if case.effect == "fine_roughness" and label == "calibration":
        ok = "q1_per_m" in ((diag.get("verdict") or {}).get("calibrated") or {})
        return ok, ok, label
    strict = names == [case.effect]
    lenient = case.effect in names
    return strict, lenient, label


def _fmt_params(p):
    return ", ".join(f"{k}={v:.3g}" if isinstance(v, float) else f"{k}={v}" for k, v in p.items())


def run_friction_level(seed, n_cases, n_nulls, jobs, keep=None):
    """``n_cases`` friction-level effect cases and ``n_nulls`` nulls from ``seed``; returns the rows."""
    root = Path(keep) if keep else Path(tempfile.mkdtemp(prefix="blind_diag_"))
    specs = [(seed + i, EFFECTS[i % len(EFFECTS)]) for i in range(n_cases)]
    specs += [(seed + 100000 + i, None) for i in range(n_nulls)]
    t0 = time.perf_counter()
    cases = [make_case(s, e, root / f"case_{s}_{e or 'null'}") for s, e in specs]
    t_gen = time.perf_counter() - t0
    print(f"generated {len(cases)} cases in {t_gen:.1f} s under {root}", flush=True)
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as ex:
        results = list(ex.map(run_diagnose, cases))
    rows = []
    for c, (diag, dt) in zip(cases, results):
        strict, lenient, label = score(c, diag)
        ver = diag.get("verdict") or {}
        rows.append(
            dict(
                seed=c.seed,
                seed_set=seed,
                effect=c.effect or "null",
                called=label,
                strict=strict,
                lenient=lenient,
                strong=c.strong,
                unambiguous=c.unambiguous,
                signal_gap=c.signal_gap,
                noise_log10=c.noise_log10,
                alt=c.alt,
                seconds=dt,
                kind=c.surface.kind + c.surface.info.get("file", ""),
                shrink=ver.get("shrink"),
                gap_validate=ver.get("gap_validate"),
                validate_model_gap=(c.validate or {}).get("model_gap"),
                validate_cond=(c.validate or {}).get("cond"),
                baseline_gap=diag.get("baseline_gap"),
                noise_est=diag.get("noise"),
                params=c.params,
                v_range=[float(c.v[0]), float(c.v[-1]), int(c.v.size)],
                error=diag.get("error"),
                inconclusive=ver.get("inconclusive"),
                top=[(e.get("name"), e.get("gap_heldout")) for e in (diag.get("effects") or [])[:3]],
            )
        )
    if not keep:
        shutil.rmtree(root, ignore_errors=True)
    return rows, t_gen


def summary_tables(surf, fric):
    from bench_diagnose_blind_surface import SURFACE_KINDS

    """The per-kind table over every seed set (the issue's 'Done when' figures)."""
    out = []
    if surf:
        seeds = sorted({r["seed_set"] for r in surf})
        out.append("\n== surface level, all seed sets ==")
        out.append("  kind          " + "  ".join(f"seed {s:>6}" for s in seeds) + "   total")
        for k in SURFACE_KINDS:
            name = k or "null"
            cells, tot, n = [], 0, 0
            for s in seeds:
                sel = [r for r in surf if r["kind"] == name and r["seed_set"] == s]
                ok = sum(r.get("right", False) for r in sel)
                cells.append(f"{ok:>5}/{len(sel):<5}")
                tot, n = tot + ok, n + len(sel)
            out.append(f"  {name:12s}  " + "  ".join(cells) + f"   {tot}/{n}")
        eff = [r for r in surf if r["kind"] != "null"]
        nul = [r for r in surf if r["kind"] == "null"]
        ok = sum(r.get("right", False) for r in eff)
        sh = [r["shrink"] for r in eff if r.get("right") and r.get("shrink") is not None]
        out.append(
            f"  effect cases named right {ok}/{len(eff)} = "
            f"{100 * ok / max(1, len(eff)):.0f} "
            "% (target >= 80 %, "
            f">= 3/5 per kind); false positives {sum(not r.get('right', False) for r in nul)}/{len(nul)} "
            "(<= 10 %); median held-out shrink of right verdicts "
            f"{np.median(sh) if sh else float('nan'):.2f} "
            f"(>= 0.5); median time per diagnosis {np.median([r['seconds'] for r in surf]):.1f} s"
        )
    if fric:
        seeds = sorted({r["seed_set"] for r in fric})
        out.append(
            "\n== friction level, all seed sets (counted: signal "
            "> 3 x noise, no own alternative within 1.5 x) =="
        )
        for s in seeds + [None]:
            sel = [r for r in fric if s is None or r["seed_set"] == s]
            eff = [r for r in sel if r["effect"] != "null" and r["strong"] and r["unambiguous"]]
            nul = [r for r in sel if r["effect"] == "null"]
            ok = sum(r["strict"] for r in eff)
            sh = [r["shrink"] for r in eff if r["strict"] and r["shrink"] is not None]
            allc = [r for r in sel if r["effect"] != "null"]
            out.append(
                f"  {'all' if s is None else 'seed ' + str(s):10s} counted {ok}/{len(eff)} = "
                f"{100 * ok / max(1, len(eff)):.1f} % "
                f"(unfiltered {sum(r['strict'] for r in allc)}/{len(allc)}); "
                f"false positives {sum(named(r['called']) for r in nul)}/{len(nul)}; median shrink "
                f"{np.median(sh) if sh else float('nan'):.3f}"
            )
        per = collections.defaultdict(lambda: [0, 0])
        for r in fric:
            if r["effect"] != "null" and r["strong"] and r["unambiguous"]:
                per[r["effect"]][0] += r["strict"]
                per[r["effect"]][1] += 1
        out.append(
            "  per effect (counted): " + ", ".join(f"{e} {a}/{b}" for e, (a, b) in sorted(per.items()))
        )
    return "\n".join(out)


def report(rows, t_gen=0.0):
    eff = [r for r in rows if r["effect"] != "null"]
    nul = [r for r in rows if r["effect"] == "null"]

    def acc(sel, key):
        return (sum(r[key] for r in sel) / len(sel), len(sel)) if sel else (float("nan"), 0)

    print("\n== top-1 attribution accuracy ==")
    for name, sel in (
        ("unfiltered", eff),
        (f"signal > {K_SIGNAL:g} x noise", [r for r in eff if r["strong"]]),
        (f"+ no own alt. fit within {K_ALT:g} x noise", [r for r in eff if r["strong"] and r["unambiguous"]]),
    ):
        s, n = acc(sel, "strict")
        lenient, _ = acc(sel, "lenient")
        print(
            f"  {name:40s} n={n:3d}  strict {100 * s:5.1f} %   lenient (pair contains) {100 * lenient:5.1f} %"
        )
    counted = [r for r in eff if r["strong"] and r["unambiguous"]]
    sh = [r["shrink"] for r in counted if r["shrink"] is not None and r["strict"]]
    sh_all = [r["shrink"] for r in counted if r["shrink"] is not None]
    print(
        f"  median held-out shrink (counted, correct verdict): "
        f"{np.median(sh) if sh else float('nan'):.3f}  (all counted with a verdict: "
        f"{np.median(sh_all) if sh_all else float('nan'):.3f})"
    )
    fp = [r for r in nul if named(r["called"])]
    print(f"  false positives on nulls: {len(fp)}/{len(nul)} = {100 * len(fp) / max(1, len(nul)):.0f} %")
    gv = [
        (r["gap_validate"], r["validate_model_gap"])
        for r in counted
        if r["strict"] and r["gap_validate"] is not None and r["validate_model_gap"]
    ]
    if gv:
        ratio = [g / m for g, m in gv]
        print(
            f"  --validate (correct verdicts): median gap_validate / model gap on that data = "
            f"{np.median(ratio):.3f} over {len(gv)} cases"
        )
    t = [r["seconds"] for r in rows]
    print(
        f"  run time per diagnosis: median {np.median(t):.1f} s, max {np.max(t):.1f} s "
        f"(generation {t_gen:.1f} s total)"
    )

    print("\n== confusion (hidden -> called), all effect cases; [counted] in brackets ==")
    conf = collections.defaultdict(collections.Counter)
    confc = collections.defaultdict(collections.Counter)
    for r in rows:
        conf[r["effect"]][r["called"]] += 1
        if r["effect"] == "null" or (r["strong"] and r["unambiguous"]):
            confc[r["effect"]][r["called"]] += 1
    for e in list(EFFECTS) + ["null"]:
        if e in conf:
            items = ", ".join(f"{k}: {n} [{confc[e][k]}]" for k, n in conf[e].most_common())
            print(f"  {e:20s} -> {items}")

    print("\n== misses (hidden effect, parameters, called, gaps) ==")
    for r in rows:
        if not r["strict"]:
            alt = ""
            if r["alt"]:
                k = min(r["alt"], key=r["alt"].get)
                alt = f" best own alt {k} rms {r['alt'][k]:.4f}"
            print(
                f"  seed {r['seed']} {r['effect']} ({r['kind']}) -> {r['called']}; "
                f"signal {r['signal_gap']:.3f} noise {r['noise_log10']:.4f} "
                f"strong={r['strong']} unamb={r['unambiguous']}{alt}; v {r['v_range']}; "
                f"params {_fmt_params(r['params'])}; tool top3 {r['top']}"
                + (f"; ERROR {r['error']}" if r["error"] else "")
            )
