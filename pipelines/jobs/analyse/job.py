"""The ``analyse`` job: one scan -> spectrum, fit, roughness figures, mu(v), plots and report.

``pipelines.analyse`` (:mod:`pipelines.jobs.analyse.call`) is the Python call of ``roadscan
analyse``; :func:`analyse_scan` is the computation every door calls, :mod:`pipelines.jobs.analyse.outputs`
writes its files.

Outputs (one directory per scan): ``summary.json``, ``psd.csv`` (``q_per_m,C_m4``; for a line
profile the isotropic 2D estimate, with the profile's own 1D PSD in ``psd1d.csv``,
``q_per_m,C1_m3``),
``mu.csv`` (``v_m_per_s,mu,area_fraction`` with A/A0 = P(q1); ``T_flash_max_C`` added with
flash), ``heightmap.png`` (or ``profile.png``), ``psd.png``,
``psd2d.png`` (areas), ``mu.png`` and a self-contained ``report.html``; the road engineer's
texture figures (:mod:`pipelines.jobs.texture.outputs`): ``texture_spectrum.csv``
(``centre_wavelength_m,band_lo_m,band_hi_m,level_dB``), ``texture_spectrum.png`` and the
``summary.json`` keys ``texture_level_dB``, ``etd_m``, ``ifi_speed_constant_kmh`` (``ifi_F60``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pipelines.output import report
from pipelines.settings.friction import FrictionSettings  # its one home; re-exported here
from roadscan.heightmap import Profile

__all__ = ["FrictionSettings", "summarise", "run_analysis", "write_outputs", "nominal_band", "analyse_scan"]

import json

from pipelines.jobs.analyse.outputs import (
    draw_psd2d_figure,
    psd2d_picture,
    write_outputs,
)


def nominal_band(obj):
    """(2 pi / L of the longer side, pi / a of the coarser spacing) [1/m]: the wave vectors the
    scan holds at all (``q_min_per_m``, ``q_max_per_m`` of summary.json). The reliable band
    (:func:`pipelines.chain.reliable.geometry_of`) takes the shorter side instead: window
    leakage comes from the side with the fewest modes.

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
    analysis : pipelines.chain.surface.SurfaceAnalysis
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
    from pipelines.output.headline import hurst_keys, peak_keys

    fit = analysis.fit
    qmin, qmax = nominal_band(analysis.source)
    src = analysis.source
    out = {
        "name": analysis.name,
        "kind": "profile" if analysis.is_profile else "area",
        "shape": list(src.heights_m.shape),
        "spacing_m": [src.dx_m] if analysis.is_profile else [src.dx_m, src.dy_m],
        # H is a headline only over half a decade and within [0, 1]; else null with hurst_note
        # (the fitted value in hurst_fit): pipelines.output.headline
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
    if isinstance(src.meta.get("instrument"), dict):  # what the reader found (JSON-safe)
        out["instrument"] = src.meta["instrument"]
    from pipelines.settings.scan_input import read_record

    out.update(read_record(src))  # how the file was read
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


def run_analysis(
    obj,
    out_dir,
    settings=None,
    window_alpha=0.25,
    fit_band=None,
    despike=False,
    mpd_settings=None,
    figures=True,
    drawer=None,
    texture=None,
    resolution_m=None,
):
    """Analyse one scan (:func:`pipelines.analyse_scan`) and write all outputs into
    ``out_dir`` (:func:`write_outputs`). Returns the summary dict.

    ``texture``: :class:`pipelines.jobs.texture.outputs.TextureSettings` (driving direction, IFI
    inputs; default x, none). ``resolution_m``: the instrument's lateral resolution [m] for the
    reliable band (default: the file's metadata, else none).

    ``figures=False`` (``roadscan batch`` without ``--figures``) skips the PNGs; the numbers,
    the CSV/JSON files and ``report.html`` (tables only) are the same. ``drawer``: where the
    figures are drawn (:mod:`pipelines.output.figure_process`; default in this process): the height
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
        Figure process (:mod:`pipelines.output.figure_process`).
    texture : TextureSettings, optional
        Texture options.
    resolution_m : float, optional
        Lateral resolution [m].

    Returns
    -------
    dict
        The summary.
    """
    from pipelines.output.figure_process import InProcess

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    drawer = drawer if drawer is not None else InProcess()
    drawer.discard()  # nothing of an earlier scan is taken for this one's

    from pipelines.jobs.texture.iso import figure_note

    def draw_map(levelled):  # the height map is drawn while the spectrum is made
        if figures and not isinstance(levelled, Profile):
            drawer.submit(
                report.draw_heightmap,
                report.heightmap_picture(levelled),
                out_dir / "heightmap.png",
                title=f"{obj.name}: levelled heights{figure_note(texture)}",
            )

    def draw_psd2d(spec2d):  # and the 2D spectrum while the fit is made
        if figures:
            drawer.submit(draw_psd2d_figure, psd2d_picture(spec2d), out_dir / "psd2d.png", obj.name)

    try:
        result = analyse_scan(
            obj,
            settings,
            window_alpha,
            fit_band,
            despike,
            mpd_settings,
            texture,
            resolution_m,
            on_levelled=draw_map,
            on_spectrum2d=draw_psd2d,
        )
        write_outputs(result, out_dir, figures, drawer, early=True)
    except BaseException:
        drawer.discard()  # a failed scan's figures are not drawn again here
        raise
    return result.summary


def analyse_scan(
    scan,
    settings=None,
    window_alpha=0.25,
    fit_band=None,
    despike=False,
    mpd_settings=None,
    texture=None,
    resolution_m=None,
    on_levelled=None,
    on_spectrum2d=None,
):
    """Analyse a read HeightMap/Profile with checked options -> :class:`AnalysisResult`.

    The warnings are those of the current scope (:func:`pipelines.checks.validate.collecting`).

    Parameters
    ----------
    scan : HeightMap or Profile
        The scan [m].
    settings : FrictionSettings, optional
        Friction options (default: the defaults).
    window_alpha : float, optional
        Tukey window.
    fit_band : tuple of float, optional
        Fit band [1/m].
    despike : bool, optional
        Replace spikes first.
    mpd_settings : dict, optional
        ISO 13473-1 settings.
    texture : TextureSettings, optional
        Texture options.
    resolution_m : float, optional
        Lateral resolution [m].
    on_levelled, on_spectrum2d : callable, optional
        Hooks called with the levelled map and the 2D spectrum.

    Returns
    -------
    AnalysisResult
    """
    from pipelines.chain import band as analyse_band
    from pipelines.chain.steps import measure, scan_friction
    from pipelines.checks.validate import warnings_list
    from pipelines.jobs.texture import outputs as texture_outputs
    from pipelines.jobs.texture.prefetch import TextureFigures
    from pipelines.settings.friction import FrictionSettings

    settings = settings or FrictionSettings()
    figures = TextureFigures((texture or texture_outputs.TextureSettings()).direction)

    def levelled_hook(levelled):
        figures.start(levelled)
        if on_levelled is not None:
            on_levelled(levelled)

    an, rb = measure(
        scan, window_alpha, fit_band, despike, mpd_settings, resolution_m, levelled_hook, on_spectrum2d
    )
    out = scan_friction(an, rb, settings) if settings.enabled else None
    fr = None if out is None else out.result
    summary = summarise(an, fr, window_alpha=window_alpha)
    summary.update(analyse_band.summary_keys(rb, an.name))
    if fr is not None:
        summary["friction"].update(
            q0_per_m=float(fr.q_per_m[0]),
            sigma0_Pa=settings.sigma0_Pa,
            nu=settings.nu,
            contact_gamma=settings.contact_gamma,
            area_fraction_range=[float(fr.P[:, -1].min()), float(fr.P[:, -1].max())],
        )
        if out.band is not None:
            summary["friction"]["band"] = out.band
        if out.checks is not None:
            summary["friction"]["rubber_checks"] = out.checks
    if out is not None:
        analyse_band.add_provenance(summary, out.provenance, out.psd.q_min_per_m, out.psd.q1_per_m)
    summary, tex = texture_outputs.add_to_summary(summary, an, texture, mpd_settings, figures)
    summary["warnings"] = warnings_list()
    from pipelines.jobs.analyse.result import AnalysisResult

    return AnalysisResult(
        an.name,
        _as_json(summary),
        list(summary["warnings"]),
        an,
        rb,
        out,
        tex,
        window_alpha=window_alpha,
        settings=settings,
    )


def _as_json(summary):
    """The dict as ``summary.json`` holds it (numpy numbers as floats, tuples as lists,
    non-finite numbers as null), so that ``.summary`` equals the file key for key."""

    from pipelines.output.report import _jsonable

    return json.loads(json.dumps(_jsonable(summary)))
