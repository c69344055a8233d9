"""The dry-vs-wet job (thesis section 4.4): rain-fill a scan and compare spectra and mu(v).

Water fills the road's cavities and the sliding rubber seals them, so the rubber "feels" the
filled (wet) surface. The dry surface is levelled (plane, ignoring unmeasured points), filled
with water by :func:`roadscan.rain.rain_fill` in that levelled frame, and both surfaces go
through the same spectrum and friction chain. The friction engine uses the dry surface's q0
for both, so that only the surface changes.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from roadscan.errors import InputError
from roadscan.heightmap import HeightMap
from roadscan.io.atomic import atomic_save_npy

from pipelines.output import report
from pipelines.jobs.analyse.job import nominal_band
from pipelines.settings.friction import FrictionSettings
from pipelines.chain.surface import analyse_surface

__all__ = ["dry_vs_wet", "run_dry_vs_wet", "speed_table", "mu_by_speed"]


def dry_vs_wet(scan, out, **options):
    """``roadscan dry-vs-wet`` as one call: the scan rain-filled, and its spectrum and mu(v)
    dry and wet compared (:func:`run_dry_vs_wet`), written into ``out`` (all or none).

    ``options`` are the command's long flags with dashes as underscores, taking what the flag
    takes (``connectivity=8``, ``max_depth=5e-4``, ``spacing="5e-5"``, ``sigma0="0.25MPa"``,
    ``nu=0.45``, ``window_alpha=0.3``), parsed by the command's own option definitions
    (:func:`pipelines.settings.water.add_dry_vs_wet_options`). Water fills the depressions up
    to their spill level (morphological reconstruction: Soille, *Morphological Image
    Analysis*, 2003, sec. 6.3.7); friction: Persson, J. Chem. Phys. 115, 3840 (2001).

    Parameters
    ----------
    scan : str, os.PathLike or HeightMap
        An area height file, or a scan in memory [m].
    out : str or Path
        Output folder, as ``--out``.
    **options
        ``roadscan dry-vs-wet``'s long flags with dashes as underscores.

    Returns
    -------
    dict
        The ``comparison.json`` content: ``rms_height_dry_m``, ``rms_height_wet_m`` [m],
        ``hurst_dry``, ``hurst_wet``, ``wetted_fraction``, ``water_volume_m3_per_m2`` [m],
        ``connectivity``, ``max_depth_m``, ``water_film_m``, ``psd_ratio_wet_to_dry_median``,
        ``mu_dry`` and ``mu_wet`` (``{"v": mu}``, or None without friction),
        ``max_difference_v_m_per_s`` [m/s], ``max_difference_mu``, ``mu_peak_dry``,
        ``mu_peak_wet``, ``rubber``, ``warnings`` and how the file was read. Files: that JSON,
        ``wet.npy``, ``wet.npz``, ``mu.csv`` (with friction), the PNGs and ``report.html``.

    Raises
    ------
    TypeError
        An unknown keyword.
    roadscan.errors.InputError
        A value the flag refuses, or a scan the job cannot use (one line).
    """
    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    from pipelines.settings.analyse import options_from_kwargs, spectrum_kwargs
    from pipelines.settings.friction import settings_from_args
    from pipelines.settings.scan_input import scan_of, source_path
    from pipelines.checks.validate import collecting
    from pipelines.settings.water import add_dry_vs_wet_options, check_water_options

    args = options_from_kwargs(options, "dry_vs_wet", add_dry_vs_wet_options)
    path = source_path(scan)
    inputs = [path] if path is not None else []
    with collecting():
        check_water_options(args)
        check_output_dir(out, inputs=inputs)
        settings = settings_from_args(args)
        sk = spectrum_kwargs(args)
        obj = scan_of(scan, args)
        try:
            with atomic_output_dir(out, inputs=inputs) as tmp:
                return run_dry_vs_wet(obj, tmp, settings, connectivity=args.connectivity,
                                      max_depth_m=args.max_depth, water_film_m=args.water_film, **sk)
        except InputError as exc:
            if path is None or "out" in exc.hint_option or str(exc.path or "").startswith(str(out)):
                raise                      # about the output, which it names: not the scan
            raise exc.reworded(path) from None


def mu_by_speed(v_m_per_s, mu):
    """{f"{v:g}": mu} (the JSON form of a mu(v) curve in comparison reports).

    Parameters
    ----------
    v_m_per_s, mu : array_like
        The curve.

    Returns
    -------
    dict
    """
    return {f"{float(v):g}": float(m) for v, m in zip(v_m_per_s, mu)}


def speed_table(v_m_per_s):
    """Speeds at whole decades within the grid (for the report's table).

    Parameters
    ----------
    v_m_per_s : array_like
        Speeds [m/s].

    Returns
    -------
    list of int
        Indices.
    """
    lv = np.log10(v_m_per_s)
    return [i for i, x in enumerate(lv) if abs(x - round(x)) < 1e-6]


def run_dry_vs_wet(scan, out_dir, settings=None, connectivity=4, max_depth_m=None,
                   water_film_m=None, window_alpha=0.25, resolution_m=None, fit_band=None,
                   despike=False):
    """Compute and write the dry-vs-wet comparison; returns the ``comparison.json`` dict.

    Both surfaces go through the one chain (:mod:`pipelines.chain.steps`) with every friction option
    of ``settings``: the dry mu(v) is the one ``roadscan analyse`` gives for the scan (its
    reliable band, lateral resolution ``resolution_m`` [m] or the file's, and fit, over
    ``fit_band`` when given; ``despike`` marks the dry scan's spikes as analyse does); the wet
    spectrum is integrated over the dry band with the dry fit, so that only the surface changes.

    Parameters
    ----------
    scan : HeightMap
        The scan [m].
    out_dir : str or Path
        Output folder.
    settings : FrictionSettings, optional
        Friction options.
    connectivity : {4, 8}, optional
        Rain-fill neighbourhood.
    max_depth_m, water_film_m : float, optional
        Limited water [m].
    window_alpha : float, optional
        Tukey window.
    resolution_m : float, optional
        Lateral resolution [m].

    Returns
    -------
    dict
        ``comparison.json``.
    """
    from pipelines.chain.steps import measure, scan_friction
    from roadscan import level
    from roadscan.rain import rain_fill

    if not isinstance(scan, HeightMap):
        raise InputError(scan.name or None, "dry-vs-wet needs an area scan (a height map), not a line profile")
    settings = settings or FrictionSettings()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)

    dry = level.level(scan, degree=1)
    rain = rain_fill(dry, connectivity=connectivity, max_depth_m=max_depth_m, water_film_m=water_film_m)
    wet = rain.wet
    an_dry, rb_dry = measure(dry, window_alpha=window_alpha, fit_band=fit_band, despike=despike,
                             resolution_m=resolution_m)
    an_wet = analyse_surface(wet, window_alpha=window_alpha)

    atomic_save_npy(out_dir / "wet.npy", wet.heights_m)   # NaN where unmeasured
    from roadscan.io import write

    write(out_dir / "wet.npz", wet)    # the same with its spacing: heights, dx, dy, unmeasured

    from pipelines.output.headline import WET_MODEL, hurst_keys, peak_keys, side_keys

    result = {
        "name": scan.name,
        "rms_height_dry_m": an_dry.roughness["Sq_m"],
        "rms_height_wet_m": an_wet.roughness["Sq_m"],
        "hurst_dry": an_dry.fit.hurst,
        "hurst_wet": an_wet.fit.hurst,
        "hurst_stderr_dry": an_dry.fit.hurst_stderr,
        "hurst_stderr_wet": an_wet.fit.hurst_stderr,
        # H a headline only over half a decade and within [0, 1] (pipelines.output.headline)
        **side_keys(hurst_keys(an_dry.fit.hurst, an_dry.fit.hurst_stderr, an_dry.fit.fit_band_per_m), "dry"),
        **side_keys(hurst_keys(an_wet.fit.hurst, an_wet.fit.hurst_stderr, an_wet.fit.fit_band_per_m), "wet"),
        "wetted_fraction": rain.wetted_fraction,
        "water_volume_m3_per_m2": rain.water_volume_m3_per_m2,
        "connectivity": connectivity,
        "max_depth_m": max_depth_m,
        "water_film_m": water_film_m,
        "q_range_per_m": list(nominal_band(scan)),
    }
    # ratio of spectra, band by band: the thesis found the wet PSD about four times lower
    q = an_dry.spectrum.q_per_m
    C_wet_on_dry = np.interp(np.log(q), np.log(an_wet.spectrum.q_per_m), an_wet.spectrum.C_m4)
    psd_ratio = C_wet_on_dry / an_dry.spectrum.C_m4
    result["psd_ratio_wet_to_dry_median"] = float(np.median(psd_ratio))

    figs = [report.plot_heightmap(dry, out_dir / "dry_heightmap.png", title=f"{scan.name}: dry (levelled)"),
            report.plot_heightmap(dry, out_dir / "water_depth.png", depth_m=rain.depth_m,
                                  title=f"{scan.name}: water depth ({connectivity}-connected fill)")]
    figs.append(report.plot_psd([("dry", q, an_dry.spectrum.C_m4),
                                 ("wet (rain-filled)", an_wet.spectrum.q_per_m, an_wet.spectrum.C_m4)],
                                out_dir / "psd_dry_wet.png", title=f"{scan.name}: PSD dry and wet"))
    from pipelines.checks import validate
    from pipelines.jobs.render3d import render_3d_view

    view = render_3d_view(dry, rain.depth_m, out_dir / "surface_3d.png", title=f"{scan.name}: surface and water")
    result["renderer_3d"] = view.renderer          # pyvista | matplotlib | None (not drawn)
    if view.path is not None:
        figs.append(view.path)
    if view.note:
        result["render_note"] = view.note
    if view.warning:
        validate.warn(view.warning)

    od = ow = None
    if settings.enabled:
        od = scan_friction(an_dry, rb_dry, settings)      # analyse's mu(v) of this scan
        if od.result is not None:
            ow = scan_friction(an_wet, rb_dry, settings, fit=an_dry.fit,
                               v_m_per_s=od.result.v_m_per_s, name=f"{scan.name} (wet)")
        if ow is None or ow.result is None:
            result["friction_refused"] = (od if od.result is None else ow).provenance["refused"]
    if ow is not None and ow.result is not None:
        from pipelines.chain.provenance import rubber_label

        fd, fw = od.result, ow.result
        v = fd.v_m_per_s
        result["model"] = "flash temperature" if settings.flash else "isothermal"
        result["mu_dry"] = mu_by_speed(v, fd.mu)
        result["mu_wet"] = mu_by_speed(v, fw.mu)
        i = int(np.argmax(np.abs(fd.mu - fw.mu)))
        result["max_difference_v_m_per_s"] = float(v[i])
        result["max_difference_mu"] = float(fd.mu[i] - fw.mu[i])
        result["mu_peak_dry"] = float(fd.mu.max())
        result["mu_peak_wet"] = float(fw.mu.max())
        for side, curve in (("dry", fd), ("wet", fw)):     # largest mu at a grid end: no peak
            result.update(side_keys({k: x for k, x in peak_keys(v, curve.mu).items()
                                     if k.startswith("peak_")}, side))
        result["wet_model"] = WET_MODEL           # what the wet/dry ratio covers and leaves out
        result["rubber"] = rubber_label(settings.rubber, settings.sigma0_Pa, fd.meta.get("T0_C"))
        report.write_csv(out_dir / "mu.csv", ["v_m_per_s", "mu_dry", "mu_wet"], [v, fd.mu, fw.mu])
        figs.append(report.plot_mu([("dry", v, fd.mu), ("wet (rain-filled)", v, fw.mu)],
                                   out_dir / "mu_dry_wet.png",
                                   title=f"{scan.name}: μ(v) dry and wet, {result['rubber']}"))
        ratio = np.divide(fw.mu, fd.mu, out=np.full_like(fw.mu, np.nan), where=fd.mu > 0)
        figs.append(report.plot_mu([("μ_wet / μ_dry", v, ratio)], out_dir / "mu_ratio.png",
                                   title=f"{scan.name}: wet-to-dry friction ratio",
                                   ylabel="μ_wet / μ_dry [-]"))
    else:
        result["mu_dry"] = result["mu_wet"] = None
        result["max_difference_v_m_per_s"] = None

    result["warnings"] = validate.warnings_list()   # every line this run printed
    from pipelines.settings.scan_input import read_record

    result.update(read_record(scan))           # how the file was read: channel, overrides
    report.write_json(out_dir / "comparison.json", result)
    _write_report(out_dir, scan.name, result, figs)
    return result


def _write_report(out_dir, name, r, figs):
    from pipelines.output.headline import hurst_pair_text, wet_model_html
    from pipelines.output.units import length, sig3

    key = {
        "rms height dry / wet": f"{length(r['rms_height_dry_m'])} / {length(r['rms_height_wet_m'])}",
        "Hurst exponent dry / wet": hurst_pair_text(r),
        "median PSD ratio wet / dry": r["psd_ratio_wet_to_dry_median"],
        "wetted area fraction": (f"{sig3(100 * r['wetted_fraction'])} %"
                                 if r["wetted_fraction"] is not None else None),
        "water per area (volume / area, as a depth)": length(r["water_volume_m3_per_m2"]),
        "connectivity of the fill": r["connectivity"],
        **({"water depth cap (--max-depth)": length(r["max_depth_m"])} if r.get("max_depth_m") else {}),
        **({"water film per area (--water-film)": length(r["water_film_m"])}
           if r.get("water_film_m") else {}),
        "3D view drawn with": r.get("renderer_3d") or "not drawn",
        "rubber (friction)": r.get("rubber") or "—",
    }
    sections = [("Key figures", report.table_html(key, ["quantity", "value"]))]
    notes = list(r.get("warnings") or []) + ([r["render_note"]] if r.get("render_note") else [])
    if notes:
        sections.append(("Warnings and notes", report.list_html(notes)))
    if r.get("mu_dry"):
        vs = list(r["mu_dry"])
        v = np.array([float(s) for s in vs])
        rows = [(s, r["mu_dry"][s], r["mu_wet"][s], r["mu_wet"][s] / r["mu_dry"][s] if r["mu_dry"][s] else None)
                for s, i in zip(vs, range(len(vs))) if i in speed_table(v)]
        sections.append((f"Friction ({r['model']}); largest difference at v = "
                         f"{r['max_difference_v_m_per_s']:.3g} m/s",
                         report.table_html(rows, ["v [m/s]", "μ dry", "μ wet", "wet / dry"])))
    if r.get("wet_model"):
        sections.append(("What the wet model covers", wet_model_html()))
    sections.append(("Figures", [list(figs)]))
    note = ("Water fills every depression not connected to the border up to its spill level "
            "(grayscale imfill / morphological reconstruction)"
            + (f", at most {length(r['max_depth_m'])} deep" if r.get("max_depth_m") else "")
            + (f", with {length(r['water_film_m'])} of water per area" if r.get("water_film_m") else "")
            + "; the rubber slides over the filled surface.")
    report.write_html(out_dir / "report.html", f"roadscan dry-vs-wet: {name}", sections, intro=note)
