"""Surface-level cases of the blind diagnosis benchmark (issue 11; see ``bench_diagnose_blind.py``):
scans made from ``roadscan.synth.self_affine_surface`` with one hidden surface effect each, run
through the command line."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
from bench_diagnose_blind_cases import ROOT
from bench_diagnose_blind_run import _label, verdict_names
from scipy import optimize

SURFACE_KINDS = ("anisotropy", "height_skew", "seams", "rolloff", "noise_floor", None)


def make_surface_heights(kind, seed, n=256):
    """(heights [m], spacing [m], truth dict) of one surface-level case (see module docstring)."""
    from scipy import stats
    from scipy.ndimage import gaussian_filter, zoom

    from roadscan.synth import self_affine_surface

    rng = np.random.default_rng(seed)
    dx = rng.uniform(40e-6, 80e-6)
    H = rng.uniform(0.7, 0.9)
    rms = rng.uniform(3e-4, 1e-3)
    L = n * dx
    truth = dict(H=H, dx_m=dx)
    if kind == "rolloff":
        qr = 2 * np.pi / L * rng.uniform(3, 6)
        truth["q_roll_per_m"] = qr
        return (
            self_affine_surface(
                n, dx_m=dx, hurst=H, rms_height_m=rms, q_roll_per_m=qr, seed=int(rng.integers(2**31))
            ).heights_m,
            dx,
            truth,
        )
    big = self_affine_surface(
        2 * n, dx_m=dx, hurst=H, rms_height_m=rms, seed=int(rng.integers(2**31))
    ).heights_m
    h = big[:n, :n].copy()
    if kind == "anisotropy":
        r = rng.uniform(2, 4)
        truth["stretch"] = r
        h = zoom(big[:n, : int(n / r) + 2], (1, r), order=3)[:, :n]
    elif kind == "height_skew":
        sk = rng.uniform(0.8, 1.8) * rng.choice([-1, 1])
        truth["skewness"] = sk
        flat = h.ravel()
        u = (stats.rankdata(flat) - 0.5) / flat.size
        k = 4 / sk**2
        g = stats.gamma.ppf(u if sk > 0 else 1 - u, k)
        h = ((g - k) / np.sqrt(k) * np.sign(sk) * flat.std()).reshape(h.shape)
    elif kind == "seams":
        if rng.random() < 0.5:
            nt = int(rng.choice([3, 4]))
            off = rng.normal(0, rng.uniform(0.2, 0.5) * h.std(), (nt, nt))
            e = np.linspace(0, n, nt + 1).astype(int)
            for j in range(nt):
                for i in range(nt):
                    h[e[j] : e[j + 1], e[i] : e[i + 1]] += off[j, i]
            truth["tiles"] = nt
        else:
            k = int(rng.integers(2, 5))
            for _ in range(k):
                pos = int(rng.integers(n // 8, 7 * n // 8))
                step = rng.normal(0, rng.uniform(0.2, 0.5) * h.std())
                if rng.random() < 0.5:
                    h[:, pos:] += step
                else:
                    h[pos:, :] += step
            truth["steps"] = k
    elif kind == "noise_floor":
        if rng.random() < 0.5:
            a = rng.uniform(0.02, 0.06)
            h = h + rng.normal(0, a * h.std(), h.shape)
            truth["white_noise_rel"] = a
        else:
            b = rng.uniform(1.5, 3)
            h = gaussian_filter(h, b)
            truth["blur_points"] = b
    # a third of the cases of four kinds are made another way (own stream of random numbers, so
    # the draws above do not change): the blind check must not depend on one recipe per effect
    alt = np.random.default_rng([seed, 7])
    if kind in ("anisotropy", "height_skew", "seams", "rolloff") and alt.random() < 1 / 3:
        h, truth = _surface_variant(kind, alt, n, dx, H, rms, truth)
    return h, dx, truth


def _surface_variant(kind, rng, n, dx, H, rms, truth):
    """The other recipe of a surface effect (see the module docstring)."""
    from scipy.ndimage import rotate, zoom

    from roadscan.synth import self_affine_surface

    truth = dict(H=truth["H"], dx_m=truth["dx_m"], variant=True)
    if kind == "rolloff":
        # roll-off on a map twice as large, cropped (not periodic)
        qr = 2 * np.pi / (n * dx) * rng.uniform(3, 6)
        big = self_affine_surface(
            2 * n, dx_m=dx, hurst=H, rms_height_m=rms, q_roll_per_m=qr, seed=int(rng.integers(2**31))
        ).heights_m
        return big[:n, :n].copy(), dict(truth, q_roll_per_m=qr, cropped=True)
    big = self_affine_surface(
        3 * n, dx_m=dx, hurst=H, rms_height_m=rms, seed=int(rng.integers(2**31))
    ).heights_m
    if kind == "anisotropy":
        # stretched by 2-4 along x, then turned by 15-75 degrees (cubic), centre cut out
        r, ang = rng.uniform(2, 4), rng.uniform(15, 75) * rng.choice([-1, 1])
        st = zoom(big[:, : int(3 * n / r) + 2], (1, r), order=3)[:, : 3 * n]
        h = rotate(st, ang, reshape=False, order=3)[n : 2 * n, n : 2 * n]
        return h.copy(), dict(truth, stretch=r, angle_deg=ang)
    h = big[:n, :n].copy()
    if kind == "height_skew":
        # exponential map of the Gaussian heights (log-normal law), sign random
        sk = rng.uniform(0.8, 1.8)
        s2 = optimize.brentq(lambda x: (np.exp(x) + 2) * np.sqrt(np.exp(x) - 1) - sk, 1e-6, 3.0)
        z = (h - h.mean()) / h.std()
        sign = rng.choice([-1, 1])
        g = sign * np.exp(np.sqrt(s2) * z)
        return (g - g.mean()) / g.std() * h.std(), dict(truth, skewness=float(sign * sk), law="lognormal")
    # seams: 3 x 3 or 4 x 4 tiles each with its own plane (offset and tilt residue)
    nt = int(rng.choice([3, 4]))
    e = np.linspace(0, n, nt + 1).astype(int)
    amp = rng.uniform(0.2, 0.5) * h.std()
    for j in range(nt):
        for i in range(nt):
            yy, xx = np.mgrid[e[j] : e[j + 1], e[i] : e[i + 1]]
            sy, sx = rng.normal(0, amp, 2) / (n / nt)
            h[e[j] : e[j + 1], e[i] : e[i + 1]] += (
                rng.normal(0, amp) + sx * (xx - xx.mean()) + sy * (yy - yy.mean())
            )
    return h, dict(truth, tiles=nt, tilt=True)


def run_surface_case(kind, seed, root):
    h, dx, truth = make_surface_heights(kind, seed)
    d = Path(root) / f"surface_{seed}_{kind or 'null'}"
    d.mkdir(parents=True, exist_ok=True)
    np.save(d / "scan.npy", h)
    cmd = [
        sys.executable,
        "-m",
        "pipelines.cli",
        "diagnose",
        "--scan",
        str(d / "scan.npy"),
        "--spacing",
        f"{dx:.10g}",
        "--out",
        str(d / "out"),
    ]
    t = time.perf_counter()
    pr = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    dt = time.perf_counter() - t
    if pr.returncode != 0:
        return dict(kind=kind or "null", seed=seed, error=pr.stderr.strip()[-300:], seconds=dt, truth=truth)
    diag = json.loads((d / "out" / "diagnosis.json").read_text())
    names = verdict_names(diag)
    label = _label(diag, names)
    return dict(
        kind=kind or "null",
        seed=seed,
        called=label,
        right=(names == [kind]) if kind else label == "null",
        shrink=(diag.get("verdict") or {}).get("shrink"),
        seconds=dt,
        truth=truth,
        inconclusive=(diag.get("verdict") or {}).get("inconclusive"),
        families={k: round(v["gap_baseline"], 2) for k, v in (diag.get("families") or {}).items()},
    )


def surface_report(rows):
    print("\n== surface level (k-fold over blocks) ==")
    for k in SURFACE_KINDS:
        sel = [r for r in rows if r["kind"] == (k or "null")]
        if sel:
            print(
                f"  {k or 'null':12s} {sum(r.get('right', False) for r in sel)}/{len(sel)}  called: "
                + ", ".join(r.get("called", "ERROR") for r in sel)
            )
    eff = [r for r in rows if r["kind"] != "null"]
    nul = [r for r in rows if r["kind"] == "null"]
    ok = sum(r.get("right", False) for r in eff)
    sh = [r["shrink"] for r in eff if r.get("right") and r.get("shrink") is not None]
    print(
        f"  effect cases named right: {ok}/{len(eff)} = {100 * ok / max(1, len(eff)):.0f} %; "
        f"false positives on nulls: {sum(not r.get('right', False) for r in nul)}/{len(nul)}; "
        f"median shrink (right verdicts) {np.median(sh) if sh else float('nan'):.2f}; "
        f"median time {np.median([r['seconds'] for r in rows]):.1f} s"
    )
    for r in rows:
        if not r.get("right"):
            print(
                f"  miss: {r['kind']} seed {r['seed']} -> {r.get('called')} {r.get('error', '')} "
                f"truth {r['truth']} families {r.get('families')}"
            )


def run_surface_level(seed, per_kind, jobs, keep=None):
    """``per_kind`` surface cases of each kind from ``seed``; returns the rows."""
    root = Path(keep) if keep else Path(tempfile.mkdtemp(prefix="blind_surf_"))
    specs = [(k, seed + 7919 * i + 17 * j) for j, k in enumerate(SURFACE_KINDS) for i in range(per_kind)]
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as ex:
        rows = list(ex.map(lambda kv: run_surface_case(kv[0], kv[1], root), specs))
    if not keep:
        shutil.rmtree(root, ignore_errors=True)
    for r in rows:
        r["seed_set"] = seed
    return rows
