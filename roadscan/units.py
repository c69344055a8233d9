"""Lengths and numbers as a person reads them: three significant digits, a unit by size.

SI inside, the unit in the name (``mpd_m``); a message, warning or report says "3.28 mm",
"397 µm", "12.0 nm". One formatter for both layers: ``roadscan`` words its messages with it
and :mod:`pipelines.output.units` re-exports it for reports and figures.

>>> length(0.0032755905236328256)
'3.28 mm'
>>> length(0.0003974), length(0.06), length(1.80872)
('397 µm', '60.0 mm', '1.81 m')
>>> sig3(2530.4), sig3(0.000123), sig3(1.849e-05)
('2530', '0.000123', '1.85e-05')
>>> sig3(123456), sig3(999.7), sig3(0.5)
('123000', '1000', '0.500')
>>> lengths((5e-5, 5e-5))
'50.0 µm x 50.0 µm'
"""

from __future__ import annotations

import math
from collections.abc import Iterable

__all__ = ["LENGTH_UNITS", "sig3", "length", "lengths"]

#: (name, metres per unit), largest first: the units a length is shown in
LENGTH_UNITS = (("m", 1.0), ("mm", 1e-3), ("µm", 1e-6), ("nm", 1e-9))


def sig3(x: float | None, digits: int = 3) -> str:
    """``x`` to ``digits`` significant digits, trailing zeros kept.

    Plain notation for 1e-4 <= |x| < 1e6 ("2530", "0.0123", "3.28", "0.500"), scientific
    otherwise ("1.85e-05"); "—" for None, NaN or inf.

    Parameters
    ----------
    x : float or None
    digits : int
        Significant digits (the reports' convention is 3).

    Returns
    -------
    str
    """
    if x is None:
        return "—"
    x = float(x)
    if not math.isfinite(x):
        return "—"
    if x == 0:
        return "0"
    e = math.floor(math.log10(abs(x)))
    if not -4 <= e < 6:
        return f"{x:.{digits - 1}e}"
    decimals = digits - 1 - e
    r = round(x, decimals)
    if r != 0 and math.floor(math.log10(abs(r))) > e:  # 999.7 -> 1000: one decimal fewer
        decimals -= 1
        r = round(x, decimals)
    return f"{r:.{max(0, decimals)}f}"


def length(x_m: float | None, unit: str | None = None) -> str:
    """A length [m] as text: "1.81 m", "3.28 mm", "397 µm" or "12.0 nm".

    The unit is the largest of m, mm, µm, nm in which the value is at least 1 (after rounding
    to three significant digits), nm below; ``unit`` forces one of :data:`LENGTH_UNITS`.

    Parameters
    ----------
    x_m : float or None
        Length [m] (negative allowed: the sign is kept).
    unit : str or None
        "m", "mm", "µm" (or "um") or "nm".

    Returns
    -------
    str
        "—" for None, NaN or inf; "0 mm" for zero.
    """
    if x_m is None or not math.isfinite(float(x_m)):
        return "—"
    x = float(x_m)
    if x == 0 and unit is None:
        return "0 mm"
    if unit is None:
        unit, f = next(((u, f) for u, f in LENGTH_UNITS if abs(x) >= f * (1 - 5e-4)), LENGTH_UNITS[-1])
    else:
        unit = "µm" if unit == "um" else unit
        f = dict(LENGTH_UNITS)[unit]
    return f"{sig3(x / f)} {unit}"


def lengths(values_m: Iterable[float], sep: str = " x ") -> str:
    """Several lengths [m] joined: ``(5e-5, 5e-5)`` -> "50.0 µm x 50.0 µm".

    Parameters
    ----------
    values_m : iterable of float
        Lengths [m].
    sep : str, optional
        Separator.

    Returns
    -------
    str
    """
    return sep.join(length(v) for v in values_m)
