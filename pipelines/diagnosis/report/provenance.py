"""Provenance of a friction-level diagnosis: the model inputs it used, where they came from, and
which of them were assumed (``diagnosis.json`` key ``inputs``).

``inputs``: ``sigma0_Pa`` (nominal pressure [Pa], median over rows), ``q0_per_m`` and
``q1_per_m`` (the spectrum's band [1/m] the baseline integrates), ``temperature_C`` (background
temperature T0 [C], median over rows; the rubber's T_ref when none was given), ``psd_scale``
(factor on C(q), 1 nominal), ``files`` (each ``{role, path, sha256}``), ``assumed`` (names of
the keys above whose value was a default, not given), ``uncertain`` (per fitted input: its range
[SI] and whether it was given or a default) and ``notes``.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

__all__ = ["sha256", "file_entries", "inputs_json"]

KEYS = ("sigma0_Pa", "q0_per_m", "q1_per_m", "temperature_C", "psd_scale")


def sha256(path):
    """Hex SHA-256 of a file's bytes (streamed in 1 MiB chunks).

    Parameters
    ----------
    path : str or Path
        The file to hash.

    Returns
    -------
    str
        64 lowercase hex digits.
    """
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def file_entries(files):
    """[(role, path)] -> [{role, path, sha256}] for the files that exist.

    Parameters
    ----------
    files : iterable of tuple
        (role, path) pairs, e.g. ("psd", "psd.csv"); an empty path or a missing file is left out.

    Returns
    -------
    list of dict
        dict(role, path, sha256) per existing file, in the given order.
    """
    out = []
    for role, path in files:
        if path and Path(path).is_file():
            out.append(dict(role=role, path=str(path), sha256=sha256(path)))
    return out


def inputs_json(ctx, d, given=None):
    """The ``inputs`` dict of a diagnosis (``given``: dict with ``files`` [(role, path)] and
    ``given`` (names of :data:`KEYS` the user set); None: judged from the data alone).

    Parameters
    ----------
    ctx : FrictionContext
        The diagnosed context: its nominal inputs and spectrum band are reported.
    d : Diagnosis
        The diagnosis: its fitted uncertain ranges and cut-off sensitivity are reported.
    given : dict, optional
        Files and keys the user set.

    Returns
    -------
    dict
        The ``inputs`` entry of ``diagnosis.json`` (keys in the module docstring).
    """
    from pipelines.diagnosis.fit.calibration import nominal

    given = given or {}
    nom = nominal(ctx)
    psd = ctx.base.psd
    set_ = set(given.get("given", ()))
    T_rows = np.isfinite(ctx.T0_C).any()
    assumed = []
    if "sigma0_Pa" not in set_:
        assumed.append("sigma0_Pa")
    for k in ("q0_per_m", "q1_per_m", "psd_scale"):
        if k not in set_:
            assumed.append(k)
    if "temperature_C" not in set_ and not T_rows:
        assumed.append("temperature_C")
    unc = {}
    notes = []
    for k, u in (d.uncertain or {}).items():
        unc[k] = dict(range=[float(u.lo), float(u.hi)], source=u.source)
        if u.source == "default" and k == "q1":
            notes.append(
                f"q1 was not declared known and mu depends on it (carried by the spectrum's cut-off, or "
                f"a decade of q1 moves mu by more than the noise): q1 is uncertain "
                f"over a decade either side ({u.lo:.3g}..{u.hi:.3g} 1/m) by default"
            )
    if "temperature_C" in assumed:
        notes.append(f"T0 assumed: the rubber's reference temperature {nom['temperature']:.3g} C")
    if "sigma0_Pa" in assumed:
        notes.append(f"sigma0 assumed: the default {nom['sigma0']:.3g} Pa")
    return dict(
        sigma0_Pa=nom["sigma0"],
        q0_per_m=float(psd.q_min_per_m),
        q1_per_m=float(psd.q1_per_m),
        temperature_C=nom["temperature"],
        psd_scale=1.0,
        files=file_entries(given.get("files", ())),
        assumed=assumed,
        uncertain=unc,
        cutoff_sensitivity=d.cutoff_sensitivity,
        notes=notes,
        **({"scan_read": given["scan_read"]} if given.get("scan_read") else {}),
    )
