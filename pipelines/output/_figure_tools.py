"""The tools every figure of roadscan uses: ``pyplot`` on the Agg backend (imported on first
use), log axes labelled in plain Unicode, wrapped titles, fixed margins, a wavelength axis over a
wave-vector axis, the display image of a large map, and the atomic PNG save.

:mod:`pipelines.output.report` re-exports every name here and draws the figures two jobs share
with them; call them through it (``report.save_figure``), where a test may replace them.
"""

from __future__ import annotations

import os
import re
import sys
import textwrap
from pathlib import Path

import numpy as np

from roadscan.io.atomic import atomic_path

# Figures are files, never windows: the Agg backend. matplotlib itself (0.3 to 1 s to import)
# is loaded only when a figure is drawn (--no-figures, CSV/JSON-only runs and --help
# do without it); until then the backend is chosen through the environment.
if "matplotlib" in sys.modules:
    sys.modules["matplotlib"].use("Agg")
else:
    os.environ["MPLBACKEND"] = "Agg"

__all__ = [
    "pyplot",
    "save_figure",
    "fixed_margins",
    "set_title",
    "plain_log_ticks",
    "wavelength_axis",
    "display_image",
    "FIGSIZE",
    "DPI",
    "PNG_COMPRESSION",
    "DISPLAY_POINTS",
    "WAVELENGTH_AXIS_TOP",
]

FIGSIZE = (6.4, 4.4)
DPI = 120
#: zlib level of the PNGs: 3 writes them in half the time of the default 6, 5 % larger
PNG_COMPRESSION = 3
#: a height map is shown as block means with at least this many points along its longer side
#: (more than the axes have pixels at ``FIGSIZE`` and ``DPI``); the data are not changed
DISPLAY_POINTS = 500
#: room above a wave-vector axes for its secondary wavelength axis (ticks and label) [in]
WAVELENGTH_AXIS_TOP = 0.62


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
            if type(fmt) is LogFormatterSciNotation:  # the log scale's own: same settings
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
    parts = []  # the memory used is a band's
    for r in range(0, data.shape[0], step):
        band = data[r : r + step]
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

    nb = "\u00a0"  # textwrap breaks only at ASCII whitespace
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
        fig.subplots_adjust(
            left=margins["left"] / w,
            right=1 - margins["right"] / w,
            bottom=margins["bottom"] / h,
            top=1 - margins["top"] / h,
        )
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=DPI, format="png", pil_kwargs={"compress_level": PNG_COMPRESSION})
    plt.close(fig)
    return Path(path)


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
