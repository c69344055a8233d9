"""The ``analyse`` job: one scan -> spectrum, fit, roughness figures, mu(v), plots and report.

This module is also callable: ``pipelines.analyse(source, **options)`` is
:func:`pipelines.api.analyse` (the computation; this module writes its outputs).

Outputs (one directory per scan): ``summary.json``, ``psd.csv`` (``q_per_m,C_m4``; for a line
profile the isotropic 2D estimate, with the profile's own 1D PSD in ``psd1d.csv``,
``q_per_m,C1_m3``),
``mu.csv`` (``v_m_per_s,mu,area_fraction`` with A/A0 = P(q1); ``T_flash_max_C`` added with
flash), ``heightmap.png`` (or ``profile.png``), ``psd.png``,
``psd2d.png`` (areas), ``mu.png`` and a self-contained ``report.html``; the road engineer's
texture figures (:mod:`pipelines.texture_outputs`): ``texture_spectrum.csv``
(``centre_wavelength_m,band_lo_m,band_hi_m,level_dB``), ``texture_spectrum.png`` and the
``summary.json`` keys ``texture_level_dB``, ``etd_m``, ``ifi_speed_constant_kmh`` (``ifi_F60``).
"""
from __future__ import annotations

import sys
import types
from pathlib import Path

import numpy as np

from roadscan.heightmap import Profile

from . import report
from .friction_options import FrictionSettings  # its one home; re-exported here

__all__ = ["FrictionSettings", "summarise", "run_analysis", "write_outputs", "nominal_band"]

PSD_HEADER = ["q_per_m", "C_m4"]
MU_HEADER = ["v_m_per_s", "mu"]
MU_EXTRA = ["area_fraction", "T_flash_max_C"]   # A/A0 = P(q1); hottest flash temperature
PSD1D_HEADER = ["q_per_m", "C1_m3"]


def nominal_band(obj):
    """(2 pi / L of the longer side, pi / a of the coarser spacing) [1/m].

    Parameters
    ----------
    obj : HeightMap or Profile
        The scan.

    Returns
    -------
    tuple of float
        (q_min, q_max) [1/m].
    """
    if isinstance(obj, Profile):
        return 2 * np.pi / obj.length_m, np.pi / obj.dx_m
    lx, ly = obj.size_m
    return 2 * np.pi / max(lx, ly), np.pi / max(obj.dx_m, obj.dy_m)


def summarise(analysis, fr=None, window_alpha=0.25):
    """The ``summary.json`` dictionary of one analysed scan (its keys are a contract).

    Parameters
    ----------
    analysis : pipelines.spectrum_bridge.SurfaceAnalysis
        The analysed scan.
    fr : friction.FrictionResult, optional
        Its friction (None: not computed).
    window_alpha : float, optional
        Tukey window used.

    Returns
    -------
    dict
        The summary (JSON-ready).
    """
    from .headline import hurst_keys, peak_keys

    fit = analysis.fit
    qmin, qmax = nominal_band(analysis.source)
    src = analysis.source
    out = {
        "name": analysis.name,
        "kind": "profile" if analysis.is_profile else "area",
        "shape": list(src.heights_m.shape),
        "spacing_m": [src.dx_m] if analysis.is_profile else [src.dx_m, src.dy_m],
        # H is a headline only over half a decade and within [0, 1]; else null with hurst_note
        # (the fitted value in hurst_fit): pipelines.headline
        **hurst_keys(fit.hurst, fit.hurst_stderr, fit.fit_band_per_m),
        "rms_height_m": analysis.roughness.get("Sq_m", analysis.roughness.get("Rq_m")),
        "band_rms_m": fit.band_rms_m,
        # h0 of the thesis form is undefined for H <= 0 (C falls no faster than white noise):
        # null, and validate.check_fit's warning says why (never a NaN written as null)
        "h0_m": fit.h0_m if np.isfinite(fit.h0_m) else None,
        "q_min_per_m": qmin,
        "q_max_per_m": qmax,
        "fit_band_per_m": [float(b) for b in fit.fit_band_per_m],
        "q_roll_per_m": fit.q_roll_per_m,
        "roughness": analysis.roughness,
        "mpd_m": analysis.mpd_m,
        "mpd_note": analysis.mpd_note,
        "filled_fraction": analysis.filled_fraction,
        "psd_convention": f"Persson: <h^2> = 2 pi integral q C(q) dq; C in m^4; Tukey window "
                          f"alpha {window_alpha:g} with its power loss corrected",
    }
    if "trim_note" in src.meta:
        out["trim_note"] = src.meta["trim_note"]
    if isinstance(src.meta.get("instrument"), dict):   # what the reader found (JSON-safe)
        out["instrument"] = src.meta["instrument"]
    from .scan_input import read_record

    out.update(read_record(src))                      # how the file was read
    if analysis.is_profile:
        out["psd_conversion"] = analysis.spectrum.meta.get("conversion")
    if analysis.anisotropy is not None:
        out["anisotropy"] = analysis.anisotropy
    if fr is not None:
        out["friction"] = {
            "model": "flash temperature" if fr.T_q_C is not None else "isothermal",
            # mu_peak, v_peak_m_per_s, peak_at_edge (largest mu at the first or last speed: no
            # peak in the range) and peak_note
            **peak_keys(fr.v_m_per_s, fr.mu),
            "q1_per_m": float(fr.q_per_m[-1]),
        }
    return out


def run_analysis(obj, out_dir, settings=None, window_alpha=0.25, fit_band=None, despike=False,
                 mpd_settings=None, figures=True, drawer=None, texture=None, resolution_m=None):
    """Analyse one scan (:func:`pipelines.api.analyse_scan`) and write all outputs into
    ``out_dir`` (:func:`write_outputs`). Returns the summary dict.

    ``texture``: :class:`pipelines.texture_outputs.TextureSettings` (driving direction, IFI
    inputs; default x, none). ``resolution_m``: the instrument's lateral resolution [m] for the
    reliable band (default: the file's metadata, else none).

    ``figures=False`` (``roadscan batch`` without ``--figures``) skips the PNGs; the numbers,
    the CSV/JSON files and ``report.html`` (tables only) are the same. ``drawer``: where the
    figures are drawn (:mod:`pipelines.figure_process`; default in this process): the height
    map and the 2D spectrum are handed to it as soon as they exist.

    Parameters
    ----------
    obj : HeightMap or Profile
        The scan [m].
    out_dir : str or Path
        Output folder.
    settings : FrictionSettings, optional
        Friction options.
    window_alpha : float, optional
        Tukey window.
    fit_band : tuple of float, optional
        Band of the self-affine fit [1/m].
    despike : bool, optional
        Replace spikes before the spectrum.
    mpd_settings : dict, optional
        ISO 13473-1 settings.
    figures : bool, optional
        Draw the PNGs.
    drawer : object, optional
        Figure process (:mod:`pipelines.figure_process`).
    texture : TextureSettings, optional
        Texture options.
    resolution_m : float, optional
        Lateral resolution [m].

    Returns
    -------
    dict
        The summary.
    """
    from .api import analyse_scan
    from .figure_process import InProcess

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    drawer = drawer if drawer is not None else InProcess()
    drawer.discard()                      # nothing of an earlier scan is taken for this one's

    def draw_map(levelled):               # the height map is drawn while the spectrum is made
        if figures and not isinstance(levelled, Profile):
            drawer.submit(report.draw_heightmap, report.heightmap_picture(levelled),
                          out_dir / "heightmap.png", title=f"{obj.name}: levelled heights")

    def draw_psd2d(spec2d):               # and the 2D spectrum while the fit is made
        if figures:
            drawer.submit(draw_psd2d_figure, psd2d_picture(spec2d), out_dir / "psd2d.png", obj.name)

    try:
        result = analyse_scan(obj, settings, window_alpha, fit_band, despike, mpd_settings,
                              texture, resolution_m, on_levelled=draw_map, on_spectrum2d=draw_psd2d)
        write_outputs(result, out_dir, figures, drawer, early=True)
    except BaseException:
        drawer.discard()                  # a failed scan's figures are not drawn again here
        raise
    return result.summary


def write_outputs(result, out_dir, figures=True, drawer=None, early=False):
    """Write the files of one analysed scan (:class:`pipelines.api.AnalysisResult`) into
    ``out_dir``: summary.json, psd.csv and its band (psd_band.json), mu.csv, the texture
    spectrum, the figures and report.html. ``early``: the height map and 2D spectrum were
    already handed to ``drawer``.

    Parameters
    ----------
    result : pipelines.api.AnalysisResult
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
    from . import texture_outputs
    from .chain import band_sidecar
    from .figure_process import InProcess

    drawer = drawer if drawer is not None else InProcess()
    an, summary, tex = result.analysis, result.summary, result.texture
    spec, fit, fr = an.spectrum, an.fit, result.friction
    prov = result.friction_outcome.provenance if result.friction_outcome is not None else None
    if figures and not early:
        if not an.is_profile:
            drawer.submit(report.draw_heightmap, report.heightmap_picture(an.levelled),
                          out_dir / "heightmap.png", title=f"{an.name}: levelled heights")
        if an.spec2d is not None:
            drawer.submit(draw_psd2d_figure, psd2d_picture(an.spec2d), out_dir / "psd2d.png", an.name)
    texture_outputs.write_texture_csv(out_dir / "texture_spectrum.csv", tex)
    texture_outputs.write_extras(out_dir, tex)                  # mpd_segments.csv
    report.write_csv(out_dir / "psd.csv", PSD_HEADER, [spec.q_per_m, spec.C_m4])
    report.write_json(out_dir / "psd_band.json", band_sidecar(result.reliable_band, fit,
                                                              result.window_alpha))
    figs = []
    if an.is_profile:
        q1d, c1d = an.psd1d
        keep = (q1d > 0) & (c1d > 0)
        report.write_csv(out_dir / "psd1d.csv", PSD1D_HEADER, [q1d[keep], c1d[keep]])
    if fr is not None:
        cols = [fr.v_m_per_s, fr.mu, fr.P[:, -1]]
        if fr.T_q_C is not None:
            cols.append(np.max(fr.T_q_C, axis=1))
        head = MU_HEADER + MU_EXTRA[:len(cols) - 2] + ["extrapolated_share"]
        report.write_csv(out_dir / "mu.csv", head, cols + [prov["extrapolated_share"]])
    if figures:
        st = result.settings
        _figures(drawer, out_dir, an, fit, fr, spec, st.q1_per_m if st.enabled else None, summary)
        if tex.level_dB.size:
            drawer.submit(texture_outputs.draw_texture_spectrum, texture_outputs.texture_picture(tex),
                          out_dir / "texture_spectrum.png",
                          f"{an.name}: texture spectrum (ISO 13473-4)")
        texture_outputs.draw_extras(drawer, out_dir, an.name, summary, tex)   # mpd_segments.png
        figs = drawer.collect()
    report.write_json(out_dir / "summary.json", summary)
    _write_report(out_dir, an, summary, figs, tex, fr)
    return out_dir


def _figures(drawer, out_dir, an, fit, fr, spec, q1_per_m, summary):
    """The PNGs of one scan after its height map and 2D spectrum (skipped by ``roadscan batch``
    without ``--figures``), submitted to ``drawer`` in the report's order."""
    from .headline import hurst_text
    from .units_format import wavelength_of_q

    if an.is_profile:
        q1d, c1d = an.psd1d
        keep = (q1d > 0) & (c1d > 0)
        drawer.submit(report.plot_profile, an.levelled, out_dir / "profile.png",
                      title=f"{an.name}: levelled profile")
        drawer.submit(_plot_psd1d, q1d[keep], c1d[keep], out_dir / "psd1d.png", an.name)
    lo, hi = fit.fit_band_per_m
    q_top = max(hi, q1_per_m or 0.0)
    qf = np.geomspace(lo, q_top, 60)
    curves = [("measured (angular average)" if not an.is_profile else
               "2D estimate from the profile's 1D PSD", spec.q_per_m, spec.C_m4)]
    if "reliable_band_per_m" in summary:    # the part the fit and friction use
        rlo, rhi = summary["reliable_band_per_m"]
        inb = (spec.q_per_m >= rlo * (1 - 1e-9)) & (spec.q_per_m <= rhi * (1 + 1e-9))
        if inb.any():
            curves.append((f"reliable band, λ = {wavelength_of_q(rhi)} to {wavelength_of_q(rlo)}",
                           spec.q_per_m[inb], spec.C_m4[inb]))
    drawer.submit(report.plot_psd,
                  curves, out_dir / "psd.png", title=f"{an.name}: PSD, H = {hurst_text(summary, short=True)}",
                  fits=[(f"self-affine fit, λ = {wavelength_of_q(lo)} to {wavelength_of_q(hi)}"
                         + (f", extended to {wavelength_of_q(q_top)}" if q_top > hi else ""), qf, fit.model_C(qf))])
    if fr is not None:
        rub = summary["friction"].get("rubber", "thesis rubber")   # name, T0 and sigma0
        drawer.submit(report.plot_mu, [(f"{summary['friction']['model']}, {rub}", fr.v_m_per_s, fr.mu)],
                      out_dir / "mu.png", title=f"{an.name}: friction μ(v)")


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
    anisotropy shows (only this part of the map is built) -> (qx, qy, C, qlim)."""
    qx, qy = np.asarray(spec2d.qx_per_m), np.asarray(spec2d.qy_per_m)
    qlim = min(np.abs(qx).max(), np.abs(qy).max()) / zoom
    qxs, qys, C = spec2d.central(qlim)
    return qxs, qys, C, qlim


def draw_psd2d_figure(picture, path, name):
    """log10 C(qx, qy) around the origin, from :func:`psd2d_picture`."""
    plt = report.pyplot()

    qxs, qys, C, qlim = picture
    pos = C[C > 0]
    lo = np.percentile(pos, 2) if pos.size else 1e-30
    fig, ax = plt.subplots(figsize=report.FIGSIZE)
    p = int(np.floor(np.log10(qlim)))     # axes in 10^p 1/m: no offset text under the title
    f = 10.0 ** p
    im = ax.imshow(np.log10(np.maximum(C, lo)), origin="lower", cmap="magma",
                   extent=(qxs[0] / f, qxs[-1] / f, qys[0] / f, qys[-1] / f), aspect="equal")
    unit = "1/m" if p == 0 else f"10{str(p).translate(str.maketrans('-0123456789', '⁻⁰¹²³⁴⁵⁶⁷⁸⁹'))} 1/m"
    ax.set_xlabel(f"wave vector qx [{unit}]")
    ax.set_ylabel(f"wave vector qy [{unit}]")
    from .units_format import sig3, wavelength_of_q
    report.set_title(ax, f"{name}: 2D PSD, |q| < {sig3(qlim)} 1/m (λ > {wavelength_of_q(qlim)})")
    cb = fig.colorbar(im, ax=ax)
    cb.set_label("log₁₀ C [m⁴]")
    return report.save_figure(fig, path, report.fixed_margins(ax, right=1.15, top=0.4))


def _write_report(out_dir, an, summary, figs, tex=None, fr=None):
    from . import texture_outputs
    from .units_format import length, quantity, sig3

    from .headline import hurst_text
    from .texture_iso import roughness_section

    rough = roughness_section(summary)          # ISO 25178-2 / 21920-2 set, filters
    key = {
        "Hurst exponent H": hurst_text(summary),     # the note when the fit is no headline
        "rms height (Sq of levelled measured heights)": length(summary["rms_height_m"]),
        "band rms from fit": length(summary["band_rms_m"]),
        "h0 (thesis form)": length(summary["h0_m"]),
        "q range": quantity("q_per_m", [summary["q_min_per_m"], summary["q_max_per_m"]]),
        "fitted band": quantity("q_per_m", summary["fit_band_per_m"]),
        "roll-off q": quantity("q_per_m", summary["q_roll_per_m"]),
        "filled (unmeasured) fraction": f"{sig3(100 * summary['filled_fraction'])} %",
    }
    from . import analyse_band

    key.update(analyse_band.report_rows(summary))   # band, rubber, mu's provenance
    texture = [report.table_html(texture_outputs.depth_rows(summary), ["quantity", "value"])]
    if tex is not None and tex.level_dB.size:
        texture.append(f"<p class='note'>{texture_outputs.html_escape(tex.note)}</p>")
        texture.append(texture_outputs.texture_table_html(tex))
    sections = [("Key figures", report.table_html(key, ["quantity", "value"])),
                ("Road texture (ISO 13473-1, ISO 13473-4, ASTM E1960)", texture),
                ("Roughness (ISO 25178-2 / 21920-2 / 4287)", rough),
                ("Figures", [list(figs)])]
    if not figs:
        sections.pop()
    warned = analyse_band.warnings_section(summary)     # every warning in the report
    if warned:
        sections.insert(1, warned)
    shares = analyse_band.share_section(summary, fr)    # mu's provenance per speed
    if shares:
        sections.insert(-1 if figs else len(sections), shares)
    report.write_html(out_dir / "report.html", f"roadscan analyse: {an.name}", sections,
                      intro=report.instrument_html(summary.get("instrument")))


class _CallableModule(types.ModuleType):
    """``pipelines.analyse`` is both this module (its outputs, for the command) and the call
    ``pipelines.analyse(source, **options)`` (:func:`pipelines.api.analyse`)."""

    def __call__(self, source, **options):
        from .api import analyse

        return analyse(source, **options)


sys.modules[__name__].__class__ = _CallableModule
