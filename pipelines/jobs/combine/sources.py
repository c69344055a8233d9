"""One measurement of ``roadscan combine`` -> its spectrum on the common grid and its reliable
band; the scan itself is dropped before the next one is read (memory bounded by the largest
single input).

Areas: levelled (plane), unmeasured points filled (biharmonic), Tukey-windowed (alpha 0.5, see
:data:`AREA_WINDOW_ALPHA`) angular average :func:`roadscan.spectrum.psd_area` on rings aligned with the common
grid (:func:`roadscan.spectrum_merge.aligned_range`). Profiles: the road section
(:func:`roadscan.trim.road_section`), levelled (line) and filled, the 1D spectrum (alpha 0.25)
:func:`roadscan.spectrum.psd_profile` binned on the same grid and turned into the isotropic 2D
estimate C(q) = C1(q) / q Gamma(1 + H) / (sqrt(pi) Gamma(H + 1/2)) (the H psd_profile fitted).
The reliable band (:func:`roadscan.reliable_band.reliable_band`) is found on what was measured:
an area's C, a profile's C1. Where it finds a white noise floor (the top rings flatter than
q^-1), that level is taken off C (white noise adds a constant to the periodogram); where it
finds none, a white level fitted under the top (``_band_corrections._white_level``) is taken off when
significant. With a lateral resolution r (given, or from the file), C is then
divided by the Gaussian response T(q)^2 = exp(-2 ln 2 (q r / 2 pi)^2) inside the band, where
T^2 >= 0.64 (``RESPONSE_MIN`` squared): the merged curve is not pulled down at each band's top (Jacobs, Junge,
Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017)).

The band's adjustments (noise floor, white level, leakage at its start, roll-off) live in
``pipelines.jobs.combine._band_corrections``; :func:`with_roll_off_verdict` is re-exported here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pipelines.jobs.combine._band_corrections import (  # noqa: F401 (with_roll_off_verdict: re-exported)
    _noise_after_correction,
    _trim_leaky_start,
    _white_level,
    with_roll_off_verdict,
)
from roadscan.errors import InputError

__all__ = ["SourceSpectrum", "source_spectrum", "resolution_of"]

WINDOW_ALPHA = 0.25
#: areas: Tukey 0.5, whose side lobes fall faster than 0.25's, so the modes longer than the view
#: leak less into the lowest rings and the band of a steep spectrum starts lower (k x 2 pi / L
#: with k = 6 instead of 12 at q^-3.6, :func:`roadscan.reliable_band.leakage_factor`; mean
#: bias of C over 30 views at q^-3.6: 1.09 at 6 x, 0.99 at 7 x, against 1.39 and 1.36 with
#: 0.25), for 23 % fewer degrees of freedom per ring (equivalent noise bandwidth 1.22 per axis)
AREA_WINDOW_ALPHA = 0.5
#: variance of a ring's C over what its count and the window's equivalent noise bandwidth
#: predict: 1.15-1.36 measured over 25 non-periodic synthetic views (256 x 256, H = 0.8, rings
#: of 200 to 2200 lattice points; the window correlates neighbours in both directions)
VARIANCE_EXCESS = 1.3


@dataclass
class SourceSpectrum:
    """What ``combine`` keeps of one input (no heights).

    Attributes
    ----------
    label, path, kind : str
        Name, file and ``"area"`` or ``"profile"``.
    shape, spacing_m, size_m : list
        Grid, spacing [m], size [m].
    resolution_m : float or None
        Lateral resolution [m].
    resolution_source : str
        Where it came from.
    q_per_m, C_m4, count : ndarray
        Its rings.
    band : ReliableBand
        Its reliable band.
    dof_per_count : float
        Degrees of freedom per lattice point.
    meta : dict
        Reader metadata.
    """

    label: str
    path: str
    kind: str  # "area" or "profile"
    shape: list
    spacing_m: list
    size_m: list
    resolution_m: float
    resolution_source: str
    q_per_m: np.ndarray  # rings (aligned with the common grid)
    C_m4: np.ndarray  # 2D C (a profile's estimate)
    count: np.ndarray
    band: object  # roadscan.reliable_band.ReliableBand
    dof_per_count: float
    meta: dict = field(default_factory=dict)
    #: its knee judged (roadscan.rolloff_origin.RollOffVerdict) and the bends it passes to the
    #: merge: set by combine's job once every input is read
    roll_off: object = None
    bends: tuple = ()

    @property
    def q_fov_per_m(self):
        """2 pi / L [1/m], L the shorter side of an area or a profile's length."""
        return float(2 * np.pi / min(self.size_m))

    def as_dict(self):
        d = {
            "label": self.label,
            "file": self.path,
            "kind": self.kind,
            "shape": self.shape,
            "spacing_m": self.spacing_m,
            "size_m": self.size_m,
            "resolution_m": self.resolution_m,
            "resolution_source": self.resolution_source,
            "reliable_band_per_m": self.band.band,
            "reliable_band_reasons": self.band.reasons,
            "limits_per_m": dict(self.band.limits),
            "q_roll_per_m": self.band.q_roll_per_m,
            "spectrum_slope": self.band.slope,
            "reliable_band_valid": self.band.valid,
            "roll_off": None if self.roll_off is None else self.roll_off.as_dict(),
        }
        d.update(self.meta)
        return d


def resolution_of(obj, given):
    """(lateral resolution [m] or None, where it came from): the manifest / option value,
    else the file's instrument metadata (``lateral_resolution_m``), else None.

    Parameters
    ----------
    obj : HeightMap or Profile
        The scan.
    given : float or None
        Given resolution [m].

    Returns
    -------
    resolution_m : float or None
    source : str
    """
    from roadscan.resolution import resolution_of as read_resolution

    res, src = read_resolution(obj, given)
    if res is None:
        return None, "none (no resolution given nor in the file: the band ends at Nyquist or the noise)"
    return res, src


def _enbw(n, alpha=WINDOW_ALPHA):
    """Equivalent noise bandwidth of the n-point Tukey window in bins: n sum w^2 / (sum w)^2."""
    from roadscan.windows import tukey

    w = tukey(n, alpha)
    return float(n * np.sum(w**2) / np.sum(w) ** 2)


def _area_spectrum(hm, per_decade):
    from roadscan import inpaint, level
    from roadscan.spectrum import psd_area
    from roadscan.spectrum_merge import aligned_range

    lev = level.level(hm, degree=1)
    values = inpaint.unmeasured_fill(lev) if lev.unmeasured.any() else None
    lx, ly = hm.size_m
    q_lo, q_hi = aligned_range(2 * np.pi / max(lx, ly), np.pi / max(hm.dx_m, hm.dy_m), per_decade)
    spec, _ = psd_area(
        lev,
        window_alpha=AREA_WINDOW_ALPHA,
        rings_per_decade=per_decade,
        q_min=q_lo,
        q_max=q_hi,
        fill_values=values,
    )
    ny, nx = hm.shape
    # full-lattice count: each pair of points, 2 dof
    dof = 1.0 / (_enbw(nx, AREA_WINDOW_ALPHA) * _enbw(ny, AREA_WINDOW_ALPHA) * VARIANCE_EXCESS)
    q, C, n = spec.q_per_m, spec.C_m4, np.asarray(spec.count, float)
    return q, C, n, C, dof, {}


def _profile_spectrum(pr, per_decade):
    from roadscan import inpaint, level
    from roadscan.profile_spectrum import profile_to_area_factor
    from roadscan.spectrum import psd_profile

    filled, _ = inpaint.fill_unmeasured(level.level(pr, degree=1))
    q1, C1, spec = psd_profile(filled, window_alpha=WINDOW_ALPHA)
    hurst = float(spec.meta["conversion_hurst"])
    b = np.floor(per_decade * np.log10(q1) + 1e-9).astype(np.int64)
    b -= b.min()
    n = np.bincount(b).astype(float)
    keep = n > 0
    qb = np.bincount(b, q1)[keep] / n[keep]
    c1b = np.bincount(b, C1)[keep] / n[keep]
    C = c1b / qb * profile_to_area_factor(hurst)
    n_prof = int(spec.meta.get("n_profiles", 1))
    return (
        qb,
        C,
        n[keep] * n_prof,
        c1b,
        2.0 / (_enbw(filled.heights_m.size) * VARIANCE_EXCESS),
        {"conversion": spec.meta["conversion"], "conversion_hurst": hurst},
    )


def source_spectrum(obj, path, label, resolution_m=None, per_decade=20):
    """A read HeightMap or Profile -> :class:`SourceSpectrum` (see module docstring).

    Parameters
    ----------
    obj : HeightMap or Profile
        The scan [m].
    path : str or Path
        Its file.
    label : str
        Its label.
    resolution_m : float, optional
        Lateral resolution [m].
    per_decade : int, optional
        Rings per decade.

    Returns
    -------
    SourceSpectrum
    """
    from roadscan.heightmap import Profile
    from roadscan.reliable_band import gaussian_response, reliable_band

    res, res_src = resolution_of(obj, resolution_m)
    if isinstance(obj, Profile):
        from roadscan.trim import road_section

        obj = road_section(obj)  # a profiler's reference plates are not road (as in analyse)
        q, C, n, measured, dof, meta = _profile_spectrum(obj, per_decade)
        length, spacing = obj.length_m, obj.dx_m
        kind, spacing_list, size = "profile", [obj.dx_m], [obj.length_m]
        alpha = WINDOW_ALPHA
    else:
        q, C, n, measured, dof, meta = _area_spectrum(obj, per_decade)
        lx, ly = obj.size_m
        length, spacing = min(lx, ly), max(obj.dx_m, obj.dy_m)
        kind, spacing_list, size = "area", [obj.dx_m, obj.dy_m], [lx, ly]
        alpha = AREA_WINDOW_ALPHA
    try:
        band = reliable_band(q, measured, n, length, spacing, resolution_m=res, window_alpha=alpha)
    except InputError as exc:  # too few usable points (roadscan.reliable_band)
        raise InputError(path, f"no reliable band in its spectrum ({exc.problem})") from None
    level, how = (
        band.noise_floor,
        ("the white level of the spectrum's top rings taken off C before the resolution correction"),
    )
    if level is None:
        level = _white_level(q, measured, n * dof, band, res)
        how = (
            "the white level fitted with the power law times the resolution's response, "
            "C = A q^s T(q)^2 + N, to the rings from the band's middle to Nyquist, taken "
            "off C before the resolution correction"
        )
    if level is not None and level > 0:
        # a white floor adds its level to every ring: taken off (C scales as the measured C)
        C = C * (1.0 - level / measured)
        meta["noise_floor_subtracted"] = {
            "level": float(level),
            "units": "m^4" if kind == "area" else "m^3 (of C1)",
            "applied": how,
        }
    if res is not None:
        # the instrument's Gaussian low-pass undone inside the band (C / T^2 <= 1 / 0.64 there)
        T2 = gaussian_response(q, res) ** 2
        C = C / T2
        band = _noise_after_correction(band, q, measured / T2, n, length, spacing, alpha)
        inside = (q >= band.lo_per_m) & (q <= band.hi_per_m)
        meta["resolution_correction"] = {
            "applied": "C divided by T(q)^2, T = exp(-ln 2 (q r / 2 pi)^2) (Gaussian lateral "
            "response, 50 % amplitude at the wavelength r)",
            "max_factor": float(1.0 / T2[inside].min()) if inside.any() else 1.0,
        }
    band = _trim_leaky_start(band, q, C, n * dof)  # the roll-off: with_roll_off_verdict
    from pipelines.settings.scan_input import read_record

    meta.update(read_record(obj))  # how the file was read: channel, overrides
    return SourceSpectrum(
        label,
        str(path),
        kind,
        list(obj.heights_m.shape),
        spacing_list,
        size,
        res,
        res_src,
        q,
        C,
        n,
        band,
        float(dof),
        meta,
    )
