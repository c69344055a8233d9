"""The ISO 13473-1 segments behind a scan's MPD: ``mpd_segments.csv`` and ``mpd_segments.png``,
and the validity keys of ``summary.json``.

``mpd_segments.csv`` (header ``start_m,end_m,msd_m,valid,reason``): one row per 100 mm segment,
line after line (a profile is one line; an area's lines are its rows, or its columns with
``--direction y``, each with the same number of segments, so row k belongs to line
k // segments-per-line); positions along the line from its first sample [m], MSD [m],
``valid`` true/false, ``reason`` why a segment is invalid (dropouts or spikes above the
standard's limits), empty when valid.

Validity (ISO 13473-1:2019): the MPD is reported as valid when at least half of the segments
are valid; otherwise ``mpd_valid`` is false, and ETD and the IFI figures derived from the MPD
are null with the reason.
"""

from __future__ import annotations

import csv
import io

__all__ = [
    "SEGMENTS_HEADER",
    "validity_keys",
    "invalid_mpd_warning",
    "write_segments_csv",
    "segments_picture",
    "draw_segments",
    "segments_title",
    "depth_rows",
    "write_extras",
    "draw_extras",
]

SEGMENTS_HEADER = ["start_m", "end_m", "msd_m", "valid", "reason"]


def validity_keys(seg):
    """``mpd_valid``, ``mpd_valid_segments``, ``mpd_total_segments`` of an
    :class:`roadscan.texture_depth.MpdSegments` (None: no segment fits the scan).

    Parameters
    ----------
    seg : MpdSegments or None
        The segments.

    Returns
    -------
    dict
    """
    if seg is None:
        return {"mpd_valid": False, "mpd_valid_segments": 0, "mpd_total_segments": 0}
    return {"mpd_valid": seg.mpd_valid, "mpd_valid_segments": seg.n_valid, "mpd_total_segments": seg.n_total}


def invalid_mpd_warning(name, seg, alpha_to_pass=None, iso_at_alpha=False):
    """The warning of an MPD that is not valid per ISO 13473-1, or None when it is valid (or
    there is no segment): which rule the segments failed and the option that relaxes it.

    The rules (ISO 13473-1:2019): a 100 mm segment is invalid with more than 10 % dropouts or
    more than 5 % spikes (|dh| >= alpha x the resampled interval, alpha = 3); the MPD is valid
    when at least half of the segments are. ``--mpd-spike-alpha`` relaxes the spike rule (the
    threshold ``alpha_to_pass`` that would pass, from
    :func:`roadscan.texture_depth.spike_alpha_to_pass`); no option relaxes the dropout limit.

    Parameters
    ----------
    name : str
        Scan name.
    seg : MpdSegments or None
        The segments.
    alpha_to_pass : float, optional
        The smallest spike alpha giving an MPD (None: none found, or not searched).
    iso_at_alpha : bool, optional
        That MPD is valid per ISO 13473-1 (at least half the segments valid).

    Returns
    -------
    str or None
    """
    if seg is None or seg.n_total == 0 or seg.mpd_valid:
        return None
    from pipelines.output.units import length

    failed = seg.failed_rules()
    need = seg.min_valid_fraction
    what = (
        f"MPD {length(seg.mpd_m)} is not valid per ISO 13473-1"
        if seg.mpd_m is not None
        else "no MPD per ISO 13473-1"
    )
    rules = []
    if failed["spikes"]:
        rules.append(
            f"{failed['spikes']} fail the spike rule (over "
            f"{100 * seg.max_spike_fraction:g} % spikes, |dh| >= {seg.spike_alpha:g} x the "
            f"resampled interval)"
        )
    if failed["dropouts"]:
        rules.append(
            f"{failed['dropouts']} the dropout rule (over {100 * seg.max_dropout_fraction:g} % dropouts)"
        )
    line = (
        f"{name}: {what}: {seg.n_valid} of {seg.n_total} segments valid, fewer than the "
        f"{100 * need:g} % the standard asks (too few valid segments); of the "
        f"{seg.n_total}, {' and '.join(rules)}"
    )
    if failed["spikes"] and alpha_to_pass is not None:
        gives = "an MPD valid per ISO 13473-1" if iso_at_alpha else "an MPD (still not valid per ISO 13473-1)"
        line += (
            f"; --mpd-spike-alpha {alpha_to_pass:g} relaxes the spike rule and gives {gives} "
            f"(steep stone edges, e.g. of chip seals, read as spikes)"
        )
    elif failed["spikes"]:
        line += "; no --mpd-spike-alpha up to 50 gives a valid segment: the dropouts decide"
    if failed["dropouts"] and not failed["spikes"]:
        line += (
            "; no option relaxes the dropout rule: fill or trim the dropouts (e.g. the "
            "profile's ends) before, or measure again"
        )
    return line


def write_segments_csv(path, seg):
    """``mpd_segments.csv`` (module docstring); nothing written when ``seg`` is None.

    Parameters
    ----------
    path : str or Path
        Output CSV.
    seg : MpdSegments or None
        The segments.

    Returns
    -------
    Path or None
    """
    if seg is None:
        return None
    from roadscan.io.atomic import atomic_write_text

    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(SEGMENTS_HEADER)
    for a, b, m, ok, why in zip(seg.start_m, seg.end_m, seg.msd_m, seg.valid, seg.reason):
        w.writerow([f"{a:.10g}", f"{b:.10g}", f"{m:.10g}", "true" if ok else "false", why])
    atomic_write_text(path, buf.getvalue())
    return path


def segments_title(name, summary):
    """Figure title: the MPD and its validity in the reader's units.

    Parameters
    ----------
    name : str
        Scan name.
    summary : dict
        Its summary.

    Returns
    -------
    str
    """
    from pipelines.output.units import length

    n, t = summary.get("mpd_valid_segments"), summary.get("mpd_total_segments")
    what = "valid" if summary.get("mpd_valid") else "NOT valid"
    return f"{name}: MPD {length(summary.get('mpd_m'))}, {what} per ISO 13473-1 ({n} of {t} segments)"


def segments_picture(seg, line_spacing_m=None):
    """What :func:`draw_segments` needs (small, picklable): per segment for one line, per line
    (mean MSD of its valid segments, share valid) for several.

    Parameters
    ----------
    seg : MpdSegments
        The segments.
    line_spacing_m : float, optional
        Spacing of the lines of a map [m].

    Returns
    -------
    dict
    """
    import numpy as np

    lines = int(seg.line.max()) + 1 if seg.line.size else 0
    if lines <= 1:
        return {
            "kind": "profile",
            "start_mm": seg.start_m * 1e3,
            "end_mm": seg.end_m * 1e3,
            "msd_mm": seg.msd_m * 1e3,
            "valid": seg.valid.copy(),
            "mpd_mm": None if seg.mpd_m is None else seg.mpd_m * 1e3,
        }
    per = seg.valid.size // lines
    msd = seg.msd_m.reshape(lines, per)
    ok = seg.valid.reshape(lines, per)
    with np.errstate(invalid="ignore"):
        mean = np.where(ok.any(axis=1), np.nanmean(np.where(ok, msd, np.nan), axis=1), np.nan)
    pos = np.arange(lines) * (line_spacing_m or 1.0) * 1e3
    return {
        "kind": "area",
        "pos_mm": pos,
        "line_msd_mm": mean * 1e3,
        "share_valid": ok.mean(axis=1),
        "per_line": per,
        "positional": line_spacing_m is not None,
        "mpd_mm": None if seg.mpd_m is None else seg.mpd_m * 1e3,
    }


def draw_segments(picture, path, title):
    """Segment plot [mm]: a profile's MSD per 100 mm segment (valid in blue, invalid hatched
    grey), or an area's mean MSD of each line's valid segments; the MPD as a line.

    Parameters
    ----------
    picture : dict
        From :func:`segments_picture`.
    path : str or Path
        Output PNG.
    title : str
        Title.

    Returns
    -------
    Path
    """
    import numpy as np

    from pipelines.output import report

    plt = report.pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    mpd = picture["mpd_mm"]
    if picture["kind"] == "profile":
        a, b, m, ok = (picture[k] for k in ("start_mm", "end_mm", "msd_mm", "valid"))
        ax.bar(
            a[ok],
            m[ok],
            width=(b - a)[ok] * 0.92,
            align="edge",
            color="C0",
            edgecolor="0.2",
            lw=0.5,
            label="valid segment",
        )
        if (~ok).any():
            ax.bar(
                a[~ok],
                m[~ok],
                width=(b - a)[~ok] * 0.92,
                align="edge",
                color="0.85",
                edgecolor="0.4",
                hatch="//",
                lw=0.5,
                label="invalid (dropouts or spikes)",
            )
        ax.set_xlabel("position along the profile [mm] (100 mm segments)")
    else:
        ax.plot(
            picture["pos_mm"],
            picture["line_msd_mm"],
            lw=0.8,
            color="C0",
            label=f"mean MSD of each line's valid segments ({picture['per_line']} per line)",
        )
        bad = picture["share_valid"] < 0.5
        if bad.any():
            ax.plot(
                picture["pos_mm"][bad],
                np.zeros(bad.sum()),
                "|",
                color="C3",
                ms=8,
                label="line with fewer than half its segments valid",
            )
        ax.set_xlabel("line position across the scan [mm]" if picture["positional"] else "line")
    if mpd is not None:
        ax.axhline(mpd, color="C1", lw=1.2, ls="--", label=f"MPD {mpd:#.3g} mm")
    ax.set_ylabel("mean segment depth MSD [mm]")
    top = np.nanmax(np.r_[picture.get("msd_mm", []), picture.get("line_msd_mm", []), mpd or 0.0, 1e-3])
    ax.set_ylim(0, top * 1.3)  # room for the legend above the bars
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=8, loc="upper center", ncol=3)
    report.set_title(ax, title)
    return report.save_figure(fig, path, report.fixed_margins(ax))


def depth_rows(summary):
    """Report rows (label, text) for MPD, ETD, IFI and the short-baseline depth.

    Parameters
    ----------
    summary : dict
        A summary.

    Returns
    -------
    list of tuple
    """
    from pipelines.output.units import length, sig3, speed_kmh

    rows = []
    n, t = summary.get("mpd_valid_segments"), summary.get("mpd_total_segments")
    if summary.get("mpd_m") is not None and summary.get("mpd_valid", True):
        rows.append(
            (
                "mean profile depth MPD (ISO 13473-1)",
                f"{length(summary['mpd_m'])}, valid per ISO 13473-1 ({n} of {t} segments)"
                if t
                else length(summary["mpd_m"]),
            )
        )
    elif summary.get("mpd_m") is not None:
        rows.append(
            (
                "mean profile depth MPD (ISO 13473-1)",
                f"{length(summary['mpd_m'])}: not valid per ISO 13473-1 ({n} of {t} segments)",
            )
        )
    else:
        rows.append(("mean profile depth MPD (ISO 13473-1)", summary.get("mpd_note") or "—"))
    if summary.get("etd_note"):
        rows.append(("ETD, IFI", summary["etd_note"]))
    if summary.get("etd_m") is not None:
        rows.append(("estimated texture depth ETD = 0.2 mm + 0.8 MPD", length(summary["etd_m"])))
    if summary.get("ifi_speed_constant_kmh") is not None:
        rows.append(
            (
                "IFI speed constant Sp = 14.2 + 89.7 MPD[mm] (ASTM E1960)",
                speed_kmh(summary["ifi_speed_constant_kmh"]),
            )
        )
    if "ifi_F60" in summary:
        inp = summary.get("ifi_inputs") or {}
        rows.append(
            (
                f"IFI F60 (ASTM E1960; F = {sig3(inp.get('friction'))} at "
                f"{sig3(inp.get('slip_speed_kmh'))} km/h)",
                sig3(summary["ifi_F60"]),
            )
        )
    if summary.get("msd_short_m") is not None:
        rows.append(
            (
                f"short-baseline mean segment depth over "
                f"{length(summary['msd_short_baseline_m'])} (NOT ISO 13473-1 MPD)",
                length(summary["msd_short_m"]),
            )
        )
    return rows


def write_extras(out_dir, ts):
    """``mpd_segments.csv`` next to ``summary.json`` (:mod:`pipelines.jobs.texture.mpd`).

    Parameters
    ----------
    out_dir : str or Path
        Output folder.
    ts : object
        The analysis' texture result.

    Returns
    -------
    None
    """
    from pathlib import Path

    seg = getattr(ts, "mpd_segments", None)
    if seg is not None:
        write_segments_csv(Path(out_dir) / "mpd_segments.csv", seg)


def draw_extras(drawer, out_dir, name, summary, ts):
    """``mpd_segments.png`` handed to ``drawer`` (:mod:`pipelines.output.figure_process`).

    Parameters
    ----------
    drawer : object
        Figure process.
    out_dir : str or Path
        Output folder.
    name : str
        Scan name.
    summary : dict
        Its summary.
    ts : object
        The texture result.

    Returns
    -------
    None
    """
    from pathlib import Path

    seg = getattr(ts, "mpd_segments", None)
    if seg is not None and seg.n_total:
        sp = summary.get("spacing_m") or []
        across = None if len(sp) < 2 else (sp[0] if summary.get("texture_direction") == "y" else sp[1])
        drawer.submit(
            draw_segments,
            segments_picture(seg, across),
            Path(out_dir) / "mpd_segments.png",
            segments_title(name, summary),
        )
