"""Numbers in the reader's units for reports and figure labels.

:func:`sig3` and :func:`length` are :mod:`roadscan.units`' (one formatter for both layers);
this module adds the report's other quantities (dB, km/h, 1/m with its wavelength, Pa, °C).

Files keep SI with the unit in the name (``mpd_m``, ``rms_height_m``); what a person reads
says "3.28 mm", "397 µm", "45.3 dB": three significant digits, no exponent between 1e-3 and
1e6, a unit a road engineer uses (heights and lengths in m, mm, µm or nm by size).

>>> length(0.0032755905236328256)
'3.28 mm'
>>> length(0.0003974)
'397 µm'
>>> length(2.53e-3), length(1.80872)
('2.53 mm', '1.81 m')
>>> sig3(2530.4), sig3(0.000123), sig3(1.849e-05)
('2530', '0.000123', '1.85e-05')
>>> sig3(123456), sig3(999.7), sig3(0.5)
('123000', '1000', '0.500')
"""

from __future__ import annotations

import math

from roadscan.units import LENGTH_UNITS, length, sig3

__all__ = [
    "sig3",
    "length",
    "height",
    "wavelength_of_q",
    "decibel",
    "speed_kmh",
    "quantity",
    "label_of",
    "add_wavelength_axis",
]

_LENGTH_UNITS = LENGTH_UNITS


def height(x_m):
    """A height [m]: mm from 1 mm, µm below (as :func:`length`, never metres below 1 m).

    Parameters
    ----------
    x_m : float
        Height [m].

    Returns
    -------
    str
    """
    return length(x_m)


def wavelength_of_q(q_per_m):
    """The wavelength 2 pi / q of a wave vector [1/m], as a length.

    Parameters
    ----------
    q_per_m : float
        Wave vector [1/m].

    Returns
    -------
    str
    """
    if q_per_m is None or not float(q_per_m) > 0:
        return "—"
    return length(2 * math.pi / float(q_per_m))


def decibel(x):
    """A level in dB with one decimal ("45.3 dB").

    Parameters
    ----------
    x : float or None
        Level [dB].

    Returns
    -------
    str
    """
    if x is None or not math.isfinite(float(x)):
        return "—"
    return f"{float(x):.1f} dB"


def speed_kmh(x):
    """A speed in km/h with three significant digits.

    Parameters
    ----------
    x : float or None
        Speed [km/h].

    Returns
    -------
    str
    """
    return "—" if x is None else f"{sig3(x)} km/h"


#: key suffix -> (label suffix removed, formatter)
_SUFFIXES = (
    ("_per_m", lambda v: f"{sig3(v)} 1/m (λ = {wavelength_of_q(v)})"),
    ("_m_per_s", lambda v: f"{sig3(v)} m/s"),
    ("_dB", decibel),
    ("_kmh", speed_kmh),
    ("_Pa", lambda v: f"{sig3(v / 1e6)} MPa" if abs(v) >= 1e5 else f"{sig3(v)} Pa"),
    ("_C", lambda v: f"{sig3(v)} °C"),
    ("_m", length),
)


def quantity(key, value):
    """A summary value formatted by its key's unit suffix (``mpd_m`` -> "3.28 mm",
    ``q_roll_per_m`` -> "1.2e+03 1/m (λ = 5.2 mm)"); lists element by element; other numbers
    to three significant digits; text as is.

    Parameters
    ----------
    key : str
        Summary key with its unit suffix.
    value : object
        Its value.

    Returns
    -------
    str
    """
    if isinstance(value, (list, tuple)):
        return ", ".join(quantity(key, v) for v in value)
    if value is None:
        return "—"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return str(value)
    if not math.isfinite(float(value)):
        return "—"
    for suffix, fmt in _SUFFIXES:
        if key.endswith(suffix):
            return fmt(float(value))
    return sig3(value)


def label_of(key):
    """A key without its unit suffix, underscores as spaces (``rms_height_m`` -> "rms height").

    Parameters
    ----------
    key : str
        Summary key.

    Returns
    -------
    str
    """
    for suffix, _ in _SUFFIXES:
        if key.endswith(suffix) and len(key) > len(suffix):
            key = key[: -len(suffix)]
            break
    return key.replace("_", " ")


def add_wavelength_axis(ax, label="wavelength λ = 2π/q [mm]"):
    """A secondary x axis on a log wave-vector axis [1/m]: lambda = 2 pi / q in mm.

    Parameters
    ----------
    ax : matplotlib Axes
        Axes with a log wave-vector x axis [1/m].
    label : str, optional
        Axis label.

    Returns
    -------
    matplotlib Axes
        The secondary axis.
    """

    def q_to_mm(q):
        import numpy as np

        q = np.asarray(q, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(q > 0, 2e3 * np.pi / np.where(q > 0, q, 1.0), np.inf)

    sec = ax.secondary_xaxis("top", functions=(q_to_mm, q_to_mm))  # its own inverse
    sec.set_xlabel(label, fontsize=9)
    return sec
