"""Blind check of ``roadscan diagnose`` (issue 5, "Proof on withheld effects").

The cases are made here, independently of ``pipelines/diagnose`` (which is treated as a black box:
only its command line and its ``diagnosis.json`` contract are used). Each effect is implemented
in its own way from the issue text and DESIGN.md, on top of the friction engine's public API:

=====================  =====================================================================
hidden effect           how the "real" mu(v) is made here
=====================  =====================================================================
flash_temperature       ``friction.mu_flash`` with zeta_m ~ U(2, 5), conductivity ~ U(0.15, 0.5)
                        W/(m K), rho ~ U(1000, 1400) kg/m^3, c_v ~ U(1200, 2000) J/(kg K)
relaxation_spectrum     a Prony series of 6-10 terms whose weights follow a log-normal
                        distribution of relaxation times (width 0.4-1.5 decades, centre within
                        +-0.3 decades of the SLS's Prony time tau/(1+a1)), same rubbery and glassy
                        moduli as the SLS, same WLF
temperature_offset      the run's background temperature T0 = T_ref + dT, |dT| ~ U(5, 25) C
fine_roughness          the true surface continues its self-affine law beyond the Nyquist wave
                        vector of the scan / psd.csv up to q1 = f q_Nyquist, f ~ logU(3, 30)
water                   (scans only) the rain-filled scan (roadscan.rain.rain_fill, 4-connected)
                        with a water film of 20-100 % of the depressions' capacity
adhesion                mu_adh = tau_f / sigma0 * P(q1, v) * s(v), tau_f ~ logU(0.5, 10) MPa,
                        P(q1, v) the engine's relative contact area at the finest scale, s a
                        bell in log10 v (centre 1e-6..1e-3 m/s, width 0.7-1.5 decades) or a
                        decreasing 1 / (1 + v / v_c) (v_c 1e-6..1e-3 m/s)
load                    the true sigma0 differs from the nominal by a factor logU in
                        [0.2, 0.6] or [1.7, 5]
contact_correction      ``contact_gamma`` = gamma ~ U(0.25, 0.6) in the engine
null                    the model itself
=====================  =====================================================================

All with multiplicative log-normal noise of 2-5 % and 20-40 log-spaced speeds (jittered) spanning
3-5 decades within 1e-6..30 m/s. Surfaces are a ``psd.csv`` (Persson's normalisation, header
``q_per_m,C_m4``) tabulated from an analytic self-affine spectrum with a roll-off, or a scan made by
``roadscan.synth.self_affine_surface`` written as ``.npy`` (+ ``--spacing``) or ``.x3p``.

Identifiability (issue 5): a case *counts* when (a) its clean effect moves mu by
rms log10(mu_eff / mu_model) > ``K_SIGNAL`` x the noise rms (log10), and (b) none of the other
effects, fitted here with simple one- or two-parameter versions of this file's own effect models
(temperature_offset, load, contact_correction, fine_roughness, flash zeta_m, adhesion amplitude and
v_c, relaxation spread with its centre fixed; water is not refitted), explains the noisy data to within
``K_ALT`` x the noise rms. Accuracy is printed unfiltered, with (a) only, and with (a)+(b).

Surface level (issue 11, ``--surface N``: N cases of each kind per seed set): area scans
made here from ``roadscan.synth.self_affine_surface`` (cropped from a map twice as large, so not
periodic; 256 x 256, spacing 40-80 um, H 0.7-0.9), written as ``.npy`` with ``--spacing``:

=====================  =====================================================================
hidden surface effect   how the scan is made here
=====================  =====================================================================
anisotropy              a self-affine map stretched along x by 2-4 (cubic resampling); a third
                        of the cases: stretched, then turned by 15-75 degrees
height_skew             heights rank-mapped onto a gamma law of skewness +-(0.8-1.8); a third:
                        an exponential map (log-normal law) of skewness +-(0.8-1.8)
seams                   stitching: tiles of 3 or 4 per side with random height offsets of
                        0.2-0.5 rms, or 2-4 straight steps along x or y at random positions; a
                        third: 3 x 3 or 4 x 4 tiles each with its own offset and tilt residue
rolloff                 the synthesis' own roll-off at q_r = (3-6) 2 pi / L (periodic map); a
                        third: a map twice as large with the roll-off, cropped
noise_floor             white measurement noise of 2-6 % rms, or optical smoothing (Gaussian
                        blur of 1.5-3 points)
null                    the cropped self-affine map itself
=====================  =====================================================================

The variants draw from their own random stream, so a seed's main recipe does not change.
Several seed sets (``--seeds``, default 1000,2000,3000) give the per-kind table over all of them
at the end; ``--quick`` runs one seed set small (2 surface cases per kind, 8 friction cases and 3
nulls). The generator imports ``friction``, ``roadscan`` and ``pipelines.spectrum_bridge`` (the
metrology chain, for the scan surfaces' PSD), never ``pipelines.diagnose``.

Usage::

    .venv/bin/python benchmarks/bench_diagnose_blind.py [--seeds 1000,2000,3000] [--surface 5]
        [--cases 40] [--nulls 10] [--level both|surface|friction] [--quick] [--jobs 2]
        [--keep DIR] [--json FILE]
"""
from __future__ import annotations

import argparse
import collections
import json
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import optimize

import friction as F

ROOT = Path(__file__).resolve().parents[1]
EFFECTS = ("flash_temperature", "relaxation_spectrum", "temperature_offset", "fine_roughness",
           "water", "adhesion", "load", "contact_correction")
SIGMA0_PA = 0.2e6
K_SIGNAL = 3.0   # effect counts when its clean gap exceeds this many noise rms
K_ALT = 1.5      # another effect "explains it" when its best fit leaves <= this many noise rms
LN10 = np.log(10.0)


# ----------------------------------------------------------------------------- surfaces
@dataclass
class Surface:
    """A surface as the diagnosis sees it (CLI arguments) and as the truth knows it."""

    cli: list                    # e.g. ["--psd", path] or ["--scan", path, "--spacing", "5e-5"]
    kind: str                    # "psd" or "scan"
    psd: object                  # friction PSD of what was given (what the model integrates)
    q_nyq_per_m: float
    extend: callable             # q1 -> friction PSD continued by the true law up to q1
    heightmap: object = None     # levelled scan (for water)
    info: dict = field(default_factory=dict)


def _psd_surface(rng, d):
    H = rng.uniform(0.7, 0.9)
    q0 = 10 ** rng.uniform(np.log10(600), np.log10(3000))
    q_roll = q0 / rng.uniform(2.0, 5.0)
    a_m = rng.uniform(20e-6, 80e-6)
    q_nyq = np.pi / a_m
    band_rms = rng.uniform(0.2e-3, 1.0e-3)
    h0 = np.sqrt(2) * band_rms / np.sqrt(1 - (q_nyq / q0) ** (-2 * H))
    truth = lambda q1: F.SelfAffinePSD(H, h0, q0, q1, q_roll_per_m=q_roll)
    q = np.logspace(np.log10(q_roll), np.log10(q_nyq), int(20 * np.log10(q_nyq / q_roll)) + 1)
    C = truth(q_nyq).C(q)
    path = d / "psd.csv"
    np.savetxt(path, np.column_stack([q, C]), delimiter=",", header="q_per_m,C_m4",
               comments="", fmt="%.10e")
    given = F.TabulatedPSD(q, C)

    def extend(q1):
        qe = np.logspace(np.log10(q_roll), np.log10(q1), int(20 * np.log10(q1 / q_roll)) + 1)
        return F.TabulatedPSD(qe, truth(q1).C(qe))

    return Surface(["--psd", str(path)], "psd", given, q_nyq, extend,
                   info=dict(H=H, q0=q0, q_roll=q_roll, a_m=a_m, band_rms_m=band_rms))


def _scan_surface(rng, d, small=False):
    from pipelines.spectrum_bridge import analyse_surface, surface_psd
    from roadscan import io as rio
    from roadscan.synth import model_psd, self_affine_surface

    n = int(rng.choice([128, 160, 192]) if small else rng.choice([256, 320, 384]))
    dx = rng.uniform(40e-6, 80e-6)
    H = rng.uniform(0.7, 0.9)
    L = n * dx
    q_roll = 2 * np.pi / L * rng.uniform(3.0, 6.0)
    rms = rng.uniform(0.3e-3, 1.0e-3)
    hm = self_affine_surface(n, dx_m=dx, hurst=H, rms_height_m=rms, q_roll_per_m=q_roll,
                             seed=int(rng.integers(2**31)))
    K = hm.meta["model"]["prefactor_m4"]
    if rng.random() < 0.5:
        path = d / "scan.npy"
        rio.write(path, hm)
        cli = ["--scan", str(path), "--spacing", f"{dx:.10g}"]
    else:
        path = d / "scan.x3p"
        rio.write(path, hm)
        cli = ["--scan", str(path)]
    sa = analyse_surface(hm)
    given = surface_psd(sa.spectrum, sa.fit)
    q_nyq = np.pi / dx

    def extend(q1):
        qm, Cm = given.q_per_m, given.C_m4
        qe = np.logspace(np.log10(qm[-1]), np.log10(q1), int(20 * np.log10(q1 / qm[-1])) + 2)[1:]
        # the synthesis' own law beyond Nyquist, matched to the measured level at the top decade
        top = qm > qm[-1] / 10
        scale = np.exp(np.mean(np.log(Cm[top] / model_psd(qm[top], H, K))))
        return F.TabulatedPSD(np.r_[qm, qe], np.r_[Cm, scale * model_psd(qe, H, K)],
                              q0_per_m=given.q0_per_m)

    return Surface(cli, "scan", given, q_nyq, extend, heightmap=sa.levelled,
                   info=dict(H=H, n=n, dx_m=dx, q_roll=q_roll, rms_m=rms, file=path.suffix))


# ----------------------------------------------------------------------------- effects
def lognormal_prony(spread_dec, shift_dec, n_terms, base=None):
    """A Prony series with the SLS's rubbery/glassy moduli and log-normally spread times.

    Weights E_i ~ exp(-(log10 tau_i - c)^2 / (2 s^2)) on ``n_terms`` log-spaced times over
    c +- 2.5 s, normalised to the SLS's relaxation strength E1 a1 / (1 + a1);
    c = log10(tau / (1 + a1)) + ``shift_dec``.
    """
    sls = F.thesis_rubber() if base is None else base
    E_inf = sls.E1_Pa / (1 + sls.a1)
    strength = sls.E1_Pa * sls.a1 / (1 + sls.a1)
    c = np.log10(sls.tau_s / (1 + sls.a1)) + shift_dec
    s = max(spread_dec, 1e-3)
    lt = np.linspace(c - 2.5 * s, c + 2.5 * s, n_terms)
    w = np.exp(-0.5 * ((lt - c) / s) ** 2)
    return F.Prony(E_inf, strength * w / w.sum(), 10 ** lt, T_ref_C=sls.T_ref_C, shift=sls.shift,
                   thermal=sls.thermal)


def adhesion_shape(v, kind, v_c, width_dec=1.0):
    v = np.asarray(v, float)
    if kind == "bell":
        return np.exp(-0.5 * (np.log10(v / v_c) / width_dec) ** 2)
    return 1.0 / (1.0 + v / v_c)


def draw_params(rng, effect, surf):
    if effect == "flash_temperature":
        return dict(zeta_m=rng.uniform(2, 5), conductivity_W_mK=rng.uniform(0.15, 0.5),
                    rho_kg_m3=rng.uniform(1000, 1400), c_v_J_kgK=rng.uniform(1200, 2000))
    if effect == "relaxation_spectrum":
        return dict(spread_dec=rng.uniform(0.4, 1.5), shift_dec=rng.uniform(-0.3, 0.3),
                    n_terms=int(rng.integers(6, 11)))
    if effect == "temperature_offset":
        return dict(dT_C=float(rng.choice([-1, 1]) * rng.uniform(5, 25)))
    if effect == "fine_roughness":
        f = 10 ** rng.uniform(np.log10(3), np.log10(30))
        return dict(q1_factor=f, q1_per_m=f * surf.q_nyq_per_m)
    if effect == "water":
        return dict(film_fraction=rng.uniform(0.2, 1.0))
    if effect == "adhesion":
        kind = str(rng.choice(["bell", "decreasing"]))
        return dict(tau_f_Pa=10 ** rng.uniform(np.log10(0.5e6), np.log10(10e6)), shape=kind,
                    v_c_m_per_s=10 ** rng.uniform(-6, -3), width_dec=rng.uniform(0.7, 1.5))
    if effect == "load":
        lo = rng.random() < 0.5
        f = 10 ** (rng.uniform(np.log10(0.2), np.log10(0.6)) if lo
                   else rng.uniform(np.log10(1.7), np.log10(5)))
        return dict(sigma0_factor=f)
    if effect == "contact_correction":
        return dict(gamma=rng.uniform(0.25, 0.6))
    return {}


def true_mu(effect, p, surf, v, T0_C=None, sigma0_Pa=SIGMA0_PA, cache=None):
    """mu(v) of the hidden truth at the given conditions (``effect`` None: the model itself)."""
    rub = F.thesis_rubber()
    psd = surf.psd
    kw = dict(sigma0_Pa=sigma0_Pa, T0_C=T0_C)
    if effect is None:
        return F.mu_isothermal(psd, rub, v, **kw).mu
    if effect == "flash_temperature":
        th = F.Thermal(p["rho_kg_m3"], p["c_v_J_kgK"], p["conductivity_W_mK"])
        r = F.StandardLinearSolid(T_ref_C=rub.T_ref_C, shift=rub.shift, thermal=th)
        return F.mu_flash(psd, r, v, zeta_m=p["zeta_m"], tol=2e-3, **kw).mu
    if effect == "relaxation_spectrum":
        r = lognormal_prony(p["spread_dec"], p["shift_dec"], p["n_terms"])
        return F.mu_isothermal(psd, r, v, **kw).mu
    if effect == "temperature_offset":
        T = (rub.T_ref_C if T0_C is None else T0_C) + p["dT_C"]
        return F.mu_isothermal(psd, rub, v, sigma0_Pa=sigma0_Pa, T0_C=T).mu
    if effect == "fine_roughness":
        return F.mu_isothermal(surf.extend(p["q1_per_m"]), rub, v, **kw).mu
    if effect == "water":
        wet = _wet_psd(surf, p["film_fraction"], cache)
        return F.mu_isothermal(wet, rub, v, **kw).mu
    if effect == "adhesion":
        res = F.mu_isothermal(psd, rub, v, **kw)
        a_frac = res.P[:, -1]
        return res.mu + p["tau_f_Pa"] / sigma0_Pa * a_frac * adhesion_shape(
            v, p["shape"], p["v_c_m_per_s"], p["width_dec"])
    if effect == "load":
        return F.mu_isothermal(psd, rub, v, sigma0_Pa=sigma0_Pa * p["sigma0_factor"],
                               T0_C=T0_C).mu
    if effect == "contact_correction":
        return F.mu_isothermal(psd, rub, v, contact_gamma=p["gamma"], **kw).mu
    raise ValueError(effect)


def _wet_psd(surf, film_fraction, cache=None):
    from pipelines.spectrum_bridge import analyse_surface, surface_psd
    from roadscan.rain import rain_fill

    key = ("wet", round(film_fraction, 6))
    if cache is not None and key in cache:
        return cache[key]
    cap = rain_fill(surf.heightmap).meta["capacity_m3_per_m2"]
    rf = rain_fill(surf.heightmap, water_film_m=film_fraction * cap) if film_fraction < 1 \
        else rain_fill(surf.heightmap)
    sa = analyse_surface(rf.wet)
    out = surface_psd(sa.spectrum, sa.fit)
    if cache is not None:
        cache[key] = out
    return out


# ----------------------------------------------------------------------------- own alternative fits
def _rms(x):
    return float(np.sqrt(np.mean(np.square(x))))


def alternative_fits(y_log, surf, v, skip):
    """Best rms log10 residual of each simple alternative effect fitted to log10 mu data.

    ``skip`` is the hidden effect (not refitted). Each family is this file's own model with one
    or two parameters fitted by bounded scalar minimisation or Nelder-Mead.
    """
    rub = F.thesis_rubber()
    base = F.mu_isothermal(surf.psd, rub, v)
    out = {}

    def res(mu):
        return _rms(y_log - np.log10(np.maximum(mu, 1e-300)))

    def fit1(fun, lo, hi):
        r = optimize.minimize_scalar(lambda x: res(fun(x)), bounds=(lo, hi), method="bounded",
                                     options=dict(xatol=1e-3 * (hi - lo)))
        grid = [res(fun(x)) for x in np.linspace(lo, hi, 7)]
        return min(float(r.fun), min(grid))

    if skip != "temperature_offset":
        out["temperature_offset"] = fit1(
            lambda dT: F.mu_isothermal(surf.psd, rub, v, T0_C=rub.T_ref_C + dT).mu, -40, 40)
    if skip != "load":
        out["load"] = fit1(lambda lf: F.mu_isothermal(surf.psd, rub, v,
                                                      sigma0_Pa=SIGMA0_PA * 10 ** lf).mu, -1, 1)
    if skip != "contact_correction":
        out["contact_correction"] = fit1(
            lambda g: F.mu_isothermal(surf.psd, rub, v, contact_gamma=g).mu, 0.0, 1.0)
    if skip != "fine_roughness":
        out["fine_roughness"] = fit1(
            lambda lf: F.mu_isothermal(surf.extend(surf.q_nyq_per_m * 10 ** lf), rub, v).mu,
            0.01, 2.0)
    if skip != "flash_temperature":
        out["flash_temperature"] = min(
            res(F.mu_flash(surf.psd, rub, v, zeta_m=z, tol=3e-3).mu) for z in (2.0, 3.0, 4.0, 5.0))
    if skip != "adhesion":
        a_frac = base.P[:, -1]

        def adh(x):
            lt, lv, w = np.clip(x, [3.0, -9.0, 0.1], [9.0, 2.0, 5.0])
            return base.mu + 10 ** lt / SIGMA0_PA * a_frac * adhesion_shape(v, "bell", 10 ** lv, w)
        best = min(optimize.minimize(lambda x: res(adh(x)), x0, method="Nelder-Mead",
                                     options=dict(maxiter=300)).fun
                   for x0 in ([6.0, -5.0, 1.0], [7.0, -3.0, 1.5], [5.0, -1.0, 1.0]))
        out["adhesion"] = float(best)
    if skip != "relaxation_spectrum":
        # spread only, centre fixed at the SLS's time: with a free centre the family would
        # contain the temperature offset itself (a pure shift of log tau), which has fewer
        # parameters and must win on parsimony
        out["relaxation_spectrum"] = fit1(
            lambda s: F.mu_isothermal(surf.psd, lognormal_prony(s, 0.0, 8), v).mu, 0.05, 2.0)
    return out


# ----------------------------------------------------------------------------- cases
@dataclass
class Case:
    seed: int
    effect: str | None
    params: dict
    surface: Surface
    v: np.ndarray
    mu_model: np.ndarray
    mu_clean: np.ndarray
    mu_meas: np.ndarray
    noise_rel: float
    dir: Path
    validate: dict = None        # condition, path, model gap of the validation data
    signal_gap: float = 0.0      # rms log10(mu_clean / mu_model)
    alt: dict = None

    @property
    def noise_log10(self):
        return self.noise_rel / LN10

    @property
    def strong(self):
        return self.effect is None or self.signal_gap > K_SIGNAL * self.noise_log10

    @property
    def unambiguous(self):
        if self.effect is None or not self.alt:
            return True
        return min(self.alt.values()) > K_ALT * self.noise_log10


def draw_speeds(rng, n=None):
    n = int(rng.integers(20, 41)) if n is None else n
    span = rng.uniform(3.0, 5.0)
    hi_max = np.log10(30.0)
    # make the top end reach at least 1e-2 m/s half of the time, so high-speed effects can show
    lo = rng.uniform(-6.0, hi_max - span)
    lv = np.linspace(lo, lo + span, n)
    lv[1:-1] += rng.uniform(-0.3, 0.3, n - 2) * span / (n - 1)
    return 10 ** np.sort(lv)


def write_mu_csv(path, v, mu, T0_C=None, sigma0_Pa=None):
    cols, names = [v, mu], ["v_m_per_s", "mu"]
    if T0_C is not None:
        cols.append(np.full_like(v, T0_C)); names.append("T0_C")
    if sigma0_Pa is not None:
        cols.append(np.full_like(v, sigma0_Pa)); names.append("sigma0_Pa")
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=",".join(names), comments="",
               fmt="%.10e")


def make_case(seed, effect, workdir, kind=None, small=False, with_alt=True, with_validate=True):
    """One blind case in ``workdir`` (files: mu.csv, psd.csv or scan, validate.csv)."""
    rng = np.random.default_rng(seed)
    d = Path(workdir)
    d.mkdir(parents=True, exist_ok=True)
    if kind is None:
        kind = "scan" if (effect == "water" or rng.random() < 0.35) else "psd"
    surf = _scan_surface(rng, d, small) if kind == "scan" else _psd_surface(rng, d)
    v = draw_speeds(rng)
    p = draw_params(rng, effect, surf)
    cache = {}
    mu_model = F.mu_isothermal(surf.psd, F.thesis_rubber(), v).mu
    mu_clean = true_mu(effect, p, surf, v, cache=cache)
    noise = rng.uniform(0.02, 0.05)
    mu_meas = mu_clean * np.exp(noise * rng.standard_normal(v.size))
    write_mu_csv(d / "mu.csv", v, mu_meas)
    case = Case(seed, effect, p, surf, v, mu_model, mu_clean, mu_meas, noise, d)
    case.signal_gap = _rms(np.log10(mu_clean / mu_model))
    if with_validate and effect is not None:
        # a second measurement at another temperature (or load), same hidden effect
        if rng.random() < 0.5:
            cond = dict(T0_C=60.0 + float(rng.choice([-1, 1]) * rng.uniform(8, 15)))
        else:
            cond = dict(sigma0_Pa=SIGMA0_PA * float(rng.choice([0.5, 2.0])))
        vv = draw_speeds(rng, 20)
        mv_clean = true_mu(effect, p, surf, vv, cache=cache, **cond)
        mv_model = F.mu_isothermal(surf.psd, F.thesis_rubber(), vv, **cond).mu
        mv = mv_clean * np.exp(noise * rng.standard_normal(vv.size))
        write_mu_csv(d / "validate.csv", vv, mv, **cond)
        case.validate = dict(cond=cond, path=str(d / "validate.csv"),
                             model_gap=_rms(np.log10(mv / mv_model)),
                             clean_gap=_rms(np.log10(mv_clean / mv_model)))
    if with_alt and effect is not None and case.strong:
        case.alt = alternative_fits(np.log10(mu_meas), surf, v, effect)
    return case


# ----------------------------------------------------------------------------- running
def run_diagnose(case, extra=(), validate=True, out_name="out"):
    out = case.dir / out_name
    cmd = [sys.executable, "-m", "pipelines.cli", "diagnose", "--measured",
           str(case.dir / "mu.csv"), *case.surface.cli, "--out", str(out), *extra]
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


def score(case, diag):
    """(strict hit, lenient hit, called label). On a null case, an inconclusive verdict is a
    miss (it is not "no effect")."""
    names = verdict_names(diag) if "error" not in diag else ["<error>"]
    label = _label(diag, names)
    if case.effect is None:
        return label == "null", label == "null", label
    strict = names == [case.effect]
    lenient = case.effect in names
    return strict, lenient, label


def _fmt_params(p):
    return ", ".join(f"{k}={v:.3g}" if isinstance(v, float) else f"{k}={v}" for k, v in p.items())


# ----------------------------------------------------------------------------- surface level
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
        return self_affine_surface(n, dx_m=dx, hurst=H, rms_height_m=rms, q_roll_per_m=qr,
                                   seed=int(rng.integers(2**31))).heights_m, dx, truth
    big = self_affine_surface(2 * n, dx_m=dx, hurst=H, rms_height_m=rms, seed=int(rng.integers(2**31))).heights_m
    h = big[:n, :n].copy()
    if kind == "anisotropy":
        r = rng.uniform(2, 4)
        truth["stretch"] = r
        h = zoom(big[:n, :int(n / r) + 2], (1, r), order=3)[:, :n]
    elif kind == "height_skew":
        sk = rng.uniform(0.8, 1.8) * rng.choice([-1, 1])
        truth["skewness"] = sk
        flat = h.ravel()
        u = (stats.rankdata(flat) - 0.5) / flat.size
        k = 4 / sk ** 2
        g = stats.gamma.ppf(u if sk > 0 else 1 - u, k)
        h = ((g - k) / np.sqrt(k) * np.sign(sk) * flat.std()).reshape(h.shape)
    elif kind == "seams":
        if rng.random() < 0.5:
            nt = int(rng.choice([3, 4]))
            off = rng.normal(0, rng.uniform(0.2, 0.5) * h.std(), (nt, nt))
            e = np.linspace(0, n, nt + 1).astype(int)
            for j in range(nt):
                for i in range(nt):
                    h[e[j]:e[j + 1], e[i]:e[i + 1]] += off[j, i]
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
    from scipy import optimize
    from scipy.ndimage import rotate, zoom
    from roadscan.synth import self_affine_surface

    truth = dict(H=truth["H"], dx_m=truth["dx_m"], variant=True)
    if kind == "rolloff":
        # roll-off on a map twice as large, cropped (not periodic)
        qr = 2 * np.pi / (n * dx) * rng.uniform(3, 6)
        big = self_affine_surface(2 * n, dx_m=dx, hurst=H, rms_height_m=rms, q_roll_per_m=qr,
                                  seed=int(rng.integers(2**31))).heights_m
        return big[:n, :n].copy(), dict(truth, q_roll_per_m=qr, cropped=True)
    big = self_affine_surface(3 * n, dx_m=dx, hurst=H, rms_height_m=rms, seed=int(rng.integers(2**31))).heights_m
    if kind == "anisotropy":
        # stretched by 2-4 along x, then turned by 15-75 degrees (cubic), centre cut out
        r, ang = rng.uniform(2, 4), rng.uniform(15, 75) * rng.choice([-1, 1])
        st = zoom(big[:, :int(3 * n / r) + 2], (1, r), order=3)[:, :3 * n]
        h = rotate(st, ang, reshape=False, order=3)[n:2 * n, n:2 * n]
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
            yy, xx = np.mgrid[e[j]:e[j + 1], e[i]:e[i + 1]]
            sy, sx = rng.normal(0, amp, 2) / (n / nt)
            h[e[j]:e[j + 1], e[i]:e[i + 1]] += rng.normal(0, amp) + sx * (xx - xx.mean()) + sy * (yy - yy.mean())
    return h, dict(truth, tiles=nt, tilt=True)


def run_surface_case(kind, seed, root):
    h, dx, truth = make_surface_heights(kind, seed)
    d = Path(root) / f"surface_{seed}_{kind or 'null'}"
    d.mkdir(parents=True, exist_ok=True)
    np.save(d / "scan.npy", h)
    cmd = [sys.executable, "-m", "pipelines.cli", "diagnose", "--scan", str(d / "scan.npy"),
           "--spacing", f"{dx:.10g}", "--out", str(d / "out")]
    t = time.perf_counter()
    pr = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    dt = time.perf_counter() - t
    if pr.returncode != 0:
        return dict(kind=kind or "null", seed=seed, error=pr.stderr.strip()[-300:], seconds=dt, truth=truth)
    diag = json.loads((d / "out" / "diagnosis.json").read_text())
    names = verdict_names(diag)
    label = _label(diag, names)
    return dict(kind=kind or "null", seed=seed, called=label,
                right=(names == [kind]) if kind else label == "null",
                shrink=(diag.get("verdict") or {}).get("shrink"), seconds=dt, truth=truth,
                inconclusive=(diag.get("verdict") or {}).get("inconclusive"),
                families={k: round(v["gap_baseline"], 2) for k, v in (diag.get("families") or {}).items()})


def surface_report(rows):
    print("\n== surface level (k-fold over blocks) ==")
    for k in SURFACE_KINDS:
        sel = [r for r in rows if r["kind"] == (k or "null")]
        if sel:
            print(f"  {k or 'null':12s} {sum(r.get('right', False) for r in sel)}/{len(sel)}  called: "
                  + ", ".join(r.get("called", "ERROR") for r in sel))
    eff = [r for r in rows if r["kind"] != "null"]
    nul = [r for r in rows if r["kind"] == "null"]
    ok = sum(r.get("right", False) for r in eff)
    sh = [r["shrink"] for r in eff if r.get("right") and r.get("shrink") is not None]
    print(f"  effect cases named right: {ok}/{len(eff)} = {100 * ok / max(1, len(eff)):.0f} %; "
          f"false positives on nulls: {sum(not r.get('right', False) for r in nul)}/{len(nul)}; "
          f"median shrink (right verdicts) {np.median(sh) if sh else float('nan'):.2f}; "
          f"median time {np.median([r['seconds'] for r in rows]):.1f} s")
    for r in rows:
        if not r.get("right"):
            print(f"  miss: {r['kind']} seed {r['seed']} -> {r.get('called')} {r.get('error', '')} "
                  f"truth {r['truth']} families {r.get('families')}")


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
        rows.append(dict(seed=c.seed, seed_set=seed, effect=c.effect or "null", called=label, strict=strict,
                         lenient=lenient, strong=c.strong, unambiguous=c.unambiguous,
                         signal_gap=c.signal_gap, noise_log10=c.noise_log10,
                         alt=c.alt, seconds=dt, kind=c.surface.kind + c.surface.info.get("file", ""),
                         shrink=ver.get("shrink"), gap_validate=ver.get("gap_validate"),
                         validate_model_gap=(c.validate or {}).get("model_gap"),
                         validate_cond=(c.validate or {}).get("cond"),
                         baseline_gap=diag.get("baseline_gap"), noise_est=diag.get("noise"),
                         params=c.params, v_range=[float(c.v[0]), float(c.v[-1]), int(c.v.size)],
                         error=diag.get("error"), inconclusive=ver.get("inconclusive"),
                         top=[(e.get("name"), e.get("gap_heldout")) for e in
                              (diag.get("effects") or [])[:3]]))
    if not keep:
        shutil.rmtree(root, ignore_errors=True)
    return rows, t_gen


def summary_tables(surf, fric):
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
        out.append(f"  effect cases named right {ok}/{len(eff)} = {100 * ok / max(1, len(eff)):.0f} % (target >= 80 %, "
                   f">= 3/5 per kind); false positives {sum(not r.get('right', False) for r in nul)}/{len(nul)} "
                   f"(<= 10 %); median held-out shrink of right verdicts {np.median(sh) if sh else float('nan'):.2f} "
                   f"(>= 0.5); median time per diagnosis {np.median([r['seconds'] for r in surf]):.1f} s")
    if fric:
        seeds = sorted({r["seed_set"] for r in fric})
        out.append("\n== friction level, all seed sets (counted: signal > 3 x noise, no own alternative within 1.5 x) ==")
        for s in seeds + [None]:
            sel = [r for r in fric if s is None or r["seed_set"] == s]
            eff = [r for r in sel if r["effect"] != "null" and r["strong"] and r["unambiguous"]]
            nul = [r for r in sel if r["effect"] == "null"]
            ok = sum(r["strict"] for r in eff)
            sh = [r["shrink"] for r in eff if r["strict"] and r["shrink"] is not None]
            allc = [r for r in sel if r["effect"] != "null"]
            out.append(f"  {'all' if s is None else 'seed ' + str(s):10s} counted {ok}/{len(eff)} = "
                       f"{100 * ok / max(1, len(eff)):.1f} % (unfiltered {sum(r['strict'] for r in allc)}/{len(allc)}); "
                       f"false positives {sum(r['called'] != 'null' for r in nul)}/{len(nul)}; median shrink "
                       f"{np.median(sh) if sh else float('nan'):.3f}")
        per = collections.defaultdict(lambda: [0, 0])
        for r in fric:
            if r["effect"] != "null" and r["strong"] and r["unambiguous"]:
                per[r["effect"]][0] += r["strict"]
                per[r["effect"]][1] += 1
        out.append("  per effect (counted): " + ", ".join(f"{e} {a}/{b}" for e, (a, b) in sorted(per.items())))
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", type=int, default=40, help="friction-level effect cases per seed set (default 40)")
    ap.add_argument("--nulls", type=int, default=10, help="friction-level null cases per seed set (default 10)")
    ap.add_argument("--seed", type=int, default=None, help="one seed set (same as --seeds N)")
    ap.add_argument("--seeds", default="1000,2000,3000", help="comma-separated seed sets (default 1000,2000,3000)")
    ap.add_argument("--jobs", type=int, default=2, help="diagnoses run in parallel")
    ap.add_argument("--keep", default=None, help="keep case files here")
    ap.add_argument("--json", default=None, help="write per-case results (both levels) here")
    ap.add_argument("--surface", type=int, default=5, help="surface-level cases per kind and seed set (default 5; 0: none)")
    ap.add_argument("--level", choices=("both", "surface", "friction"), default="both")
    ap.add_argument("--quick", action="store_true",
                    help="one seed set, 2 surface cases per kind, 8 friction cases and 3 nulls (about 5 min on 2 cores)")
    a = ap.parse_args(argv)
    seeds = [a.seed] if a.seed is not None else [int(x) for x in a.seeds.split(",") if x.strip()]
    if a.quick:
        seeds, a.surface, a.cases, a.nulls = seeds[:1], 2, 8, 3
    t_all = time.perf_counter()
    surf, fric = [], []
    for s in seeds:
        keep = None if a.keep is None else str(Path(a.keep) / f"seed_{s}")
        if a.level in ("both", "surface") and a.surface:
            rows = run_surface_level(s, a.surface, a.jobs, keep and keep + "_surface")
            print(f"\n#### seed set {s}")
            surface_report(rows)
            surf += rows
        if a.level in ("both", "friction") and (a.cases or a.nulls):
            rows, t_gen = run_friction_level(s, a.cases, a.nulls, a.jobs, keep and keep + "_friction")
            print(f"\n#### seed set {s}")
            report(rows, t_gen)
            fric += rows
    print(summary_tables(surf, fric))
    print(f"\ntotal wall time {time.perf_counter() - t_all:.0f} s ({a.jobs} jobs)")
    if a.json:
        Path(a.json).write_text(json.dumps(dict(surface=surf, friction=fric), indent=1, default=str))
    return 0


def report(rows, t_gen=0.0):
    eff = [r for r in rows if r["effect"] != "null"]
    nul = [r for r in rows if r["effect"] == "null"]

    def acc(sel, key):
        return (sum(r[key] for r in sel) / len(sel), len(sel)) if sel else (float("nan"), 0)

    print("\n== top-1 attribution accuracy ==")
    for name, sel in (("unfiltered", eff),
                      (f"signal > {K_SIGNAL:g} x noise", [r for r in eff if r["strong"]]),
                      (f"+ no own alt. fit within {K_ALT:g} x noise",
                       [r for r in eff if r["strong"] and r["unambiguous"]])):
        s, n = acc(sel, "strict")
        l, _ = acc(sel, "lenient")
        print(f"  {name:40s} n={n:3d}  strict {100 * s:5.1f} %   lenient (pair contains) "
              f"{100 * l:5.1f} %")
    counted = [r for r in eff if r["strong"] and r["unambiguous"]]
    sh = [r["shrink"] for r in counted if r["shrink"] is not None and r["strict"]]
    sh_all = [r["shrink"] for r in counted if r["shrink"] is not None]
    print(f"  median held-out shrink (counted, correct verdict): "
          f"{np.median(sh) if sh else float('nan'):.3f}  (all counted with a verdict: "
          f"{np.median(sh_all) if sh_all else float('nan'):.3f})")
    fp = [r for r in nul if r["called"] != "null"]
    print(f"  false positives on nulls: {len(fp)}/{len(nul)} = "
          f"{100 * len(fp) / max(1, len(nul)):.0f} %")
    gv = [(r["gap_validate"], r["validate_model_gap"]) for r in counted
          if r["strict"] and r["gap_validate"] is not None and r["validate_model_gap"]]
    if gv:
        ratio = [g / m for g, m in gv]
        print(f"  --validate (correct verdicts): median gap_validate / model gap on that data = "
              f"{np.median(ratio):.3f} over {len(gv)} cases")
    t = [r["seconds"] for r in rows]
    print(f"  run time per diagnosis: median {np.median(t):.1f} s, max {np.max(t):.1f} s "
          f"(generation {t_gen:.1f} s total)")

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
            print(f"  seed {r['seed']} {r['effect']} ({r['kind']}) -> {r['called']}; "
                  f"signal {r['signal_gap']:.3f} noise {r['noise_log10']:.4f} "
                  f"strong={r['strong']} unamb={r['unambiguous']}{alt}; v {r['v_range']}; "
                  f"params {_fmt_params(r['params'])}; tool top3 {r['top']}"
                  + (f"; ERROR {r['error']}" if r["error"] else ""))


if __name__ == "__main__":
    sys.exit(main())
