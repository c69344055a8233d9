"""Case generator of the blind diagnosis benchmark (see ``bench_diagnose_blind.py``): surfaces, this
file's own implementation of every hidden effect on the friction engine's public API, its own
alternative fits (the identifiability filter) and the seeded cases written as CLI inputs. Never
imports ``pipelines.diagnosis``."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import optimize

import friction as F

ROOT = Path(__file__).resolve().parents[1]
EFFECTS = (
    "flash_temperature",
    "relaxation_spectrum",
    "temperature_offset",
    "fine_roughness",
    "water",
    "adhesion",
    "load",
    "contact_correction",
)
SIGMA0_PA = 0.2e6
K_SIGNAL = 3.0  # effect counts when its clean gap exceeds this many noise rms
K_ALT = 1.5  # another effect "explains it" when its best fit leaves <= this many noise rms
LN10 = np.log(10.0)


# ----------------------------------------------------------------------------- surfaces
@dataclass
class Surface:
    """A surface as the diagnosis sees it (CLI arguments) and as the truth knows it."""

    cli: list  # e.g. ["--psd", path] or ["--scan", path, "--spacing", "5e-5"]
    kind: str  # "psd" or "scan"
    psd: object  # friction PSD of what was given (what the model integrates)
    q_nyq_per_m: float
    extend: callable  # q1 -> friction PSD continued by the true law up to q1
    heightmap: object = None  # levelled scan (for water)
    info: dict = field(default_factory=dict)


def _psd_surface(rng, d):
    H = rng.uniform(0.7, 0.9)
    q0 = 10 ** rng.uniform(np.log10(600), np.log10(3000))
    q_roll = q0 / rng.uniform(2.0, 5.0)
    a_m = rng.uniform(20e-6, 80e-6)
    q_nyq = np.pi / a_m
    band_rms = rng.uniform(0.2e-3, 1.0e-3)
    h0 = np.sqrt(2) * band_rms / np.sqrt(1 - (q_nyq / q0) ** (-2 * H))

    def truth(q1):
        return F.SelfAffinePSD(H, h0, q0, q1, q_roll_per_m=q_roll)

    q = np.logspace(np.log10(q_roll), np.log10(q_nyq), int(20 * np.log10(q_nyq / q_roll)) + 1)
    C = truth(q_nyq).C(q)
    path = d / "psd.csv"
    np.savetxt(path, np.column_stack([q, C]), delimiter=",", header="q_per_m,C_m4", comments="", fmt="%.10e")
    given = F.TabulatedPSD(q, C)

    def extend(q1):
        qe = np.logspace(np.log10(q_roll), np.log10(q1), int(20 * np.log10(q1 / q_roll)) + 1)
        return F.TabulatedPSD(qe, truth(q1).C(qe))

    return Surface(
        ["--psd", str(path)],
        "psd",
        given,
        q_nyq,
        extend,
        info=dict(H=H, q0=q0, q_roll=q_roll, a_m=a_m, band_rms_m=band_rms),
    )


def _scan_surface(rng, d, small=False):
    from pipelines.chain.surface import analyse_surface, surface_psd
    from roadscan import io as rio
    from roadscan.synth import model_psd, self_affine_surface

    n = int(rng.choice([128, 160, 192]) if small else rng.choice([256, 320, 384]))
    dx = rng.uniform(40e-6, 80e-6)
    H = rng.uniform(0.7, 0.9)
    L = n * dx
    q_roll = 2 * np.pi / L * rng.uniform(3.0, 6.0)
    rms = rng.uniform(0.3e-3, 1.0e-3)
    hm = self_affine_surface(
        n, dx_m=dx, hurst=H, rms_height_m=rms, q_roll_per_m=q_roll, seed=int(rng.integers(2**31))
    )
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
        return F.TabulatedPSD(np.r_[qm, qe], np.r_[Cm, scale * model_psd(qe, H, K)], q0_per_m=given.q0_per_m)

    return Surface(
        cli,
        "scan",
        given,
        q_nyq,
        extend,
        heightmap=sa.levelled,
        info=dict(H=H, n=n, dx_m=dx, q_roll=q_roll, rms_m=rms, file=path.suffix),
    )


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
    return F.Prony(
        E_inf, strength * w / w.sum(), 10**lt, T_ref_C=sls.T_ref_C, shift=sls.shift, thermal=sls.thermal
    )


def adhesion_shape(v, kind, v_c, width_dec=1.0):
    v = np.asarray(v, float)
    if kind == "bell":
        return np.exp(-0.5 * (np.log10(v / v_c) / width_dec) ** 2)
    return 1.0 / (1.0 + v / v_c)


def draw_params(rng, effect, surf):
    if effect == "flash_temperature":
        return dict(
            zeta_m=rng.uniform(2, 5),
            conductivity_W_mK=rng.uniform(0.15, 0.5),
            rho_kg_m3=rng.uniform(1000, 1400),
            c_v_J_kgK=rng.uniform(1200, 2000),
        )
    if effect == "relaxation_spectrum":
        return dict(
            spread_dec=rng.uniform(0.4, 1.5),
            shift_dec=rng.uniform(-0.3, 0.3),
            n_terms=int(rng.integers(6, 11)),
        )
    if effect == "temperature_offset":
        return dict(dT_C=float(rng.choice([-1, 1]) * rng.uniform(5, 25)))
    if effect == "fine_roughness":
        f = 10 ** rng.uniform(np.log10(3), np.log10(30))
        return dict(q1_factor=f, q1_per_m=f * surf.q_nyq_per_m)
    if effect == "water":
        return dict(film_fraction=rng.uniform(0.2, 1.0))
    if effect == "adhesion":
        kind = str(rng.choice(["bell", "decreasing"]))
        return dict(
            tau_f_Pa=10 ** rng.uniform(np.log10(0.5e6), np.log10(10e6)),
            shape=kind,
            v_c_m_per_s=10 ** rng.uniform(-6, -3),
            width_dec=rng.uniform(0.7, 1.5),
        )
    if effect == "load":
        lo = rng.random() < 0.5
        f = 10 ** (
            rng.uniform(np.log10(0.2), np.log10(0.6)) if lo else rng.uniform(np.log10(1.7), np.log10(5))
        )
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
            v, p["shape"], p["v_c_m_per_s"], p["width_dec"]
        )
    if effect == "load":
        return F.mu_isothermal(psd, rub, v, sigma0_Pa=sigma0_Pa * p["sigma0_factor"], T0_C=T0_C).mu
    if effect == "contact_correction":
        return F.mu_isothermal(psd, rub, v, contact_gamma=p["gamma"], **kw).mu
    raise ValueError(effect)


def _wet_psd(surf, film_fraction, cache=None):
    from pipelines.chain.surface import analyse_surface, surface_psd
    from roadscan.rain import rain_fill

    key = ("wet", round(film_fraction, 6))
    if cache is not None and key in cache:
        return cache[key]
    cap = rain_fill(surf.heightmap).meta["capacity_m3_per_m2"]
    rf = (
        rain_fill(surf.heightmap, water_film_m=film_fraction * cap)
        if film_fraction < 1
        else rain_fill(surf.heightmap)
    )
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
        r = optimize.minimize_scalar(
            lambda x: res(fun(x)), bounds=(lo, hi), method="bounded", options=dict(xatol=1e-3 * (hi - lo))
        )
        grid = [res(fun(x)) for x in np.linspace(lo, hi, 7)]
        return min(float(r.fun), min(grid))

    if skip != "temperature_offset":
        out["temperature_offset"] = fit1(
            lambda dT: F.mu_isothermal(surf.psd, rub, v, T0_C=rub.T_ref_C + dT).mu, -40, 40
        )
    if skip != "load":
        out["load"] = fit1(
            lambda lf: F.mu_isothermal(surf.psd, rub, v, sigma0_Pa=SIGMA0_PA * 10**lf).mu, -1, 1
        )
    if skip != "contact_correction":
        out["contact_correction"] = fit1(
            lambda g: F.mu_isothermal(surf.psd, rub, v, contact_gamma=g).mu, 0.0, 1.0
        )
    if skip != "fine_roughness":
        out["fine_roughness"] = fit1(
            lambda lf: F.mu_isothermal(surf.extend(surf.q_nyq_per_m * 10**lf), rub, v).mu, 0.01, 2.0
        )
    if skip != "flash_temperature":
        out["flash_temperature"] = min(
            res(F.mu_flash(surf.psd, rub, v, zeta_m=z, tol=3e-3).mu) for z in (2.0, 3.0, 4.0, 5.0)
        )
    if skip != "adhesion":
        a_frac = base.P[:, -1]

        def adh(x):
            lt, lv, w = np.clip(x, [3.0, -9.0, 0.1], [9.0, 2.0, 5.0])
            return base.mu + 10**lt / SIGMA0_PA * a_frac * adhesion_shape(v, "bell", 10**lv, w)

        best = min(
            optimize.minimize(lambda x: res(adh(x)), x0, method="Nelder-Mead", options=dict(maxiter=300)).fun
            for x0 in ([6.0, -5.0, 1.0], [7.0, -3.0, 1.5], [5.0, -1.0, 1.0])
        )
        out["adhesion"] = float(best)
    if skip != "relaxation_spectrum":
        # spread only, centre fixed at the SLS's time: with a free centre the family would
        # contain the temperature offset itself (a pure shift of log tau), which has fewer
        # parameters and must win on parsimony
        out["relaxation_spectrum"] = fit1(
            lambda s: F.mu_isothermal(surf.psd, lognormal_prony(s, 0.0, 8), v).mu, 0.05, 2.0
        )
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
    validate: dict = None  # condition, path, model gap of the validation data
    signal_gap: float = 0.0  # rms log10(mu_clean / mu_model)
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
        cols.append(np.full_like(v, T0_C))
        names.append("T0_C")
    if sigma0_Pa is not None:
        cols.append(np.full_like(v, sigma0_Pa))
        names.append("sigma0_Pa")
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=",".join(names), comments="", fmt="%.10e")


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
        case.validate = dict(
            cond=cond,
            path=str(d / "validate.csv"),
            model_gap=_rms(np.log10(mv / mv_model)),
            clean_gap=_rms(np.log10(mv_clean / mv_model)),
        )
    if with_alt and effect is not None and case.strong:
        case.alt = alternative_fits(np.log10(mu_meas), surf, v, effect)
    return case
