"""``combine.png`` and ``report.html`` of ``roadscan combine``.

The figure shows each input's spectrum (its reliable band in colour, the rest grey), the merged
C(q) in black with its 5-95 % band shaded, gaps dashed, and the self-affine fit; wave vector
q [1/m] below, wavelength 2 pi / q [mm] on top. The report (self-contained, the PNG embedded)
lists lengths in mm / um with 3 significant digits (:mod:`pipelines.output.units`).
"""

from __future__ import annotations

import html

import numpy as np

__all__ = ["draw_combine", "write_combine_report"]


def draw_combine(sources, merged, fit, path):
    """Draw ``combine.png``; returns its path.

    Parameters
    ----------
    sources : list of SourceSpectrum
        The inputs.
    merged : MergedSpectrum
        The merged spectrum.
    fit : dict or None
        Its fit.
    path : str or Path
        Output PNG.

    Returns
    -------
    Path
    """
    from pipelines.output import report

    fig, ax = report.pyplot().subplots(figsize=(7.2, 4.8))
    for i, s in enumerate(sources):
        q, C = s.q_per_m, s.C_m4
        lo, hi = s.band.band
        ok = C > 0
        ax.loglog(q[ok], C[ok], "-", lw=0.9, color="0.75", zorder=1)
        inb = ok & (q >= lo) & (q <= hi)
        ax.loglog(
            q[inb],
            C[inb],
            "-",
            lw=1.2,
            color=f"C{i % 10}",
            zorder=5,
            label=f"{s.label} ({s.kind}), reliable part",
        )
    q, C = merged.q_per_m, merged.C_m4
    ax.fill_between(
        q, merged.C_lo_m4, merged.C_hi_m4, color="k", alpha=0.15, lw=0, zorder=3, label="merged 5-95 % band"
    )
    measured = np.ma.masked_where(merged.n_sources == 0, C)
    ax.loglog(q, measured, "-", color="k", lw=3.0, alpha=0.45, zorder=4, label="merged C(q)")
    if merged.gaps:
        bridged = np.ma.masked_where(merged.n_sources > 0, C)
        ax.loglog(q, bridged, ":", color="k", lw=1.6, zorder=4, label="gap (bridged)")
    if fit:
        qf = np.geomspace(fit["fit_band_per_m"][0], fit["fit_band_per_m"][1], 40)
        Cf = fit["C_at_q0_m4"] * (qf / fit["q0_per_m"]) ** (-2.0 * (fit["hurst"] + 1.0))
        ax.loglog(
            qf, Cf, "--", color="C3", lw=1.0, zorder=6, label=f"self-affine fit, H = {fit['hurst']:.3f}"
        )
    ax.set_xlabel("wave vector q [1/m]")
    ax.set_ylabel("C(q) [m⁴]")
    report.plain_log_ticks(ax)
    report.wavelength_axis(ax)
    report.set_title(ax, "merged spectrum (grey: outside each input's reliable band)")
    ax.grid(which="major", alpha=0.25)
    ax.legend(fontsize=7, loc="lower left")
    return report.save_figure(fig, path, report.fixed_margins(ax, top=report.WAVELENGTH_AXIS_TOP))


def _band_text(band):
    from pipelines.output.units import sig3, wavelength_of_q

    lo, hi = band
    return f"{sig3(lo)} – {sig3(hi)} 1/m (λ {wavelength_of_q(hi)} – {wavelength_of_q(lo)})"


def write_combine_report(path, summary, figure=None):
    """The self-contained ``report.html`` from the ``combine.json`` dictionary.

    Parameters
    ----------
    path : str or Path
        Output HTML.
    summary : dict
        ``combine.json``.
    figure : str or Path, optional
        ``combine.png``.

    Returns
    -------
    Path
    """
    from pipelines.output import report
    from pipelines.output.units import length, sig3, wavelength_of_q

    rows = []
    for d in summary["inputs"]:
        rows.append(
            (
                d["label"],
                d["kind"],
                " × ".join(length(v) for v in d["spacing_m"]),
                " × ".join(length(v) for v in d["size_m"]),
                length(d["resolution_m"]) if d["resolution_m"] else "—",
                _band_text(d["reliable_band_per_m"]),
                f"low: {d['reliable_band_reasons']['lo']}; high: {d['reliable_band_reasons']['hi']}",
            )
        )
    inputs = report.table_html(
        rows, ["input", "kind", "spacing", "size", "lateral resolution", "reliable band", "why it ends there"]
    )
    gaps = (
        report.paragraph_html("none: the reliable bands overlap or touch")
        if not summary["gap_details"]
        else report.table_html(
            [
                (_band_text([g["q_from_per_m"], g["q_to_per_m"]]), sig3(g["factor"]), g["bridged_by"])
                for g in summary["gap_details"]
            ],
            ["gap (no input reliable)", "factor in q", "bridged by"],
        )
    )
    fit = summary.get("fit")
    fit_html = (
        report.paragraph_html("no fit")
        if not fit
        else report.table_html(
            {
                "Hurst exponent H": f"{fit['hurst']:.3f} ± {fit['hurst_stderr']:.3f}",
                "h0 (thesis form)": length(fit["h0_m"]),
                "band rms from fit": length(fit["band_rms_m"]),
                "fit band": _band_text(fit["fit_band_per_m"]),
                "roll-off": (
                    f"{sig3(fit['q_roll_per_m'])} 1/m (λ {wavelength_of_q(fit['q_roll_per_m'])})"
                    if fit.get("q_roll_per_m")
                    else "none found"
                ),
            }
        )
    )
    warn = summary.get("warnings") or []
    warn_html = report.paragraph_html("none") if not warn else report.list_html(warn)
    sections = [
        ("Inputs and their reliable bands", inputs),
        (
            "Merged spectrum",
            [
                report.paragraph_html(
                    f"merged band: {_band_text(summary['merged_band_per_m'])}; {summary['rows']} rows "
                    f"in psd.csv (q_per_m,C_m4,C_lo_m4,C_hi_m4,n_sources)"
                )
            ]
            + ([figure] if figure else []),
        ),
        ("Gaps", gaps),
        ("Self-affine fit of the merged spectrum", fit_html),
        (
            "q0, the surface's roll-off",
            report.paragraph_html(
                (
                    f"q0 = {sig3(summary['q0_per_m'])} 1/m (λ {wavelength_of_q(summary['q0_per_m'])}): "
                    if summary.get("q0_per_m")
                    else ""
                )
                + summary.get("q0_how", "")
            ),
        ),
        ("Warnings", warn_html),
    ]
    intro = html.escape(summary["method"])
    return report.write_html(
        path, "roadscan combine: one spectrum from several measurements", sections, intro=intro
    )
