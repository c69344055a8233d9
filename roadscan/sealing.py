"""Water sealed in the pools a sliding contact closes (Persson et al., PRB 71, 035428 (2005)).

At low speed a rubber block seals the road's water-filled pools: the regions out of contact at
the magnification where the non-contact area stops percolating. Given that magnification's
wave vector q_c and the contact fraction there (both from the friction engine, passed in as
numbers: roadscan knows no rubber), :func:`seal_pools` finds the pools on a height map:

1. the map as the rubber sees it at that magnification: its Fourier components with |q| <= q_c
   (a sharp low-pass, Persson's magnification; the map is treated as periodic);
2. the contact: the highest ``contact_fraction`` of that smoothed map, above the level z_c
   (which regions touch is the bearing-area picture; the fraction is Persson's);
3. the pools: the connected regions (4-connected by default) below z_c that do not reach the
   map's border: the contact around them closes them. Regions reaching the border are taken
   as open (their water can leave the scan) unless ``open_border=False``: for a scan inside a
   contact larger than itself (a tyre's footprint) every region out of contact is a pool, since
   at the percolation threshold the non-contact clusters are finite and only the contact's
   own edge lets water out;
4. the water: each pool holds water up to z_c (the rubber's surface over it), on the
   full-resolution heights; with a limited water film w (volume per area) the level in every
   pool is lowered alike until the sealed volume per area is w.

Unmeasured points stay unmeasured and are never part of a pool.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .heightmap import HeightMap

__all__ = ["SealedPools", "seal_pools"]


@dataclass(frozen=True, eq=False)
class SealedPools:
    """The road with its sealed pools filled.

    Attributes
    ----------
    wet : HeightMap
        Heights with the water surface in the pools [m].
    depth_m : ndarray
        Water depth [m] (0 outside the pools, NaN where unmeasured).
    pools : ndarray of bool
        Points of the sealed pools.
    sealed_fraction : float
        Fraction of the measured area under sealed water.
    volume_m3_per_m2 : float
        Sealed water per nominal area [m].
    level_m : float
        Water level in the pools [m] (z_c, or lower with limited water).
    pool_count : int
        Number of sealed pools.
    """

    wet: HeightMap
    depth_m: np.ndarray
    pools: np.ndarray
    sealed_fraction: float
    volume_m3_per_m2: float
    level_m: float
    pool_count: int


def _low_pass(h, dx, dy, q_c):
    ny, nx = h.shape
    qx = 2 * np.pi * np.fft.rfftfreq(nx, dx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, dy)
    keep = np.hypot(qx[None, :], qy[:, None]) <= q_c
    if keep.all():
        return h
    return np.fft.irfft2(np.fft.rfft2(h) * keep, s=h.shape)


def seal_pools(hm, *, q_seal_per_m, contact_fraction, water_film_m=None, connectivity=4, open_border=True):
    """Fill the pools sealed at wave vector ``q_seal_per_m`` (module docstring).

    Parameters
    ----------
    hm : HeightMap
        Levelled road heights [m].
    q_seal_per_m : float
        Wave vector of the percolation magnification [1/m] (above Nyquist: no smoothing).
    contact_fraction : float
        Fraction of the area in contact at that magnification (0 < f < 1; Persson's 0.42).
    water_film_m : float, optional
        Water per nominal area [m]; None: every pool full to z_c.
    connectivity : {4, 8}, optional
        Neighbourhood of a pool.
    open_border : bool, optional
        True (default): regions reaching the map's border are open, their water leaves the
        scan. False: every region out of contact is a pool -- the map lies inside a contact
        larger than itself (a scan inside a tyre's footprint), whose edge, not the scan's, lets
        water out; at the percolation threshold the non-contact clusters are finite, so all of
        them are sealed.

    Returns
    -------
    SealedPools

    References
    ----------
    B.N.J. Persson, U. Tartaglino, O. Albohr, E. Tosatti, Phys. Rev. B 71, 035428 (2005),
    doi:10.1103/PhysRevB.71.035428.
    """
    from scipy import ndimage

    if not isinstance(hm, HeightMap):
        raise TypeError(f"expected a HeightMap, got {type(hm).__name__}")
    if not (0.0 < contact_fraction < 1.0) or not (q_seal_per_m > 0):
        raise ValueError("need 0 < contact_fraction < 1 and q_seal_per_m > 0")
    h = np.asarray(hm.heights_m, dtype=float)
    measured = np.isfinite(h)
    mean = float(np.mean(h[measured]))
    hs = _low_pass(np.where(measured, h, mean) - mean, hm.dx_m, hm.dy_m, q_seal_per_m) + mean
    z_c = float(np.quantile(hs[measured], 1.0 - contact_fraction))
    low = (hs < z_c) & measured
    footprint = ndimage.generate_binary_structure(2, 1 if connectivity == 4 else 2)
    labels, _n = ndimage.label(low, structure=footprint)
    if open_border:
        border = np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]]))
        pools = low & ~np.isin(labels, border)
    else:
        pools = low
    count = int(np.unique(labels[pools]).size)
    hp = np.where(pools, h, np.inf)
    n_meas = int(measured.sum())

    def volume(level):
        return float(np.sum(np.maximum(level - hp[pools], 0.0))) / n_meas

    level = z_c
    if water_film_m is not None and count and volume(z_c) > water_film_m:
        lo, hi = float(np.min(hp[pools])), z_c
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if volume(mid) < water_film_m else (lo, mid)
        level = 0.5 * (lo + hi)
    wet_h = np.where(pools & (h < level), level, h)
    depth = np.where(measured, wet_h - h, np.nan)
    under = pools & (h < level)
    wet = HeightMap(
        np.where(measured, wet_h, np.nan),
        hm.dx_m,
        hm.dy_m,
        name=f"{hm.name} (sealed)" if hm.name else "sealed",
        meta=dict(hm.meta or {}),
    )
    return SealedPools(
        wet, depth, under, float(under.sum()) / n_meas, volume(level) if count else 0.0, level, count
    )
