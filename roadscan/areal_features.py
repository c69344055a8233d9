"""Feature parameters of ISO 25178-2:2012 (section 4.6): Spd, Spc, S5p, S5v and S10z.

Segmentation (ISO 25178-2 section 6, ISO 16610-85): the surface is cut into hills by a
watershed from its peaks (and into dales from its pits), and hills are merged by Wolf pruning:
a hill whose height above its lowest saddle to a higher hill is below the threshold
T = 5 % of Sz is merged into that neighbour, smallest first, until none is left. A peak
survives Wolf pruning exactly when its dynamic (topographic prominence: its height above the
highest saddle through which a higher point can be reached) is at least T, which is what the
h-maxima transform computes (the regional maxima of the morphological reconstruction by
dilation of z - T under z; scikit-image ``h_maxima``). The significant peaks are those
maxima (a plateau counts once); pits likewise on -z.

- Spd [1/m^2] = number of significant peaks / projected area;
- Spc [1/m] = -(1/2) mean over significant peaks of (d2z/dx2 + d2z/dy2), second differences
  at the peak's highest point (peaks on the border excluded);
- S5p [m] = mean height of the five highest significant peaks, S5v [m] = mean depth of the
  five deepest significant pits (heights from the mean plane; fewer when fewer exist);
  S10z = S5p + S5v.

A peak or pit whose extreme point lies on the border of the field is not counted (it may
be the flank of a feature cut by the field's edge).

Large maps: above :data:`MAX_POINTS` points the segmentation runs on the central window of
MAX_POINTS points at full resolution (the note says so): Spd and Spc are densities and means,
unbiased on a window; S5p, S5v and S10z over the whole map can only be higher. Decimating the
map instead would merge peaks and change the count. Unmeasured points take the mean height
(zero) before segmentation.
"""
from __future__ import annotations

import numpy as np

__all__ = ["feature_parameters", "MAX_POINTS", "PRUNE_FRACTION"]

#: largest map segmented at full resolution
MAX_POINTS = 1 << 20
#: Wolf pruning threshold as a fraction of Sz (ISO 25178-2 default for Spd and S10z)
PRUNE_FRACTION = 0.05


def _significant(z, threshold):
    """(row, column) of the highest point of each significant interior peak of ``z`` and its
    height (the h-maxima transform, module docstring)."""
    from scipy import ndimage as ndi
    from skimage.morphology import h_maxima

    marks = h_maxima(z, threshold)
    lab, n = ndi.label(marks, structure=np.ones((3, 3)))
    if n == 0:
        return np.zeros((0, 2), dtype=np.int64), np.zeros(0)
    pos = np.asarray(ndi.maximum_position(z, lab, np.arange(1, n + 1)), dtype=np.int64)
    ny, nx = z.shape
    inner = (pos[:, 0] > 0) & (pos[:, 0] < ny - 1) & (pos[:, 1] > 0) & (pos[:, 1] < nx - 1)
    pos = pos[inner]
    return pos, z[pos[:, 0], pos[:, 1]]


def feature_parameters(heights_m, dx_m, dy_m, prune_fraction=PRUNE_FRACTION):
    """Spd, Spc, S5p, S5v, S10z of a levelled height map (module docstring).

    Parameters
    ----------
    heights_m : (ny, nx) array [m] (mean plane at zero), NaN where unmeasured
    dx_m, dy_m : float
        Spacings along x (columns) and y (rows) [m].
    prune_fraction : float
        Wolf pruning threshold as a fraction of Sz (0.05).

    Returns
    -------
    dict with keys ``Spd_per_m2``, ``Spc_per_m``, ``S10z_m``, ``S5p_m``, ``S5v_m`` and
    ``features_note`` (the threshold, the counts and the block size used).
    """
    z = np.asarray(heights_m, dtype=np.float64)
    if np.isnan(z).any():
        z = np.where(np.isfinite(z), z, 0.0)
    ny0, nx0 = z.shape
    window = ""
    if ny0 * nx0 > MAX_POINTS:
        side = int(np.sqrt(MAX_POINTS))
        wy, wx = min(ny0, side), min(nx0, MAX_POINTS // min(ny0, side))
        y0, x0 = (ny0 - wy) // 2, (nx0 - wx) // 2
        z = z[y0:y0 + wy, x0:x0 + wx]
        window = (f"; over the central {wy} x {wx} points of the {ny0} x {nx0} map (S5p, S5v, "
                  f"S10z of the whole map can only be higher)")
    ny, nx = z.shape
    sz = float(z.max() - z.min())
    if sz <= 0:
        return {"Spd_per_m2": 0.0, "Spc_per_m": None, "S10z_m": 0.0, "S5p_m": 0.0, "S5v_m": 0.0,
                "features_note": "flat surface: no peak, no pit"}
    T = prune_fraction * sz
    peaks, hp = _significant(z, T)
    pits, hv = _significant(-z, T)
    area = ny * dy_m * nx * dx_m
    top = np.sort(hp)[::-1][:5]
    deep = np.sort(hv)[::-1][:5]
    s5p = float(top.mean()) if top.size else None
    s5v = float(deep.mean()) if deep.size else None
    spc = None
    if len(peaks):
        r, c = peaks[:, 0], peaks[:, 1]
        zxx = (z[r, c + 1] - 2 * z[r, c] + z[r, c - 1]) / dx_m ** 2
        zyy = (z[r + 1, c] - 2 * z[r, c] + z[r - 1, c]) / dy_m ** 2
        spc = float(-0.5 * np.mean(zxx + zyy))
    note = (f"watershed segmentation with Wolf pruning at {100 * prune_fraction:g} % of Sz "
            f"({T * 1e6:.3g} µm): {len(hp)} significant peaks, {len(hv)} pits"
            + window)
    return {"Spd_per_m2": len(hp) / area, "Spc_per_m": spc,
            "S10z_m": None if s5p is None or s5v is None else s5p + s5v,
            "S5p_m": s5p, "S5v_m": s5v, "features_note": note}
