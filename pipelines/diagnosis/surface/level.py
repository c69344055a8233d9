"""The surface level: a measured scan against Gaussian self-affine twins of it, held out in space.

The "sim" is what the self-affine model and the synthetic tests assume: Gaussian heights with the
pure power law C(q) = C(q0) (q/q0)^(-2(H+1)) of the scan's self-affine fit, isotropic, seamless
(:mod:`.twin`: synthesised on a grid twice as large and cropped, levelled like the scan).

The scan and ``N_TWINS`` twins are split into the same blocks (:mod:`.blocks`: tiles of an area,
sections of a profile) and every block gives five descriptor families: spectrum bands,
height distribution (L-skewness, L-kurtosis, curvature L-skewness), anisotropy components,
straight line discontinuities (seams) and rain-fill response (areas only for the last three). The twin's
prediction of an entry is its mean over the twins' blocks; its per-block noise sigma^2 = var_twin x max(1,
lambda_f) x (1 + 1 / n_twin_blocks), var_twin the variance over the twins' blocks (the null hypothesis's own
scatter) and lambda_f the family's median ratio of the measured blocks' variance to it (the
measured scatter, when larger, widens the noise of the whole family). Each family so has its own
noise and, in noise units, one family's gap counts as much as another's.

Effects (``effects/`` level "surface") modify the twin's prediction; parameters are fitted on some
blocks and scored on the held-out one (k-fold, :mod:`.surface_search`).

The mu(v) the measured spectrum and the pure power law produce (isothermal, docs: Theory
defaults) is reported as ``mu_gap`` (rms log10 ratio over 1e-6..10 m/s), and ``where`` gives the
whole scan's spectrum against the power law per half decade of q.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from itertools import pairwise
from pathlib import Path

import numpy as np

from pipelines.diagnosis import gap as gapmod

__all__ = ["SurfaceContext", "descriptors", "run_surface"]

LOG10E = math.log10(math.e)
N_TWINS = 8
N_SKEW_TWINS = 4
SKEW_GRID = (-3.0, -2.0, -1.2, -0.6, 0.0, 0.6, 1.2, 2.0, 3.0)


@dataclass(eq=False)
class SurfaceContext:
    """What the surface-level effects and the k-fold search work on.

    Attributes
    ----------
    geo : Geometry
        Block layout: equal tiles of the area scan or sections of the profile.
    families : tuple of str
        Descriptor families compared: spectrum, height, and on areas anisotropy, seams, rain.
    meas, twin_mean, sigma : dict
        Measured descriptors, twins' mean and noise per family.
    twin_rings, twin_bands, ring_q : ndarray
        Twins' ring spectra, bands and ring wave vectors.
    fit : SelfAffineFit
        The scan's self-affine fit (Hurst exponent, C at q0) the Gaussian twins are drawn from.
    is_profile : bool
        True for a line profile (no anisotropy, seams or rain families).
    inputs : set of str
        ``{"spectrum"}``, plus ``"area"`` for an area scan: effects needing others are skipped.
    skew_table, moments, noise_inflation : dict
        Skewed twins' descriptors per skewness; measured and twin moments; family -> factor >= 1
        on the twins' variance to match the measured blocks' robust scatter.
    whole_twins : ndarray
        Twins' whole-scan spectra.
    whole_height : dict
        Whole-scan height statistics.
    cache : dict
        Shared by effects for precomputed results.
    """

    geo: object                 # blocks.Geometry
    families: tuple
    meas: dict                  # family -> (n_blocks, n_entries) measured
    twin_mean: dict             # family -> (n_entries,) twin prediction
    sigma: dict                 # family -> (n_entries,) per-block noise
    twin_rings: np.ndarray      # twin's ring-level log10 spectrum (mean over twin blocks)
    twin_bands: np.ndarray      # twin's band log10 spectrum (mean over twin blocks)
    ring_q: np.ndarray          # ring mean |q| [1/m]
    fit: object
    is_profile: bool
    inputs: set = field(default_factory=set)
    skew_table: dict | None = None     # skewness grid -> height family, d rain family (height_skew)
    moments: dict | None = None        # moment skewness / excess kurtosis: measured and twin block means
    noise_inflation: dict = field(default_factory=dict)
    whole_twins: np.ndarray | None = None  # (n_twins, n_rings) log10 C of the twins' whole-scan spectra
    whole_height: dict | None = None       # whole-scan height-law statistics: measured, twins, skewed-twin table
    cache: dict = field(default_factory=dict)

    @property
    def n_blocks(self):
        return len(self.geo.starts)


def _power_law(fit, q):
    return fit.C_at_q0_m4 * (np.asarray(q, float) / fit.q0_per_m) ** (-2.0 * (fit.hurst + 1.0))


def descriptors(an, seed=0, log=None, n_twins=N_TWINS):
    """Build the :class:`SurfaceContext` of a :class:`spectrum_bridge.SurfaceAnalysis`.

    Parameters
    ----------
    an : SurfaceAnalysis
        The analysed scan: its filled heights [m] are split into blocks, its fit makes the twins.
    seed : int, optional
        Twin i is drawn with seed + 1000 i (default 0): the same seed gives the same context.
    log : callable, optional
        Called with one progress line (str) per stage; None: silent.
    n_twins : int, optional
        Number of Gaussian self-affine twins drawn (default 8).

    Returns
    -------
    SurfaceContext
        Measured block descriptors, the twins' prediction and per-block noise, and the effects' tables.
    """
    from pipelines.diagnosis.surface import blocks as bl
    from pipelines.diagnosis.surface.twin import skewed_set, twin_heights

    say = log or (lambda *_: None)
    t = time.perf_counter()
    lev = an.filled
    geo = bl.geometry(lev)
    meas = bl.describe(lev.heights_m, geo)
    tw_h = [twin_heights(lev, an.fit, seed + 1000 * i) for i in range(n_twins)]
    tw = [bl.describe(h, geo) for h in tw_h]
    fams = geo.families()
    twin_all = {f: np.concatenate([d[f] for d in tw]) for f in list(fams) + ["spec_rings", "moments", "bands"]}
    twin_mean = {f: twin_all[f].mean(axis=0) for f in fams}
    # entries whose expectation under the Gaussian isotropic twin is 0 by symmetry (h -> -h:
    # L-skewness of the heights and of the curvature; an isotropic texture on a symmetric lattice: the
    # anisotropy components) take that exact value; the twins' mean would only add their noise
    twin_mean["height"][[0, 2]] = 0.0
    if geo.symmetric:
        twin_mean["anisotropy"][:] = 0.0
    n_t = twin_all[fams[0]].shape[0]
    sigma, infl = {}, {}
    for f in fams:
        vt = np.maximum(twin_all[f].var(axis=0, ddof=1), 1e-12)
        # robust scatter of the measured blocks (1.4826 x median absolute deviation): one block
        # with a deep valley must not make the whole family's noise
        dev = np.abs(meas[f] - np.median(meas[f], axis=0))
        vm = (1.4826 * np.median(dev, axis=0)) ** 2
        lam = float(max(1.0, np.median(vm / vt)))
        infl[f] = lam
        sigma[f] = np.sqrt(vt * lam * (1.0 + 1.0 / n_t))
    # the skewed twins: height family (and rain response) against the moment skewness of the law
    sk_h = skewed_set(tw_h[:N_SKEW_TWINS], SKEW_GRID)
    sk = []
    for s in SKEW_GRID:
        d = [bl.describe(h, geo, rain="rain" in fams and i < 2) for i, h in enumerate(sk_h[s])]
        sk.append(d)
    h_tab = np.array([np.mean([dd["height"].mean(axis=0) for dd in d], axis=0) for d in sk])
    h_tab = h_tab - h_tab[SKEW_GRID.index(0.0)] + twin_mean["height"]
    r_tab = None
    if "rain" in fams:
        r_tab = np.array([np.mean([dd["rain"].mean(axis=0) for dd in d[:2]], axis=0) for d in sk])
        r_tab = r_tab - r_tab[SKEW_GRID.index(0.0)]
    skew_table = dict(s=np.array(SKEW_GRID), height=h_tab, rain=r_tab)
    # the same law on the whole scan (:func:`.surface_whole.whole_height_check`)
    from pipelines.diagnosis.surface.whole import whole_height_stats

    wt = np.array([whole_height_stats(h) for h in tw_h])
    ws = np.array([np.mean([whole_height_stats(hs) - w0 for hs, w0 in zip(sk_h[s], wt)], axis=0) for s in SKEW_GRID])
    whole_height = dict(measured=whole_height_stats(lev.heights_m), twins=wt, skew_s=np.array(SKEW_GRID), skew_tab=ws)
    if not an.is_profile:
        from pipelines.diagnosis.surface.whole import whole_seam_stats

        whole_height["seams_measured"] = whole_seam_stats(lev.heights_m)
        whole_height["seams_twins"] = np.array([whole_seam_stats(h) for h in tw_h])
    say(f"surface descriptors of {geo.n_blocks if hasattr(geo, 'n_blocks') else len(geo.starts)} blocks, "
        f"{n_twins} twins: {time.perf_counter() - t:.1f} s")
    inputs = {"spectrum"} | (set() if an.is_profile else {"area"})
    return SurfaceContext(geo, fams, meas, twin_mean, sigma, twin_all["spec_rings"].mean(axis=0),
                          twin_all["bands"].mean(axis=0),
                          geo.rings[1], an.fit, an.is_profile, inputs, skew_table,
                          dict(measured=meas["moments"].mean(axis=0).tolist(),
                               twin=twin_all["moments"].mean(axis=0).tolist()), infl,
                          twin_whole_spectra(an, tw_h), whole_height)


def _off_axis_rings(spec2d, edges):
    """(mean |q|, mean C, count) of a 2D PSD map over the rings ``edges``, lattice axes left out."""
    from pipelines.diagnosis.surface.blocks import near_axes

    qx, qy = np.asarray(spec2d.qx_per_m), np.asarray(spec2d.qy_per_m)
    kx = np.fft.fftshift(np.fft.fftfreq(qx.size) * qx.size).round()
    ky = np.fft.fftshift(np.fft.fftfreq(qy.size) * qy.size).round()
    KX, KY = np.meshgrid(kx, ky)
    q = np.hypot(qx[None, :], qy[:, None])
    edges = np.asarray(edges, float)
    n = edges.size - 1
    ring = np.searchsorted(edges, q, side="right") - 1
    ring[q == edges[-1]] = n - 1
    sel = (ring >= 0) & (ring < n) & ~near_axes(KX, KY) & (q > 0)
    r = ring[sel]
    cnt = np.bincount(r, minlength=n).astype(float)
    keep = cnt > 0
    C = np.bincount(r, np.asarray(spec2d.C_m4)[sel], minlength=n)[keep] / cnt[keep]
    qm = np.bincount(r, q[sel], minlength=n)[keep] / cnt[keep]
    return qm, C, cnt[keep]


def off_axis(an):
    """``an`` with its ring-averaged spectrum and self-affine fit taken off the lattice axes.

    Seams, steps and stitching put their power on the axes of the 2D spectrum: a fit to the full
    ring average would take a seamed scan's spectrum as flatter than its texture, and the twins
    (and the blocks' spectrum family, which leaves the axes out) would disagree for that reason
    alone. The rings and the fit band are the scan's own; the lattice points on the axes are left
    out (:func:`.blocks.near_axes`). Profiles are returned as they are.
    """
    import dataclasses

    from roadscan import fit as fitmod
    from roadscan.spectrum_types import Spectrum

    edges = (an.spectrum.meta or {}).get("ring_edges_per_m")
    if an.spec2d is None or edges is None:
        return an
    qm, C, cnt = _off_axis_rings(an.spec2d, edges)
    if qm.size < 4:
        return an
    spec = Spectrum(qm, C, count=np.rint(cnt).astype(np.int64), kind="area",
                    meta=dict(an.spectrum.meta, off_axis=True))
    try:
        fit = fitmod.fit_self_affine(spec, band=an.fit.fit_band_per_m)
    except (ValueError, np.linalg.LinAlgError):
        return an
    if not (np.isfinite(fit.hurst) and fit.C_at_q0_m4 > 0):
        return an
    return dataclasses.replace(an, spectrum=spec, fit=fit)


def twin_whole_spectra(an, twins):
    """log10 C of each twin's whole-scan spectrum on the scan's rings (same window, rings and,
    for areas, axes left out): the reference and the noise of the whole-scan check
    (:mod:`.surface_whole`). Returns (n_twins, n_rings)."""
    from pipelines.chain.surface import spectrum_of
    from roadscan.heightmap import HeightMap, Profile

    q = np.asarray(an.spectrum.q_per_m, float)
    edges = (an.spectrum.meta or {}).get("ring_edges_per_m")
    out = []
    for h in twins:
        if an.is_profile:
            sp, _, _ = spectrum_of(Profile(h, an.filled.dx_m, name="twin"))
            qt, Ct = np.asarray(sp.q_per_m, float), np.asarray(sp.C_m4, float)
        else:
            _, s2, _ = spectrum_of(HeightMap(h, an.filled.dx_m, an.filled.dy_m, name="twin"))
            qt, Ct, _ = _off_axis_rings(s2, edges)
        ok = np.isfinite(Ct) & (Ct > 0)
        out.append(np.interp(np.log(q), np.log(qt[ok]), np.log10(Ct[ok])))
    return np.array(out)


def _mu_gap(an, q, C_pl):
    import friction
    from friction import TabulatedPSD
    from pipelines.chain.surface import surface_psd

    v = np.logspace(-6, 1, 36)
    r = friction.thesis_rubber()
    psd_real = surface_psd(an.spectrum, an.fit)
    psd_twin = TabulatedPSD(q, C_pl, q0_per_m=psd_real.q0_per_m)
    m1 = friction.mu_isothermal(psd_real, r, v).mu
    m2 = friction.mu_isothermal(psd_twin, r, v).mu
    return v, m1, m2


def run_surface(obj, out_dir, log=None, seed=0):
    """Surface-level diagnosis of a HeightMap or Profile; writes DIR/diagnosis.json, report.html.

    Parameters
    ----------
    obj : HeightMap or Profile
        The road scan, heights in m.
    out_dir : str or Path
        Folder written: diagnosis.json, report.html and its figures.
    log : callable, optional
        Called with one progress line (str) per stage; None: silent.
    seed : int, optional
        Seed of the twins (see :func:`descriptors`): the same seed gives the same diagnosis.

    Returns
    -------
    dict
        The content written to ``diagnosis.json``.
    """
    import tempfile

    import matplotlib.pyplot as plt
    from scipy import stats

    from pipelines.chain.surface import analyse_surface
    from pipelines.diagnosis.report.single import write_surface_report
    from pipelines.diagnosis.surface.search import MIN_SHRINK, _predict, surface_search
    from pipelines.output import report as rep

    t0 = time.perf_counter()
    say = log or (lambda *_: None)
    an = off_axis(analyse_surface(obj))
    ctx = descriptors(an, seed=seed, log=say)
    res = surface_search(ctx)
    verdict, best = res["verdict"], res["best"]
    from pipelines.diagnosis.surface.whole import (
        MIN_SHRINK_WHOLE,
        STRONG_P_WHOLE,
        whole_height_check,
        whole_seams_check,
        whole_spectrum_check,
    )

    whole = whole_spectrum_check(an, ctx.whole_twins)
    wh = ctx.whole_height
    whole_h = whole_height_check(wh["measured"], wh["twins"], wh["skew_s"], wh["skew_tab"])
    whole_s = whole_seams_check(wh["seams_measured"], wh["seams_twins"]) if "seams_measured" in wh else None
    verdict["evidence"] = "blocks (k-fold)" if verdict["effect"] else None
    if verdict["effect"] is None and not verdict["inconclusive"]:
        # the whole-scan checks, for what the blocks cannot see: of those that are significant
        # and reach MIN_SHRINK_WHOLE, the one whose descriptor family carries the largest gap in
        # the blocks (a smoothed texture also raises the line scores a little; its spectrum gap
        # is far larger), then the largest held-out shrink
        fam_gap = {f: d["gap_baseline"] for f, d in res["families"].items()}
        opts = []      # (family gap, held-out shrink, effect, evidence, why) of accepted checks
        if whole["significant"]:
            w = next(c for c in whole["candidates"] if c["p_value"] < 1e-3)
            # a spectral bend at the lowest rings (a roll-off within a few 2 pi / L) touches few
            # of the held-out rings, so its held-out shrink is diluted by rings with nothing to
            # explain: with a training likelihood ratio at p < STRONG_P_WHOLE, any held-out
            # improvement counts
            if w["shrink"] >= MIN_SHRINK_WHOLE or (w["p_value"] < STRONG_P_WHOLE and w["shrink"] > 0):
                opts.append((fam_gap.get("spectrum", 0.0), w["shrink"], w["name"], "whole-scan spectrum (every third ring held out)",
                             f"{w['name']} closes {w['shrink']:.0%} of the whole scan's spectral gap on held-out "
                             "rings (the blocks lose the lowest wave vectors)"))
        if whole_h["significant"] and whole_h["shrink"] >= MIN_SHRINK_WHOLE:
            opts.append((fam_gap.get("height", 0.0), whole_h["shrink"], "height_skew", "whole-scan height law (curvature at lags 1 and 4 held out)",
                         f"a height law of skewness {whole_h['skewness']:.2f} "
                         "(fitted to the whole scan's L-skewness "
                         f"of heights and curvature) closes {whole_h['shrink']:.0%} of the gap of the held-out "
                         "curvature lags (the height law shows unevenly from block to block)"))
        if whole_s is not None and whole_s["significant"] and whole_s["shrink"] >= MIN_SHRINK_WHOLE:
            opts.append((fam_gap.get("seams", 0.0), whole_s["shrink"], "seams", "whole-scan line scores (two-fold over halves along the lines)",
                         f"straight line discontinuities: the line-score excess of one half of the scan predicts "
                         f"the other's and closes {whole_s['shrink']:.0%} "
                         "of the gap (a seam crosses only some blocks)"))
        if opts:
            _, sh, name, ev, why = max(opts)
            verdict.update(effect=name, shrink=sh, shrink_interval=None, confidence="medium", evidence=ev,
                           reason="the blocks name nothing, but " + why)
    spec = an.spectrum
    ok = np.isfinite(spec.C_m4) & (spec.C_m4 > 0)
    q, C = spec.q_per_m[ok], spec.C_m4[ok]
    C_pl = _power_law(an.fit, q)
    rs = np.log10(C / C_pl)
    where = []
    lq = np.log10(q)
    edges = np.arange(np.floor(lq[0] * 2) / 2, lq[-1] + 0.5, 0.5)
    cnt = np.maximum(np.asarray(spec.count, float)[ok], 1) if spec.count is not None else np.full(q.size, 4.0)
    sig = LOG10E * np.sqrt(2.0 / cnt)
    for a, b in pairwise(edges):
        m = (lq >= a) & (lq < b)
        if m.any():
            g = float(np.sqrt(np.mean(rs[m] ** 2)))
            ns = float(np.sqrt(np.mean(sig[m] ** 2)))
            where.append(dict(q_min_per_m=10 ** a, q_max_per_m=10 ** b, gap=g, n=int(m.sum()),
                              mean_log_ratio=float(np.mean(rs[m])), noise=ns,
                              significant=gapmod.is_significant(g, ns, int(m.sum()))))
    v, mu_real, mu_twin = _mu_gap(an, q, C_pl)
    r6 = lambda x: None if x is None or not np.isfinite(x) else float(round(float(x), 6))  # noqa: E731
    effects = [dict(name=c["name"], params=c["params"], n_params=c["n_params"], gap_train=r6(c["gap_train"]),
                    gap_heldout=r6(c["gap_heldout"]), shrink=r6(c["shrink"]), shrink_raw=r6(c["shrink_raw"]),
                    shrink_interval=[r6(x) for x in c["shrink_interval"]], score=r6(c["score"]),
                    family_gaps={k: r6(x) for k, x in c["family_gaps"].items()}, at_bound=c["at_bound"])
               for c in res["candidates"]]
    verdict = dict(verdict, shrink=r6(verdict["shrink"]),
                   shrink_interval=None if verdict["shrink_interval"] is None else [r6(x) for x in verdict["shrink_interval"]])
    geo = ctx.geo
    data = dict(
        level="surface", name=obj.name, kind="profile" if ctx.is_profile else "area",
        baseline_gap=r6(res["baseline_gap"]), noise=1.0, significant=res["significant"],
        gap_units="noise units: each descriptor's residual divided by its own per-block noise",
        gap_definition=("per family f: g_f = rms over entries and held-out blocks of "
                        "(measured - twin prediction) / noise; total = sqrt(mean_f g_f^2), every family "
                        "weighing the same (see pipelines/diagnosis/surface_search.py)"),
        shrink_definition=(f"1 - sqrt(E_after / E_before), E = mean_f max(g_f^2 - 1, 0) (the gap beyond the "
                           f"noise); verdict needs >= {MIN_SHRINK:.0%}; interval: 5-95 % bootstrap over folds"),
        heldout=(f"k-fold over {ctx.n_blocks} blocks ({'sections' if ctx.is_profile else 'tiles'} of "
                 f"{' x '.join(str(s) for s in geo.shape)} points): parameters fitted on the others, "
                 "scored on the held-out block"),
        blocks=dict(n=ctx.n_blocks, shape=list(geo.shape), twins=N_TWINS),
        families=res["families"],
        family_noise={f: dict(entries=(["l_skewness_tau3", "l_kurtosis_tau4", "curvature_l_skewness"] if f == "height" else
                                       ["rain_log_ratio_low_q", "rain_log_ratio_mid_q", "rain_log_ratio_high_q",
                                        "wetted_fraction"] if f == "rain" else
                                       ["anisotropy_a_xx_minus_yy", "anisotropy_b_xy"] if f == "anisotropy" else
                                       ["log10_max_over_median_line_score"] if f == "seams" else
                                       ["log10_C_lowest_band_minus_mid", "log10_C_highest_band_minus_mid"]),
                              measured=ctx.meas[f].mean(axis=0).tolist(), twin=ctx.twin_mean[f].tolist(),
                              noise_per_block=ctx.sigma[f].tolist(),
                              measured_scatter_ratio=ctx.noise_inflation[f])
                      for f in ctx.families},
        spectrum_band_q_per_m=geo.band_q.tolist(),
        height_moments=dict(skewness=ctx.moments["measured"][0], excess_kurtosis=ctx.moments["measured"][1],
                            twin_skewness=ctx.moments["twin"][0], twin_excess_kurtosis=ctx.moments["twin"][1],
                            note="block means (each block levelled by its own plane)"),
        twin=dict(hurst=ctx.fit.hurst, C_at_q0_m4=ctx.fit.C_at_q0_m4, q0_per_m=ctx.fit.q0_per_m,
                  fit_band_per_m=list(ctx.fit.fit_band_per_m), q_roll_per_m=ctx.fit.q_roll_per_m),
        where=where,
        mu_gap=float(np.sqrt(np.mean(np.log10(mu_real / mu_twin) ** 2))),
        effects=effects, skipped=res["skipped"], verdict=verdict,
        whole_spectrum={k: (r6(v) if isinstance(v, float) else v) for k, v in whole.items()},
        whole_height={k: (r6(v) if isinstance(v, float) else v) for k, v in whole_h.items()},
        whole_seams=None if whole_s is None else {k: (r6(v) if isinstance(v, float) else v) for k, v in whole_s.items()},
        inconclusive=verdict["inconclusive"], at_bound=verdict["at_bound"],
        seconds=round(time.perf_counter() - t0, 2))
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rep.write_json(out_dir / "diagnosis.json", data)
    with tempfile.TemporaryDirectory() as t:
        t = Path(t)
        bq = geo.band_q
        curves = [("measured blocks (mean)", bq, 10 ** ctx.meas["bands"].mean(axis=0)),
                  ("self-affine twins (mean)", bq, 10 ** ctx.twin_bands)]
        if best is not None:
            pr = _predict(ctx, best["_effs"], best["_params"])
            curves.append((f"twin + {best['name']}", bq, 10 ** (geo.band_matrix @ pr["spec_rings"])))
        figs = [rep.plot_psd(curves, t / "psd.png", title="block spectra (off-axis rings): measured, twin, corrected")]
        fig, ax = plt.subplots(figsize=rep.FIGSIZE)
        h = an.levelled.heights_m
        h = h[np.isfinite(h)] * 1e3
        ax.hist(h, bins=80, density=True, alpha=0.6, label="measured")
        xs = np.linspace(h.min(), h.max(), 200)
        ax.plot(xs, stats.norm.pdf(xs, h.mean(), h.std()), "r-", label="Gaussian twin")
        ax.set_xlabel("height [mm]")
        ax.set_ylabel("probability density [1/mm]")
        ax.set_title(f"heights: skew {stats.skew(h):.2f}, excess kurtosis {stats.kurtosis(h):.2f}")
        ax.legend(fontsize=8)
        figs.append(rep.save_figure(fig, t / "hist.png", rep.fixed_margins(ax)))
        figs.append(rep.plot_mu([("measured spectrum", v, mu_real), ("self-affine power law", v, mu_twin)],
                                t / "mu.png", title="μ(v) each spectrum produces (isothermal)"))
        write_surface_report(out_dir, obj.name, data, figs)
    return data
