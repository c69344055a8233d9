"""Plots and self-contained HTML reports shared by every pipeline.

Every figure has labelled axes with units and log scales where the thesis uses them; every
report embeds its PNGs (base64) so that ``report.html`` opens offline from anywhere.
"""
from __future__ import annotations

import os
import re
import sys
import textwrap
from pathlib import Path

import numpy as np

from pipelines.output.result_files import _jsonable, write_csv, write_json  # noqa: F401 (their home)
from pipelines.output.templates import (  # the report writers
    instrument_html,
    list_html,
    paragraph_html,
    table_html,
    write_html,
)
from roadscan.io.atomic import atomic_path

# Figures are files, never windows: the Agg backend. matplotlib itself (0.3 to 1 s to import)
# is loaded only when a figure is drawn (--no-figures, CSV/JSON-only runs and --help
# do without it); until then the backend is chosen through the environment.
if "matplotlib" in sys.modules:
    sys.modules["matplotlib"].use("Agg")
else:
    os.environ["MPLBACKEND"] = "Agg"

__all__ = [
    "pyplot", "save_figure", "fixed_margins", "plot_heightmap", "plot_profile", "plot_psd", "plot_mu",
    "write_html",
    "write_json", "write_csv", "table_html", "list_html", "paragraph_html", "instrument_html",
]

FIGSIZE = (6.4, 4.4)
DPI = 120
#: zlib level of the PNGs: 3 writes them in half the time of the default 6, 5 % larger
PNG_COMPRESSION = 3
#: a height map is shown as block means with at least this many points along its longer side
#: (more than the axes have pixels at ``FIGSIZE`` and ``DPI``); the data are not changed
DISPLAY_POINTS = 500


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend, imported on first use.

    Parameters
    ----------
    None

    Returns
    -------
    module
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


_SUPERSCRIPT = str.maketrans("0123456789-+", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺")
_MATH = re.compile(r"^\$\\mathdefault\{(.*)\}\$$")


def _plain_log_label(text):
    """matplotlib's log-axis label ``$\\mathdefault{10^{-5}}$`` as plain Unicode ``10⁻⁵``."""
    m = _MATH.match(text)
    if not m:
        return text
    body = m.group(1).replace("\\times", "×")
    return re.sub(r"\^\{([^}]*)\}", lambda g: g.group(1).translate(_SUPERSCRIPT), body)


def plain_log_ticks(ax):
    """Label the log axes of ``ax`` with Unicode exponents (``10⁻⁵``) instead of mathtext.

    The tick labels read the same; mathtext's parser costs 0.3 s or more the first time a
    process draws a log axis. Call it after the axis scales are set."""
    from matplotlib.ticker import LogFormatterSciNotation

    global _PlainLogFormatter
    if _PlainLogFormatter is None:
        class _PlainLogFormatter(LogFormatterSciNotation):
            def __call__(self, x, pos=None):
                return _plain_log_label(super().__call__(x, pos))

    for axis in (ax.xaxis, ax.yaxis):
        for fmt in (axis.get_major_formatter(), axis.get_minor_formatter()):
            if type(fmt) is LogFormatterSciNotation:   # the log scale's own: same settings
                fmt.__class__ = _PlainLogFormatter
        if axis.get_scale() == "log":
            axis.set_major_locator(_in_view(axis.get_major_locator()))
            axis.set_minor_locator(_in_view(axis.get_minor_locator()))


_PlainLogFormatter = None


def _in_view(locator):
    """``locator`` giving only the ticks inside the axis's view interval (in the axis's own
    scale, with a 1e-6 tolerance: every tick matplotlib would draw). A log locator returns a
    decade beyond each end, and matplotlib builds a tick (three lines, two texts) for each
    location before it drops the ones outside: 0.5 ms a tick, about 15 % of a log figure."""
    from matplotlib.ticker import Locator

    class _InView(Locator):
        def __call__(self):
            locs = np.asarray(locator(), dtype=float)
            if self.axis is None or locs.size == 0:
                return locs
            tr = self.axis.get_transform()
            lo, hi = sorted(tr.transform(np.asarray(self.axis.get_view_interval(), float)))
            with np.errstate(invalid="ignore", divide="ignore"):
                t = tr.transform(locs)
            tol = 1e-6 * (hi - lo)
            return locs[(t >= lo - tol) & (t <= hi + tol)]

        def set_axis(self, axis):
            super().set_axis(axis)
            locator.set_axis(axis)

        def tick_values(self, vmin, vmax):
            return locator.tick_values(vmin, vmax)

        def nonsingular(self, v0, v1):
            return locator.nonsingular(v0, v1)

        def view_limits(self, vmin, vmax):
            return locator.view_limits(vmin, vmax)

    return _InView()


def display_image(data, points=DISPLAY_POINTS):
    """``data`` (2D, NaN where unmeasured) reduced for display by ``k x k`` block means,
    ``k = max(1, max(shape) // points)``; a block without finite values stays NaN. The
    picture keeps at least ``points`` pixels along its longer side, more than a figure shows,
    so it looks the same as the full map; drawing and saving it is several times faster."""
    data = np.asarray(data, dtype=float)
    k = max(1, max(data.shape) // int(points))
    if k == 1 or data.ndim != 2:
        return data
    cols = np.arange(0, data.shape[1], k)
    step = k * max(1, (1 << 22) // (8 * data.shape[1] * k))  # whole blocks, about 4 MiB a band:
    parts = []                                             # the memory used is a band's
    for r in range(0, data.shape[0], step):
        band = data[r:r + step]
        ok = np.isfinite(band)
        rows = np.arange(0, band.shape[0], k)
        total = np.add.reduceat(np.add.reduceat(np.where(ok, band, 0.0), rows, axis=0), cols, axis=1)
        count = np.add.reduceat(np.add.reduceat(ok.astype(np.int32), rows, axis=0), cols, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            parts.append(np.where(count > 0, total / np.maximum(count, 1), np.nan))
    return np.concatenate(parts, axis=0)


def set_title(ax, text, width=58, y=None):
    """A title wrapped to the axes width (long scan names must not run off the figure): after
    the scan's name when the rest fits one line, never inside "T0 = 60 °C" or "0.2 MPa".

    ``y=1.0``: the title right above the axes (its usual place when nothing is drawn there), not
    moved at draw time above top tick labels or an offset text, which matplotlib otherwise
    measures by laying out the tick labels of every axis once more (about 15 % of a figure's
    time). Only for axes with no ticks, labels or offset text on top."""

    nb = "\u00a0"                       # textwrap breaks only at ASCII whitespace
    text = re.sub(r"(?<=\S) ([=±]) (?=\S)", nb + r"\1" + nb, str(text))
    text = re.sub(r"(?<=\d) (?=[^\W\d_]|°|%)", nb, text)
    head, sep, tail = text.partition(": ")
    if len(text) > width and sep and len(head) < width and len(tail) <= width:
        lines = [head + ":", tail]
    else:
        lines = textwrap.wrap(text, width)
    ax.set_title("\n".join(lines) or "", fontsize=10, **({} if y is None else {"y": y}))


def fixed_margins(ax, left=0.95, right=0.25, bottom=0.62, top=0.18):
    """Figure margins [inches] for one axes with tick labels and axis labels on the left and
    bottom, plus room for its title (0.19 in a line, see :func:`set_title`) above ``top``.

    Passed to :func:`save_figure` instead of ``tight_layout``, which draws every figure a
    second time to measure its texts (0.05 s a figure).

    Parameters
    ----------
    ax : matplotlib Axes
        The axes.
    left, right, bottom, top : float, optional
        Margins [in].

    Returns
    -------
    dict
    """
    title = ax.get_title()
    lines = title.count("\n") + 1 if title else 0
    return {"left": left, "right": right, "bottom": bottom, "top": top + 0.19 * lines}


def save_figure(fig, path, margins=None):
    """Save ``fig`` as PNG atomically and close it.

    ``margins``: ``{"left", "right", "bottom", "top"}`` in inches (:func:`fixed_margins`);
    None lays the figure out with ``tight_layout``.

    Parameters
    ----------
    fig : matplotlib Figure
        The figure.
    path : str or Path
        Output PNG.
    margins : dict, optional
        Margins [in].

    Returns
    -------
    Path
    """
    plt = pyplot()
    if margins is None:
        fig.tight_layout()
    else:
        w, h = fig.get_size_inches()
        fig.subplots_adjust(left=margins["left"] / w, right=1 - margins["right"] / w,
                            bottom=margins["bottom"] / h, top=1 - margins["top"] / h)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=DPI, format="png", pil_kwargs={"compress_level": PNG_COMPRESSION})
    plt.close(fig)
    return Path(path)


def heightmap_picture(hm, depth_m=None):
    """What :func:`draw_heightmap` shows of a height map (or of a water depth map over it),
    computed without matplotlib: the display image (:func:`display_image`, in um or mm), its
    colour limits from every measured point (0.5 and 99.5 percentiles), the extent in mm."""
    data, unit = (hm.heights_m, 1e6) if depth_m is None else (depth_m, 1e3)   # scaled when shown
    lx, ly = hm.size_m
    finite = data[np.isfinite(data)]             # one copy of the measured points, sorted in place
    vmin, vmax = (np.percentile(finite, [0.5, 99.5], overwrite_input=True) * unit
                  if finite.size else (0, 1))
    del finite
    if depth_m is not None:
        vmin = 0.0
    label = "water depth [mm]" if depth_m is not None else "height [µm]"
    if depth_m is None and max(abs(vmin), abs(vmax)) >= 1e3:   # "2.0 mm", not "2000 µm"
        unit, vmin, vmax, label = 1e3, vmin / 1e3, vmax / 1e3, "height [mm]"
    shown = display_image(data) * unit   # colour limits from every point, the picture from block means
    return {"image": shown, "vmin": float(vmin), "vmax": float(max(vmax, vmin + 1e-12)),
            "extent_mm": (0.0, lx * 1e3, 0.0, ly * 1e3), "depth": depth_m is not None,
            "label": label}


def draw_heightmap(picture, path, title=None):
    """Draw a :func:`heightmap_picture`: x, y in mm, heights in µm (in mm from 1 mm; depths in
    mm), unmeasured points grey."""
    plt = pyplot()
    import matplotlib

    depth = picture["depth"]
    fig, ax = plt.subplots(figsize=FIGSIZE)
    cmap = matplotlib.colormaps["Blues" if depth else "viridis"].with_extremes(bad="0.6")
    im = ax.imshow(np.ma.masked_invalid(picture["image"]), origin="lower", extent=picture["extent_mm"],
                   cmap=cmap, vmin=picture["vmin"], vmax=picture["vmax"], interpolation="nearest")
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
    else:                                   # a campaign's section: its place along the road
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
    if lo > 0 and hi / lo > 1e5:    # many decades: minor ticks and lines only on the q axis
        from matplotlib.ticker import NullLocator

        ax.yaxis.set_minor_locator(NullLocator())
    set_title(ax, title)
    ax.grid(which="both", alpha=0.25)
    ax.legend(fontsize=8, loc="best")
    return save_figure(fig, path, fixed_margins(ax, top=WAVELENGTH_AXIS_TOP))


#: room above a wave-vector axes for its secondary wavelength axis (ticks and label) [in]
WAVELENGTH_AXIS_TOP = 0.62


def wavelength_axis(ax):
    """A secondary axis on top of a log wave-vector axis: wavelength 2 pi / q in mm
    (:func:`pipelines.output.units.add_wavelength_axis`), with plain tick labels."""
    from matplotlib.ticker import FuncFormatter

    from pipelines.output.units import add_wavelength_axis

    sec = add_wavelength_axis(ax)
    sec.xaxis.set_major_formatter(FuncFormatter(lambda x, pos: f"{x:g}"))
    sec.xaxis.set_minor_formatter(FuncFormatter(lambda x, pos: ""))
    sec.xaxis.set_major_locator(_in_view(sec.xaxis.get_major_locator()))
    sec.xaxis.set_minor_locator(_in_view(sec.xaxis.get_minor_locator()))
    sec.tick_params(labelsize=8)
    return sec


def _wrapped(label, width=48):
    """A legend entry broken over lines of at most ``width`` characters (a long rubber label
    otherwise runs over the axes and the y label)."""

    if not label:
        return label
    for unit in (" MPa", " kPa", " Pa", " °C", " m/s", " = "):   # a number stays with its unit
        label = label.replace(unit, unit.replace(" ", "\u00a0"))
    return "\n".join(textwrap.wrap(label, width))


def plot_mu(curves, path, title="friction coefficient", ylabel="friction coefficient μ [-]",
            logy=False):
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
    plain = logy          # no offset text above the y axis: the title stays where it is
    if logy:
        ax.set_yscale("log")
    else:                  # a nearly flat curve: a span of 10 %, ticks "0.58" and not "0.5925"
        ys = np.concatenate([np.asarray(c[2], float).ravel() for c in curves] or [np.zeros(0)])
        ys = ys[np.isfinite(ys)]
        big = float(np.abs(ys).max()) if ys.size else 0.0
        if big > 0 and np.ptp(ys) < 0.1 * big:
            mid = 0.5 * (ys.min() + ys.max())
            ax.set_ylim(mid - 0.05 * big, mid + 0.05 * big)
        plain = 1e-3 <= big < 1e4     # ticks spanning 10 % or more of values of this size
    ax.set_xlabel("sliding speed v [m/s]")
    ax.set_ylabel(ylabel)
    plain_log_ticks(ax)
    set_title(ax, title, y=1.0 if plain else None)
    ax.grid(which="both", alpha=0.25)
    if len(curves) > 1 or (curves and curves[0][0]):
        ax.legend(fontsize=8)
    return save_figure(fig, path, fixed_margins(ax))
