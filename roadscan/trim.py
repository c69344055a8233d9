"""Cropping measured data to the surface of interest."""

from __future__ import annotations

import numpy as np

from .heightmap import Profile

__all__ = ["road_section"]


def road_section(profile: Profile, plate_height_m: float = 0.02, margin_m: float = 2e-3) -> Profile:
    """Crop a stationary laser profiler reading to the road between its reference plates.

    Stationary profilers such as CAPTIF's SLP start and end each reading on raised reference
    plates (about +47 mm in the CAPTIF files). Points more than ``plate_height_m`` above the
    median height are taken as plate; the road is what lies between the last plate point in the
    first half and the first plate point in the second half, less ``margin_m`` at each side
    (the plate edges). A profile with no plates is returned unchanged.

    Parameters
    ----------
    profile : Profile
    plate_height_m : float
        Height above the median that marks a plate [m].
    margin_m : float
        Extra length removed next to each plate [m].

    Returns
    -------
    Profile
        The road section; ``meta['trimmed_m']`` holds the (start, end) positions kept [m]
        relative to the first sample of the input.
    """
    if not isinstance(profile, Profile):
        raise TypeError("road_section takes a Profile")
    h = profile.heights_m
    med = np.nanmedian(h)
    plate = np.flatnonzero(np.nan_to_num(h - med, nan=-np.inf) > plate_height_m)
    if plate.size == 0:
        return profile
    n = profile.n
    margin = int(np.ceil(margin_m / profile.dx_m))
    left = plate[plate < n // 2]
    right = plate[plate >= n // 2]
    start = left.max() + 1 + margin if left.size else 0
    stop = right.min() - margin if right.size else n
    if stop - start < 16:
        return profile
    meta = dict(
        profile.meta,
        trimmed_m=(start * profile.dx_m, stop * profile.dx_m),
        trim_note=f"reference plates removed: kept {start * profile.dx_m * 1e3:.1f} to "
        f"{stop * profile.dx_m * 1e3:.1f} mm",
    )
    return Profile(h[start:stop], profile.dx_m, profile.unmeasured[start:stop], profile.name, meta)
