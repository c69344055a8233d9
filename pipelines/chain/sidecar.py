"""The band beside ``psd.csv``: ``psd_band.json``, what ``roadscan friction --psd psd.csv``
needs to integrate analyse's spectrum exactly as analyse did (the reliable band, its roll-off,
the self-affine fit that continues C(q) above the scan), written by ``roadscan analyse`` and
read back by ``roadscan friction``."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from pipelines.chain.steps import noise_floor_end

__all__ = ["band_sidecar", "read_band_sidecar", "BAND_SIDECAR_SUFFIX"]

BAND_SIDECAR_SUFFIX = "_band.json"


def band_sidecar(rb, fit, window_alpha):
    """What ``roadscan friction --psd psd.csv`` needs to integrate analyse's spectrum exactly as
    analyse did: the reliable band, its roll-off and the self-affine fit (for C(q) above the
    scan). Written as ``psd_band.json`` beside ``psd.csv``.

    Parameters
    ----------
    rb : ReliableBand
        The band.
    fit : SelfAffineFit
        The fit.
    window_alpha : float
        Tukey window.

    Returns
    -------
    dict
    """
    band = None
    if rb is not None and rb.valid:
        band = {
            "lo_per_m": float(rb.lo_per_m),
            "hi_per_m": float(rb.hi_per_m),
            "q_roll_per_m": rb.q_roll_per_m,
            "noise_floor_end": noise_floor_end(rb),
            "reasons": rb.reasons,
        }
    d = fit.as_dict()
    d = {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in d.items()}
    return {
        "about": "the band roadscan analyse integrated psd.csv over (q0 = lo, or the roll-off "
        "inside the band; q1 = hi) and its self-affine fit, which continues C(q) "
        "above the last row; read by roadscan friction --psd",
        "reliable_band": band,
        "fit": d,
        "window_alpha": window_alpha,
    }


def read_band_sidecar(psd_path):
    """(band-like object or None, SelfAffineFit) from the sidecar of ``psd_path``, or None
    when there is none. InputError naming the sidecar when it cannot be read.

    Parameters
    ----------
    psd_path : str or Path
        The ``psd.csv``.

    Returns
    -------
    tuple or None
    """

    from roadscan.errors import InputError
    from roadscan.fit import SelfAffineFit

    p = Path(psd_path)
    side = p.with_name(p.stem + BAND_SIDECAR_SUFFIX)
    if not side.is_file():
        return None
    try:  # the parser's own errors only: unreadable or not JSON
        d = json.loads(side.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(side, f"cannot read the band of {p.name} ({type(exc).__name__}: {exc})") from None
    problem = _sidecar_problem(d, [x.name for x in dataclasses.fields(SelfAffineFit)])
    if problem:
        raise InputError(side, f"cannot read the band of {p.name} ({problem})")
    f = dict(d["fit"])
    f["fit_band_per_m"] = tuple(f["fit_band_per_m"])
    f = {
        k: (float("nan") if v is None and k in ("h0_m", "band_rms_m", "hurst_stderr") else v)
        for k, v in f.items()
    }
    fit = SelfAffineFit(**f)
    b = d.get("reliable_band")
    rb = (
        None
        if b is None
        else SimpleNamespace(
            valid=True,
            lo_per_m=float(b["lo_per_m"]),
            hi_per_m=float(b["hi_per_m"]),
            q_roll_per_m=b.get("q_roll_per_m"),
            noise_floor_end=bool(b.get("noise_floor_end")),
        )
    )
    return rb, fit, side


def _number(x, none=False):
    return (x is None and none) or (isinstance(x, (int, float)) and not isinstance(x, bool))


def _sidecar_problem(d, fields):
    """What is wrong with the parsed JSON ``d`` of a band sidecar (:func:`band_sidecar`), or
    None: ``fit`` holds exactly the ``fields`` of the self-affine fit, numbers (or null) and
    ``fit_band_per_m`` two numbers; ``reliable_band`` is null or has numbers ``lo_per_m``,
    ``hi_per_m`` and ``q_roll_per_m`` a number or null."""
    f = d.get("fit") if isinstance(d, dict) else None
    if not isinstance(f, dict) or set(f) != set(fields):
        return "'fit' must hold " + ", ".join(fields)
    band = f["fit_band_per_m"]
    if not (isinstance(band, list) and len(band) == 2 and all(_number(x) for x in band)):
        return "'fit_band_per_m' must be two numbers"
    bad = [k for k, x in f.items() if k != "fit_band_per_m" and not _number(x, none=True)]
    if bad:
        return "not a number: " + ", ".join(bad)
    b = d.get("reliable_band")
    if b is not None and not (
        isinstance(b, dict)
        and _number(b.get("lo_per_m"))
        and _number(b.get("hi_per_m"))
        and _number(b.get("q_roll_per_m"), none=True)
    ):
        return "'reliable_band' must hold the numbers lo_per_m and hi_per_m"
    return None
