"""The files of one analysed scan (``roadscan analyse --out``, :meth:`pipelines.AnalysisResult.write`):
``summary.json``, ``psd.csv`` (``q_per_m,C_m4``; for a line profile the isotropic 2D estimate,
with the profile's own 1D PSD in ``psd1d.csv``, ``q_per_m,C1_m3``) and ``psd_band.json`` (the
band friction integrated it over, and the fit above it), ``mu.csv``
(``v_m_per_s,mu,area_fraction[,T_flash_max_C],extrapolated_share``), ``texture_spectrum.csv``,
the figures (``heightmap.png`` or ``profile.png``, ``psd.png``, ``psd2d.png``, ``mu.png``,
``texture_spectrum.png``) and a self-contained ``report.html``. Several scans in one run: also
``summary.csv`` and a summary ``report.html`` beside their folders (:func:`write_many_summary`).
"""

from __future__ import annotations

import numpy as np

from pipelines.output import report

__all__ = [
    "write_outputs",
    "psd2d_picture",
    "draw_psd2d_figure",
    "PSD_HEADER",
    "MU_HEADER",
    "MU_EXTRA",
    "PSD1D_HEADER",
    "SUMMARY_HEADER",
    "summary_rows",
    "write_many_summary",
]

PSD_HEADER = ["q_per_m", "C_m4"]
MU_HEADER = ["v_m_per_s", "mu"]
MU_EXTRA = ["area_fraction", "T_flash_max_C"]  # A/A0 = P(q1); hottest flash temperature
PSD1D_HEADER = ["q_per_m", "C1_m3"]


def write_outputs(result, out_dir, figures=True, drawer=None, early=False):
    """Write the files of one analysed scan (:class:`pipelines.AnalysisResult`) into
    ``out_dir``: summary.json, psd.csv and its band (psd_band.json), mu.csv, the texture
    spectrum, the figures and report.html. ``early``: the height map and 2D spectrum were
    already handed to ``drawer``.

    Parameters
    ----------
    result : pipelines.AnalysisResult
        The analysed scan.
    out_dir : str or Path
        Output folder.
    figures : bool, optional
        Draw the PNGs.
    drawer : object, optional
        Figure process.
    early : bool, optional
        Whether the early figures were already handed over.

    Returns
    -------
    Path
        The output folder.
    """
    from pipelines.chain.sidecar import band_sidecar
    from pipelines.jobs.texture import outputs as texture_outputs
    from pipelines.jobs.texture.iso import figure_note
    from pipelines.output.figure_process import InProcess

    drawer = drawer if drawer is not None else InProcess()
    an, summary, tex = result.analysis, result.summary, result.texture
    spec, fit, fr = an.spectrum, an.fit, result.friction
    prov = result.friction_outcome.provenance if result.friction_outcome is not None else None
    if figures and not early:
        if not an.is_profile:
            drawer.submit(
                report.draw_heightmap,
                report.heightmap_picture(an.levelled),
                out_dir / "heightmap.png",
                title=f"{an.name}: levelled heights{figure_note(summary.get('filters'))}",
            )
        if an.spec2d is not None:
            drawer.submit(draw_psd2d_figure, psd2d_picture(an.spec2d), out_dir / "psd2d.png", an.name)
    texture_outputs.write_texture_csv(out_dir / "texture_spectrum.csv", tex)
    texture_outputs.write_extras(out_dir, tex)  # mpd_segments.csv
    report.write_csv(out_dir / "psd.csv", PSD_HEADER, [spec.q_per_m, spec.C_m4])
    report.write_json(out_dir / "psd_band.json", band_sidecar(result.reliable_band, fit, result.window_alpha))
    figs = []
    if an.is_profile:
        q1d, c1d = an.psd1d
        keep = (q1d > 0) & (c1d > 0)
        report.write_csv(out_dir / "psd1d.csv", PSD1D_HEADER, [q1d[keep], c1d[keep]])
    if fr is not None:
        cols = [fr.v_m_per_s, fr.mu, fr.P[:, -1]]
        if fr.T_q_C is not None:
            cols.append(np.max(fr.T_q_C, axis=1))
        head = MU_HEADER + MU_EXTRA[: len(cols) - 2] + ["extrapolated_share"]
        report.write_csv(out_dir / "mu.csv", head, cols + [prov["extrapolated_share"]])
    if figures:
        st = result.settings
        _figures(drawer, out_dir, an, fit, fr, spec, st.q1_per_m if st.enabled else None, summary)
        if tex.level_dB.size:
            drawer.submit(
                texture_outputs.draw_texture_spectrum,
                texture_outputs.texture_picture(tex),
                out_dir / "texture_spectrum.png",
                f"{an.name}: texture spectrum (ISO 13473-4)",
            )
        texture_outputs.draw_extras(drawer, out_dir, an.name, summary, tex)  # mpd_segments.png
    page = _report_sections(an, summary, tex, fr)  # while a helper process draws the figures
    if figures:
        figs = drawer.collect()
    report.write_json(out_dir / "summary.json", summary)
    _write_report(out_dir, an, page, figs)
    return out_dir


def _figures(drawer, out_dir, an, fit, fr, spec, q1_per_m, summary):
    """The PNGs of one scan after its height map and 2D spectrum (skipped by ``roadscan batch``
    without ``--figures``), submitted to ``drawer`` in the report's order."""
    from pipelines.jobs.texture.iso import figure_note
    from pipelines.output.headline import hurst_text
    from pipelines.output.units import wavelength_of_q

    if an.is_profile:
        q1d, c1d = an.psd1d
        keep = (q1d > 0) & (c1d > 0)
        drawer.submit(
            report.plot_profile,
            an.levelled,
            out_dir / "profile.png",
            title=f"{an.name}: levelled profile{figure_note(summary.get('filters'))}",
        )
        drawer.submit(_plot_psd1d, q1d[keep], c1d[keep], out_dir / "psd1d.png", an.name)
    lo, hi = fit.fit_band_per_m
    q_top = max(hi, q1_per_m or 0.0)
    qf = np.geomspace(lo, q_top, 60)
    curves = [
        (
            "measured (angular average)" if not an.is_profile else "2D estimate from the profile's 1D PSD",
            spec.q_per_m,
            spec.C_m4,
        )
    ]
    if "reliable_band_per_m" in summary:  # the part the fit and friction use
        rlo, rhi = summary["reliable_band_per_m"]
        inb = (spec.q_per_m >= rlo * (1 - 1e-9)) & (spec.q_per_m <= rhi * (1 + 1e-9))
        if inb.any():
            curves.append(
                (
                    f"reliable band, λ = {wavelength_of_q(rhi)} to {wavelength_of_q(rlo)}",
                    spec.q_per_m[inb],
                    spec.C_m4[inb],
                )
            )
    drawer.submit(
        report.plot_psd,
        curves,
        out_dir / "psd.png",
        title=f"{an.name}: PSD, H = {hurst_text(summary, short=True)}",
        fits=[
            (
                f"self-affine fit, λ = {wavelength_of_q(lo)} to {wavelength_of_q(hi)}"
                + (f", extended to {wavelength_of_q(q_top)}" if q_top > hi else ""),
                qf,
                fit.model_C(qf),
            )
        ],
    )
    if fr is not None:
        rub = summary["friction"].get("rubber", "thesis rubber")  # name, T0 and sigma0
        drawer.submit(
            report.plot_mu,
            [(f"{summary['friction']['model']}, {rub}", fr.v_m_per_s, fr.mu)],
            out_dir / "mu.png",
            title=f"{an.name}: friction μ(v)",
        )


def _plot_psd1d(q, C1, path, name):
    """The line profile's own 1D PSD C1(q) [m^3] (<h^2> = 2 integral C1 dq)."""
    plt = report.pyplot()

    fig, ax = plt.subplots(figsize=report.FIGSIZE)
    ax.loglog(q, C1, lw=0.8, color="C2", label="1D PSD of the profile")
    ax.set_xlabel("wave vector q [1/m]")
    ax.set_ylabel("C₁(q) [m³]")
    report.plain_log_ticks(ax)
    report.wavelength_axis(ax)
    report.set_title(ax, f"{name}: 1D PSD (<h²> = 2 ∫ C₁ dq)")
    ax.grid(which="both", alpha=0.25)
    ax.legend(fontsize=8)
    return report.save_figure(fig, path, report.fixed_margins(ax, top=report.WAVELENGTH_AXIS_TOP))


def psd2d_picture(spec2d, zoom=4):
    """The part of the 2D PSD :func:`draw_psd2d_figure` shows: |q| up to Nyquist / ``zoom``, where
    anisotropy shows (only this part of the map is built) -> (qx, qy, C, qlim).

    Parameters
    ----------
    spec2d : roadscan.Spectrum2D
        The 2D spectrum.
    zoom : float, optional
        Fraction of Nyquist shown is 1 / zoom.

    Returns
    -------
    qx, qy : ndarray
        Wave vectors [1/m].
    C : ndarray
        The map's central part [m^4].
    qlim : float
        Largest |q| shown [1/m].
    """
    qx, qy = np.asarray(spec2d.qx_per_m), np.asarray(spec2d.qy_per_m)
    qlim = min(np.abs(qx).max(), np.abs(qy).max()) / zoom
    qxs, qys, C = spec2d.central(qlim)
    return qxs, qys, C, qlim


def draw_psd2d_figure(picture, path, name):
    """log10 C(qx, qy) around the origin, from :func:`psd2d_picture`.

    Parameters
    ----------
    picture : tuple
        From :func:`psd2d_picture`.
    path : str or Path
        Output PNG.
    name : str
        Scan name for the title.

    Returns
    -------
    Path
    """
    plt = report.pyplot()

    qxs, qys, C, qlim = picture
    pos = C[C > 0]
    lo = np.percentile(pos, 2) if pos.size else 1e-30
    fig, ax = plt.subplots(figsize=report.FIGSIZE)
    p = int(np.floor(np.log10(qlim)))  # axes in 10^p 1/m: no offset text under the title
    f = 10.0**p
    im = ax.imshow(
        np.log10(np.maximum(C, lo)),
        origin="lower",
        cmap="magma",
        extent=(qxs[0] / f, qxs[-1] / f, qys[0] / f, qys[-1] / f),
        aspect="equal",
    )
    unit = "1/m" if p == 0 else f"10{str(p).translate(str.maketrans('-0123456789', '⁻⁰¹²³⁴⁵⁶⁷⁸⁹'))} 1/m"
    ax.set_xlabel(f"wave vector qx [{unit}]")
    ax.set_ylabel(f"wave vector qy [{unit}]")
    from pipelines.output.units import sig3, wavelength_of_q

    report.set_title(ax, f"{name}: 2D PSD, |q| < {sig3(qlim)} 1/m (λ > {wavelength_of_q(qlim)})", y=1.0)
    cb = fig.colorbar(im, ax=ax)
    cb.set_label("log₁₀ C [m⁴]")
    return report.save_figure(fig, path, report.fixed_margins(ax, right=1.15, top=0.4))


def _report_sections(an, summary, tex=None, fr=None):
    """The sections of ``report.html`` before its figures, and its intro."""
    from pipelines.jobs.texture import outputs as texture_outputs
    from pipelines.jobs.texture.iso import roughness_section
    from pipelines.output.headline import hurst_text
    from pipelines.output.units import length, quantity, sig3

    rough = roughness_section(summary)  # ISO 25178-2 / 21920-2 set, filters
    key = {
        "Hurst exponent H": hurst_text(summary),  # the note when the fit is no headline
        "rms height (Sq of levelled measured heights)": length(summary["rms_height_m"]),
        "band rms from fit": length(summary["band_rms_m"]),
        "h0 (thesis form)": length(summary["h0_m"]),
        "q range": quantity("q_per_m", [summary["q_min_per_m"], summary["q_max_per_m"]]),
        "fitted band": quantity("q_per_m", summary["fit_band_per_m"]),
        "roll-off q": quantity("q_per_m", summary["q_roll_per_m"]),
        "filled (unmeasured) fraction": f"{sig3(100 * summary['filled_fraction'])} %",
    }
    from pipelines.chain import band as analyse_band

    key.update(analyse_band.report_rows(summary))  # band, rubber, mu's provenance
    texture = [report.table_html(texture_outputs.depth_rows(summary), ["quantity", "value"])]
    if tex is not None and tex.level_dB.size:
        texture.append(report.paragraph_html(tex.note, note=True))
        texture.append(texture_outputs.texture_table_html(tex))
    sections = [
        ("Key figures", report.table_html(key, ["quantity", "value"])),
        ("Road texture (ISO 13473-1, ISO 13473-4, ASTM E1960)", texture),
        ("Roughness (ISO 25178-2 / 21920-2 / 4287)", rough),
    ]
    warned = analyse_band.warnings_section(summary)  # every warning in the report
    if warned:
        sections.insert(1, warned)
    shares = analyse_band.share_section(summary, fr)  # mu's provenance per speed
    if shares:
        sections.append(shares)
    return sections, report.instrument_html(summary.get("instrument"))


def _write_report(out_dir, an, page, figs):
    """``report.html``: the sections of :func:`_report_sections`, then the figures (if any)."""
    sections, intro = page
    if figs:
        sections = sections + [("Figures", [list(figs)])]
    report.write_html(out_dir / "report.html", f"roadscan analyse: {an.name}", sections, intro=intro)


#: the columns of a several-scan run's ``summary.csv`` (SI units; ``report.html`` shows them in
#: the reader's units), then ``warnings``
SUMMARY_HEADER = [
    "scan",
    "hurst",
    "hurst_stderr",
    "rms_height_m",
    "h0_m",
    "mpd_m",
    "filled_fraction",
    "mu_peak",
    "etd_m",
    "ifi_speed_constant_kmh",
]


def summary_rows(rows):
    """One row of ``summary.csv`` per analysed scan, in :data:`SUMMARY_HEADER`'s order (SI; None
    where a quantity was not computed, e.g. no friction).

    Parameters
    ----------
    rows : list of tuple
        (output sub-folder, the scan's summary.json dict).

    Returns
    -------
    list of list
    """
    return [
        [
            s,
            d["hurst"],
            d["hurst_stderr"],
            d["rms_height_m"],
            d["h0_m"],
            d["mpd_m"],
            d["filled_fraction"],
            d.get("friction", {}).get("mu_peak"),
            d.get("etd_m"),
            d.get("ifi_speed_constant_kmh"),
        ]
        for s, d in rows
    ]


def write_many_summary(out_dir, rows, warnings):
    """Write the files of a several-scan ``roadscan analyse``: ``summary.csv`` (one row a scan,
    :data:`SUMMARY_HEADER` then ``warnings``: that scan's warnings in one quoted cell joined by
    " | ", floats to 6 significant digits) and ``report.html`` (the table in the reader's units,
    the warnings, links to each scan's report), both written atomically.

    Parameters
    ----------
    out_dir : Path
        Output folder (each scan's files in a sub-folder named as in ``rows``).
    rows : list of tuple
        (sub-folder, the scan's summary.json dict).
    warnings : list of list of str
        Each scan's warnings.

    Returns
    -------
    list of list
        The rows of summary.csv (without the warnings).
    """
    from roadscan.io.atomic import atomic_write_text

    header, table = SUMMARY_HEADER, summary_rows(rows)
    lines = [",".join(header)] + [
        ",".join("" if c is None else (f"{c:.6g}" if isinstance(c, float) else str(c)) for c in r)
        for r in table
    ]
    lines = [lines[0] + ",warnings"] + [
        f'{ln},"{" | ".join(w).replace(chr(34), chr(34) * 2)}"' for ln, w in zip(lines[1:], warnings)
    ]
    atomic_write_text(out_dir / "summary.csv", "\n".join(lines) + "\n")
    links = report.list_html([s for s, _ in rows], links=[f"{s}/report.html" for s, _ in rows])
    sections = [("Scans", _scans_html(table, header)), ("Reports", links)]
    warned = [[s, w] for (s, _), ws in zip(rows, warnings) for w in ws]
    if warned:
        sections.insert(1, ("Warnings", report.table_html(warned, ["scan", "warning"])))
    report.write_html(out_dir / "report.html", "roadscan analyse: summary", sections)
    return table


def _scans_html(table, header):
    """The summary table in the reader's units (mm, µm, %, km/h; summary.csv keeps SI)."""
    from pipelines.output.units import label_of, quantity, sig3

    shown = [
        [r[0]]
        + [
            f"{sig3(100 * c)} %" if k == "filled_fraction" and c is not None else quantity(k, c)
            for k, c in zip(header[1:], r[1:])
        ]
        for r in table
    ]
    names = {
        "hurst": "H",
        "hurst_stderr": "± H",
        "mpd_m": "MPD",
        "etd_m": "ETD",
        "mu_peak": "peak μ",
        "ifi_speed_constant_kmh": "IFI Sp",
    }
    return report.table_html(shown, [names.get(h, label_of(h)) for h in header])
