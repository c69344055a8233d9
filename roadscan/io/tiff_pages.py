"""Which image of a TIFF holds the heights: pages, samples and palettes (``--channel``).

A TIFF may hold several images (pages: a stack, a time series, an ImageJ hyperstack), several
samples per pixel (RGB, RGBA, grey + alpha) or palette indices (colours looked up in a colour
map). None of these is a height map by itself, and picking the first silently is how a colour
picture of a surface comes out as "heights". The rule:

- one page of one sample, not a palette: read, ``channel`` may be 0 (or absent);
- several pages (reduced-resolution thumbnails not counted): ``channel`` = page index
  0..N-1, else refused;
- several samples per pixel: ``channel`` = sample index 0..S-1 (or ``r``/``g``/``b``/``a``),
  else refused;
- a palette-colour image: ``channel="index"`` reads the raw palette indices as heights, else
  refused (the colours are a rendering, not a measurement).

The choice is recorded in ``meta["channel"]`` (the value given) and ``meta["channel_note"]``.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["select_page", "select_sample"]

_PALETTE = 3
_SAMPLE_NAMES = {"r": 0, "red": 0, "g": 1, "green": 1, "b": 2, "blue": 2, "a": 3, "alpha": 3}
#: pages inspected for thumbnails at most (beyond: every page counts)
_MAX_SCAN = 4096


def _main_pages(tif):
    n = len(tif.pages)
    if n == 1:
        return [0]
    out = []
    for i in range(min(n, _MAX_SCAN)):
        page = tif.pages[i]
        if not getattr(page, "is_reduced", False):
            out.append(i)
    out.extend(range(_MAX_SCAN, n))
    return out


def select_page(path, tif, channel, meta):
    """The page to read. ``channel`` is None, an int or a str; fills ``meta``; the page's
    samples and palette are then checked by :func:`select_sample`.

    Parameters
    ----------
    path : str or Path
        File named in errors.
    tif : tifffile.TiffFile
        The open file.
    channel : int, str or None
        The choice.
    meta : dict
        Reader metadata (updated).

    Returns
    -------
    page : tifffile.TiffPage
    channel_left : int, str or None
        What of ``channel`` remains to choose a sample.
    """
    pages = _main_pages(tif)
    if len(pages) == 1:
        return tif.pages[pages[0]], channel
    if channel is None:
        raise InputError(
            path,
            f"holds {len(pages)} images (pages: a stack or series), not one "
            f"height map: choose one with {{channel}} 0..{len(pages) - 1}",
            "channel",
        )
    if not isinstance(channel, int) or not 0 <= channel < len(pages):
        raise InputError(
            path,
            f"{{channel}} {channel}: choose a page 0..{len(pages) - 1} of the {len(pages)} in this TIFF",
            "channel",
        )
    meta["channel"] = channel
    meta["channel_note"] = f"page {channel} of {len(pages)}"
    return tif.pages[pages[channel]], None


def select_sample(path, page, arr, channel, meta):
    """The 2D height array of ``arr`` (the page's data) given what is left of ``channel``
    after :func:`select_page` (None when the page was chosen by it).

    Parameters
    ----------
    path : str or Path
        File named in errors.
    page : tifffile.TiffPage
        The page.
    arr : ndarray
        Its data.
    channel : int, str or None
        What is left of the choice.
    meta : dict
        Reader metadata (updated).

    Returns
    -------
    ndarray, shape (ny, nx)
    """
    samples = int(getattr(page, "samplesperpixel", 1) or 1)
    palette = int(getattr(page, "photometric", 0) or 0) == _PALETTE
    chosen_page = "channel" in meta
    if samples > 1:
        if channel is None:
            where = f"page {meta['channel']} " if chosen_page else ""
            raise InputError(
                path,
                f"{where}is a colour or multi-sample image ({samples} samples per "
                f"pixel: RGB, alpha...), not heights: choose one with {{channel}} "
                f"0..{samples - 1}"
                + ("" if not chosen_page else " (pages of colour images are not supported)"),
                "channel",
            )
        k = _SAMPLE_NAMES.get(channel.lower(), channel) if isinstance(channel, str) else channel
        if not isinstance(k, int) or not 0 <= k < samples:
            raise InputError(
                path,
                f"{{channel}} {channel}: choose a sample 0..{samples - 1} of the {samples} per pixel",
                "channel",
            )
        axes = str(getattr(page, "axes", ""))
        ax = axes.index("S") if "S" in axes else arr.ndim - 1
        meta["channel"] = channel
        meta["channel_note"] = f"sample {k} of {samples} per pixel"
        return np.take(arr, k, axis=ax)
    if palette:
        if channel != "index":
            raise InputError(
                path,
                "is a palette-colour image (colours looked up in a colour map, "
                "not heights); {channel} index reads its raw palette indices "
                "as heights",
                "channel",
            )
        meta["channel"] = "index"
        meta["channel_note"] = "raw palette indices"
        return arr
    if channel is not None and channel != 0:
        raise InputError(
            path,
            f"{{channel}} {channel}: this TIFF holds one height image ({{channel}} 0 or none)",
            "channel",
        )
    if channel == 0 and not chosen_page:
        meta["channel"] = 0
        meta["channel_note"] = "the only image"
    return arr
