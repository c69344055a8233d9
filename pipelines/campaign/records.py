"""Campaign records: the small dicts a worker returns for each scan or section.

``record = {"file", "label", "chainage_m", "status", "error", "dir", "values", "mu_at"}``:
``values`` holds the scalars of ``summary.json`` flattened by :func:`flatten_summary`;
``mu_at`` maps a few report speeds [m/s] to mu (for ``report.html``).

Flattening (the column names of ``campaign.csv``): top-level scalar keys keep their names
(``hurst``, ``rms_height_m``, ``mpd_m``...); ``warnings`` is one column, the scan's warnings
joined by " | "; a nested dict's scalars are joined with a dot
(``roughness.Sq_m``, ``friction.mu_peak``, ``anisotropy.ratio``); a list of scalars gives one
column per element with its index (``fit_band_per_m.0``, ``fit_band_per_m.1``,
``shape.0``...). Nothing else is dropped: every scalar of ``summary.json`` has a column
(the anisotropy sectors in ``campaign_anisotropy.csv``, see :mod:`.table`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["flatten_summary", "ok_record", "error_record", "REPORT_SPEEDS_M_PER_S", "mu_at_speeds"]

# speeds at which report.html shows mu [m/s]: a slow slide, a walking pace, a braking car
REPORT_SPEEDS_M_PER_S = (1e-2, 1.0, 30.0)


def _scalar(v):
    return v is None or isinstance(v, (bool, int, float, str, np.generic))


def _plain(v):
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not np.isfinite(v):
        return None
    return v


def flatten_summary(summary, prefix=""):
    """``summary.json`` dict -> flat {column: scalar} (see module docstring).

    Parameters
    ----------
    summary : dict
        A ``summary.json``.
    prefix : str, optional
        Prefix of the keys.

    Returns
    -------
    dict
    """
    out = {}
    for key, v in summary.items():
        name = f"{prefix}{key}"
        if isinstance(v, dict):
            out.update(flatten_summary(v, prefix=name + "."))
        elif isinstance(v, (list, tuple)):
            if all(_scalar(x) for x in v):
                for i, x in enumerate(v):
                    out[f"{name}.{i}"] = _plain(x)
            else:
                for i, x in enumerate(v):
                    if isinstance(x, dict):
                        out.update(flatten_summary(x, prefix=f"{name}.{i}."))
        elif _scalar(v):
            out[name] = _plain(v)
    return out


def mu_at_speeds(v_m_per_s, mu, speeds=REPORT_SPEEDS_M_PER_S):
    """mu interpolated linearly in log10 v at ``speeds`` (None outside the computed range).

    Parameters
    ----------
    v_m_per_s, mu : array_like
        The friction curve.
    speeds : tuple of float, optional
        Speeds [m/s].

    Returns
    -------
    dict
        Speed -> mu or None.
    """
    v, mu = np.asarray(v_m_per_s, float), np.asarray(mu, float)
    out = {}
    for s in speeds:
        ok = v.size > 1 and v[0] <= s <= v[-1]
        out[f"{s:g}"] = float(np.interp(np.log10(s), np.log10(v), mu)) if ok else None
    return out


#: list keys of summary.json kept out of campaign.csv's columns (the warnings go into one
#: ``warnings`` column, joined by " | "; the per-speed shares stay in each scan's mu.csv)
_LIST_COLUMNS_DROPPED = ("warnings.", "friction.extrapolated_share.")


def ok_record(job, summary, subdir, mu_at=None, extra=None, chainage_m=None):
    """The campaign row of a scan analysed without error.

    Parameters
    ----------
    job : dict
        The job.
    summary : dict
        Its summary.
    subdir : str
        Its output folder.
    mu_at : dict, optional
        mu at the report speeds.
    extra : dict, optional
        More columns.
    chainage_m : float, optional
        Chainage [m].

    Returns
    -------
    dict
    """
    values = dict(extra or {})
    flat = flatten_summary(summary)
    values.update({k: v for k, v in flat.items() if not k.startswith(_LIST_COLUMNS_DROPPED)})
    values["warnings"] = " | ".join(summary.get("warnings") or [])
    return {
        "file": job["file"],
        "label": job.get("label") or "",
        "chainage_m": job.get("chainage_m") if chainage_m is None else chainage_m,
        "status": "ok",
        "error": "",
        "dir": subdir,
        "values": values,
        "mu_at": mu_at or {},
    }


def error_record(job, message, subdir=None, extra=None, chainage_m=None):
    """The campaign row of an input that failed (``status=error`` and the one-line ``error``).

    Parameters
    ----------
    job : dict
        The job.
    message : str
        The error.
    subdir : str, optional
        Its output folder.
    extra : dict, optional
        More columns.
    chainage_m : float, optional
        Chainage [m].

    Returns
    -------
    dict
    """
    msg = " ".join(str(message).split()) or "failed"
    return {
        "file": job["file"],
        "label": job.get("label") or "",
        "chainage_m": job.get("chainage_m") if chainage_m is None else chainage_m,
        "status": "error",
        "error": msg,
        "dir": subdir,
        "values": dict(extra or {}),
        "mu_at": {},
    }
