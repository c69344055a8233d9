"""Plots and self-contained HTML reports shared by every pipeline.

Every figure has labelled axes with units and log scales where the thesis uses them; every
report embeds its PNGs (base64) so that ``report.html`` opens offline from anywhere.

The tools every figure uses (``pyplot``, ``save_figure``, ``set_title``, ``fixed_margins``,
``plain_log_ticks``, ``wavelength_axis``, ``display_image`` and the figure constants) live in
``pipelines.output._figure_tools`` and are re-exported here: call them as ``report.save_figure``.
"""

from __future__ import annotations

import textwrap

import numpy as np

from pipelines.output._figure_tools import (  # noqa: F401 (re-exported: the figures' tools)
    DISPLAY_POINTS,
    DPI,
    FIGSIZE,
    PNG_COMPRESSION,
    WAVELENGTH_AXIS_TOP,
    display_image,
    fixed_margins,
    plain_log_ticks,
    pyplot,
    save_figure,
    set_title,
    wavelength_axis,
)
from pipelines.output.result_files import _jsonable, write_csv, write_json  # noqa: F401 (their home)
from pipelines.output.templates import (  # the report writers
    instrument_html,
    list_html,
    paragraph_html,
    table_html,
    write_html,
)

__all__ = [
    "pyplot",
    "save_figure",
    "fixed_margins",
    "plot_heightmap",
    "plot_profile",
    "plot_psd",
    "plot_mu",
    "write_html",
    "write_json",
    "write_csv",
    "table_html",
    "list_html",
    "paragraph_html",
    "instrument_html",
]


def heightmap_picture(hm, depth_m=None):
    """What :func:`draw_heightmap` shows of a height map (or of a water depth map over it),
    computed without matplotlib: the display image (:func:`display_image`, in um or mm), its
    colour limits from every measured point (0.5 and 99.5 percentiles), the extent in mm."""
    data, unit = (hm.heights_m, 1e6) if depth_m is None else (depth_m, 1e3)  # scaled when shown
    lx, ly = hm.size_m
    finite = data[np.isfinite(data)]  # one copy of the measured points, sorted in place
    vmin, vmax = np.percentile(finite, [0.5, 99.5], overwrite_input=True) * unit if finite.size else (0, 1)
    del finite
    if depth_m is not None:
        vmin = 0.0
    label = "water depth [mm]" if depth_m is not None else "height [µm]"
    if depth_m is None and max(abs(vmin), abs(vmax)) >= 1e3:  # "2.0 mm", not "2000 µm"
        unit, vmin, vmax, label = 1e3, vmin / 1e3, vmax / 1e3, "height [mm]"
    shown = display_image(data) * unit  # colour limits from every point, the picture from block means
    return {
        "image": shown,
        "vmin": float(vmin),
        "vmax": float(max(vmax, vmin + 1e-12)),
        "extent_mm": (0.0, lx * 1e3, 0.0, ly * 1e3),
        "depth": depth_m is not None,
        "label": label,
    }


def draw_heightmap(picture, path, title=None):
    """Draw a :func:`heightmap_picture`: x, y in mm, heights in µm (in mm from 1 mm; depths in
    mm), unmeasured points grey."""
    plt = pyplot()
    import matplotlib

    depth = picture["depth"]
    fig, ax = plt.subplots(figsize=FIGSIZE)
    cmap = matplotlib.colormaps["Blues" if depth else "viridis"].with_extremes(bad="0.6")
    im = ax.imshow(
        np.ma.masked_invalid(picture["image"]),
        origin="lower",
        extent=picture["extent_mm"],
        cmap=cmap,
        vmin=picture["vmin"],
        vmax=picture["vmax"],
        interpolation="nearest",
    )
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    cb = fig.colorbar(im, ax=ax, shrink=0.9)
    cb.set_label(picture.get("label") or ("water depth [mm]" if depth else "height [µm]"))
    set_title(ax, title or ("water depth" if depth else "height map"), y=1.0)
    return save_figure(fig, path, fixed_margins(ax, right=1.1))


def plot_heightmap(hm, path, title=None, depth_m=None):
    """Height map image: x, y in mm, heights in um, unmeasured points grey.

    Parameters
    ----------
    hm : HeightMap
        The map [m].
    path : str or Path
        Output PNG.
    title : str, optional
        Title.
    depth_m : ndarray, optional
        Water depth [m] drawn on top.

    Returns
    -------
    Path
    """
    return draw_heightmap(heightmap_picture(hm, depth_m), path, title)


def plot_profile(profile, path, title=None):
    """Line profile: distance in mm, height in mm.

    Parameters
    ----------
    profile : Profile
        The profile [m].
    path : str or Path
        Output PNG.
    title : str, optional
        Title.

    Returns
    -------
    Path
    """
    fig, ax = pyplot().subplots(figsize=(7.5, 3.4))
    start = (getattr(profile, "meta", None) or {}).get("section_start_m")
    if start is None:
        ax.plot(profile.x_m() * 1e3, profile.heights_m * 1e3, lw=0.5, color="C0")
        ax.set_xlabel("distance [mm]")
    else:  # a campaign's section: its place along the road
        ax.plot(start + profile.x_m(), profile.heights_m * 1e3, lw=0.5, color="C0")
        ax.set_xlabel("chainage [m]")
    ax.set_ylabel("height [mm]")
    set_title(ax, title or "profile")
    ax.grid(alpha=0.3)
    return save_figure(fig, path, fixed_margins(ax))


def plot_psd(curves, path, title="power spectral density", fits=()):
    """Log-log C(q). ``curves``: iterable of (label, q_per_m, C_m4); ``fits`` the same, dashed.

    Parameters
    ----------
    curves : iterable of tuple
        (label, q_per_m, C_m4).
    path : str or Path
        Output PNG.
    title : str, optional
        Title.
    fits : iterable of tuple, optional
        Dashed curves.

    Returns
    -------
    Path
    """
    fig, ax = pyplot().subplots(figsize=FIGSIZE)
    for i, (label, q, C) in enumerate(curves):
        ok = np.asarray(C) > 0
        ax.loglog(np.asarray(q)[ok], np.asarray(C)[ok], "-", lw=1.4, color=f"C{i}", label=label)
    for i, (label, q, C) in enumerate(fits):
        ok = np.asarray(C) > 0
        ax.loglog(np.asarray(q)[ok], np.asarray(C)[ok], "--", lw=1.2, color=f"C{i + 3}", label=label)
    ax.set_xlabel("wave vector q [1/m]")
    ax.set_ylabel("C(q) [m⁴]")
    plain_log_ticks(ax)
    wavelength_axis(ax)
    lo, hi = ax.get_ylim()
    if lo > 0 and hi / lo > 1e5:  # many decades: minor ticks and lines only on the q axis
        from matplotlib.ticker import NullLocator

        ax.yaxis.set_minor_locator(NullLocator())
    set_title(ax, title)
    ax.grid(which="both", alpha=0.25)
    ax.legend(fontsize=8, loc="best")
    return save_figure(fig, path, fixed_margins(ax, top=WAVELENGTH_AXIS_TOP))


def _wrapped(label, width=48):
    """A legend entry broken over lines of at most ``width`` characters (a long rubber label
    otherwise runs over the axes and the y label)."""

    if not label:
        return label
    for unit in (" MPa", " kPa", " Pa", " °C", " m/s", " = "):  # a number stays with its unit
        label = label.replace(unit, unit.replace(" ", "\u00a0"))
    return "\n".join(textwrap.wrap(label, width))


def plot_mu(curves, path, title="friction coefficient", ylabel="friction coefficient μ [-]", logy=False):
    """mu(v) on a log speed axis. ``curves``: iterable of (label, v_m_per_s, mu) or with a 4th
    element, a matplotlib style string.

    Parameters
    ----------
    curves : iterable of tuple
        (label, v_m_per_s, mu[, style]).
    path : str or Path
        Output PNG.
    title : str, optional
        Title.
    ylabel : str, optional
        Y label.
    logy : bool, optional
        Logarithmic mu axis.

    Returns
    -------
    Path
    """
    fig, ax = pyplot().subplots(figsize=FIGSIZE)
    for i, curve in enumerate(curves):
        label, v, mu = curve[:3]
        style = curve[3] if len(curve) > 3 else "-"
        ax.plot(v, mu, style, lw=1.5, color=f"C{i}", label=_wrapped(label), ms=4)
    ax.set_xscale("log")
    plain = logy  # no offset text above the y axis: the title stays where it is
    if logy:
        ax.set_yscale("log")
    else:  # a nearly flat curve: a span of 10 %, ticks "0.58" and not "0.5925"
        ys = np.concatenate([np.asarray(c[2], float).ravel() for c in curves] or [np.zeros(0)])
        ys = ys[np.isfinite(ys)]
        big = float(np.abs(ys).max()) if ys.size else 0.0
        if big > 0 and np.ptp(ys) < 0.1 * big:
            mid = 0.5 * (ys.min() + ys.max())
            ax.set_ylim(mid - 0.05 * big, mid + 0.05 * big)
        plain = 1e-3 <= big < 1e4  # ticks spanning 10 % or more of values of this size
    ax.set_xlabel("sliding speed v [m/s]")
    ax.set_ylabel(ylabel)
    plain_log_ticks(ax)
    set_title(ax, title, y=1.0 if plain else None)
    ax.grid(which="both", alpha=0.25)
    if len(curves) > 1 or (curves and curves[0][0]):
        ax.legend(fontsize=8)
    return save_figure(fig, path, fixed_margins(ax))
