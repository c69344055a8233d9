"""The dry-vs-wet job (thesis section 4.4): rain-fill a scan and compare spectra and mu(v).

Water fills the road's cavities and the sliding rubber seals them, so the rubber "feels" the
filled (wet) surface. The dry surface is levelled (plane, ignoring unmeasured points), filled
with water by :func:`roadscan.rain.rain_fill` in that levelled frame, and both surfaces go
through the same spectrum and friction chain. The friction engine uses the dry surface's q0
for both, so that only the surface changes.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from pipelines.chain.surface import analyse_surface
from pipelines.jobs.analyse.job import nominal_band
from pipelines.output import report
from pipelines.output.job_result import returns_job_result
from pipelines.settings.friction import FrictionSettings
from pipelines.settings.option_docs import document_options
from roadscan.errors import InputError
from roadscan.heightmap import HeightMap
from roadscan.io.atomic import atomic_save_npy

if TYPE_CHECKING:  # numpy's typing only for checkers: the command's --help stays light
    from numpy.typing import ArrayLike

__all__ = ["dry_vs_wet", "run_dry_vs_wet", "speed_table", "mu_by_speed"]


@returns_job_result("dry_vs_wet")
@document_options()
def dry_vs_wet(
    scan: Any,
    out: str | os.PathLike[str],
    *,
    spacing: float | str | tuple[float, float] | None = None,
    units: Literal["m", "mm", "um", "nm"] | None = None,
    x_units: Literal["m", "mm", "um", "nm"] | None = None,
    override_calibration: bool = False,
    channel: int | str | None = None,
    connectivity: Literal[4, 8] = 4,
    max_depth: float | None = None,
    water_film: float | None = None,
    wet_model: Literal["persson", "fill"] = "persson",
    water_depth: float | None = None,
    water_temperature: float | None = None,
    footprint: float | None = None,
    block_size: float | None = None,
    shear_stress: float | None = None,
    window_alpha: float = 0.25,
    fit_band: tuple[float, float] | str | None = None,
    despike: bool = False,
    resolution: float | None = None,
    rubber: str | os.PathLike[str] | Any | None = None,
    sigma0: float | str = 200000.0,
    temperature: float | None = None,
    flash: bool = False,
    velocities: ArrayLike | str | None = None,
    q0: float | None = None,
    q1: float | None = None,
    contact_gamma: float | None = None,
    nu: float = 0.5,
    extrapolate: Literal["powerlaw", "hold"] = "powerlaw",
    no_friction: bool = False,
    no_figures: bool = False,
) -> dict[str, Any]:
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
    {options}

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
    from pipelines.checks.validate import collecting
    from pipelines.settings.analyse import spectrum_kwargs
    from pipelines.settings.friction import settings_from_args
    from pipelines.settings.keywords import options_of
    from pipelines.settings.scan_input import scan_of, source_path
    from pipelines.settings.water import check_water_options, wet_conditions
    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    args = options_of(dry_vs_wet, locals())
    path = source_path(scan)
    inputs = [path] if path is not None else []
    with collecting():
        check_water_options(args)
        conditions = wet_conditions(args)
        unused = [
            f"--{k.replace('_', '-')}"
            for k in ("water_depth", "water_temperature", "footprint", "block_size", "shear_stress")
            if args.wet_model == "fill" and getattr(args, k) is not None
        ]
        if unused:
            from pipelines.checks.validate import warn

            warn(f"{', '.join(unused)}: used by --wet-model persson only; the fill model ignores them")
        check_output_dir(out, inputs=inputs)
        settings = settings_from_args(args)
        sk = spectrum_kwargs(args)
        obj = scan_of(scan, args)
        try:
            with atomic_output_dir(out, inputs=inputs) as tmp:
                return run_dry_vs_wet(
                    obj,
                    tmp,
                    settings,
                    connectivity=args.connectivity,
                    max_depth_m=args.max_depth,
                    water_film_m=args.water_film,
                    wet_model=args.wet_model,
                    wet_conditions=conditions,
                    figures=not args.no_figures,
                    **sk,
                )
        except InputError as exc:
            if path is None or "out" in exc.hint_option or str(exc.path or "").startswith(str(out)):
                raise  # about the output, which it names: not the scan
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


def run_dry_vs_wet(
    scan,
    out_dir,
    settings=None,
    connectivity=4,
    max_depth_m=None,
    water_film_m=None,
    window_alpha=0.25,
    resolution_m=None,
    fit_band=None,
    despike=False,
    wet_model="persson",
    wet_conditions=None,
    figures=True,
):
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
    wet_model : {"persson", "fill"}, optional
        mu_wet by Persson's sealing, squeeze-out and adhesion (:mod:`pipelines.jobs.wet_persson`)
        or, as the thesis, on the rain-filled surface.
    wet_conditions : friction.wet.WetConditions, optional
        Water and tyre of the persson model (defaults with their sources).
    figures : bool, optional
        Draw the PNGs and the 3D view (``--no-figures``: False; every number is the same, and
        ``renderer_3d`` is None with the ``render_note`` saying why).

    Returns
    -------
    dict
        ``comparison.json``.
    """
    from pipelines.chain.steps import measure, scan_friction
    from roadscan import level
    from roadscan.rain import rain_fill

    if not isinstance(scan, HeightMap):
        raise InputError(
            scan.name or None, "dry-vs-wet needs an area scan (a height map), not a line profile"
        )
    settings = settings or FrictionSettings()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)

    dry = level.level(scan, degree=1)
    rain = rain_fill(dry, connectivity=connectivity, max_depth_m=max_depth_m, water_film_m=water_film_m)
    wet = rain.wet
    an_dry, rb_dry = measure(
        dry, window_alpha=window_alpha, fit_band=fit_band, despike=despike, resolution_m=resolution_m
    )
    an_wet = analyse_surface(wet, window_alpha=window_alpha)

    atomic_save_npy(out_dir / "wet.npy", wet.heights_m)  # NaN where unmeasured
    from roadscan.io import write

    write(out_dir / "wet.npz", wet)  # the same with its spacing: heights, dx, dy, unmeasured

    from pipelines.jobs.wet_persson import wet_model_keys
    from pipelines.output.dry_wet_report import dry_wet_figures, write_dry_wet_report
    from pipelines.output.headline import hurst_keys, peak_keys, side_keys
    from roadscan.texture_depth import ifi_speed_constant

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

    from pipelines.checks import validate

    if figures:
        figs = _maps_and_view(scan.name, dry, rain, an_dry, an_wet, out_dir, connectivity, result)
    else:
        figs = []
        result["renderer_3d"] = None
        result["render_note"] = "figures and 3D view not drawn (--no-figures)"

    od = ow = None
    if settings.enabled:
        od = scan_friction(an_dry, rb_dry, settings)  # analyse's mu(v) of this scan
        if od.result is not None and wet_model == "fill":
            ow = scan_friction(
                an_wet,
                rb_dry,
                settings,
                fit=an_dry.fit,
                v_m_per_s=od.result.v_m_per_s,
                name=f"{scan.name} (wet)",
            )
        refused = od if od.result is None else (ow if ow is not None and ow.result is None else None)
        if refused is not None:
            result["friction_refused"] = refused.provenance["refused"]
    result["mpd_m"] = an_dry.mpd_m  # ISO 13473-1 on the levelled scan, as analyse
    result["ifi_speed_constant_kmh"] = ifi_speed_constant(an_dry.mpd_m)  # ASTM E1960
    if an_dry.mpd_m is None:
        result["mpd_note"] = an_dry.mpd_note
    result.update(film_m=None, mechanisms=None, contact_lost_v_m_per_s=None, speed_constant_model_kmh=None)
    wf = None
    if od is not None and od.result is not None and wet_model == "persson":
        from friction.wet.water import WetConditions
        from pipelines.jobs.wet_persson import persson_wet

        wf, wet_keys = persson_wet(
            dry, an_dry, rb_dry, od, settings, wet_conditions or WetConditions(), window_alpha=window_alpha
        )
        result.update(wet_keys)
        mu_d, mu_w = wf.mu_dry, wf.mu_wet
    elif ow is not None and ow.result is not None:
        mu_d, mu_w = od.result.mu, ow.result.mu
    else:
        mu_d = mu_w = None
    if wet_model == "fill" or wf is None:
        result["wet_model"] = wet_model_keys(
            wet_model, connectivity, max_depth_m, water_film_m, wet_conditions, settings
        )
    if mu_d is not None:
        from pipelines.chain.provenance import rubber_label
        from pipelines.jobs.wet_persson import fall_split, speed_constant_kmh

        v = od.result.v_m_per_s
        result["model"] = "flash temperature" if settings.flash else "isothermal"
        result["mu_dry"] = mu_by_speed(v, mu_d)
        result["mu_wet"] = mu_by_speed(v, mu_w)
        i = int(np.argmax(np.abs(mu_d - mu_w)))
        result["max_difference_v_m_per_s"] = float(v[i])
        result["max_difference_mu"] = float(mu_d[i] - mu_w[i])
        result["mu_peak_dry"] = float(mu_d.max())
        result["mu_peak_wet"] = float(mu_w.max())
        for side, mu in (("dry", mu_d), ("wet", mu_w)):  # largest mu at a grid end: no peak
            result.update(
                side_keys({k: x for k, x in peak_keys(v, mu).items() if k.startswith("peak_")}, side)
            )
        result["speed_constant_model_kmh"] = speed_constant_kmh(v, mu_w)
        result["fall_20_100_kmh"] = fall_split(v, mu_d, mu_w)
        result["rubber"] = rubber_label(settings.rubber, settings.sigma0_Pa, od.result.meta.get("T0_C"))
        report.write_csv(out_dir / "mu.csv", ["v_m_per_s", "mu_dry", "mu_wet"], [v, mu_d, mu_w])
        if figures:
            figs.extend(dry_wet_figures(out_dir, scan.name, result, v, mu_d, mu_w, wf))
    else:
        result["mu_dry"] = result["mu_wet"] = None
        result["max_difference_v_m_per_s"] = None

    result["warnings"] = validate.warnings_list()  # every line this run printed
    from pipelines.settings.scan_input import read_record

    result.update(read_record(scan))  # how the file was read: channel, overrides
    report.write_json(out_dir / "comparison.json", result)
    write_dry_wet_report(out_dir, result, figs)
    return result


def _maps_and_view(name, dry, rain, an_dry, an_wet, out_dir, connectivity, result):
    """The dry height map, the water depth map, the PSD dry and wet and the 3D view, as PNGs in
    ``out_dir``; records the renderer (and why a view was not drawn) in ``result``. Returns the
    figures' paths in the report's order."""
    from pipelines.checks import validate
    from pipelines.jobs.render3d import render_3d_view

    figs = [
        report.plot_heightmap(dry, out_dir / "dry_heightmap.png", title=f"{name}: dry (levelled)"),
        report.plot_heightmap(
            dry,
            out_dir / "water_depth.png",
            depth_m=rain.depth_m,
            title=f"{name}: water depth ({connectivity}-connected fill)",
        ),
        report.plot_psd(
            [
                ("dry", an_dry.spectrum.q_per_m, an_dry.spectrum.C_m4),
                ("wet (rain-filled)", an_wet.spectrum.q_per_m, an_wet.spectrum.C_m4),
            ],
            out_dir / "psd_dry_wet.png",
            title=f"{name}: PSD dry and wet",
        ),
    ]
    view = render_3d_view(dry, rain.depth_m, out_dir / "surface_3d.png", title=f"{name}: surface and water")
    result["renderer_3d"] = view.renderer  # pyvista | matplotlib | None (not drawn)
    if view.path is not None:
        figs.append(view.path)
    if view.note:
        result["render_note"] = view.note
    if view.warning:
        validate.warn(view.warning)
    return figs
