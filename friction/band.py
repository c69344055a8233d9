"""The integration band [q0, q1] of Persson's integrals within a tabulated spectrum.

Persson's program integrates ``mu = 1/2 int_{q0}^{q1} dq q^3 C(q) S(q) P(q) M(q)`` (and G, P
over the same band): q0 is the lowest wave vector of the rough surface taken into account
(usually the roll-off) and q1 the cut-off (the smallest asperities that matter). A measured
spectrum usually covers a different band. :func:`integration_band` returns the spectrum
restricted (or extended) to exactly [q0, q1]:

* inside the table, C is interpolated linearly in (log q, log C) (the table's own rule);
* above the last tabulated point, C continues as the power law fitted to the top decade of
  the table (:class:`friction.TabulatedPSD`), i.e. self-affine roughness below the scan's
  resolution; the result says how far (``extended_decades``);
* q0 must lie inside the table: the spectrum is never extrapolated towards long wavelengths.

Conventions: q in 1/m, C in m^4 (Persson's normalisation, ``<h^2> = 2 pi int q C dq``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .psd import TabulatedPSD

__all__ = ["integration_band", "band_problem"]

_REL = 1e-6  # relative slack on q comparisons (rounded numbers typed on a command line)


def _ends(psd, q0_per_m, q1_per_m, q0_slack):
    """(q0, q1, reason): the band's ends as :func:`integration_band` takes them, reason None
    when they make a band."""
    qt = psd.q_per_m
    q0 = float(qt[0]) if q0_per_m is None else float(q0_per_m)
    q1 = float(psd.q1_per_m) if q1_per_m is None else float(q1_per_m)
    if not (np.isfinite(q0) and q0 > 0 and np.isfinite(q1) and q1 > 0):
        return q0, q1, "q0 and q1 must be positive wave vectors [1/m]"
    if q0 < qt[0] * (1 - _REL):
        if q0 < qt[0] * (1 - q0_slack):
            return (
                q0,
                q1,
                (
                    f"q0 = {q0:.6g} 1/m is below the spectrum's lowest wave vector "
                    f"{qt[0]:.6g} 1/m (the spectrum is not extrapolated to long wavelengths)"
                ),
            )
        q0 = float(qt[0])
    if not q1 > q0 * (1 + _REL):
        return q0, q1, f"need q0 < q1 (q0 = {q0:.6g}, q1 = {q1:.6g} 1/m)"
    return q0, q1, None


def band_problem(
    psd: TabulatedPSD, q0_per_m: float | None = None, q1_per_m: float | None = None, q0_slack: float = 0.01
) -> str | None:
    """Why ``[q0, q1]`` makes no integration band for ``psd`` (one line), or None when it does:
    the check :func:`integration_band` applies, for callers that report bad input before the
    computation.

    Parameters
    ----------
    psd : TabulatedPSD
        The spectrum.
    q0_per_m, q1_per_m : float or None
        Band ends [1/m] (None: the table's).
    q0_slack : float, optional
        As in :func:`integration_band`.

    Returns
    -------
    str or None
    """
    return _ends(psd, q0_per_m, q1_per_m, q0_slack)[2]


def integration_band(
    psd: TabulatedPSD, q0_per_m: float | None = None, q1_per_m: float | None = None, q0_slack: float = 0.01
) -> tuple[TabulatedPSD, dict[str, Any]]:
    """The spectrum on exactly ``[q0, q1]`` (see module docstring).

    Parameters
    ----------
    psd : TabulatedPSD
    q0_per_m : float or None
        Lower end [1/m]; None keeps the table's lowest q. A q0 below the lowest tabulated q by
        less than ``q0_slack`` (relative) is taken as the lowest q; further below is an error.
    q1_per_m : float or None
        Upper end [1/m]; None keeps the table's q1. Above the last tabulated point the fitted
        power law continues the table.

    Returns
    -------
    (TabulatedPSD, dict)
        The table's nodes strictly inside (q0, q1) plus the two ends, with ``q0_per_m`` = q0
        (so the macro-asperity wave vector of the flash model is ``zeta_m q0``); and a dict:
        ``q0_per_m``, ``q1_per_m``, ``q_table_min_per_m``, ``q_table_max_per_m``,
        ``extended_decades`` (log10 of q1 over the last tabulated q, 0 when inside),
        ``tail_exponent`` (C ~ q^exponent above the table; None when not extended).

    Raises
    ------
    ValueError with a one-line reason (q0 below the table, q0 >= q1, non-positive values).
    """
    if not isinstance(psd, TabulatedPSD):
        raise TypeError("integration_band needs a TabulatedPSD")
    qt = psd.q_per_m
    q0, q1, problem = _ends(psd, q0_per_m, q1_per_m, q0_slack)
    if problem is not None:
        raise ValueError(problem)
    ext = psd.with_q1(max(q1, float(qt[-1])))
    inner = qt[(qt > q0 * (1 + _REL)) & (qt < q1 * (1 - _REL))]
    q = np.concatenate([[q0], inner, [q1]])
    C = ext.C(q)
    extended = q1 > qt[-1] * (1 + _REL)
    info = dict(
        q0_per_m=q0,
        q1_per_m=q1,
        q_table_min_per_m=float(qt[0]),
        q_table_max_per_m=float(qt[-1]),
        extended_decades=float(np.log10(q1 / qt[-1])) if extended else 0.0,
        tail_exponent=float(psd.tail_exponent) if extended else None,
    )
    return TabulatedPSD(q, C, q0_per_m=q0, q1_per_m=q1), info
