"""Mean profile depth (MPD) of ISO 13473-1:2019: the mean segment depths of 100 mm baselines
of a profile, or of every row of a height map.

Heights in metres. The public names are re-exported by :mod:`roadscan.roughness`, their home
for users; :mod:`roadscan.texture_depth` builds the estimated texture depth and the segment
table on them.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .bands import gap_neighbours, row_chunks
from .heightmap import HeightMap, Profile
from .windows import butter2_lowpass, filtfilt2

__all__ = ["mean_profile_depth", "mean_profile_depth_area", "segment_depths", "MPD_SETTINGS"]


#: Settings of ISO 13473-1:2019 as used here (see :func:`segment_depths`).
MPD_SETTINGS = {
    "segment_m": 0.100,  # baseline (segment) length
    "max_sampling_m": 1.0e-3,  # coarsest sampling interval the standard accepts
    "resample_fine_m": 0.5e-3,  # resampling interval when the input is <= 0.5 mm
    "resample_coarse_m": 1.0e-3,  # ... when it is between 0.5 and 1 mm
    "spike_alpha": 3.0,  # Annex E: spike if |dh| >= alpha x sampling interval
    "lowpass_cutoff_m": 2.4e-3,  # Annex D: 2nd-order Butterworth low-pass, zero phase
    "max_dropout_fraction": 0.10,  # segment invalid above this fraction of dropouts
    "max_spike_fraction": 0.05,  # segment invalid above this fraction of spikes
    "min_valid_fraction": 0.5,  # result flagged when fewer segments are valid
}


def _interp_rows(z, bad):
    """Linear interpolation over ``bad`` along each row; ends held at the nearest good value.

    A bad point i between the good points p < i < q of its row takes
    ``(z[q] - z[p]) / (q - p) * (i - p) + z[p]``, the formula of :func:`numpy.interp` (the
    same float64 operations, so the same bits); before a row's first or after its last good
    value it takes that value; a row without any good value stays as it is. p and q are found
    on the bad points only, from their runs along the flattened map.
    """
    out = z.copy()
    rows, n = z.shape
    flat = out.reshape(-1)  # a view: out is C-contiguous
    at = np.flatnonzero(bad)
    if at.size:
        at = at[~bad.all(axis=1)[at // n]]  # rows with a good value only
    if not at.size:
        return out
    p, q = gap_neighbours(at, rows * n)  # previous and next good point
    lo = at - at % n  # the row's first point
    lead, trail = p < lo, q >= lo + n
    mid = ~(lead | trail)
    vals = np.empty(at.size)
    vals[lead] = flat[q[lead]]
    vals[trail] = flat[p[trail]]
    pm, qm, xm = p[mid], q[mid], at[mid]
    f0, f1 = flat[pm], flat[qm]
    xp0, xp1, x = pm.astype(np.float64), qm.astype(np.float64), xm.astype(np.float64)
    slope = (f1 - f0) / (xp1 - xp0)
    v = slope * (x - xp0) + f0
    nan = np.isnan(v)
    if nan.any():  # numpy.interp's fallbacks
        v[nan] = slope[nan] * (x[nan] - xp1[nan]) + f1[nan]
        still = np.isnan(v) & (f0 == f1)
        v[still] = f0[still]
    vals[mid] = v
    flat[at] = vals
    return out


def segment_depths(
    heights_m: ArrayLike, dx_m: float, unmeasured: ArrayLike | None = None, **settings: Any
) -> dict[str, Any]:
    """Mean segment depths (MSD) of ISO 13473-1:2019 for each row of ``heights_m``.

    Steps (ISO 13473-1:2019 sections 7.2 to 7.8 and annexes D and E, following the public
    description of the standard and the CAPTIF implementation, captif-slp):

    1. dropouts (NaN / ``unmeasured``) are replaced by linear interpolation, at the ends by the
       nearest valid height; a segment with more than 10 % dropouts (in the original samples)
       is invalid;
    2. resampling by averaging in bins of 0.5 mm (input interval <= 0.5 mm) or 1.0 mm (input
       interval <= 1 mm; coarser input is refused);
    3. spikes (Annex E): where |h[i+1] - h[i]| >= alpha x interval (alpha = 3), both points are
       flagged, removed and interpolated; a segment with more than 5 % spikes is invalid;
    4. low-pass filter (Annex D): 2nd-order Butterworth with a 2.4 mm cut-off wavelength,
       applied forwards and backwards (zero phase) along the whole profile;
    5. the profile is cut into consecutive 100 mm segments from its start (an incomplete last
       segment is dropped); in each, the least-squares line is removed (slope suppression);
    6. MSD = (highest peak of the first half + highest peak of the second half) / 2 - segment
       mean (zero after step 5).

    Parameters
    ----------
    heights_m : (n,) or (rows, n) array
        Heights [m] along x; NaN where unmeasured.
    dx_m : float
        Sampling interval [m].
    unmeasured : bool array, optional
    **settings
        Overrides of :data:`MPD_SETTINGS`.

    Returns
    -------
    dict
        ``msd_m`` (rows, segments), ``valid`` (rows, segments), ``dropout_fraction``,
        ``spike_fraction`` (rows, segments), ``resampled_m`` (the interval used),
        ``n_spikes`` (total) and ``settings``.
    """
    cfg = dict(MPD_SETTINGS)
    unknown = set(settings) - set(cfg)
    if unknown:
        raise TypeError(f"unknown MPD settings: {sorted(unknown)}")
    cfg.update(settings)
    z = np.atleast_2d(np.asarray(heights_m, dtype=np.float64))
    bad = ~np.isfinite(z)
    if unmeasured is not None:
        bad |= np.atleast_2d(np.asarray(unmeasured, dtype=bool))
    rows, n = z.shape
    tol = 1e-6
    if dx_m > cfg["max_sampling_m"] * (1 + tol):
        raise ValueError(
            f"sampling interval {dx_m * 1e3:.3g} mm is coarser than the "
            f"{cfg['max_sampling_m'] * 1e3:.3g} mm ISO 13473-1 accepts"
        )
    t = cfg["resample_fine_m"] if dx_m <= cfg["resample_fine_m"] * (1 + tol) else cfg["resample_coarse_m"]
    seg = cfg["segment_m"]
    m = int(round(seg / t))  # resampled points per segment
    n_seg = int(np.floor(n * dx_m / seg + 1e-9))
    if n_seg < 1:
        raise ValueError(
            f"profile is {n * dx_m * 1e3:.1f} mm long, shorter than one "
            f"{seg * 1e3:.0f} mm ISO 13473-1 segment"
        )
    # 1. dropouts
    zf = _interp_rows(np.where(bad, 0.0, z), bad)
    seg_of_sample = np.floor(np.arange(n) * dx_m / seg + 1e-9).astype(np.int64)
    in_seg = seg_of_sample < n_seg
    seg_start = np.searchsorted(seg_of_sample, np.arange(n_seg))  # each segment's first sample
    drop = np.add.reduceat(bad[:, in_seg].astype(np.float64), seg_start, axis=1) / np.bincount(
        seg_of_sample[in_seg], minlength=n_seg
    )
    # 2. resampling (bin averages)
    if abs(dx_m - t) <= tol * t:
        zr = zf
    else:
        b = np.floor(np.arange(n) * dx_m / t + 1e-9).astype(np.int64)
        starts = np.flatnonzero(np.r_[True, np.diff(b) > 0])
        zr = np.add.reduceat(zf, starts, axis=1) / np.diff(np.r_[starts, n])[None, :]
    # 3. spikes
    jump = np.abs(np.diff(zr, axis=1)) >= cfg["spike_alpha"] * t
    spike = np.zeros(zr.shape, dtype=bool)
    spike[:, 1:] |= jump
    spike[:, :-1] |= jump
    if spike.any():
        zr = _interp_rows(zr, spike)
    # 4. low-pass
    # (numpy-only equivalent of scipy.signal butter(2, ...) + sosfiltfilt, roadscan.windows)
    b, a = butter2_lowpass(t / cfg["lowpass_cutoff_m"] * 2.0)
    if zr.shape[1] > 9:
        zr = filtfilt2(b, a, zr)
    # 5. segments and slope suppression
    n_seg = min(n_seg, zr.shape[1] // m)
    zs = zr[:, : n_seg * m].reshape(rows, n_seg, m)
    xc = np.arange(m) - (m - 1) / 2.0
    zs = zs - zs.mean(axis=2, keepdims=True)
    zs = zs - (zs @ xc / (xc @ xc))[..., None] * xc
    # 6. mean segment depth
    half = m // 2
    msd = 0.5 * (zs[..., :half].max(axis=2) + zs[..., half:].max(axis=2)) - zs.mean(axis=2)
    spike_frac = spike[:, : n_seg * m].reshape(rows, n_seg, m).mean(axis=2)
    drop = drop[:, :n_seg]
    valid = (drop <= cfg["max_dropout_fraction"]) & (spike_frac <= cfg["max_spike_fraction"])
    return {
        "msd_m": msd,
        "valid": valid,
        "dropout_fraction": drop,
        "spike_fraction": spike_frac,
        "resampled_m": t,
        "n_spikes": int(spike.sum()),
        "settings": cfg,
    }


def _summarise(res, what):
    valid, msd = res["valid"], res["msd_m"]
    nv, nt = int(valid.sum()), valid.size
    base = (
        f"ISO 13473-1 MPD over {what}: {nv} of {nt} 100 mm segments valid, resampled to "
        f"{res['resampled_m'] * 1e3:g} mm, {res['n_spikes']} spike points replaced, "
        f"low-pass {res['settings']['lowpass_cutoff_m'] * 1e3:g} mm"
    )
    if nv == 0:
        return None, base + "; no valid segment (too many dropouts or spikes)"
    mpd = float(msd[valid].mean())
    if nv < res["settings"]["min_valid_fraction"] * nt:
        base += "; fewer than half the segments valid: result not valid per ISO 13473-1"
    return mpd, base


def mean_profile_depth(profile: Profile, **settings: Any) -> tuple[float | None, str]:
    """Mean profile depth [m] of a line profile per ISO 13473-1 (see :func:`segment_depths`).

    MPD = mean of the valid segments' MSDs.

    Returns
    -------
    mpd_m : float or None
        Mean profile depth [m].
    note : str
        How many segments were valid and what was done, or why no MPD could be computed.

    Parameters
    ----------
    profile : Profile
        Line profile [m], spacing at most 1 mm, at least 100 mm long.
    **settings
        Overrides of :data:`MPD_SETTINGS` (e.g. ``spike_alpha=6``).

    References
    ----------
    ISO 13473-1:2019, Characterization of pavement texture by use of surface profiles -- Part 1:
    Determination of mean profile depth.

    Examples
    --------
    >>> from roadscan.io import read
    >>> from roadscan.roughness import mean_profile_depth
    >>> mpd_m, note = mean_profile_depth(read("sample_scans/captif_station_1_excerpt.dat"),
    ...                                  spike_alpha=6)   # doctest: +SKIP
    """
    if not isinstance(profile, Profile):
        raise TypeError(f"expected a Profile, got {type(profile).__name__}")
    try:
        res = segment_depths(profile.heights_m, profile.dx_m, profile.unmeasured, **settings)
    except ValueError as err:
        return None, f"no MPD: {err}"
    return _summarise(res, f"a {_size(profile.length_m)} profile")


def _size(L):
    """A length [m] to 3 significant digits, in m from 1 m: "1.81 m", "54.2 mm"."""
    return (f"{L:#.3g}".rstrip(".") + " m") if L >= 1 else (f"{L * 1e3:#.3g}".rstrip(".") + " mm")


def mean_profile_depth_area(hm: HeightMap, **settings: Any) -> tuple[float | None, str]:
    """MPD of a height map averaged over its rows (profiles along x), per ISO 13473-1.

    Every row is processed as a profile (:func:`segment_depths`) and the MSDs of all valid
    segments of all rows are averaged. Returns (None, reason) when the rows are shorter than
    the 100 mm baseline or the spacing is coarser than 1 mm.

    Returns
    -------
    (mpd_m or None, note)

    Parameters
    ----------
    hm : HeightMap
        Height map [m]; its rows are the profiles.
    **settings
        Overrides of :data:`MPD_SETTINGS`.

    References
    ----------
    ISO 13473-1:2019.
    """
    if not isinstance(hm, HeightMap):
        raise TypeError(f"expected a HeightMap, got {type(hm).__name__}")
    L = hm.nx * hm.dx_m
    seg = settings.get("segment_m", MPD_SETTINGS["segment_m"])
    if L < seg * (1 - 1e-9):
        return None, (
            f"no MPD: rows are {L * 1e3:.1f} mm long, shorter than the "
            f"{seg * 1e3:.0f} mm baseline of ISO 13473-1"
        )
    try:
        res = _segment_depths_by_bands(hm, settings)
    except ValueError as err:
        return None, f"no MPD: {err}"
    return _summarise(res, f"{hm.ny} rows of {_size(L)}")


def _segment_depths_by_bands(hm, settings):
    """:func:`segment_depths` of every row, run on bands of rows (each row is processed on
    its own, so the result is the same as one call on the whole map; the memory used is a
    band's, not the map's)."""
    parts = [
        segment_depths(hm.heights_m[sl], hm.dx_m, hm.unmeasured[sl], **settings)
        for sl in row_chunks(hm.ny, hm.nx, 1 << 23)
    ]
    res = dict(parts[0])
    for key in ("msd_m", "valid", "dropout_fraction", "spike_fraction"):
        res[key] = np.concatenate([p[key] for p in parts], axis=0)
    res["n_spikes"] = sum(p["n_spikes"] for p in parts)
    return res
