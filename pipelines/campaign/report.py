"""``report.html`` of a campaign: distributions, values along chainage, outliers, scan table.

Quantities: Hurst exponent H (``hurst``), Sq (``rms_height_m``), MPD (``mpd_m``) and mu at the
speeds of :data:`.records.REPORT_SPEEDS_M_PER_S` (from each scan's ``mu.csv``).

Outliers: modified z-score of Iglewicz and Hoaglin (1993), ``|0.6745 (x - median) / MAD| >
3.5`` over the campaign's successful rows, per quantity (needs at least 5 values and a
non-zero MAD). They are drawn red in every plot and flagged in the table.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pipelines.output import report
from pipelines.output.units import sig3

__all__ = ["QUANTITIES", "outlier_mask", "write_campaign_report"]

Z_OUTLIER = 3.5


def QUANTITIES(speeds):
    """(key, label, scale to display units, getter) for the report's quantities.

    Parameters
    ----------
    speeds : sequence of float
        Speeds of the mu columns [m/s].

    Returns
    -------
    list of tuple
    """
    q = [
        ("hurst", "Hurst exponent H [-]", 1.0, lambda r: r["values"].get("hurst")),
        ("rms_height_m", "Sq, rms height [µm]", 1e6, lambda r: r["values"].get("rms_height_m")),
        ("mpd_m", "MPD (ISO 13473-1) [mm]", 1e3, lambda r: r["values"].get("mpd_m")),
    ]
    for band in ("80", "5"):  # what noise studies plot along chainage (ISO 13473-4)
        key = f"texture_level_dB.{band}"
        q.append((key, f"texture level {band} mm [dB re 1 µm]", 1.0, lambda r, key=key: r["values"].get(key)))
    for s in speeds:
        q.append((f"mu@{s}", f"μ at {s} m/s [-]", 1.0, lambda r, s=s: r["mu_at"].get(s)))
    return q


def outlier_mask(x):
    """Modified z-score outliers of ``x`` (NaN ignored) -> bool array.

    Parameters
    ----------
    x : array_like
        Values.

    Returns
    -------
    ndarray of bool

    References
    ----------
    B. Iglewicz, D. Hoaglin, How to Detect and Handle Outliers, ASQC (1993): modified z-score
    above 3.5.
    """
    x = np.asarray(x, float)
    ok = np.isfinite(x)
    out = np.zeros(x.shape, bool)
    if ok.sum() < 5:
        return out
    med = np.median(x[ok])
    mad = np.median(np.abs(x[ok] - med))
    if mad <= 0:
        return out
    out[ok] = np.abs(0.6745 * (x[ok] - med) / mad) > Z_OUTLIER
    return out


def _values(records, quantities):
    vals = {}
    for key, _, scale, get in quantities:
        v = np.array(
            [np.nan if (r["status"] != "ok" or get(r) is None) else float(get(r)) * scale for r in records]
        )
        vals[key] = v
    return vals


def _hist_bins(x, n_ok):
    """Histogram bins for the values ``x``: sqrt-rule bins, or one bar around the value when all
    scans agree to 1e-9 (matplotlib refuses many bins over a range of a few ulps)."""
    if x.size == 0:
        return {"bins": 5}
    centre, span = float(np.mean(x)), float(np.ptp(x))
    if span <= 1e-9 * max(abs(centre), float(np.abs(x).max()), 1e-300):
        half = max(0.01 * abs(centre), 1e-12)
        return {"bins": 1, "range": (centre - half, centre + half)}
    return {"bins": min(30, max(5, int(np.sqrt(n_ok)) + 1))}


def _plot_grid(path, quantities, vals, chain=None, groups=None):
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    shown = [q for q in quantities if np.isfinite(vals[q[0]]).any()]
    quantities = shown or quantities[:1]  # no panel of "no values"
    n = len(quantities)
    ncol = 3
    nrow = int(np.ceil((n + (chain is not None)) / ncol))  # along chainage: a spare for the legend
    fig, axes = plt.subplots(nrow, ncol, figsize=(11, 3.2 * nrow), squeeze=False)
    for ax, (key, label, _, _) in zip(axes.flat, quantities):
        v = vals[key]
        ok = np.isfinite(v)
        bad = outlier_mask(v)
        if chain is None:
            if ok.any():
                ax.hist(
                    v[ok & ~bad], **_hist_bins(v[ok & ~bad], ok.sum()), color="C0", alpha=0.8, label="scans"
                )
                if bad.any():
                    ax.plot(v[bad], np.zeros(bad.sum()), "v", color="red", ms=8, label="outliers")
                ax.legend(fontsize=7)
            ax.set_xlabel(label)
            ax.set_ylabel("count")
            ax.yaxis.set_major_locator(MaxNLocator(integer=True))  # whole scans
        else:
            has = ok & np.isfinite(chain)
            keys = np.asarray(groups)
            uniq = list(dict.fromkeys(keys[has]))
            single = len(uniq) == int(has.sum())  # one row per file: one line along the road
            for gi, g in enumerate([None] if single else uniq):
                sel = has if g is None else has & (keys == g)
                order = np.argsort(chain[sel])
                lab = "scans" if g is None else (Path(g).stem if len(uniq) <= 8 else None)
                ax.plot(
                    chain[sel][order],
                    v[sel][order],
                    "o-",
                    ms=3,
                    lw=0.8,
                    color=f"C{gi % 10}" if len(uniq) <= 10 else "C0",
                    label=lab,
                )
            if (bad & has).any():
                ax.plot(chain[bad & has], v[bad & has], "o", color="red", ms=6, label="outliers")
            ax.set_xlabel("chainage [m]")
            ax.set_ylabel(label)
        if not ok.any():
            ax.text(0.5, 0.5, "no values", transform=ax.transAxes, ha="center")
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    if chain is not None:  # one legend in the spare panel, over no data
        legend = {}
        for ax in list(axes.flat)[:n]:
            legend.update(zip(*reversed(ax.get_legend_handles_labels())))
        if legend:
            axes.flat[n].legend(
                list(legend.values()), list(legend.keys()), loc="center", fontsize=8, frameon=False
            )
    return report.save_figure(fig, path)


def _reader_units(quantities, vals):
    """Heights shown in µm switch to mm for the whole column when their median is 1 mm or more
    (CAPTIF profiles: "2.53", not "2530")."""
    out = []
    for key, label, scale, get in quantities:
        v = vals[key]
        if scale == 1e6 and "[µm]" in label and np.isfinite(v).any() and np.nanmedian(np.abs(v)) >= 1e3:
            label, scale, vals[key] = label.replace("[µm]", "[mm]"), 1e3, v / 1e3
        out.append((key, label, scale, get))
    return out, vals


def _table(records, quantities, vals, masks):
    """The scans' table (``templates/campaign_table.html.j2``): outliers in red, links to each
    scan's folder and report."""
    from pipelines.output.templates import render

    head = (
        ["#", "file", "label", "chainage [m]", "status"]
        + [q[1] for q in quantities]
        + ["outlier in", "outputs"]
    )
    rows = []
    for i, r in enumerate(records):
        rows.append(
            {
                "n": i + 1,
                "file": Path(r["file"]).name,
                "label": r["label"] or "",
                "chainage": "—" if r["chainage_m"] is None else f"{r['chainage_m']:.6g}",
                "error": None if r["status"] == "ok" else str(r["error"]),
                "cells": [
                    (
                        sig3(vals[q[0]][i])
                        + (
                            " not valid (ISO 13473-1)"
                            if q[0] == "mpd_m"
                            and r["values"].get("mpd_valid") is False
                            and r["values"].get("mpd_m") is not None
                            else ""
                        ),
                        bool(masks[q[0]][i]),
                    )
                    for q in quantities
                ],
                "flags": [q[0] for q in quantities if masks[q[0]][i]],
                "dir": r.get("dir") or None,
            }
        )
    return render("campaign_table.html.j2", header=head, rows=rows)


def write_campaign_report(out_dir, records, speeds, title="roadscan batch: campaign"):
    """Write ``out_dir/report.html`` (figures embedded; PNGs written beside it are removed).

    Parameters
    ----------
    out_dir : str or Path
        Campaign folder.
    records : list of dict
        The rows.
    speeds : sequence of float
        Speeds of the mu columns [m/s].
    title : str, optional
        Page title.

    Returns
    -------
    Path
        The report.
    """
    out_dir = Path(out_dir)
    quantities = QUANTITIES([f"{s:g}" for s in speeds])
    quantities, vals = _reader_units(quantities, _values(records, quantities))
    masks = {k: outlier_mask(v) for k, v in vals.items()}
    chain = np.array([np.nan if r["chainage_m"] is None else float(r["chainage_m"]) for r in records])
    n_ok = sum(r["status"] == "ok" for r in records)
    # the figures' files are removed whatever happens, a signal while one is drawn included
    # (only the report is an output; a killed campaign's are swept by the next run)
    spare = [out_dir / ".campaign_distributions.png", out_dir / ".campaign_chainage.png"]
    try:
        pngs = [_plot_grid(spare[0], quantities, vals)]
        sections = [("Distributions", [pngs[0]])]
        if np.isfinite(chain).any():
            pngs.append(_plot_grid(spare[1], quantities, vals, chain, [r["file"] for r in records]))
            sections.append(("Along chainage", [pngs[1]]))
        sections.append(("Scans", _table(records, quantities, vals, masks)))
        warned = [r for r in records if r["status"] == "ok" and r["values"].get("warnings")]
        if warned:  # every warning of every scan
            sections.append(
                (
                    "Warnings",
                    report.table_html(
                        [
                            [r.get("dir") or r["file"], w]
                            for r in warned
                            for w in r["values"]["warnings"].split(" | ")
                        ],
                        ["scan", "warning"],
                    ),
                )
            )
        from pipelines.output.templates import render

        intro = render(
            "campaign_intro.html.j2",
            rows=len(records),
            ok=n_ok,
            warned=len(warned),
            failed=len(records) - n_ok,
            z=Z_OUTLIER,
        )
        report.write_html(out_dir / "report.html", title, sections, intro=intro)
    finally:
        for p in spare:
            p.unlink(missing_ok=True)
    return out_dir / "report.html"
