"""A long line profile cut into sections of fixed length along chainage, in bounded memory.

Road authorities report texture per section of the lane (typically MPD per 10 m). Section k
covers ``[x_first + k L, x_first + (k+1) L)`` where ``x_first`` is the profile's first sample
and L the section length [m]; its chainage is the profile's chainage (manifest, else 0) plus
``k L``. A trailing remainder is a section of its own when it is at least one ISO 13473-1
segment (100 mm) long, otherwise dropped (a whole profile shorter than that is one section).

Reading in chunks (memory holds one chunk plus one section, whatever the file's length):

- ``.npy`` 1D arrays: memory-mapped; ``--spacing`` required (the file has none);
- CAPTIF SLP ``.dat``: streamed line by line after the ``*****DATA*****`` block (distance and
  depth in mm, as :mod:`roadscan.io.captif`);
- text ``x,z`` profiles (``.txt``, ``.csv``, ``.xyz``, ``.asc``): streamed; units from a
  column-title line such as ``distance (mm), height (mm)``, else x in metres and z in
  ``--units`` (as :mod:`roadscan.io.ascii_text`); a 1-column text profile needs ``--spacing``.

Any other format is read whole by the ordinary reader, then cut (memory: the whole profile).
Within a section the x values are placed on a regular grid by
:func:`roadscan.io._common.regular_axis` (missing nodes become unmeasured points), exactly as the
whole-file readers do; ``--spacing`` overrides the step.
"""

from __future__ import annotations

import io
import itertools
from pathlib import Path

import numpy as np

from roadscan.errors import InputError
from roadscan.heightmap import Profile

__all__ = ["iter_sections", "MIN_SECTION_M", "CHUNK_ROWS"]

MIN_SECTION_M = 0.1  # one ISO 13473-1 segment
CHUNK_ROWS = 1 << 16  # text rows parsed at a time
_TEXT = {".txt", ".csv", ".xyz", ".asc", ".dat"}


def _numeric(tokens):
    try:
        [float(t) for t in tokens]
        return bool(tokens)
    except ValueError:
        return False


def _split(line):
    return line.replace(",", " ").replace(";", " ").split()


def _chunks(fh, ncol, usecols, path, first_lineno):
    """Parsed (rows, len(usecols)) float arrays from the data lines of an open text file."""
    lineno = first_lineno
    while True:
        lines = [ln for ln in itertools.islice(fh, CHUNK_ROWS)]
        if not lines:
            return
        text = "".join(ln for ln in lines if ln.strip() and not ln.lstrip().startswith("#"))
        text = text.replace(",", " ").replace(";", " ")
        try:
            arr = np.loadtxt(io.StringIO(text), ndmin=2, usecols=usecols, dtype=np.float64)
        except ValueError as exc:
            raise InputError(path, f"bad data line near line {lineno}: {exc}") from None
        lineno += len(lines)
        if arr.size:
            yield arr


def _text_points(path, units):
    """(x [m] or None, z [m]) chunks of a text profile, plus its x factor; see module doc."""
    from roadscan.io._common import parse_units, unit_factor
    from roadscan.io.text_table import column_units

    zf = unit_factor(units, path)
    fh = open(path, encoding="utf-8-sig", errors="replace")
    header, lineno = [], 0
    for line in fh:
        lineno += 1
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        toks = _split(s)
        if _numeric(toks):
            break
        header.append(s)
    else:
        fh.close()
        raise InputError(path, "no numeric data lines")
    ncol = len(toks)
    if ncol > 2:
        fh.close()
        return None
    titles = column_units(header[-1]) if header else None
    factors = [parse_units(t, path) for t in titles] if titles and len(titles) == ncol else None
    if factors is None:
        factors = [1.0, zf] if ncol == 2 else [zf]
    first = np.array([float(t) for t in toks], float)[None, :]

    def gen():
        try:
            for arr in itertools.chain([first], _chunks(fh, ncol, None, path, lineno)):
                if arr.shape[1] != ncol:
                    raise InputError(path, f"rows have {arr.shape[1]} columns, expected {ncol}")
                if ncol == 2:
                    yield arr[:, 0] * factors[0], arr[:, 1] * factors[1]
                else:
                    yield None, arr[:, 0] * factors[0]
        finally:
            fh.close()

    return gen()


def _captif_points(path):
    fh = open(path, encoding="utf-8-sig", errors="replace")
    lineno = 0
    for line in fh:
        lineno += 1
        if line.strip().startswith("*****DATA*****"):
            break
    titles = [s.strip() for s in fh.readline().split("\t") if s.strip()]
    want = ["Data Point No:", "Distance (mm)", "Depth (mm)"]
    if titles != want:
        fh.close()
        raise InputError(path, f"unexpected CAPTIF columns {titles}, expected {want}")

    def gen():
        try:
            for arr in _chunks(fh, 3, (1, 2), path, lineno + 2):
                yield arr[:, 0] * 1e-3, arr[:, 1] * 1e-3
        finally:
            fh.close()

    return gen()


def _grid_section(x, z, dx_override, path, name, start_m):
    """Points of one section -> Profile on a regular grid (missing nodes unmeasured)."""
    from roadscan.io._common import regular_axis

    if x is None:
        return Profile(z, dx_override, name=name, meta={"section_start_m": start_m})
    if dx_override is not None:
        idx = np.rint((x - x[0]) / dx_override).astype(np.int64)
        if np.any(np.diff(idx) < 1):
            raise InputError(path, f"x values closer than --spacing near {start_m:.3f} m")
        dx = dx_override
    else:
        _, dx, idx = regular_axis(x, path, "x")
    h = np.full(idx[-1] + 1, np.nan)
    h[idx] = z
    return Profile(h, dx, name=name, meta={"section_start_m": start_m})


def _cut_points(chunks, L, dx_override, path, stem):
    """Sections from (x, z) chunks with x increasing (x None: regular samples dx_override)."""
    bx, bz = [], []  # buffered points of the current section
    x_first, k, count = None, 0, 0
    last_x = -np.inf
    for x, z in chunks:
        if x is None:  # regular samples: synthesize x
            x = (count + np.arange(z.size)) * dx_override
            xfree = True
        else:
            xfree = False
            if not np.all(np.isfinite(x)):
                raise InputError(path, "x column contains NaN")
            if x[0] <= last_x or np.any(np.diff(x) <= 0):
                raise InputError(
                    path, "x values are not increasing (a long profile is read in order; sort the file)"
                )
        count += z.size
        last_x = x[-1]
        if x_first is None:
            x_first = x[0]
        while True:
            end = x_first + (k + 1) * L
            j = int(np.searchsorted(x, end, side="left"))
            if j >= x.size:
                bx.append(x), bz.append(z)
                break
            bx.append(x[:j]), bz.append(z[:j])
            sx, sz = np.concatenate(bx), np.concatenate(bz)
            if sx.size >= 4:
                yield (
                    k * L,
                    _grid_section(None if xfree else sx, sz, dx_override, path, f"{stem}@{k * L:g}m", k * L),
                )
            x, z = x[j:], z[j:]
            bx, bz = [], []
            k += 1
    if bx:
        sx, sz = np.concatenate(bx), np.concatenate(bz)
        length = (sx[-1] - sx[0]) + (dx_override or (np.median(np.diff(sx)) if sx.size > 1 else 0))
        if sx.size >= 4 and (length >= MIN_SECTION_M * (1 - 1e-9) or k == 0):
            yield (
                k * L,
                _grid_section(None if xfree else sx, sz, dx_override, path, f"{stem}@{k * L:g}m", k * L),
            )


def _array_sections(h, dx, L, stem, unmeasured=None):
    n = max(1, int(round(L / dx)))
    total = h.shape[0]
    for k, i in enumerate(range(0, total, n)):
        seg = np.array(h[i : i + n], dtype=np.float64)  # a copy: one section in memory
        bad = None if unmeasured is None else np.array(unmeasured[i : i + n], dtype=bool)
        if k > 0 and seg.size * dx < MIN_SECTION_M * (1 - 1e-9):
            break
        if seg.size >= 4:
            yield k * L, Profile(seg, dx, bad, name=f"{stem}@{k * L:g}m", meta={"section_start_m": k * L})


def iter_sections(path, section_m, spacing=None, units=None):
    """Yield ``(start_m, Profile)`` for each section of the line profile in ``path``.

    ``start_m`` is the section's start relative to the profile's first sample [m]. Raises
    InputError when the file is not a line profile or cannot be read.

    Parameters
    ----------
    path : str or Path
        A line-profile file.
    section_m : float
        Section length [m].
    spacing, units : optional
        As the readers take them.

    Yields
    ------
    start_m : float
        Section start [m].
    profile : Profile
        The section.
    """
    from roadscan.io._common import check_file, resolve_spacing, unit_factor

    path = Path(path)
    check_file(path)
    if not section_m > 0:
        raise InputError(None, f"--section-length {section_m}: must be positive (metres)")
    sp = resolve_spacing(spacing, path) if spacing is not None else None
    dx_override = sp[0] if sp is not None else None
    stem, suffix = path.stem, path.suffix.lower()
    chunks = None
    if suffix == ".npy":
        try:
            arr = np.load(path, mmap_mode="r", allow_pickle=False)
        except (ValueError, OSError) as exc:
            raise InputError(path, f"not a readable NumPy file ({exc})") from None
        if arr.ndim != 1:
            raise InputError(path, f"--section-length needs a line profile, got a {arr.ndim}D array")
        if dx_override is None:
            from roadscan.io._common import NO_SPACING

            raise InputError(path, NO_SPACING)
        factor = unit_factor(units, path)
        if factor != 1.0:
            yield from (
                (s, p.with_heights(p.heights_m * factor))
                for s, p in _array_sections(arr, dx_override, section_m, stem)
            )
        else:
            yield from _array_sections(arr, dx_override, section_m, stem)
        return
    if suffix == ".dat":
        from roadscan.io.captif import is_captif

        if is_captif(path):
            chunks = _captif_points(path)
    elif suffix in _TEXT:
        chunks = _text_points(path, units)
        if chunks is not None and dx_override is None:
            first = next(chunks)
            if first[0] is None:
                from roadscan.io._common import NO_SPACING

                raise InputError(path, NO_SPACING)
            chunks = itertools.chain([first], chunks)
    if chunks is not None:
        yield from _cut_points(chunks, section_m, dx_override, path, stem)
        return
    from pipelines.settings.scan_input import load_scan

    obj = load_scan(path, spacing=spacing, units=units)
    if not isinstance(obj, Profile):
        raise InputError(path, "--section-length needs a line profile, this file is an area scan")
    yield from _array_sections(obj.heights_m, obj.dx_m, section_m, stem, obj.unmeasured)
