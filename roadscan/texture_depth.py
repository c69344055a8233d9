"""Figures road engineers derive from the mean profile depth: ETD (ISO 13473-1), the IFI speed
constant and F60 (ASTM E1960), and a labelled short-baseline segment depth for scans shorter
than the 100 mm MPD baseline (not an ISO figure).

Lengths in metres inside; the ASTM formulas take MPD in millimetres and speeds in km/h, as
the standard writes them.
"""

from __future__ import annotations

import numpy as np

from .heightmap import HeightMap, Profile

__all__ = [
    "estimated_texture_depth",
    "ifi_speed_constant",
    "ifi_f60",
    "short_segment_depth",
    "spike_alpha_to_pass",
    "SHORT_MIN_BASELINE_M",
    "MpdSegments",
    "mpd_segments",
    "mpd_and_segments",
]

#: Shortest baseline a short-scan segment depth is given for [m].
SHORT_MIN_BASELINE_M = 10e-3


def estimated_texture_depth(mpd_m):
    """Estimated texture depth [m], ISO 13473-1:2019 eq. (1): ETD = 0.2 mm + 0.8 MPD.

    ETD estimates the volumetric (sand patch, ISO 10844 / EN 13036-1) mean texture depth from
    the MPD. None when ``mpd_m`` is None.

    Parameters
    ----------
    mpd_m : float or None
        Mean profile depth [m].

    Returns
    -------
    float or None
        ETD [m].

    References
    ----------
    ISO 13473-1:2019, eq. (1).
    """
    if mpd_m is None:
        return None
    return 0.2e-3 + 0.8 * float(mpd_m)


def ifi_speed_constant(mpd_m):
    """IFI speed constant Sp [km/h], ASTM E1960-07: Sp = 14.2 + 89.7 MPD, MPD in mm.

    None when ``mpd_m`` is None.

    Parameters
    ----------
    mpd_m : float or None
        Mean profile depth [m].

    Returns
    -------
    float or None
        Sp [km/h].

    References
    ----------
    ASTM E1960-07, Standard Practice for Calculating International Friction Index of a Pavement
    Surface.
    """
    if mpd_m is None:
        return None
    return 14.2 + 89.7 * float(mpd_m) * 1e3


def ifi_f60(friction, slip_speed_kmh, mpd_m, A, B, C=0.0):
    """International Friction Index F60 of ASTM E1960-07.

    FR60 = FRS exp((S - 60) / Sp), F60 = A + B FR60 + C TX, with FRS the friction measured at
    slip speed S [km/h], Sp = 14.2 + 89.7 MPD[mm] (:func:`ifi_speed_constant`), A, B, C the
    measuring device's calibration constants and TX the texture measure, here MPD in mm
    (C = 0 for devices calibrated without it).

    Returns
    -------
    tuple of float or None
        (F60, Sp_kmh, FR60), or None when ``mpd_m`` is None.

    Parameters
    ----------
    friction : float
        Friction FRS measured at the slip speed.
    slip_speed_kmh : float
        Slip speed S [km/h].
    mpd_m : float or None
        Mean profile depth [m].
    A, B, C : float
        The device's calibration constants.

    References
    ----------
    ASTM E1960-07.
    """
    sp = ifi_speed_constant(mpd_m)
    if sp is None:
        return None
    fr60 = float(friction) * np.exp((float(slip_speed_kmh) - 60.0) / sp)
    return float(A + B * fr60 + C * float(mpd_m) * 1e3), sp, float(fr60)


def _longest_baseline(obj, resample_m=0.5e-3):
    """Longest whole-millimetre baseline [m] that fits the scan's lines along x."""
    L = (obj.n if isinstance(obj, Profile) else obj.nx) * obj.dx_m
    base = np.floor(L * 1e3 * (1 + 1e-9)) * 1e-3
    return float(base) if base >= SHORT_MIN_BASELINE_M else None


def short_segment_depth(obj, **settings):
    """Mean segment depth over the longest baseline that fits a scan shorter than 100 mm.

    NOT an ISO 13473-1 MPD: the standard's segments are 100 mm long, and a shorter baseline
    reads less depth on a coarse texture (the longest texture wavelengths are cut). The same
    steps as :func:`roadscan.roughness.segment_depths` (dropouts, resampling, spikes, 2.4 mm
    low-pass, slope suppression, peak of each half minus the mean) with the baseline B =
    the scan's length along x rounded down to whole millimetres (at least 10 mm); an area's
    rows are averaged like the MPD's.

    Returns
    -------
    msd_short_m : float or None
        Mean segment depth [m].
    baseline_m : float or None
        The baseline used [m].
    note : str
        What was done.

    Parameters
    ----------
    obj : Profile or HeightMap
        A scan shorter than 100 mm [m].
    **settings
        Overrides of the ISO 13473-1 settings.
    """
    from . import roughness

    base = _longest_baseline(obj)
    if base is None:
        return None, None, "no short-baseline segment depth: the scan is shorter than 10 mm"
    cfg = dict(settings, segment_m=base)
    if isinstance(obj, HeightMap):
        msd, note = roughness.mean_profile_depth_area(obj, **cfg)
    else:
        msd, note = roughness.mean_profile_depth(obj, **cfg)
    note = note.replace("ISO 13473-1 MPD", "short-baseline mean segment depth (not ISO 13473-1)")
    note = note.replace("100 mm segments", f"{base * 1e3:g} mm segments")
    return msd, (base if msd is not None else None), note


def _valid_counts(obj, alpha, settings):
    from . import _mean_profile_depth as iso13473

    cfg = dict(settings, spike_alpha=alpha)
    if isinstance(obj, HeightMap):
        res = iso13473._segment_depths_by_bands(obj, cfg)
    else:
        res = iso13473.segment_depths(obj.heights_m, obj.dx_m, obj.unmeasured, **cfg)
    return int(res["valid"].sum()), int(res["valid"].size)


def spike_alpha_to_pass(obj, settings=None, upper=50.0, step=0.1, max_rows=256):
    """Smallest spike threshold alpha (ISO 13473-1 Annex E: a spike where |dh| >= alpha x the
    resampled interval) at which the MPD exists, rounded up to ``step``.

    Bisection on alpha = k x ``step`` (the number of valid segments grows with alpha); aims first at an MPD
    valid per ISO 13473-1 (at least half the segments valid), else at any valid segment.

    A height map of more than ``max_rows`` rows is searched on ``max_rows`` evenly spaced rows
    (each bisection step runs the whole MPD chain; the fraction of valid segments is a mean
    over rows, well estimated from a few hundred).

    Returns
    -------
    alpha : float or None
        None when even ``upper`` leaves no valid segment (the segments fail on dropouts, not
        spikes).
    iso_valid : bool
        Whether the MPD at ``alpha`` is valid per ISO 13473-1.

    Parameters
    ----------
    obj : Profile or HeightMap
        The scan.
    settings : dict, optional
        ISO 13473-1 settings.
    upper : float, optional
        Largest alpha tried.
    step : float, optional
        Resolution of alpha.
    max_rows : int, optional
        Rows of a map searched at most.
    """
    from .roughness import MPD_SETTINGS

    if isinstance(obj, HeightMap) and obj.ny > max_rows:
        rows = np.unique(np.linspace(0, obj.ny - 1, max_rows).round().astype(int))
        obj = HeightMap(obj.heights_m[rows], obj.dx_m, obj.dy_m, obj.unmeasured[rows], obj.name)

    settings = dict(settings or {})
    lo = float(settings.get("spike_alpha", MPD_SETTINGS["spike_alpha"]))
    need_frac = settings.get("min_valid_fraction", MPD_SETTINGS["min_valid_fraction"])
    nv, nt = _valid_counts(obj, upper, settings)
    if nv == 0:
        return None, False
    iso = nv >= need_frac * nt
    need = int(np.ceil(need_frac * nt)) if iso else 1
    k_lo, k_hi = int(np.floor(lo / step + 1e-9)), int(np.ceil(upper / step - 1e-9))
    while k_hi - k_lo > 1:  # alpha = k step: k_lo fails, k_hi passes
        k = (k_lo + k_hi) // 2
        if _valid_counts(obj, k * step, settings)[0] >= need:
            k_hi = k
        else:
            k_lo = k
    alpha = k_hi * step
    return round(alpha, 6), iso


class MpdSegments:
    """The ISO 13473-1 segments behind an MPD: one row per 100 mm segment of every line.

    Attributes (arrays of the same length, line by line, segments in order along each line):
    ``line`` (line index), ``start_m``, ``end_m`` (segment ends along the line [m], from the
    line's first sample), ``msd_m`` (mean segment depth [m]), ``valid`` (bool) and ``reason``
    (why a segment is invalid, empty when valid), ``dropout_fraction`` and ``spike_fraction``
    (per segment, against the limits ``max_dropout_fraction`` and ``max_spike_fraction``; spikes
    found at ``spike_alpha``). ``mpd_m`` is the mean MSD of the valid
    segments (None without any), ``mpd_valid`` is True when at least half of the segments
    are valid (ISO 13473-1:2019, 7.9; False when there is no segment), ``n_valid``,
    ``n_total``; ``note`` says what was done (as :func:`roadscan.roughness.mean_profile_depth`).

    Parameters
    ----------
    res : dict
        The result of :func:`roadscan.roughness.segment_depths`.
    note : str
        How the MPD was computed.
    line_length_m : float
        Length of each line [m].
    """

    def __init__(self, res, note, line_length_m):
        cfg = res["settings"]
        valid = np.asarray(res["valid"], dtype=bool)
        rows, n_seg = valid.shape
        seg = cfg["segment_m"]
        self.line = np.repeat(np.arange(rows), n_seg)
        self.start_m = np.tile(np.arange(n_seg) * seg, rows)
        self.end_m = self.start_m + seg
        self.msd_m = np.asarray(res["msd_m"], dtype=float).ravel()
        self.valid = valid.ravel()
        drop, spk = np.asarray(res["dropout_fraction"]).ravel(), np.asarray(res["spike_fraction"]).ravel()
        self.dropout_fraction, self.spike_fraction = drop, spk
        self.max_dropout_fraction = float(cfg["max_dropout_fraction"])
        self.max_spike_fraction = float(cfg["max_spike_fraction"])
        self.min_valid_fraction = float(cfg["min_valid_fraction"])
        self.spike_alpha = float(cfg["spike_alpha"])
        reasons = []
        for d, sp, ok in zip(drop, spk, self.valid):
            why = []
            if d > cfg["max_dropout_fraction"]:
                why.append(f"dropouts {100 * d:.3g} % > {100 * cfg['max_dropout_fraction']:g} %")
            if sp > cfg["max_spike_fraction"]:
                why.append(f"spikes {100 * sp:.3g} % > {100 * cfg['max_spike_fraction']:g} %")
            reasons.append("" if ok else "; ".join(why))
        self.reason = reasons
        self.n_valid, self.n_total = int(self.valid.sum()), int(self.valid.size)
        self.mpd_m = float(self.msd_m[self.valid].mean()) if self.n_valid else None
        self.mpd_valid = bool(self.n_valid and self.n_valid >= cfg["min_valid_fraction"] * self.n_total)
        self.line_length_m = float(line_length_m)
        self.note = note

    def failed_rules(self):
        """How many segments break each ISO 13473-1 rule: {"dropouts": n, "spikes": n} (a
        segment breaking both counts in both), over the invalid segments.

        Returns
        -------
        dict
        """
        drop = self.dropout_fraction > self.max_dropout_fraction
        spk = self.spike_fraction > self.max_spike_fraction
        return {"dropouts": int(drop.sum()), "spikes": int(spk.sum())}

    def validity_text(self):
        """ "valid per ISO 13473-1 (17 of 18 segments)" or "not valid per ISO 13473-1 (3 of 18
        segments)"."""
        what = "valid" if self.mpd_valid else "not valid"
        return f"{what} per ISO 13473-1 ({self.n_valid} of {self.n_total} segments)"


def mpd_segments(obj, **settings):
    """The per-segment table of the ISO 13473-1 MPD of a profile or of a map's rows.

    The segments are those of :func:`roadscan.roughness.segment_depths` (100 mm baselines
    from each line's first sample; a segment is invalid with more than 10 % dropouts or 5 %
    spikes); a map's rows are its lines (transpose the map for lines along y).

    Returns
    -------
    MpdSegments or None
        None when no segment fits (line shorter than 100 mm, spacing coarser than 1 mm).

    Parameters
    ----------
    obj : Profile or HeightMap
        The scan [m].
    **settings
        Overrides of the ISO 13473-1 settings.
    """
    from . import _mean_profile_depth as iso13473

    try:
        if isinstance(obj, HeightMap):
            res = iso13473._segment_depths_by_bands(obj, settings)
            what, length = f"{obj.ny} rows", obj.nx * obj.dx_m
        else:
            res = iso13473.segment_depths(obj.heights_m, obj.dx_m, obj.unmeasured, **settings)
            what, length = "a profile", obj.length_m
    except ValueError:
        return None
    _, note = iso13473._summarise(res, what)
    return MpdSegments(res, note, length)


def mpd_and_segments(obj, **settings):
    """The ISO 13473-1 MPD and its per-segment table from one pass over the segments.

    Returns
    -------
    mpd_m : float or None
        Mean profile depth [m] (mean MSD of the valid segments), as
        :func:`roadscan.roughness.mean_profile_depth` (a Profile) or
        :func:`roadscan.roughness.mean_profile_depth_area` (a HeightMap's rows) give it.
    note : str
        Their note.
    segments : MpdSegments or None
        As :func:`mpd_segments` gives it.

    Parameters
    ----------
    obj : Profile or HeightMap
        The scan [m].
    **settings
        Overrides of the ISO 13473-1 settings.

    References
    ----------
    ISO 13473-1:2019.
    """
    from . import _mean_profile_depth as iso13473

    is_map = isinstance(obj, HeightMap)
    if not is_map and not isinstance(obj, Profile):
        raise TypeError(f"expected HeightMap or Profile, got {type(obj).__name__}")
    try:
        if is_map:
            res = iso13473._segment_depths_by_bands(obj, settings)
        else:
            res = iso13473.segment_depths(obj.heights_m, obj.dx_m, obj.unmeasured, **settings)
        err = None
    except ValueError as e:
        res, err = None, e
    if is_map:
        L = obj.nx * obj.dx_m
        seg = settings.get("segment_m", iso13473.MPD_SETTINGS["segment_m"])
        what, length = f"{obj.ny} rows", L
        if L < seg * (1 - 1e-9):
            mpd, note = (
                None,
                (
                    f"no MPD: rows are {L * 1e3:.1f} mm long, shorter than the "
                    f"{seg * 1e3:.0f} mm baseline of ISO 13473-1"
                ),
            )
        elif res is None:
            mpd, note = None, f"no MPD: {err}"
        else:
            mpd, note = iso13473._summarise(res, f"{obj.ny} rows of {iso13473._size(L)}")
    else:
        what, length = "a profile", obj.length_m
        if res is None:
            mpd, note = None, f"no MPD: {err}"
        else:
            mpd, note = iso13473._summarise(res, f"a {iso13473._size(obj.length_m)} profile")
    if res is None:
        return mpd, note, None
    return mpd, note, MpdSegments(res, iso13473._summarise(res, what)[1], length)
