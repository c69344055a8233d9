"""The ISO 25178-2 / ISO 21920-2 texture set of one scan: form removal, S- and L-filters, the
figures in ``summary.json`` ``roughness``, what was applied in ``summary.json`` ``filters``,
and the report's roughness table in mm / µm.

Options (``roadscan analyse`` and ``roadscan batch``, through
:func:`pipelines.jobs.texture.outputs.add_texture_options`): ``--form plane|poly2|poly3`` (least-
squares form removed before the roughness figures; default plane), ``--s-filter M`` and
``--l-filter M`` (Gaussian nesting indices [m], ISO 16610-61 areal / ISO 16610-21 profile).

The spectrum, the fit and friction always use the plane-levelled, unfiltered surface: the
form and the filters apply to the roughness figures only (the report says so).
"""

from __future__ import annotations

import math

from roadscan.errors import InputError

__all__ = [
    "FORMS",
    "add_iso_options",
    "iso_settings_from_args",
    "texture_surface",
    "iso_summary",
    "roughness_rows",
    "roughness_section",
    "filters_text",
    "figure_note",
    "ROUGHNESS_NOTE_KEY",
]

#: --form choice -> polynomial degree
FORMS = {"plane": 1, "poly2": 2, "poly3": 3}
ROUGHNESS_NOTE_KEY = "roughness_notes"


def add_iso_options(p):
    """``--form``, ``--s-filter``, ``--l-filter``.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser.

    Returns
    -------
    None
    """
    p.add_argument(
        "--form",
        choices=tuple(FORMS),
        default="plane",
        help="form removed before the roughness figures: least-squares plane "
        "(default), or polynomial of degree 2 or 3 (ISO 25178-2 F-operator)",
    )
    p.add_argument(
        "--s-filter",
        type=float,
        default=None,
        metavar="M",
        help="S-filter nesting index [m]: Gaussian low-pass removing scales below it "
        "(ISO 16610-61 / -21, 50 %% transmission at M) before the roughness "
        "figures",
    )
    p.add_argument(
        "--l-filter",
        type=float,
        default=None,
        metavar="M",
        help="L-filter nesting index [m]: Gaussian high-pass removing scales above it "
        "(waviness), e.g. 0.008; the spectrum and friction stay unfiltered",
    )


def iso_settings_from_args(args):
    """(form, s_filter_m, l_filter_m) checked (InputError naming the flag).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    tuple
        (form, s_filter_m, l_filter_m).
    """
    form = getattr(args, "form", None) or "plane"
    s, l_ = getattr(args, "s_filter", None), getattr(args, "l_filter", None)
    for key, v in (("s_filter", s), ("l_filter", l_)):
        if v is not None and not (math.isfinite(v) and 0 < v <= 10.0):
            raise InputError(
                None,
                f"{{{key}}} {v!r}: must be a nesting index in metres (0 < M <= 10, e.g. 0.008)",
                hint_option=key,
            )
    if s is not None and l_ is not None and s >= l_:
        raise InputError(
            None,
            f"{{s_filter}} {s:g} must be shorter than {{l_filter}} {l_:g}",
            hint_option=("s_filter", "l_filter"),
        )
    return form, s, l_


def texture_surface(analysis, form="plane", s_filter_m=None, l_filter_m=None):
    """The surface the roughness figures are taken on, and the ``filters`` record.

    The plane-levelled scan of the analysis; with a higher ``form``, the least-squares
    polynomial of that degree removed from it (the same as removing it from the raw heights:
    the plane is in its span); then the S- and L-filters (:func:`roadscan.iso_filters.
    apply_filters`). Raises InputError (naming the flag) when a filter does not fit the scan.

    Parameters
    ----------
    analysis : SurfaceAnalysis
        The analysed scan.
    form : str, optional
        Form removed.
    s_filter_m, l_filter_m : float, optional
        Filter nesting indices [m].

    Returns
    -------
    surface : HeightMap or Profile
    filters : dict
    """
    from roadscan import level
    from roadscan.iso_filters import END_EFFECTS, apply_filters

    surf = analysis.levelled
    if FORMS[form] > 1:
        surf = level.level(surf, degree=FORMS[form])
    if s_filter_m is not None or l_filter_m is not None:
        try:
            surf = apply_filters(surf, s_filter_m, l_filter_m)
        except ValueError as err:
            key = "s_filter" if "S-filter" in str(err) else "l_filter"
            raise InputError(None, f"{{{key}}}: {err}", hint_option=key) from None
    filters = {
        "form": form,
        "s_filter_m": s_filter_m,
        "l_filter_m": l_filter_m,
        "end_effects": END_EFFECTS if (s_filter_m or l_filter_m) else None,
        "applies_to": "roughness figures; the spectrum, fit and friction use the "
        "plane-levelled unfiltered surface",
    }
    return surf, filters


def iso_summary(analysis, form="plane", s_filter_m=None, l_filter_m=None, figures=None):
    """(roughness dict, filters dict, notes dict) of one analysed scan.

    With the default plane and no filter the height figures of the analysis are kept and the
    new figures added; otherwise every roughness figure is recomputed on the filtered surface
    (``rms_height_m`` stays the plane-levelled, unfiltered Sq).

    Parameters
    ----------
    analysis : SurfaceAnalysis
        The analysed scan.
    form : str, optional
        Form removed.
    s_filter_m, l_filter_m : float, optional
        Filter nesting indices [m].
    figures : pipelines.jobs.texture.prefetch.TextureFigures, optional
        The texture figures already started on the levelled map (used when the surface is it).

    Returns
    -------
    tuple of dict
        (roughness, filters, notes).

    References
    ----------
    ISO 25178-2:2021; ISO 21920-2:2021.
    """
    from roadscan import roughness
    from roadscan.iso25178 import texture_parameters

    surf, filters = texture_surface(analysis, form, s_filter_m, l_filter_m)
    if surf is analysis.levelled:
        rough = dict(analysis.roughness)
    elif analysis.is_profile:
        rough = roughness.profile_parameters(surf, level_degree=None)
    else:
        rough = roughness.area_parameters(surf, level_degree=None)
    figs, notes = texture_parameters(surf) if figures is None else figures.get(surf)
    rough.update(figs)
    return rough, filters, notes


def filters_text(filters):
    """One line for titles and reports: "form plane, S-filter none, L-filter 8 mm".

    Parameters
    ----------
    filters : dict
        The filters record.

    Returns
    -------
    str
    """
    from pipelines.output.units import length

    if not filters:
        return "form plane, no S- or L-filter"
    s, l_ = filters.get("s_filter_m"), filters.get("l_filter_m")
    return (
        f"form {filters.get('form', 'plane')}, S-filter {length(s) if s else 'none'}, "
        f"L-filter {length(l_) if l_ else 'none'}"
    )


def _fmt(key, v):
    from pipelines.output.units import length, sig3

    if v is None:
        return "—"
    if key.endswith("_m3_per_m2"):  # volume per area: µm^3/µm^2 = µm
        if abs(v) >= 1e-3:  # a road's millimetres: mm^3/mm^2
            return f"{sig3(v * 1e3)} mm³/mm² ({sig3(v * 1e6)} mL/m²)"
        return f"{sig3(v * 1e6)} µm³/µm² ({sig3(v * 1e6)} mL/m²)"
    if key.endswith("_pct"):
        return f"{sig3(v)} %"
    if key.endswith("_deg"):
        return f"{sig3(v)}°"
    if key.endswith("_per_m2"):
        return f"{sig3(v * 1e-6)} 1/mm²"
    if key.endswith("_per_m"):
        return f"{sig3(v * 1e-3)} 1/mm"
    if key.endswith("_m"):
        return length(v)
    if key == "Sdr":
        return f"{sig3(100 * v)} %"
    return sig3(v)


_LABELS = {
    "Sk_m": "Sk, core height",
    "Spk_m": "Spk, reduced peak height",
    "Svk_m": "Svk, reduced dale depth",
    "Smr1_pct": "Smr1, peak material ratio",
    "Smr2_pct": "Smr2, dale material ratio",
    "Vmp_m3_per_m2": "Vmp, peak material volume (p 10 %)",
    "Vmc_m3_per_m2": "Vmc, core material volume (10-80 %)",
    "Vvc_m3_per_m2": "Vvc, core void volume (10-80 %)",
    "Vvv_m3_per_m2": "Vvv, dale void volume (q 80 %)",
    "Sal_m": "Sal, autocorrelation length (s 0.2)",
    "Str": "Str, texture aspect ratio",
    "Std_deg": "Std, texture direction (lay, from x)",
    "Spd_per_m2": "Spd, density of peaks",
    "Spc_per_m": "Spc, mean peak curvature",
    "S10z_m": "S10z, ten-point height",
    "S5p_m": "S5p, five-point peak height",
    "S5v_m": "S5v, five-point pit depth",
    "Sdq": "Sdq, rms gradient",
    "Sdr": "Sdr, developed interfacial area ratio",
    "Rk_m": "Rk, core height",
    "Rpk_m": "Rpk, reduced peak height",
    "Rvk_m": "Rvk, reduced dale depth",
    "Rmr1_pct": "Rmr1, peak material ratio",
    "Rmr2_pct": "Rmr2, dale material ratio",
    "Rmr_pct": "Rmr, material ratio at the mean line",
    "Rdq": "Rdq, rms slope",
}


def roughness_rows(summary):
    """{label: value} of ``summary['roughness']`` in mm / µm / % with three significant
    digits (volumes per area in µm³/µm², densities per mm²).

    Parameters
    ----------
    summary : dict
        A summary.

    Returns
    -------
    dict
    """
    from pipelines.output.units import label_of

    out = {}
    for k, v in (summary.get("roughness") or {}).items():
        out[_LABELS.get(k, label_of(k))] = _fmt(k, v)
    return out


def roughness_section(summary):
    """The report's roughness section: what the figures were taken on, the table, the notes.

    Parameters
    ----------
    summary : dict
        A summary.

    Returns
    -------
    list
    """
    from pipelines.output.report import paragraph_html, table_html

    f = summary.get("filters") or {}
    head = (
        f"Taken on the levelled surface with {filters_text(f)}"
        + (f"; end effects: {f['end_effects']}" if f.get("end_effects") else "")
        + ". The spectrum, the fit and friction use the plane-levelled, unfiltered surface."
    )
    parts = [paragraph_html(head, note=True), table_html(roughness_rows(summary), ["parameter", "value"])]
    for what, note in (summary.get(ROUGHNESS_NOTE_KEY) or {}).items():
        parts.append(paragraph_html(f"{what}: {note}", note=True))
    return parts


def figure_note(filters):
    """ "" with the default form and no filter; else what a figure's title adds, e.g.
    " (unfiltered; roughness figures: form poly2, S-filter none, L-filter 8.00 mm)".

    Parameters
    ----------
    filters : dict, TextureSettings or None
        ``summary.json`` ``filters``, or the texture settings of the run.

    Returns
    -------
    str
    """
    if filters is None:
        return ""
    if not isinstance(filters, dict):
        filters = {
            "form": getattr(filters, "form", "plane"),
            "s_filter_m": getattr(filters, "s_filter_m", None),
            "l_filter_m": getattr(filters, "l_filter_m", None),
        }
    if (
        filters.get("form", "plane") == "plane"
        and not filters.get("s_filter_m")
        and not filters.get("l_filter_m")
    ):
        return ""
    return f" (unfiltered; roughness figures: {filters_text(filters)})"
