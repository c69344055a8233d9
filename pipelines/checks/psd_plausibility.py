"""Is a spectrum file one a profiler can have measured? A units slip caught before any friction.

A ``psd.csv`` holds ``q_per_m`` [1/m] and ``C_m4`` [m^4] (Persson's isotropic 2D C). Written
with q in 1/mm and C in mm^4 under that header, every wavelength comes out 1000 times too long
(a 57 mm scan becomes 57 m) and the heights 1000 times too large; the rms slope is unchanged,
so friction gives an ordinary-looking mu from a surface no road has. The table is checked
against what road and microscope profilers measure:

- wavelengths ``2 pi / q`` between 1 nm (an atomic-force microscope's pixel) and
  :data:`LAMBDA_MAX_M` = 10 m (the longest texture profiles; unevenness is not texture),
- rms height ``h = (2 pi int q C dq)^(1/2)`` at most :data:`RMS_MAX_M` = 50 mm (road
  textures reach a few mm, ISO 13473-1), at most half the longest wavelength and at least
  1e-5 of the shortest (the scan-against-itself bounds of :mod:`roadscan.plausibility`),
- rms slope ``s = (2 pi int q^3 C dq)^(1/2)`` between :data:`SLOPE_RANGE` 1e-6 and 50 (a
  polished optical flat or wafer over millimetre wavelengths to a road's texture up to its noise
  floor, a few units).

An implausible table is refused in one line naming the file, what is wrong and the unit slip
that would make it plausible (q in 1/mm and C in mm^4, q in 1/mm alone, C in mm^4 alone...).

The other common normalisation of C cannot be told from the table alone: SurfaceTopography
(and the ``C^iso`` of Jacobs, Junge and Pastewka, Surf. Topogr.: Metrol. Prop. 5 (2017)
013001) defines ``<h^2> = (1 / 2 pi) int q C dq``, a C (2 pi)^2 = 39.5 times Persson's
(``<h^2> = 2 pi int q C dq``; Persson, J. Chem. Phys. 115 (2001) 3840). Its heights and
slopes are 2 pi times too large, still plausible; so whenever a spectrum file gives an
implausible mu, :func:`normalisation_cause` is named among the likely causes.
"""

from __future__ import annotations

import numpy as np

from roadscan.errors import InputError

__all__ = [
    "spectrum_figures",
    "check_psd_table",
    "normalisation_cause",
    "LAMBDA_RANGE_M",
    "RMS_MAX_M",
    "SLOPE_RANGE",
]

LAMBDA_RANGE_M = (1e-9, 10.0)
RMS_MAX_M = 0.05
SLOPE_RANGE = (1e-6, 50.0)
#: the unit slips named, as (description, factor on q, factor on C) giving SI values
_SLIPS = (
    ("q in 1/mm and C in mm^4", 1e3, 1e-12),
    ("q in 1/um and C in um^4", 1e6, 1e-24),
    ("q in 1/mm (C in m^4)", 1e3, 1.0),
    ("C in mm^4 (q in 1/m)", 1.0, 1e-12),
    ("C in um^4 (q in 1/m)", 1.0, 1e-24),
    ("q in 1/mm and C in um^4", 1e3, 1e-24),
)


def spectrum_figures(q, C):
    """-> (shortest wavelength [m], longest [m], rms height [m], rms slope [-]) of a table
    ``q`` [1/m] (increasing), ``C`` [m^4]: ``h^2 = 2 pi int q C dq``, ``s^2 = 2 pi int q^3 C dq``
    by the trapezoidal rule over the rows.

    Parameters
    ----------
    q : ndarray
        Wave vectors [1/m], increasing.
    C : ndarray
        Spectrum [m^4].

    Returns
    -------
    tuple of float
        (shortest wavelength, longest wavelength, rms height, rms slope).
    """
    q, C = np.asarray(q, float), np.asarray(C, float)
    h2 = 2 * np.pi * np.trapezoid(q * C, q)
    s2 = 2 * np.pi * np.trapezoid(q**3 * C, q)
    return 2 * np.pi / q[-1], 2 * np.pi / q[0], float(np.sqrt(max(h2, 0.0))), float(np.sqrt(max(s2, 0.0)))


def _problems(lmin, lmax, h, s):
    out = []
    if lmax > LAMBDA_RANGE_M[1]:
        out.append(
            f"wavelengths up to {lmax:.3g} m, longer than a texture profiler measures "
            f"({LAMBDA_RANGE_M[1]:g} m)"
        )
    if lmin < LAMBDA_RANGE_M[0]:
        out.append(f"wavelengths down to {lmin:.3g} m, below an atom")
    if h > RMS_MAX_M:
        out.append(f"rms height {h:.3g} m, more than a road's texture ({RMS_MAX_M * 1e3:g} mm)")
    elif h > 0.5 * lmax:
        out.append(f"rms height {h:.3g} m, over half its longest wavelength")
    elif h < 1e-5 * lmin:
        out.append(f"rms height {h:.3g} m, under 1e-5 of its shortest wavelength")
    if not SLOPE_RANGE[0] <= s <= SLOPE_RANGE[1]:
        out.append(
            f"rms slope {s:.3g}, outside the {SLOPE_RANGE[0]:g}..{SLOPE_RANGE[1]:g} of measured surfaces"
        )
    return out


def check_psd_table(path, q, C):
    """Refuse a spectrum table no profiler can have measured (module notes), in one line.

    Parameters
    ----------
    path : str or Path
        The file (named in the message).
    q, C : arrays
        ``q_per_m`` [1/m] (increasing) and ``C_m4`` [m^4] as read.

    Returns
    -------
    dict
        ``wavelength_range_m``, ``rms_height_m``, ``rms_slope`` of the table (plausible).

    Raises
    ------
    InputError
        ``"units? ..."`` with the slip that would make it plausible, when one does.
    """
    lmin, lmax, h, s = spectrum_figures(q, C)
    bad = _problems(lmin, lmax, h, s)
    if bad:
        q, C = np.asarray(q, float), np.asarray(C, float)
        fix = None
        for what, fq, fc in _SLIPS:
            if not _problems(*spectrum_figures(q * fq, C * fc)):
                fix = (
                    f"it looks like {what} under the header q_per_m,C_m4: convert to 1/m and "
                    f"m^4 (q x {fq:g}, C x {fc:g})"
                )
                break
        fix = fix or (
            "check the units (q_per_m in 1/m, C_m4 in m^4, Persson's 2D C as roadscan analyse writes psd.csv)"
        )
        raise InputError(path, f"units? not a spectrum a profiler measures: {'; '.join(bad)}; {fix}")
    return {"wavelength_range_m": [lmin, lmax], "rms_height_m": h, "rms_slope": s}


def normalisation_cause():
    """The likely cause named when a spectrum file gives an implausible mu: C in another
    normalisation (module notes).

    Parameters
    ----------
    None

    Returns
    -------
    str
    """
    return (
        "PSD normalisation (a C in SurfaceTopography's convention, <h^2> = (1/2 pi) int q C dq, "
        "is (2 pi)^2 = 39.5 times Persson's: divide C_m4 by 39.5)"
    )
