"""The surface-comparison job (thesis section 4.3): several scans side by side.

All spectra and all mu(v) on common axes, and for each scan against the first (the
reference): at which wave vectors and speeds they differ, and by how much.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from pipelines.jobs._compare_report import draw_figures, write_report
from pipelines.jobs.analyse.job import summarise
from pipelines.jobs.dry_vs_wet import mu_by_speed
from pipelines.output import report
from pipelines.output.job_result import returns_job_result
from pipelines.settings.friction import FrictionSettings
from pipelines.settings.option_docs import document_options

if TYPE_CHECKING:  # numpy's typing only for checkers: the command's --help stays light
    from numpy.typing import ArrayLike

    from friction.rubber import Rubber

__all__ = ["compare", "run_compare", "spectrum_difference", "friction_difference"]


def spectrum_difference(spec_ref, spec, band=None, why_no_band=None):
    """Where two spectra differ: log10 ratio C/C_ref on the reference's rings, judged inside
    ``band``, where both spectra are trusted (:func:`pipelines.chain.judged.judged_band` of
    each scan, intersected; the wave vectors both spectra hold when ``band`` is None and no
    ``why_no_band`` is given).

    Parameters
    ----------
    spec_ref, spec : roadscan.Spectrum
        Reference and compared spectra.
    band : tuple of float, optional
        (lo, hi) [1/m] the ratios are judged in.
    why_no_band : str, optional
        Why there is no band both spectra are trusted on (then no ratio is judged).

    Returns
    -------
    dict
        ``common_band_per_m`` (the wave vectors both hold), ``judged_band_per_m``, ``q_per_m``
        and ``log10_ratio`` (inside it), ``psd_ratio_median``, ``psd_ratio_at_max``,
        ``q_at_max_ratio_per_m`` and ``largest_psd_ratio`` (``ratio``, ``q_per_m``,
        ``band_per_m``; None with ``largest_psd_ratio_note`` saying why).
    """
    from pipelines.chain.judged import largest_ratio, ratio_in_band

    lo = max(spec_ref.q_per_m[0], spec.q_per_m[0])
    hi = min(spec_ref.q_per_m[-1], spec.q_per_m[-1])
    if not lo < hi:
        return {
            "common_band_per_m": None,
            "note": "no common band of wave vectors",
            "largest_psd_ratio": None,
            "largest_psd_ratio_note": "no common band of wave vectors",
        }
    out = {"common_band_per_m": [float(lo), float(hi)]}
    if band is None and why_no_band is None:
        band = (float(lo), float(hi))
    q, lr = ratio_in_band(spec_ref, spec, band) if band is not None else (np.empty(0), np.empty(0))
    out["judged_band_per_m"] = None if band is None else [float(band[0]), float(band[1])]
    big = largest_ratio(q, lr, band) if band is not None else None
    out["largest_psd_ratio"] = big
    if big is None:
        out["largest_psd_ratio_note"] = why_no_band or (
            "fewer than two wave vectors of the reference inside the band both spectra are trusted on"
        )
        return out
    i = int(np.argmax(np.abs(lr)))
    out.update(
        {
            "q_per_m": q,
            "log10_ratio": lr,
            "psd_ratio_median": float(10 ** np.median(lr)),
            "psd_ratio_at_max": float(10 ** lr[i]),
            "q_at_max_ratio_per_m": float(q[i]),
        }
    )
    return out


def _bands(pairs, names):
    """Per scan its judged band (:func:`pipelines.chain.judged.judged_band`), and per scan
    after the first (band shared with the reference, or None, and why not)."""
    from pipelines.chain.judged import common_band, judged_band

    own = [judged_band(an, rb) for an, rb in pairs]
    shared = []
    for k in range(1, len(pairs)):
        band = common_band([own[0], own[k]])
        why = None
        if band is None:
            lone = [n for n, b in ((names[0], own[0]), (names[k], own[k])) if b is None]
            why = (
                f"no trusted band: the reliable band and the fit band of {', '.join(lone)} do not overlap"
                if lone
                else f"the bands {names[0]} and {names[k]} are trusted on do not overlap (each "
                f"scan's reliable band within its fit band)"
            )
        shared.append((band, why))
    return shared


def _why_missing(entry, friction_on):
    """{figure key: why it is null} for the figures of a compared surface that are missing."""
    why = {}
    if entry.get("hurst") is None:
        why["hurst"] = entry.get("hurst_note") or "no meaningful self-affine fit"
    if entry.get("h0_m") is None:
        why["h0_m"] = "h0 is undefined where H <= 0 or H is not given"
    if entry.get("mpd_m") is None:
        why["mpd_m"] = entry.get("mpd_note") or "no MPD"
    if entry.get("mu_peak") is None:
        why["mu_peak"] = (
            (entry.get("friction_refused") or "friction not computed")
            if friction_on
            else "friction not computed (--no-friction)"
        )
    d = entry.get("difference_from_reference") or {}
    if d and d.get("largest_psd_ratio") is None:
        why["largest_psd_ratio"] = d.get("largest_psd_ratio_note") or "no ratio judged"
    return why


def friction_difference(v, mu_ref, mu):
    """Where two mu(v) curves differ most (absolute and relative) and by how much.

    Parameters
    ----------
    v : ndarray
        Speeds [m/s].
    mu_ref, mu : ndarray
        Reference and compared mu.

    Returns
    -------
    dict
    """
    d = mu - mu_ref
    i = int(np.argmax(np.abs(d)))
    rel = np.divide(mu, mu_ref, out=np.full_like(mu, np.nan), where=mu_ref > 0)
    j = int(np.nanargmax(np.abs(np.log(rel)))) if np.isfinite(rel).any() else i
    return {
        "max_difference_v_m_per_s": float(v[i]),
        "max_difference_mu": float(d[i]),
        "max_ratio_v_m_per_s": float(v[j]),
        "mu_ratio_at_max": float(rel[j]),
        "mu_peak_ratio": float(mu.max() / mu_ref.max()),
    }


@returns_job_result("compare")
@document_options()
def compare(
    sources: Any,
    out: str | os.PathLike[str],
    *,
    spacing: float | str | tuple[float, float] | None = None,
    units: Literal["m", "mm", "um", "nm"] | None = None,
    x_units: Literal["m", "mm", "um", "nm"] | None = None,
    override_calibration: bool = False,
    channel: int | str | None = None,
    window_alpha: float = 0.25,
    fit_band: tuple[float, float] | str | None = None,
    despike: bool = False,
    resolution: float | None = None,
    rubber: str | os.PathLike[str] | Rubber | None = None,
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
    """``roadscan compare`` as one call: the sources (paths or HeightMaps/Profiles, the first is
    the reference) compared and written into ``out`` (all or none) -> the comparison.json dict.

    ``options`` are the command's long flags with dashes as underscores, taking what the flag
    takes (``rubber="r.toml"``, ``sigma0="0.25MPa"``, ``nu=0.45``, ``window_alpha=0.3``), parsed
    by the command's own option definitions (:func:`pipelines.settings.analyse.add_compare_options`);
    TypeError naming an unknown keyword. Each scan's mu(v) is the one ``pipelines.analyse``
    gives it with the same options (:mod:`pipelines.chain.steps`).

    Parameters
    ----------
    sources : sequence of str, Path, HeightMap or Profile
        The scans; the first is the reference.
    out : str or Path
        Output folder.
    {options}

    Returns
    -------
    dict
        The ``comparison.json`` content.
    """

    from pipelines.checks.validate import collecting
    from pipelines.settings.analyse import spectrum_kwargs, unique_stems
    from pipelines.settings.friction import settings_from_args
    from pipelines.settings.keywords import options_of
    from pipelines.settings.scan_input import scan_of, source_path
    from roadscan.errors import InputError
    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    args = options_of(compare, locals())
    sources = list(sources)
    if len(sources) < 2:
        raise InputError(None, "compare needs at least two scans")
    paths = [p for p in map(source_path, sources) if p is not None]
    with collecting():
        settings = settings_from_args(args)
        sk = spectrum_kwargs(args)
        scans = [scan_of(s, args) for s in sources]
        names = unique_stems([s if isinstance(s, (str, os.PathLike)) else f"{s.name}.x" for s in sources])
        check_output_dir(out, inputs=paths)
        with atomic_output_dir(out, inputs=paths) as tmp:
            return run_compare(scans, names, tmp, settings, figures=not args.no_figures, **sk)


def run_compare(
    scans,
    names,
    out_dir,
    settings=None,
    window_alpha=0.25,
    resolution_m=None,
    fit_band=None,
    despike=False,
    figures=True,
):
    """Compare scans (HeightMaps or Profiles); write PNGs, report.html and comparison.json.

    Each scan goes through the one chain (:mod:`pipelines.chain.steps`): its reliable band (lateral
    resolution ``resolution_m`` [m], default the file's metadata), its fit (over ``fit_band``
    when given; ``despike`` as analyse), and friction with
    every option of ``settings`` on the first scan's speeds; mu(v) is the one ``roadscan
    analyse`` gives for that scan. A scan whose band's fine end is not trusted has no mu
    (``friction_refused`` says why).

    Parameters
    ----------
    scans : list of HeightMap or Profile
        The scans.
    names : list of str
        Their names.
    out_dir : str or Path
        Output folder.
    settings : FrictionSettings, optional
        Friction options.
    window_alpha : float, optional
        Tukey window.
    resolution_m : float, optional
        Lateral resolution [m].
    figures : bool, optional
        Draw the PNGs (``--no-figures``: False; every number in comparison.json is the same).

    Returns
    -------
    dict
        ``comparison.json``.
    """
    from pipelines.chain.steps import measure, scan_friction

    settings = settings or FrictionSettings()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    pairs = [
        measure(s, window_alpha=window_alpha, fit_band=fit_band, despike=despike, resolution_m=resolution_m)
        for s in scans
    ]
    analyses = [an for an, _ in pairs]
    outcomes = []
    if settings.enabled:
        v = None
        for an, rb in pairs:
            o = scan_friction(an, rb, settings, v_m_per_s=v)
            if o.result is not None and v is None:
                v = o.result.v_m_per_s
            outcomes.append(o)
    curves = [o.result for o in outcomes]
    result = {}
    ref = analyses[0]
    # the ratios are judged where both scans are trusted (pipelines.chain.judged)
    sds = [None] + [
        spectrum_difference(ref.spectrum, a.spectrum, band, why)
        for a, (band, why) in zip(analyses[1:], _bands(pairs, names))
    ]
    for k, (name, an) in enumerate(zip(names, analyses)):
        s = summarise(an, curves[k] if curves else None, window_alpha=window_alpha)
        entry = {
            key: s[key]
            for key in (
                "hurst",
                "hurst_stderr",
                "hurst_fit",
                "hurst_fit_stderr",
                "hurst_note",
                "rms_height_m",
                "band_rms_m",
                "h0_m",
                "q_min_per_m",
                "q_max_per_m",
                "fit_band_per_m",
                "q_roll_per_m",
                "roughness",
                "mpd_m",
                "mpd_note",
                "filled_fraction",
                "kind",
            )
        }
        c = curves[k] if curves else None
        entry["mu"] = mu_by_speed(c.v_m_per_s, c.mu) if c is not None else None
        if c is not None:
            from pipelines.output.headline import peak_keys

            entry.update(peak_keys(c.v_m_per_s, c.mu))  # mu_peak, v_peak_m_per_s, peak_at_edge, peak_note
            from pipelines.chain.provenance import rubber_label

            entry["rubber"] = rubber_label(settings.rubber, settings.sigma0_Pa, c.meta.get("T0_C"))
        elif outcomes:
            entry["friction_refused"] = outcomes[k].provenance["refused"]
        if k > 0:
            diff = {"reference": names[0]}
            diff.update({kk: vv for kk, vv in sds[k].items() if kk not in ("q_per_m", "log10_ratio")})
            if curves and curves[0] is not None and curves[k] is not None:
                diff.update(friction_difference(curves[0].v_m_per_s, curves[0].mu, curves[k].mu))
            entry["difference_from_reference"] = diff
        entry["why_missing"] = _why_missing(entry, settings.enabled)  # every null figure's reason
        result[name] = entry

    figs = draw_figures(out_dir, names, analyses, sds, curves, settings) if figures else []
    from pipelines.checks import validate

    said = validate.warnings_list()  # what this run printed (readers, seams)
    srcs = [(str(sc.meta.get("source", "\0")), f"{sc.name}:") for sc in scans]
    for (src, own), entry in zip(srcs, result.values()):  # each scan's own, and those naming none
        mine = [
            w
            for w in said
            if w.startswith((src, own)) or not any(w.startswith(t) for pair in srcs for t in pair)
        ]
        if mine and isinstance(entry, dict):
            entry["warnings"] = mine
    from pipelines.settings.scan_input import read_record

    for sc, entry in zip(scans, result.values()):  # how each file was read
        if isinstance(entry, dict):
            entry.update(read_record(sc))
    report.write_json(out_dir / "comparison.json", result)
    write_report(out_dir, names, result, figs, curves)
    return result
