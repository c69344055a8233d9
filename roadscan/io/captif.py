"""CAPTIF stationary laser profiler (SLP) ``.dat`` line profiles, read as they are.

Layout (CAPTIF Road Research Centre, captif-slp project)::

    Road Name<TAB>CAPTIF<TAB>          <- header block: "key<TAB>value" lines
    ...
    *****DATA*****<TAB><TAB>
    Data Point No:<TAB>Distance (mm)<TAB>Depth (mm)
    1.000<TAB>0.000<TAB>-3.015         <- CRLF or LF line endings
    ...            NaN for a dropout

- Point numbers are not monotonic (the logger writes some pairs swapped); distances are.
  Points are sorted by distance and placed on the regular grid the distances sample
  (:func:`roadscan.io._common.regular_axis`: the distances are printed to 1 um, so 0.0375 mm
  steps appear as 0.037/0.038; the step is fitted by least squares over the whole line).
  Missing grid nodes and ``NaN`` depths become unmeasured points.
- Despite its name the "Depth" column is a height, positive up (the reference plates at the
  ends read about +47 mm); it is converted from mm to m with its sign kept.
- The header fields are kept in ``meta["header"]``; the file says mm: a contradicting ``units``
  follows :mod:`roadscan.io.calibration`.

A ``.dat`` file without the ``*****DATA*****`` marker is handed to the vendor reader
(SurfaceTopography: Zygo MetroPro ``.dat`` and its plain-text reader).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ._common import check_file, make_profile, regular_axis
from ._registry import register_reader

__all__ = ["read_captif", "is_captif"]

MARKER = b"*****DATA*****"


def is_captif(path):
    """True if the file's first 8 kB hold the ``*****DATA*****`` marker.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    bool
    """
    with open(path, "rb") as f:
        return MARKER in f.read(8192)


@register_reader(".dat")
def read_dat(path, spacing=None, units=None, channel=None):
    """Dispatch ``.dat``: CAPTIF SLP profile if it has the data marker, else a vendor format
    (``channel`` applies to the latter)."""
    check_file(path)
    if is_captif(path):
        if channel is not None:
            raise InputError(path, f"{{channel}} {channel}: a CAPTIF profile holds one channel", "channel")
        return read_captif(path, spacing=spacing, units=units)
    from .vendor import read_vendor, vendor_available

    if not vendor_available():
        raise InputError(
            path,
            "no '*****DATA*****' line: not a CAPTIF profile (other .dat "
            "formats need the optional extra: pip install 'roadscan[vendor]')",
        )
    try:
        return read_vendor(path, spacing=spacing, units=units, channel=channel)
    except InputError as exc:
        raise exc.reworded(
            path, "not a CAPTIF profile (no '*****DATA*****' line) nor a vendor .dat: "
        ) from None


def read_captif(path, spacing=None, units=None):
    """Read a CAPTIF SLP ``.dat`` file into a :class:`roadscan.Profile` (heights in m).

    Parameters
    ----------
    path : str or Path
        The ``.dat`` file.
    spacing : optional
        Only to check against the file's own (refused when it contradicts).
    units : optional
        Likewise for the height unit (mm).

    Returns
    -------
    Profile
        Heights [m], header in ``meta["header"]``.
    """
    p = check_file(path)
    text = p.read_bytes().decode("utf-8-sig", errors="replace")
    lines = text.splitlines()
    try:
        k = next(i for i, ln in enumerate(lines) if ln.strip().startswith("*****DATA*****"))
    except StopIteration:
        raise InputError(path, "no '*****DATA*****' line: not a CAPTIF profile") from None
    header = {}
    for ln in lines[:k]:
        parts = [s.strip() for s in ln.split("\t")]
        if parts and parts[0]:
            header[parts[0]] = parts[1] if len(parts) > 1 else ""
    if k + 1 >= len(lines):
        raise InputError(path, "no column titles after '*****DATA*****'")
    titles = [s.strip() for s in lines[k + 1].split("\t") if s.strip()]
    want = ["Data Point No:", "Distance (mm)", "Depth (mm)"]
    if titles != want:
        raise InputError(path, f"unexpected CAPTIF columns {titles}, expected {want}")
    rows = [ln for ln in lines[k + 2 :] if ln.strip()]
    if not rows:
        raise InputError(path, "no data rows after the column titles")
    try:
        data = np.array([ln.split("\t")[:3] for ln in rows], dtype=np.float64)
    except ValueError:
        for i, ln in enumerate(rows):
            parts = ln.split("\t")
            if len(parts) < 3:
                raise InputError(path, f"data row {i + 1} has {len(parts)} fields, expected 3") from None
            try:
                [float(s) for s in parts[:3]]
            except ValueError:
                raise InputError(path, f"non-numeric value in data row {i + 1}: {ln.strip()!r}") from None
        raise
    if data.ndim != 2 or data.shape[1] != 3:
        raise InputError(path, "data rows do not all have 3 fields")
    order = np.argsort(data[:, 1], kind="stable")
    data = data[order]
    dist_mm, depth_mm = data[:, 1], data[:, 2]
    x0, dx_mm, idx = regular_axis(dist_mm, path, "distance")
    h_mm = np.full(idx[-1] + 1, np.nan)
    h_mm[idx] = depth_mm
    meta = {
        "format": "CAPTIF SLP .dat",
        "units": "mm",
        "header": header,
        "x0_m": x0 * 1e-3,
        "rows": int(data.shape[0]),
        "missing_points": int(h_mm.size - data.shape[0]),
        "dropouts": int(np.isnan(depth_mm).sum()),
        "sign": "Depth column is height, positive up (kept as is)",
    }
    from ._common import resolve_spacing
    from .calibration import pick_spacing, pick_units

    f = pick_units(path, units, "mm", 1e-3, meta)
    sp = resolve_spacing(spacing, path)
    (dx_m,) = pick_spacing(path, None if sp is None else sp[:1], (dx_mm * 1e-3,), meta)
    return make_profile(path, h_mm * f, dx_m, meta=meta)
