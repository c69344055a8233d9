"""The figures and ``report.html`` of ``roadscan compare`` (:mod:`pipelines.jobs.compare`):
the spectra and mu(v) of every scan on common axes, their ratios to the reference, and the
tables of where and by how much each scan differs from it.
"""

from __future__ import annotations

from pipelines.jobs.dry_vs_wet import speed_table
from pipelines.output import report

__all__ = ["draw_figures", "write_report"]


def draw_figures(out_dir, names, analyses, sds, curves, settings):
    """The figures of ``roadscan compare`` in ``out_dir``: every spectrum (``psd_all.png``), each
    scan's PSD ratio to the reference where both are trusted (``psd_ratio.png``), every mu(v)
    (``mu_all.png``) and each mu(v) over the reference's (``mu_ratio.png``).

    Parameters
    ----------
    out_dir : Path
        Output folder.
    names : list of str
        The scans' names, the reference first.
    analyses : list of SurfaceAnalysis
        Each scan's analysis (its ``spectrum``).
    sds : list of dict or None
        :func:`pipelines.jobs.compare.spectrum_difference` of each scan after the first (None
        for the reference).
    curves : list of FrictionResult or None
        Each scan's mu(v) (None where friction was refused); empty without friction.
    settings : FrictionSettings
        The friction options (the rubber named in the title).

    Returns
    -------
    list of Path
        The figures drawn.
    """
    done = [c for c in curves if c is not None]
    figs = [
        report.plot_psd(
            [(n, a.spectrum.q_per_m, a.spectrum.C_m4) for n, a in zip(names, analyses)],
            out_dir / "psd_all.png",
            title="PSD of all surfaces",
        )
    ]
    ratio_curves = []
    for n, sd in zip(names[1:], sds[1:]):
        if "q_per_m" in sd:
            ratio_curves.append((f"{n} / {names[0]}", sd["q_per_m"], 10 ** sd["log10_ratio"]))
    if ratio_curves:
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=report.FIGSIZE)
        for i, (lab, q, r) in enumerate(ratio_curves):
            ax.loglog(q, r, color=f"C{i + 1}", label=lab)
        ax.axhline(1, color="0.5", lw=0.8)
        ax.set_xlabel("wave vector q [1/m]")
        ax.set_ylabel("PSD ratio C / C$_{ref}$ [-]")
        report.wavelength_axis(ax)
        report.set_title(ax, "where the spectra differ (where both are trusted)")
        ax.grid(which="both", alpha=0.25)
        ax.legend(fontsize=8)
        figs.append(
            report.save_figure(
                fig, out_dir / "psd_ratio.png", report.fixed_margins(ax, top=report.WAVELENGTH_AXIS_TOP)
            )
        )
    if done:
        from pipelines.chain.provenance import rubber_label

        figs.append(
            report.plot_mu(
                [(n, c.v_m_per_s, c.mu) for n, c in zip(names, curves) if c is not None],
                out_dir / "mu_all.png",
                title="μ(v) of all surfaces, "
                + rubber_label(settings.rubber, settings.sigma0_Pa, done[0].meta.get("T0_C")),
            )
        )
        if len(done) > 1 and curves[0] is not None:
            figs.append(
                report.plot_mu(
                    [
                        (f"{n} / {names[0]}", c.v_m_per_s, c.mu / curves[0].mu)
                        for n, c in zip(names[1:], curves[1:])
                        if c is not None
                    ],
                    out_dir / "mu_ratio.png",
                    title="where the friction differs",
                    ylabel="μ / μ$_{ref}$ [-]",
                )
            )
    return figs


def write_report(out_dir, names, result, figs, curves):
    """``report.html`` of ``roadscan compare``: the surfaces' figures (a missing one says why),
    where and by how much each differs from the reference, mu at whole decades of speed, every
    warning, and the figures.

    Parameters
    ----------
    out_dir : Path
        Output folder.
    names : list of str
        The scans' names, the reference first.
    result : dict
        The ``comparison.json`` content, one entry per scan.
    figs : list of Path
        The figures (:func:`draw_figures`).
    curves : list of FrictionResult or None
        Each scan's mu(v) (None where friction was refused); empty without friction.

    Returns
    -------
    None
    """
    from pipelines.output.units import length, quantity

    header = ["surface", "H", "rms height", "h0", "MPD (ISO 13473-1)", "peak μ", "v at peak [m/s]"]
    from pipelines.output.headline import hurst_text, peak_text

    def cell(r, key, text):  # a missing figure says why (why_missing)
        why = (r.get("why_missing") or {}).get(key)
        return f"— ({why})" if why else text

    rows = [
        [
            n,
            cell(r, "hurst", hurst_text(r)),
            length(r["rms_height_m"]),
            cell(r, "h0_m", length(r["h0_m"])),
            cell(r, "mpd_m", length(r["mpd_m"])),
            cell(
                r,
                "mu_peak",
                r.get("mu_peak")
                if not r.get("peak_at_edge")
                else peak_text(
                    **{k: r[k] for k in ("mu_peak", "v_peak_m_per_s", "peak_at_edge", "peak_note")}
                ),
            ),
            r.get("v_peak_m_per_s"),
        ]
        for n, r in result.items()
    ]
    sections = [("Surfaces", report.table_html(rows, header))]
    drows = []
    for n, r in result.items():
        d = r.get("difference_from_reference")
        if d:
            big = d.get("largest_psd_ratio")
            band = (
                (
                    quantity("q_per_m", big["band_per_m"][0])
                    + " to "
                    + quantity("q_per_m", big["band_per_m"][1])
                )
                if big
                else f"— ({d.get('largest_psd_ratio_note')})"
            )
            drows.append(
                [
                    n,
                    d["reference"],
                    band,
                    d.get("psd_ratio_median"),
                    quantity("q_per_m", big["q_per_m"]) if big else "—",
                    big["ratio"] if big else "—",
                    d.get("max_difference_v_m_per_s"),
                    d.get("max_difference_mu"),
                ]
            )
    if drows:
        sections.append(
            (
                "Where and by how much they differ",
                report.table_html(
                    drows,
                    [
                        "surface",
                        "reference",
                        "band both are trusted on",
                        "median PSD ratio",
                        "q of largest PSD ratio",
                        "largest PSD ratio",
                        "v of largest μ difference [m/s]",
                        "largest μ difference",
                    ],
                ),
            )
        )
    done = [(n, c) for n, c in zip(names, curves) if c is not None]
    if done:
        v = done[0][1].v_m_per_s
        idx = speed_table(v)
        rub = next((r["rubber"] for r in result.values() if isinstance(r, dict) and r.get("rubber")), "")
        title = f"μ at whole decades of speed, {rub}" if rub else "μ at whole decades of speed"
        sections.append(
            (
                title,
                report.table_html(
                    [[f"{v[i]:g}"] + [float(c.mu[i]) for _, c in done] for i in idx],
                    ["v [m/s]"] + [n for n, _ in done],
                ),
            )
        )
    warned = [[n, w] for n, r in result.items() if isinstance(r, dict) for w in r.get("warnings", [])]
    if warned:  # every warning in the report too
        sections.insert(1, ("Warnings", report.table_html(warned, ["surface", "warning"])))
    if figs:
        sections.append(("Figures", [list(figs)]))
    report.write_html(out_dir / "report.html", "roadscan compare: " + " vs ".join(names), sections)
