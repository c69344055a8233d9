"""What road engineers report for one scan: the ISO 13473-4 texture spectrum
(``texture_spectrum.csv``, ``texture_spectrum.png``, ``summary.json`` key ``texture_level_dB``),
ETD, the IFI speed constant and F60 (ASTM E1960), a labelled short-baseline segment depth for
scans under 100 mm, and an MPD note that names the spike threshold that would pass.

Options (``roadscan analyse`` and ``roadscan batch``): ``--direction x|y`` (driving direction
of an area scan), ``--friction-measurement F@SPEED`` (friction F measured at slip speed SPEED
km/h) with ``--ifi-constants A,B[,C]`` (the device's calibration constants), and the ISO 25178
texture options ``--form``, ``--s-filter``, ``--l-filter`` (:mod:`pipelines.jobs.texture.iso`).

MPD validity (ISO 13473-1): ``mpd_valid`` beside ``mpd_m``; when it is false, ``etd_m``,
``ifi_speed_constant_kmh`` and ``ifi_F60`` are null and ``etd_note`` says why; the segments go
to ``mpd_segments.csv`` and ``mpd_segments.png`` (:mod:`pipelines.jobs.texture.mpd`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from roadscan.errors import InputError

__all__ = [
    "TEXTURE_HEADER",
    "TextureSettings",
    "add_texture_options",
    "texture_settings_from_args",
    "texture_keys",
    "add_to_summary",
    "html_escape",
    "write_texture_csv",
    "texture_picture",
    "draw_texture_spectrum",
    "texture_table_html",
    "depth_rows",
    "write_extras",
    "draw_extras",
]

#: dropout share above which the texture levels get a warning (a linear fill carries no texture)
DROPOUT_WARN = 0.10


@dataclass
class TextureSettings:
    """Driving direction, the IFI inputs (None when not given), and the form and filters of
    the roughness figures (:mod:`pipelines.jobs.texture.iso`).

    Attributes
    ----------
    direction : str
        ``"x"`` or ``"y"``.
    friction : float or None
        Measured friction FRS.
    slip_speed_kmh : float or None
        Its slip speed [km/h].
    ifi_constants : tuple or None
        A, B[, C].
    form : str
        Form removed.
    s_filter_m, l_filter_m : float or None
        Filters [m].
    """

    direction: str = "x"
    friction: float | None = None  # FRS measured
    slip_speed_kmh: float | None = None  # S
    ifi_constants: tuple | None = None  # (A, B, C)
    form: str = "plane"  # --form
    s_filter_m: float | None = None  # --s-filter
    l_filter_m: float | None = None  # --l-filter


def add_texture_options(p):
    """``--direction``, ``--friction-measurement``, ``--ifi-constants``, ``--form``,
    ``--s-filter``, ``--l-filter``.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser.

    Returns
    -------
    None
    """
    from pipelines.jobs.texture.iso import add_iso_options

    p.add_argument(
        "--direction",
        choices=("x", "y"),
        default="x",
        help="driving direction of an area scan for the ISO 13473-4 texture spectrum "
        "(lines along it are analysed; default x)",
    )
    p.add_argument(
        "--friction-measurement",
        default=None,
        metavar="F@SPEED",
        help="friction F measured at slip speed SPEED km/h (e.g. 0.45@30): with "
        "--ifi-constants gives the IFI F60 of ASTM E1960",
    )
    p.add_argument(
        "--ifi-constants",
        default=None,
        metavar="A,B[,C]",
        help="the friction device's IFI calibration constants (ASTM E1960; C "
        "multiplies MPD in mm, default 0)",
    )
    add_iso_options(p)


def _floats(text, flag, sep, n_min, n_max, form):
    parts = text.split(sep)
    try:
        vals = [float(x) for x in parts]
    except ValueError:
        raise InputError(None, f"{flag} {text!r}: expected {form}") from None
    if not n_min <= len(vals) <= n_max or not all(math.isfinite(v) for v in vals):
        raise InputError(None, f"{flag} {text!r}: expected {form}")
    return vals


def texture_settings_from_args(args):
    """Checked :class:`TextureSettings` from parsed options (InputError naming the flag).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    TextureSettings
    """
    fm, ic = getattr(args, "friction_measurement", None), getattr(args, "ifi_constants", None)
    from pipelines.jobs.texture.iso import iso_settings_from_args

    form, s_f, l_f = iso_settings_from_args(args)
    st = TextureSettings(
        direction=getattr(args, "direction", None) or "x", form=form, s_filter_m=s_f, l_filter_m=l_f
    )
    if (fm is None) != (ic is None):
        given = "--friction-measurement" if fm is not None else "--ifi-constants"
        other = "--ifi-constants" if fm is not None else "--friction-measurement"
        raise InputError(None, f"{given} needs {other} too (ASTM E1960 F60 takes both)")
    if fm is not None:
        f, s = _floats(fm, "--friction-measurement", "@", 2, 2, "F@SPEED, e.g. 0.45@30 (km/h)")
        if not 0 < f <= 5:
            raise InputError(None, f"--friction-measurement {fm!r}: friction must be in (0, 5]")
        if not 0 < s <= 500:
            raise InputError(None, f"--friction-measurement {fm!r}: slip speed must be in (0, 500] km/h")
        c = _floats(ic, "--ifi-constants", ",", 2, 3, "A,B or A,B,C")
        st.friction, st.slip_speed_kmh = f, s
        st.ifi_constants = (c[0], c[1], c[2] if len(c) > 2 else 0.0)
    return st


def _spectrum_input(analysis):
    """The levelled scan (dropouts still unmeasured; the texture module fills them per line)."""
    return analysis.levelled


def texture_keys(analysis, settings=None, mpd_settings=None, figures=None):
    """The road-texture ``summary.json`` keys of one analysed scan and its texture spectrum.

    Returns
    -------
    (dict of keys, roadscan.texture_spectrum.TextureSpectrum)

    Parameters
    ----------
    analysis : SurfaceAnalysis
        The analysed scan.
    settings : TextureSettings, optional
        Texture options.
    mpd_settings : dict, optional
        ISO 13473-1 settings.
    figures : pipelines.jobs.texture.prefetch.TextureFigures, optional
        The texture spectrum (and a short scan's short-baseline depth) already started on the
        levelled map.
    """
    from pipelines.checks.validate import warn
    from roadscan import texture_depth as td
    from roadscan.texture_spectrum import texture_spectrum

    settings = settings or TextureSettings()
    ts = (
        texture_spectrum(_spectrum_input(analysis), direction=settings.direction)
        if figures is None
        else figures.spectrum(_spectrum_input(analysis), settings.direction)
    )
    out = {"texture_level_dB": ts.as_dict(), "texture_spectrum_note": ts.note}
    if ts.dropout_fraction > DROPOUT_WARN:
        import math

        low = -10 * math.log10(max(1e-6, 1 - ts.dropout_fraction))
        warn(
            f"{analysis.name}: {ts.dropout_fraction:.0%} of the points are dropouts, filled "
            f"linearly for the texture spectrum: its levels read up to about {low:.1f} dB low"
        )
    if not analysis.is_profile:
        out["texture_direction"] = settings.direction
    mpd, mpd_note = analysis.mpd_m, analysis.mpd_note
    src = analysis.source
    seg = getattr(analysis, "mpd_segments", None)  # computed with the MPD
    if not analysis.is_profile and settings.direction == "y":  # MPD along the driving direction
        from roadscan.heightmap import HeightMap

        src = HeightMap(src.heights_m.T, src.dy_m, src.dx_m, src.unmeasured.T, src.name, src.meta)
        mpd, mpd_note, seg = td.mpd_and_segments(src, **(mpd_settings or {}))
        mpd_note = f"{mpd_note} (lines along y, the driving direction)"
        out["mpd_m"], out["mpd_note"] = mpd, mpd_note
    elif seg is None:
        seg = td.mpd_segments(src, **(mpd_settings or {}))
    from pipelines.jobs.texture.mpd import validity_keys

    out.update(validity_keys(seg))
    out["_segments"] = seg  # taken out by add_to_summary
    usable = mpd if out["mpd_valid"] else None
    out["etd_m"] = td.estimated_texture_depth(usable)
    out["ifi_speed_constant_kmh"] = td.ifi_speed_constant(usable)
    if usable is None:
        why = (
            f"the MPD is {seg.validity_text()}" if seg is not None and mpd is not None else "there is no MPD"
        )
        out["etd_note"] = f"ETD and the IFI figures not computed: {why}"
    length = src.length_m if analysis.is_profile else src.nx * src.dx_m
    if mpd is None and length < 0.1:
        msd, base, note = (
            td.short_segment_depth(src, **(mpd_settings or {}))
            if figures is None
            else figures.short_depth(src, mpd_settings)
        )
        out.update(msd_short_m=msd, msd_short_baseline_m=base, msd_short_note=note)
    elif seg is not None and seg.n_total and not out["mpd_valid"]:
        from pipelines.jobs.texture.mpd import invalid_mpd_warning

        alpha, iso = (
            td.spike_alpha_to_pass(src, mpd_settings) if seg.failed_rules()["spikes"] else (None, False)
        )
        warn(invalid_mpd_warning(analysis.name, seg, alpha, iso))  # the rule and the option
        if alpha is not None:
            out["mpd_spike_alpha_to_pass"] = alpha
        if mpd is None and "no valid segment" in (mpd_note or ""):
            _no_valid_note(out, mpd_note, mpd_settings, alpha, iso)
    if settings.friction is not None:
        A, B, C = settings.ifi_constants
        res = td.ifi_f60(settings.friction, settings.slip_speed_kmh, usable, A, B, C)
        out["ifi_F60"] = res[0] if res else None
        out["ifi_inputs"] = {
            "friction": settings.friction,
            "slip_speed_kmh": settings.slip_speed_kmh,
            "A": A,
            "B": B,
            "C": C,
            "FR60": res[2] if res else None,
        }
        if res is None:
            why = out.get("etd_note") or out.get("mpd_note", analysis.mpd_note)
            warn(f"{analysis.name}: no IFI F60: it needs a valid MPD ({why})")
    return out, ts


def _no_valid_note(out, mpd_note, mpd_settings, alpha, iso):
    """``mpd_note`` of an MPD without a valid segment, with the spike threshold that passes."""
    if alpha is not None:
        what = (
            "an MPD valid per ISO 13473-1 (at least half the segments valid)"
            if iso
            else "an MPD (fewer than half the segments valid, not valid per ISO 13473-1)"
        )
        now = (mpd_settings or {}).get("spike_alpha", 3.0)
        out["mpd_note"] = (
            f"{mpd_note}; --mpd-spike-alpha {alpha:g} would give {what} "
            f"(steep stone edges, e.g. of chip seals, read as spikes at "
            f"alpha = {now:g}, the ISO 13473-1 default being 3)"
        )
    else:
        out["mpd_note"] = f"{mpd_note}; no --mpd-spike-alpha up to 50 helps: the segments fail on dropouts"


def add_to_summary(summary, analysis, settings=None, mpd_settings=None, figures=None):
    """``summary`` with the keys of :func:`texture_keys`: ``mpd_valid`` and the depth figures
    right after ``mpd_m``/``mpd_note`` (whose note may gain the spike threshold that passes),
    the texture spectrum at the end; ``roughness`` with the ISO 25178-2 / 21920-2 texture set
    and ``filters`` (what form and filters the roughness figures were taken with,
    :mod:`pipelines.jobs.texture.iso`). Returns (new summary dict, TextureSpectrum); the
    TextureSpectrum carries the MPD segments as ``mpd_segments`` (for :func:`write_extras`).

    Parameters
    ----------
    summary : dict
        The summary.
    analysis : SurfaceAnalysis
        The analysed scan.
    settings : TextureSettings, optional
        Texture options.
    mpd_settings : dict, optional
        ISO 13473-1 settings.
    figures : pipelines.jobs.texture.prefetch.TextureFigures, optional
        The ISO 25178-2 figures already started on the levelled map.

    Returns
    -------
    summary : dict
    ts : TextureSpectrum
    """
    from pipelines.jobs.texture.iso import ROUGHNESS_NOTE_KEY, iso_summary

    settings = settings or TextureSettings()
    keys, ts = texture_keys(analysis, settings, mpd_settings, figures)
    # the (frozen) TextureSpectrum carries the segments to write_extras / draw_extras
    object.__setattr__(ts, "mpd_segments", keys.pop("_segments", None))
    rough, filters, notes = iso_summary(
        analysis, settings.form, settings.s_filter_m, settings.l_filter_m, figures
    )
    summary = dict(summary)
    summary["roughness"] = rough
    keys["filters"] = filters
    if notes:
        keys[ROUGHNESS_NOTE_KEY] = notes
    spectrum = {
        k: keys.pop(k)
        for k in ("texture_level_dB", "texture_spectrum_note", "texture_direction")
        if k in keys
    }
    out = {}
    for k, v in summary.items():
        out[k] = keys.pop(k, v) if k in ("mpd_m", "mpd_note") else v
        if k == "mpd_m":
            out["mpd_valid"] = keys.pop("mpd_valid")
        if k == "roughness":
            out["filters"] = keys.pop("filters")
            if ROUGHNESS_NOTE_KEY in keys:
                out[ROUGHNESS_NOTE_KEY] = keys.pop(ROUGHNESS_NOTE_KEY)
        if k == "mpd_note":
            out.update(keys)
            keys = {}
    out.update(keys)
    out.update(spectrum)
    return out, ts


# the spectrum's files and the MPD's report rows live in their own modules; re-exported here
from pipelines.jobs.texture.figures import (  # noqa: E402
    TEXTURE_HEADER,
    draw_texture_spectrum,
    html_escape,
    texture_picture,
    texture_table_html,
    write_texture_csv,
)
from pipelines.jobs.texture.mpd import depth_rows, draw_extras, write_extras  # noqa: E402
