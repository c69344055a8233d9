"""Outputs of a diagnosis: ``diagnosis.json`` (its keys are a contract) and ``report.html``
(self-contained: PNGs embedded base64, opens offline), via :mod:`pipelines.output.report`."""
from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from pipelines.output import report as rep
from pipelines.output.units import length, quantity

__all__ = ["friction_json", "write_friction_report", "write_surface_report"]


def _r(x, nd=6):
    return None if x is None or not np.isfinite(x) else float(round(float(x), nd))


def friction_json(d, where, bandmap, validate=None):
    """The diagnosis.json content for a friction-level :class:`search.Diagnosis`.

    Parameters
    ----------
    d : Diagnosis
        The friction-level diagnosis (gaps, noise, candidates, verdict).
    where : list of dict
        :func:`gap.gap_by_band` of the baseline, one dict per speed band.
    bandmap : list of dict
        :func:`report.bandmap.band_map` rows: the wave vectors [1/m] carrying mu per speed band.
    validate : dict, optional
        :func:`run.validate` of ``--validate``; None: gap_validate and its baseline are None.

    Returns
    -------
    dict
        The ``diagnosis.json`` content (gaps in rms log10, rounded to 6 decimals).
    """
    return dict(
        level="friction",
        baseline_gap=_r(d.baseline_gap),
        baseline_gap_train=_r(d.baseline_gap_train),
        baseline_gap_heldout=_r(d.baseline_gap_heldout),
        noise=_r(d.noise),
        noise_source="given (--noise)" if d.noise_given else "estimated from the data (smoothing spline, modified GCV)",
        p_value=d.p_value,
        gap_definition="rms over points of log10(measured/simulated)",
        heldout=d.heldout,
        ranking=("log-evidence (Laplace approximation), best first" if d.train.all() and d.train.size < 20 else
                 "held-out rms x (1 + k / n_train), k = number of fitted parameters"),
        where=[{k: w[k] for k in ("v_min_m_per_s", "v_max_m_per_s", "gap", "n", "mean_log_ratio",
                                  "p_value", "significant")} for w in where],
        band_map=bandmap,
        effects=effect_entries(d),
        effects_nominal=[c.as_dict() for c in d.candidates if _is_nominal_single(c, d) or (c is d.best and
                         len(c.effects) == 1 and d.calibration is not None)],
        calibration=None if d.calibration is None else d.calibration.as_dict(),
        skipped=d.skipped,
        inconclusive=d.verdict["inconclusive"],
        at_bound=d.verdict["at_bound"],
        verdict=dict(effect=d.verdict["effect"], shrink=_r(d.verdict["shrink"]),
                     shrink_interval=(None if d.verdict["shrink_interval"] is None else
                                      [_r(x) for x in d.verdict["shrink_interval"]]),
                     inconclusive=d.verdict["inconclusive"], at_bound=d.verdict["at_bound"],
                     confidence=d.verdict["confidence"],
                     implausible=d.verdict.get("implausible", []),
                     implausible_why=d.verdict.get("implausible_why", []),
                     calibrated=_calibrated(d.verdict.get("calibrated") or {}),
                     extrapolated=d.verdict.get("extrapolated", []),
                     equivalent_input=_jsonable(d.verdict.get("equivalent_input")),
                     gap_validate=None if validate is None else _r(validate["gap_after"]),
                     gap_validate_baseline=None if validate is None else _r(validate["gap_before"]),
                     reason=d.verdict["reason"], evidence=_jsonable(d.verdict.get("evidence"))),
        next_measurement=_jsonable(d.verdict.get("next_measurement")),
        seconds=round(d.seconds, 2),
    )


def _jsonable(x):
    """Evidence and next-measurement dicts with numpy scalars as floats, non-finite as None."""
    if isinstance(x, dict):
        return {k: _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x) if np.isfinite(x) else None
    return x


def _is_nominal_single(c, d):
    """A single effect fitted at the nominal inputs while a calibrated version of it exists (and
    the verdict did not name the nominal fit itself)."""
    names = {x.name for x in d.candidates}
    return (len(c.effects) == 1 and c.name != "calibration" and f"calibration+{c.name}" in names
            and c is not d.best)


def _is_replaced_pair(c, d):
    """A calibration+effect fit whose effect the verdict named at the nominal inputs."""
    return (d.best is not None and len(c.effects) == 2 and c.effects[0].name == "calibration"
            and d.best.name == c.effects[1].name)


def effect_entries(d):
    """``effects`` of diagnosis.json, best first: one entry per physical candidate. With uncertain
    inputs an effect's entry is its fit together with the calibration (named after the effect;
    its params hold the effect's own and ``calibration.<input>``; ``with_calibration`` true); the
    fit at the nominal inputs is under ``effects_nominal`` and the calibration alone under
    ``calibration``."""
    out = []
    for c in d.candidates:
        if c.name == "calibration" or _is_nominal_single(c, d) or _is_replaced_pair(c, d):
            continue
        e = c.as_dict()
        if c.effects[0].name == "calibration":
            e["name"] = "+".join(c.effect_names)
            e["candidate"] = c.name
            e["params"] = dict(c.params[1], **{f"calibration.{k}": x for k, x in c.params[0].items()})
            e["with_calibration"] = True
            if hasattr(c, "beyond"):
                e["shrink_beyond_calibration"] = c.beyond
        out.append(e)
    return out


def _calibrated(cal):
    return {k: dict(value=_r(x["value"], 9), interval=[_r(a, 9) for a in x["interval"]],
                    range=[_r(a, 9) for a in x["range"]]) for k, x in cal.items()}


def _finish(ax, xlabel, ylabel, title, fontsize=8):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(which="both", alpha=0.25)
    ax.legend(fontsize=fontsize)
    rep.plain_log_ticks(ax)  # Unicode exponents: no mathtext parser (0.3 s and more a process)


def mu_axes(ax, curve, d, dense, validate=None, title="measured, simulated and corrected μ(v)"):
    """Draw measured points (fitted / held out), the baseline with the band of the uncertain
    inputs, and the corrected model over the whole speed range (``dense``: :func:`curves.report_curves`)."""
    v, mu = curve.v_m_per_s, curve.mu
    if d.train.all():   # cross-validation: every point is held out by one fold
        ax.loglog(v, mu, "s", mfc="none", color="k", ms=5, label="measured (each held out by one CV fold)")
    else:
        ax.loglog(v[d.train], mu[d.train], "o", color="k", ms=4, label="measured (fit)")
        ax.loglog(v[~d.train], mu[~d.train], "s", mfc="none", color="k", ms=5, label="measured (held out)")
    dv = dense["v"]
    if dense.get("band_lo") is not None:
        ax.fill_between(dv, dense["band_lo"], dense["band_hi"], color="C0", alpha=0.18,
                        label="simulated within the uncertain inputs' ranges")
    if dense.get("base") is not None:
        ax.loglog(dv, dense["base"], "-", color="C0", label="simulated (nominal inputs)")
    else:
        ax.loglog(v, d.baseline_mu, "-", color="C0", label="simulated (nominal inputs)")
    if d.best is not None:
        pred = dense.get("corrected")
        ax.loglog(dv if pred is not None else v, pred if pred is not None else d.best.pred, "-", color="C3",
                  label=f"corrected: {d.best.name}")
    elif d.candidates:
        ax.loglog(v, d.candidates[0].pred, ":", color="C7", label=f"best candidate: {d.candidates[0].name}")
    if validate is not None:
        ax.loglog(validate["v"], validate["mu"], "^", color="C2", ms=4, label="validation data")
        ax.loglog(validate["v"], validate["pred"], "--", color="C2", label="validation prediction")
    _finish(ax, "sliding speed v [m/s]", "friction coefficient μ [-]", title, fontsize=7)


def _plots_friction(tmp, curve, d, where, bm_curves, validate, dense):
    import matplotlib.pyplot as plt

    v, mu = curve.v_m_per_s, curve.mu
    figs = []
    fig, ax = plt.subplots(figsize=rep.FIGSIZE)
    mu_axes(ax, curve, d, dense, validate)
    figs.append(rep.save_figure(fig, tmp / "mu.png", rep.fixed_margins(ax)))

    fig, ax = plt.subplots(figsize=rep.FIGSIZE)
    r0 = np.log10(mu / d.baseline_mu)
    ax.semilogx(v, r0, "o-", color="C0", ms=4, label="log10(measured/baseline)")
    if d.best is not None:
        ax.semilogx(v, np.log10(mu / d.best.pred), "s-", color="C3", ms=4, label=f"after {d.best.name}")
    ax.axhspan(-d.noise, d.noise, color="0.85", label=f"± noise ({d.noise:.3g})")
    for w in where:
        ax.hlines([w["gap"], -w["gap"]], w["v_min_m_per_s"], w["v_max_m_per_s"],
                  colors="C1" if w["significant"] else "C7", lw=2)
    ax.axhline(0, color="k", lw=0.5)
    _finish(ax, "sliding speed v [m/s]", "log10 ratio [-]", "gap against speed (bars: band rms; orange = significant)")
    figs.append(rep.save_figure(fig, tmp / "gap.png", rep.fixed_margins(ax)))

    q, f, vc = bm_curves
    fig, ax = plt.subplots(figsize=rep.FIGSIZE)
    for i in range(f.shape[0]):
        tot = np.trapezoid(np.maximum(f[i], 0), np.log(q)) or 1.0
        ax.semilogx(q, f[i] / tot, color=plt.cm.viridis(i / max(f.shape[0] - 1, 1)),
                    label=f"v = {vc[i]:.2g} m/s")
    _finish(ax, "wave vector q [1/m]", "share of μ per ln q [-]",
            "band map: which q carries μ in each speed band", fontsize=7)
    rep.wavelength_axis(ax)  # λ = 2π/q in mm on top, as every spectrum plot
    figs.append(rep.save_figure(fig, tmp / "bandmap.png", rep.fixed_margins(ax, top=rep.WAVELENGTH_AXIS_TOP)))
    return figs


def inputs_html(inp):
    """The model inputs of a diagnosis (``diagnosis.json`` ``inputs``) as HTML: values in the
    report's units, which were assumed, the uncertain ranges, the files with their SHA-256."""
    if not inp:
        return rep.paragraph_html("inputs not recorded")
    assumed = set(inp.get("assumed") or [])
    unc = inp.get("uncertain") or {}
    key_of = {"sigma0_Pa": "sigma0", "q1_per_m": "q1", "temperature_C": "temperature", "psd_scale": "psd_scale"}

    def row(label, key, text):
        u = unc.get(key_of.get(key, ""))
        rng = "" if not u else f"uncertain {u['range'][0]:.3g} – {u['range'][1]:.3g} ({u['source']})"
        return (label, text, "assumed (default)" if key in assumed else "given", rng)

    rows = [row("nominal pressure σ0", "sigma0_Pa", f"{inp['sigma0_Pa'] / 1e6:.3g} MPa"),
            row("spectrum q0 (lowest wave vector)", "q0_per_m", f"{inp['q0_per_m']:.3g} 1/m"),
            row("spectrum q1 (cut-off)", "q1_per_m", f"{inp['q1_per_m']:.3g} 1/m (λ = {2e6 * np.pi / inp['q1_per_m']:.3g} µm)"),
            row("background temperature T0", "temperature_C", f"{inp['temperature_C']:.3g} °C"),
            row("spectrum level factor", "psd_scale", f"{inp['psd_scale']:.3g}")]
    out = rep.table_html(rows, header=["input", "value", "source", "uncertainty"])
    files = [(f["role"], f["path"], f["sha256"][:16] + "…") for f in inp.get("files") or []]
    if files:
        out += rep.table_html(files, header=["file", "path", "sha256"])
    for note in inp.get("notes") or []:
        out += rep.paragraph_html(f"{note}.", lead="Note:")
    return out


def write_friction_report(out_dir, curve, d, data, where, bm_curves, validate=None):
    """Write ``report.html`` for a friction-level diagnosis (``data``: the JSON dict).

    Parameters
    ----------
    out_dir : str or Path
        Existing folder that receives report.html and its figures.
    curve : MeasuredCurve
        The measured mu(v) plotted.
    d : Diagnosis
        The friction-level diagnosis (``d.ctx`` gives the dense model curves).
    data : dict
        The :func:`friction_json` dict (with inputs), as written to ``diagnosis.json``.
    where : list of dict
        :func:`gap.gap_by_band` of the baseline, one dict per speed band.
    bm_curves : tuple
        (q [1/m], dmu/dln q per band, band-centre speeds [m/s]) of :func:`report.bandmap.band_map`.
    validate : dict, optional
        :func:`run.validate` of ``--validate``; None: no validation figure.

    Returns
    -------
    None
        The report is written to ``out_dir``.
    """
    from pipelines.diagnosis.report.curves import report_curves

    out_dir = Path(out_dir)
    dense = report_curves(d.ctx, d) if d.ctx is not None else dict(v=curve.v_m_per_s)
    with tempfile.TemporaryDirectory() as t:
        figs = _plots_friction(Path(t), curve, d, where, bm_curves, validate, dense)
        v = data["verdict"]
        nxt = data.get("next_measurement")
        verdict = _verdict_html(dict(v, next=nxt["sentence"] if nxt else None))
        cut = [b for b in data["band_map"] if b.get("carried_by_cutoff")]
        if cut:
            verdict += rep.paragraph_html(
                "in " + ", ".join(f"{b['v_min_m_per_s']:.3g}–{b['v_max_m_per_s']:.3g} m/s "
                                  f"(d ln μ / d ln q1 = {b['dlnmu_dlnq1']:.2f})" for b in cut)
                + ": the integrand peaks at the highest wave vector, so μ there depends on where "
                  "the spectrum is cut, not only on the measured texture.",
                lead="Warning: μ is carried by the spectrum's cut-off")
        summary = rep.table_html({
            "baseline gap (rms log10, all points)": data["baseline_gap"],
            "baseline gap, held-out points": data["baseline_gap_heldout"],
            "noise (rms log10)": data["noise"], "noise source": data["noise_source"],
            "chi-square p-value of the baseline gap": data["p_value"],
            "held-out shrink of the verdict": v["shrink"],
            "shrink interval (5-95 % bootstrap)": (None if not v.get("shrink_interval") else
                                                   f"{_fmt(v['shrink_interval'][0])} – {_fmt(v['shrink_interval'][1])}"),
            "held out": data["heldout"],
            "inconclusive between": ", ".join(v.get("inconclusive") or []) or "no",
            "parameters at a bound": ", ".join(v.get("at_bound") or []) or "none",
            "validation gap (baseline → corrected)": (f"{_fmt(v['gap_validate_baseline'])} → {_fmt(v['gap_validate'])}"
                                                      if v["gap_validate"] is not None else None),
            "run time [s]": data["seconds"]})
        eff = rep.table_html([(e["name"], ", ".join(f"{k}={quantity(k, val)}" for k, val in e["params"].items()),
                               e["gap_train"], e["gap_heldout"], e["shrink"],
                               "" if not e.get("shrink_interval") or e["shrink_interval"][0] is None else
                               f"{e['shrink_interval'][0]:.2f}–{e['shrink_interval'][1]:.2f}",
                               ", ".join(e.get("at_bound") or []), e["score"])
                              for e in data["effects"]],
                             header=["effect", "fitted parameters", "gap train", "gap held-out",
                                     "shrink (held-out)", "shrink 5–95 %", "at bound", "score"])
        skipped = rep.table_html([(s["name"], s["reason"]) for s in data["skipped"]],
                                 header=["skipped effect", "reason"]) if data["skipped"] else rep.paragraph_html("none")
        bands = rep.table_html([(f"{w['v_min_m_per_s']:.3g}–{w['v_max_m_per_s']:.3g}", w["n"], w["gap"],
                                 "yes" if w["significant"] else "no",
                                 f"{b['q_min_per_m']:.3g}–{b['q_max_per_m']:.3g}",
                                 f"{length(b['length_min_m'])} – {length(b['length_max_m'])}",
                                 f"{b['omega_min_rad_s']:.3g}–{b['omega_max_rad_s']:.3g}",
                                 f"{b['dlnmu_dlnq1']:.2f}" + (" (cut-off!)" if b.get("carried_by_cutoff") else ""))
                                for w, b in zip(data["where"], data["band_map"])],
                               header=["speed band [m/s]", "points", "gap", "significant",
                                       "q carrying 80 % of μ [1/m]", "length scales",
                                       "frequencies ω = q v [rad/s]", "d ln μ / d ln q1"])
        rep.write_html(out_dir / "report.html", f"Sim-to-real gap diagnosis: {curve.name}", [
            ("Model inputs", [inputs_html(data.get("inputs"))]),
            ("Verdict", [verdict, summary]),
            ("Measured, simulated and corrected friction", [figs[0]]),
            ("Where: the gap against speed", [figs[1], bands]),
            ("Band map", [figs[2]]),
            ("Candidate effects (best first)", [eff]),
            ("Skipped effects", [skipped]),
        ], intro="Friction level: measured μ(v) against Persson's theory with the given surface, "
                 "rubber and conditions; gap = rms of log10(measured/simulated).")


def _verdict_html(v):
    """The verdict of a diagnosis as paragraphs (``templates/paragraph.html.j2``, escaped once):
    the named effect, the reason, bounds, calibrated inputs, confidence, what to measure next."""
    name_v = v["effect"] if not isinstance(v["effect"], list) else " + ".join(v["effect"])
    if name_v:
        head = str(name_v)
    elif v.get("inconclusive"):
        head = "inconclusive between " + ", ".join(v["inconclusive"])
    else:
        head = "no effect named (null)"
    extra = ""
    if v.get("shrink_interval"):
        lo, hi = v["shrink_interval"]
        extra += f" Shrink interval (5-95 %): {lo:.0%} to {hi:.0%}." if lo is not None else ""
    if v.get("at_bound"):
        extra += " Parameters at a bound (confidence lowered): " + ", ".join(v["at_bound"]) + "."
    if v.get("implausible"):
        extra += " Not physical, so not named: " + "; ".join(v.get("implausible_why") or v["implausible"]) + "."
    if v.get("extrapolated"):
        extra += " Extrapolated: " + "; ".join(v["extrapolated"]) + "."
    if v.get("equivalent_input"):
        extra += " Same physics as an input: " + v["equivalent_input"]["sentence"] + "."
    if v.get("calibrated"):
        extra += " Calibrated inputs (95 % interval): " + ", ".join(
            f"{k} = {x['value']:.3g} ({x['interval'][0]:.3g} – {x['interval'][1]:.3g})"
            for k, x in v["calibrated"].items()) + "."
    if v.get("confidence"):
        extra += f" Confidence: {v['confidence']}."
    nxt = rep.paragraph_html(f"{v['next']}.", lead="What to measure next:") if v.get("next") else ""
    return rep.paragraph_html(f"{head}. {v.get('reason', '')}.{extra}", lead="Verdict:") + nxt


def _fmt(x):
    return "" if x is None or not np.isfinite(x) else f"{x:.3g}"


def write_surface_report(out_dir, name, data, figs):
    """Write ``report.html`` for a surface-level diagnosis.

    Parameters
    ----------
    out_dir : str or Path
        Existing folder that receives report.html (the figures are already in it).
    name : str
        The scan's name, in the report's title.
    data : dict
        The surface-level ``diagnosis.json`` content.
    figs : list of Path
        Saved figures: the block spectra first, then the height histogram and mu(v) figures.

    Returns
    -------
    None
        The report is written to ``out_dir``.
    """
    v = data["verdict"]
    verdict = _verdict_html(v)
    summary = rep.table_html({"baseline gap, held out (noise units)": data["baseline_gap"],
                              "blocks (k-fold)": data["heldout"],
                              "evidence of the verdict": v.get("evidence") or "none",
                              "inconclusive between": ", ".join(data.get("inconclusive") or []) or "no",
                              "parameters at a bound": ", ".join(data.get("at_bound") or []) or "none"})
    checks = []
    ws = data.get("whole_spectrum") or {}
    for c in ws.get("candidates") or []:
        checks.append((f"spectrum (every third ring held out): {c['name']}", _fmt(c.get("p_value")),
                       _fmt(c.get("shrink")), ", ".join(f"{k}={x:.3g}" for k, x in c["params"].items())))
    wh = data.get("whole_height")
    if wh:
        checks.append(("height law (curvature lags 1, 4 held out): height_skew", _fmt(wh.get("p_value")),
                       _fmt(wh.get("shrink")), f"skewness={wh['skewness']:.3g}"))
    wsm = data.get("whole_seams")
    if wsm:
        checks.append(("line scores (two-fold over halves): seams", _fmt(wsm.get("p_value")), _fmt(wsm.get("shrink")),
                       "excess log10 rows/columns = " + ", ".join(f"{x:.2f}" for x in wsm["excess_log10"])))
    whole_tab = rep.table_html(checks, header=["whole-scan check", "p-value", "held-out shrink", "fitted"]) \
        if checks else rep.paragraph_html("none")
    fam = rep.table_html([(f, d["gap_baseline"], d["gap_after"], d["shrink"], "yes" if d["significant"] else "no",
                           d["n_entries"]) for f, d in data["families"].items()],
                         header=["descriptor family", "held-out gap, twin (noise units)", "after the verdict",
                                 "family shrink", "significant", "entries"])
    stats = rep.table_html([(f"{f}: {e}", m, t, s) for f, d in data["family_noise"].items()
                            for e, m, t, s in zip(d["entries"], d["measured"], d["twin"], d["noise_per_block"])],
                           header=["descriptor", "measured (block mean)", "self-affine twin", "noise per block"])
    eff = rep.table_html([(e["name"], ", ".join(f"{k}={quantity(k, val)}" for k, val in e["params"].items()),
                           e["gap_train"], e["gap_heldout"], e["shrink"],
                           "" if not e.get("shrink_interval") or e["shrink_interval"][0] is None else
                           f"{e['shrink_interval'][0]:.2f}–{e['shrink_interval'][1]:.2f}",
                           ", ".join(f"{k} {x:.2f}" for k, x in e["family_gaps"].items()),
                           ", ".join(e["at_bound"]) or "") for e in data["effects"]],
                         header=["effect", "fitted parameters", "gap train", "gap held-out", "shrink",
                                 "shrink 5–95 %", "held-out gap per family", "at bound"])
    where = rep.table_html([(f"{w['q_min_per_m']:.3g}–{w['q_max_per_m']:.3g}", w["gap"], w.get("mean_log_ratio"))
                            for w in data["where"]], header=["q band [1/m]", "gap (rms log10 C)", "mean log10 ratio"])
    skipped = rep.table_html([(s["name"], s["reason"]) for s in data["skipped"]],
                             header=["skipped effect", "reason"]) if data["skipped"] else rep.paragraph_html("none")
    rep.write_html(Path(out_dir) / "report.html", f"Surface-level gap diagnosis: {name}", [
        ("Verdict", [verdict, summary]),
        ("Gap per descriptor family (held out in space)", [fam]),
        ("Whole-scan checks (used when the blocks name nothing)", [whole_tab]),
        ("Spectrum: measured against the fitted self-affine surface", [figs[0], where]),
        ("Height distribution, rain fill and friction", [list(figs[1:]), stats]),
        ("Candidate effects (best first)", [eff]),
        ("Skipped effects", [skipped]),
    ], intro="Surface level: the measured scan against Gaussian self-affine twins fitted to it "
             "(the thesis's calculated-versus-fitted spectrum, section 4.2), compared block by block.")
