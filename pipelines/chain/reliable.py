"""The reliable band of a read scan's spectrum (:mod:`roadscan.reliable_band`) with the scan's
geometry and lateral resolution filled in.

An area's band comes from its angular average C(q) [m^4] (L = its shorter side, a = its coarser
spacing); a line profile's from its own binned 1D spectrum C1(q) [m^3] (L = its length), whose
slope 1 + 2H sets the window's leakage. The lateral resolution is the one given
(``--resolution`` or a manifest's ``resolution_m``), else the file's metadata, else none
(:func:`roadscan.resolution.resolution_of`, re-exported here).
"""

from __future__ import annotations

import numpy as np

from roadscan.heightmap import Profile
from roadscan.resolution import resolution_of

__all__ = ["scan_band", "resolution_of", "geometry_of"]


def geometry_of(obj):
    """(field of view L [m], spacing a [m]) used for the band: an area's shorter side and
    coarser spacing, a profile's length and spacing.

    Parameters
    ----------
    obj : HeightMap or Profile
        The scan.

    Returns
    -------
    tuple of float
        (L, a) [m].
    """
    if isinstance(obj, Profile):
        return float(obj.length_m), float(obj.dx_m)
    return float(min(obj.size_m)), float(max(obj.dx_m, obj.dy_m))


def scan_band(obj, spectrum, resolution_m=None, window_alpha=0.25):
    """:class:`roadscan.reliable_band.ReliableBand` of ``obj`` (the scan whose spectrum it is).

    ``spectrum`` is the scan's :class:`roadscan.Spectrum` (for a profile the 2D estimate, whose
    ``meta['C1_binned_m3']`` holds the 1D spectrum on the same wave vectors).

    Parameters
    ----------
    obj : HeightMap or Profile
        The scan.
    spectrum : roadscan.Spectrum
        Its spectrum.
    resolution_m : float, optional
        Lateral resolution [m] (default: the file's metadata).
    window_alpha : float, optional
        Tukey window of the spectrum.

    Returns
    -------
    ReliableBand or None
    """
    from roadscan.reliable_band import reliable_band

    L, a = geometry_of(obj)
    res, _ = resolution_of(obj, resolution_m)
    C = spectrum.C_m4
    if isinstance(obj, Profile) and "C1_binned_m3" in spectrum.meta:
        C = np.asarray(spectrum.meta["C1_binned_m3"], float)
    return reliable_band(
        spectrum.q_per_m, C, spectrum.count, L, a, resolution_m=res, window_alpha=window_alpha
    )
