"""Inputs of the friction-level diagnosis: the surface (a scan or a psd.csv) and the rubber,
assembled into a :class:`model.FrictionContext`.

``psd.csv``: header with columns ``q_per_m`` [1/m] and ``C_m4`` [m^4] (Persson's normalisation,
as written by ``roadscan analyse``); rows with C <= 0 are dropped. The engine integrates it from
its lowest to its highest q (DESIGN.md sec 5).
"""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from roadscan.errors import InputError

from .model import FrictionContext, SimSpec

__all__ = ["read_psd_csv", "write_psd_csv", "surface_from_scan", "build_context"]


def read_psd_csv(path):
    """Read ``q_per_m,C_m4`` -> friction.TabulatedPSD (InputError on bad input)."""
    from friction import TabulatedPSD

    path = Path(path)
    if not path.exists():
        raise InputError(path, "no such file")
    try:
        rows = list(csv.reader(l for l in path.read_text(encoding="utf-8-sig").splitlines()
                               if l.strip() and not l.lstrip().startswith("#")))
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(path, f"cannot read ({exc})") from None
    if not rows:
        raise InputError(path, "empty file, expected a header q_per_m,C_m4")
    head = [h.strip() for h in rows[0]]
    if "q_per_m" not in head or "C_m4" not in head:
        raise InputError(path, f"missing column q_per_m or C_m4 (header is {','.join(head)!r})")
    iq, ic = head.index("q_per_m"), head.index("C_m4")
    try:
        data = np.array([[float(r[iq]), float(r[ic])] for r in rows[1:]], float)
    except (ValueError, IndexError):
        raise InputError(path, "non-numeric or missing q_per_m/C_m4 values") from None
    if data.size == 0:
        raise InputError(path, "no data rows")
    q, C = data[:, 0], data[:, 1]
    ok = np.isfinite(q) & np.isfinite(C) & (q > 0) & (C > 0)
    q, C = q[ok], C[ok]
    o = np.argsort(q)
    q, C = q[o], C[o]
    if q.size < 4 or np.any(np.diff(q) <= 0):
        raise InputError(path, "need at least 4 rows with distinct positive q and positive C")
    return TabulatedPSD(q, C)


def write_psd_csv(path, q_per_m, C_m4):
    from ..report import write_csv

    return write_csv(path, ["q_per_m", "C_m4"], [q_per_m, C_m4])


def surface_from_scan(obj):
    """Analyse a scan -> (friction PSD, filled HeightMap/Profile, Spectrum, fit)."""
    from ..spectrum_bridge import analyse_surface, surface_psd

    an = analyse_surface(obj)
    return surface_psd(an.spectrum, an.fit), an.filled, an.spectrum, an.fit


def build_context(curve, psd, rubber=None, scan=None, spectrum=None, fit=None, extra_inputs=()):
    """The baseline model (engine defaults of DESIGN.md sec 5) on the rows of ``curve``."""
    import friction

    from roadscan.heightmap import HeightMap

    rubber = friction.thesis_rubber() if rubber is None else rubber
    inputs = {"psd", "rubber"} | set(extra_inputs)
    if isinstance(scan, HeightMap):
        inputs.add("scan")
    return FrictionContext.from_measured(curve, SimSpec(psd=psd, rubber=rubber), scan=scan,
                                         spectrum=spectrum, fit=fit, inputs=inputs)
