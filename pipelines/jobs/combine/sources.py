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
finds none, a white level fitted under the top (:func:`_white_level`) is taken off when
significant. With a lateral resolution r (given, or from the file), C is then
divided by the Gaussian response T(q)^2 = exp(-2 ln 2 (q r / 2 pi)^2) inside the band, where
T^2 >= 0.64 (``RESPONSE_MIN`` squared): the merged curve is not pulled down at each band's top (Jacobs, Junge,
Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017)).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

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
    kind: str                       # "area" or "profile"
    shape: list
    spacing_m: list
    size_m: list
    resolution_m: float
    resolution_source: str
    q_per_m: np.ndarray             # rings (aligned with the common grid)
    C_m4: np.ndarray                # 2D C (a profile's estimate)
    count: np.ndarray
    band: object                    # roadscan.reliable_band.ReliableBand
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
        d = {"label": self.label, "file": self.path, "kind": self.kind, "shape": self.shape,
             "spacing_m": self.spacing_m, "size_m": self.size_m,
             "resolution_m": self.resolution_m, "resolution_source": self.resolution_source,
             "reliable_band_per_m": self.band.band,
             "reliable_band_reasons": self.band.reasons,
             "limits_per_m": dict(self.band.limits), "q_roll_per_m": self.band.q_roll_per_m,
             "spectrum_slope": self.band.slope, "reliable_band_valid": self.band.valid,
             "roll_off": None if self.roll_off is None else self.roll_off.as_dict()}
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
    spec, _ = psd_area(lev, window_alpha=AREA_WINDOW_ALPHA, rings_per_decade=per_decade,
                       q_min=q_lo, q_max=q_hi, fill_values=values)
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
    return qb, C, n[keep] * n_prof, c1b, 2.0 / (_enbw(filled.heights_m.size) * VARIANCE_EXCESS), {
        "conversion": spec.meta["conversion"], "conversion_hurst": hurst}


def _noise_after_correction(band, q, corrected, n, length, spacing, alpha):
    """The band's top lowered to the noise floor seen in the spectrum with the resolution's
    attenuation undone: attenuation and a noise floor cancel in the measured C near the
    resolution limit, and the white floor shows only once C is divided by T^2."""
    from dataclasses import replace

    from roadscan.reliable_band import reliable_band

    try:
        again = reliable_band(q, corrected, n, length, spacing, window_alpha=alpha)
    except ValueError:
        return band
    q_noise = again.limits.get("noise_floor")
    if q_noise is None or q_noise >= band.hi_per_m or q_noise <= band.lo_per_m:
        return band
    limits = dict(band.limits, noise_floor=q_noise)
    return replace(band, hi_per_m=float(q_noise), limits=limits,
                   hi_reason=f"{again.hi_reason} (in C / T(q)^2: the resolution's attenuation "
                             f"undone, the noise floor shows)", noise_floor=again.noise_floor)


#: the band's start is raised while the rings of its first 0.1 decade lie, pooled, more than
#: this far above the power law of the rest of the band (and by over 2 standard deviations)
LEAK_EXCESS = 1.25
_LEAK_WINDOW, _LEAK_MAX, _LEAK_STEP = 0.1, 0.3, 0.05     # decades


def _trim_leaky_start(band, q, C, dof):
    """The band with its low end raised past a leakage excess of this particular view.

    The window's leakage is random from view to view (it carries the power of the modes longer
    than the view, which this view happens to have): the field-of-view end bounds its mean, not
    one view's. The power law ln C = a + s ln q is fitted (weights: degrees of freedom) to the
    band above its first 0.3 decade; while the rings of the first 0.1 decade lie on average more
    than :data:`LEAK_EXCESS` above it, by over 2 standard deviations (sqrt(2 / dof) each), the
    start moves up 0.05 decade (at most 0.3). A roll-off (C below the line) is never trimmed.
    """
    from dataclasses import replace

    lo, hi = band.lo_per_m, band.hi_per_m
    ok = (q >= lo) & (q <= hi) & (C > 0)
    ref = ok & (q >= lo * 10**_LEAK_MAX)
    if ref.sum() < 5:
        return band
    x, y, w = np.log(q), np.log(np.where(C > 0, C, 1.0)), dof
    xm, ym = np.average(x[ref], weights=w[ref]), np.average(y[ref], weights=w[ref])
    slope = np.sum(w[ref] * (x[ref] - xm) * (y[ref] - ym)) / np.sum(w[ref] * (x[ref] - xm) ** 2)
    resid = y - (ym + slope * (x - xm))
    start = lo
    while start < lo * 10 ** (_LEAK_MAX - 1e-9):
        first = ok & (q >= start) & (q < start * 10**_LEAK_WINDOW)
        if not first.any():
            break
        excess = np.average(resid[first], weights=w[first])
        sd = np.sqrt(2.0 / w[first].sum())
        if not (excess > np.log(LEAK_EXCESS) and excess > 2 * sd):
            break
        start *= 10**_LEAK_STEP
    if start == lo:
        return band
    reason = (f"{band.lo_reason}; raised {np.log10(start / lo):.2f} decade: the lowest rings lie "
              f"over {100 * (LEAK_EXCESS - 1):.0f} % above the band's power law (this view's "
              f"window leakage)")
    return replace(band, lo_per_m=float(start), lo_reason=reason)


#: a white level fitted under the band's top is taken off only when over this many standard
#: errors above zero
WHITE_SIGMAS = 3.0


def _white_level(q, measured, dof, band, resolution_m):
    """The white noise level N of a spectrum whose top shows no floor of its own, or None.

    White measurement noise adds a constant N to every ring of the periodogram; near the top of
    the band it is still far below C but biases it (by 15 % at a ring where N = 0.15 C). With
    a power law of slope s and the resolution's response T(q)^2 (1 without a resolution),
    C_i = A q_i^s T_i^2 + N is linear in A and N: fitted by weighted least squares (weights
    dof_i / C_i^2: each ring's relative variance 2 / dof_i) to the rings from the band's
    geometric middle to Nyquist, for the band's own slope and for s from -6 to 0 in steps of
    0.1 (a roll-off between the band's middle and its top changes the slope there); the s of
    least chi-square is kept. N is returned when it
    is over :data:`WHITE_SIGMAS` standard errors above zero (Jacobs, Junge, Pastewka, Surf.
    Topogr.: Metrol. Prop. 5, 013001 (2017), sec. 3: noise adds a white floor).
    """
    from roadscan.reliable_band import gaussian_response

    if not np.isfinite(band.slope):
        return None
    sel = (q >= np.sqrt(band.lo_per_m * band.hi_per_m)) & (measured > 0) & (dof > 0)
    if sel.sum() < 5:
        return None
    qs, cs, k = q[sel], measured[sel], dof[sel]
    t2 = gaussian_response(qs, resolution_m) ** 2 if resolution_m else np.ones_like(qs)
    w = k / cs**2
    best = None
    # the band's slope, or (a bend between the band's middle and its top) the slope that fits
    # these rings best
    for s in np.r_[band.slope, np.arange(-6.0, 0.01, 0.1)]:
        X = np.column_stack([(qs / qs[0]) ** s * t2, np.ones_like(qs)])
        M = X.T @ (X * w[:, None])
        try:
            cov = np.linalg.inv(M)
        except np.linalg.LinAlgError:
            continue
        coef = cov @ (X.T @ (w * cs))
        chi = float(np.sum(w * (cs - X @ coef) ** 2))
        if best is None or chi < best[0] * (1 - 1e-9):
            best = (chi, coef, cov)
    if best is None:
        return None
    _, (a, level), cov = best
    if not (a > 0 and level > WHITE_SIGMAS * np.sqrt(cov[1, 1])):
        return None
    return float(level)


def _profile_above_roll_off(band):
    """A profile's band from its roll-off up.

    The isotropic 2D estimate C(q) = C1(q) / q Gamma(1 + H) / (sqrt(pi) Gamma(H + 1/2)) holds
    for a power law: C1(q) integrates C over every 2D wave vector of modulus q or more, so below
    a roll-off, where C1 flattens and C stays flat, it puts C far above the plateau (x2 to x25
    on a synthetic profile 60 x 2 pi / L long). A band wholly under the roll-off becomes empty
    (under a factor 2: the input is left out, with its warning). Reference: Persson, Tribol.
    Lett. 63, 42 (2016) (1D and 2D spectra of road surfaces).
    """
    from dataclasses import replace

    q_r = band.q_roll_per_m
    if q_r is None or band.lo_per_m >= q_r:
        return band
    return replace(band, lo_per_m=float(q_r), hi_per_m=float(max(band.hi_per_m, q_r)),
                   lo_reason=f"{band.lo_reason}; raised to the roll-off: a profile's 2D "
                             f"estimate C1 / q x f(H) holds for a power law only")


def with_roll_off_verdict(source, *, verdict):
    """The source's reliable band and bends once its knee is judged
    (:func:`roadscan.rolloff_origin.judge_roll_offs`) -> (ReliableBand, bends [1/m]).

    - the surface's knee, an area: the band reaches down into the plateau, to
      :data:`roadscan.reliable_band.ROLL_K_MIN` x 2 pi / L (or its first ring): below a roll-off
      the modes longer than the view are as weak as the plateau, so the window leaks little
      into it (mean C / C_true 0.94-1.06 from 4 to 8 x 2 pi / L over 20 synthetic road-laser
      views); the plateau's rows carry few degrees of freedom and say so in their 5-95 % band;
    - the surface's knee, a profile: the band starts at the knee (the 2D estimate C1 / q x f(H)
      holds for a power law only, :func:`_profile_above_roll_off`);
    - the instrument's knee: the band starts at the knee when below it (its rings under it are
      bent by the instrument), and at its field-of-view end when it started at the knee below
      that end (the leakage a steep spectrum suffers there was waived for a plateau that is
      not the surface's); no bend is passed to the merge when another input measures straight
      across it, else the bend is kept (rows pool no rings across it).

    Parameters
    ----------
    source : SourceSpectrum
        One input.
    verdict : roadscan.rolloff_origin.RollOffVerdict or None
        Its knee judged; None: no knee.

    Returns
    -------
    band : ReliableBand
    bends : tuple of float
    """
    from dataclasses import replace

    from roadscan.reliable_band import ROLL_K_MIN

    band = source.band
    if verdict is None:
        return band, ()
    q_r = verdict.q_roll_per_m
    if verdict.origin == "surface":
        if source.kind == "profile":
            return _profile_above_roll_off(band), (q_r,)
        lo = max(ROLL_K_MIN * source.q_fov_per_m, float(source.q_per_m[0]))
        if lo >= band.lo_per_m:
            return band, (q_r,)
        return replace(band, lo_per_m=float(lo),
                       lo_reason=f"the plateau below the surface's roll-off ({verdict.reason}), "
                                 f"from {ROLL_K_MIN:g} x 2 pi / L: a flat spectrum leaks little "
                                 f"(the band's own low end was {band.lo_per_m:.3g} 1/m: "
                                 f"{band.lo_reason})"), (q_r,)
    refuted = bool(verdict.refuted_by)
    field_end = band.limits.get("field_of_view")
    if field_end and band.lo_per_m < field_end < band.hi_per_m and band.lo_per_m >= q_r * (1 - 1e-9):
        # the band started at the knee below its field-of-view end ("flat below: little
        # leakage"): the knee not the surface's, the leakage of a steep spectrum holds again
        band = replace(band, lo_per_m=float(field_end),
                       lo_reason=f"field of view: {field_end:.3g} 1/m, the knee at its low end "
                                 f"being the instrument's ({verdict.reason})")
    elif band.lo_per_m < q_r < band.hi_per_m:
        band = replace(band, lo_per_m=float(q_r),
                       lo_reason=f"{band.lo_reason}; raised to the instrument's knee "
                                 f"({verdict.reason})")
    if source.kind == "profile":
        band = _profile_above_roll_off(band)
    return band, (() if refuted else (q_r,))


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

        obj = road_section(obj)   # a profiler's reference plates are not road (as in analyse)
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
        band = reliable_band(q, measured, n, length, spacing, resolution_m=res,
                             window_alpha=alpha)
    except InputError as exc:    # too few usable points (roadscan.reliable_band)
        raise InputError(path, f"no reliable band in its spectrum ({exc.problem})") from None
    level, how = band.noise_floor, ("the white level of the spectrum's top rings taken off C "
                                     "before the resolution correction")
    if level is None:
        level = _white_level(q, measured, n * dof, band, res)
        how = ("the white level fitted with the power law times the resolution's response, "
               "C = A q^s T(q)^2 + N, to the rings from the band's middle to Nyquist, taken "
               "off C before the resolution correction")
    if level is not None and level > 0:
        # a white floor adds its level to every ring: taken off (C scales as the measured C)
        C = C * (1.0 - level / measured)
        meta["noise_floor_subtracted"] = {
            "level": float(level), "units": "m^4" if kind == "area" else "m^3 (of C1)",
            "applied": how}
    if res is not None:
        # the instrument's Gaussian low-pass undone inside the band (C / T^2 <= 1 / 0.64 there)
        T2 = gaussian_response(q, res) ** 2
        C = C / T2
        band = _noise_after_correction(band, q, measured / T2, n, length, spacing, alpha)
        inside = (q >= band.lo_per_m) & (q <= band.hi_per_m)
        meta["resolution_correction"] = {
            "applied": "C divided by T(q)^2, T = exp(-ln 2 (q r / 2 pi)^2) (Gaussian lateral "
                       "response, 50 % amplitude at the wavelength r)",
            "max_factor": float(1.0 / T2[inside].min()) if inside.any() else 1.0}
    band = _trim_leaky_start(band, q, C, n * dof)   # the roll-off: with_roll_off_verdict
    from pipelines.settings.scan_input import read_record

    meta.update(read_record(obj))           # how the file was read: channel, overrides
    return SourceSpectrum(label, str(path), kind, list(obj.heights_m.shape), spacing_list, size,
                          res, res_src, q, C, n, band, float(dof), meta)
