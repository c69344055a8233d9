"""The road engineer's texture set beyond the height figures, in one call per scan kind.

Areal (ISO 25178-2:2012 / 2021): the material-ratio family and volumes
(:mod:`roadscan.material_ratio`), the spatial figures (:mod:`roadscan.areal_spatial`) and the
feature figures (:mod:`roadscan.areal_features`). Profile (ISO 21920-2:2021): the Rk family and
Rmr (:func:`roadscan.material_ratio.profile_material_parameters`).

Input: a levelled (and, when asked, S- and L-filtered) HeightMap or Profile, heights in
metres, NaN where unmeasured. Output keys are SI with their unit in the name.
"""

from __future__ import annotations

import numpy as np

from .heightmap import HeightMap, Profile

__all__ = ["AREAL_KEYS", "PROFILE_KEYS", "texture_parameters"]

AREAL_KEYS = (
    "Sk_m",
    "Spk_m",
    "Svk_m",
    "Smr1_pct",
    "Smr2_pct",
    "Vmp_m3_per_m2",
    "Vmc_m3_per_m2",
    "Vvc_m3_per_m2",
    "Vvv_m3_per_m2",
    "Sal_m",
    "Str",
    "Std_deg",
    "Spd_per_m2",
    "Spc_per_m",
    "S10z_m",
    "S5p_m",
    "S5v_m",
)
PROFILE_KEYS = ("Rk_m", "Rpk_m", "Rvk_m", "Rmr1_pct", "Rmr2_pct", "Rmr_pct")


def texture_parameters(obj):
    """The figures of :data:`AREAL_KEYS` (a HeightMap) or :data:`PROFILE_KEYS` (a Profile).

    Returns
    -------
    figures : dict
        The texture figures.
    notes : dict
        ``spatial`` and ``features``: how those figures were obtained and why one is null.

    Parameters
    ----------
    obj : HeightMap or Profile
        Levelled scan [m].

    References
    ----------
    ISO 25178-2:2021; ISO 21920-2:2021.
    """
    from .material_ratio import (
        MaterialRatioCurve,
        functional_parameters,
        profile_material_parameters,
        volume_parameters,
    )

    z = obj.heights_m
    if isinstance(obj, Profile):
        good = z[np.isfinite(z)]
        if good.size < 2:
            return dict.fromkeys(PROFILE_KEYS), {}
        return profile_material_parameters(good), {}
    if not isinstance(obj, HeightMap):
        raise TypeError(f"expected HeightMap or Profile, got {type(obj).__name__}")
    mean = float(z.mean()) if z.size else np.nan
    filled = z  # all finite (the mean is): no copy
    if not np.isfinite(mean):
        ok = np.isfinite(z)
        n_ok = int(np.count_nonzero(ok))
        mean = float(np.sum(z, where=ok) / n_ok) if n_ok else np.nan
        # unmeasured points at the mean height for the segmentation (one copy, the map's
        # size; heights - mean are then 0 there exactly)
        filled = np.where(ok, z, mean) if n_ok >= 2 else None
        del ok
    from .areal_features import feature_parameters
    from .areal_spatial import spatial_parameters

    if filled is None or z.size < 2:
        return dict.fromkeys(AREAL_KEYS), {}
    curve = MaterialRatioCurve(z)  # (areal_material_parameters; NaN left out)
    out = {**functional_parameters(curve), **volume_parameters(curve)}
    # no full-size copy about the mean: the spatial figures take their own (NaN where
    # unmeasured), the features shift only the heights they use
    sp = spatial_parameters(z, obj.dx_m, obj.dy_m)
    ft = feature_parameters(
        filled, obj.dx_m, obj.dy_m, mean=mean, z_min=curve.z_min_m, z_max=curve.z_max_m, count_pits=False
    )
    del filled
    notes = {"spatial": sp.pop("spatial_note"), "features": ft.pop("features_note")}
    out.update(sp)
    out.update(ft)
    return {k: out[k] for k in AREAL_KEYS}, notes
