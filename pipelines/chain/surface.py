"""From a read scan to everything the reports need: the metrology chain in one place.

read -> level (plane, ignoring unmeasured points) -> roughness of the levelled measured heights
-> fill unmeasured points -> Tukey-windowed PSD -> self-affine fit; plus the bridge from a
measured spectrum to the friction engine's PSD (docs: Theory, "which spectrum").
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from roadscan.heightmap import HeightMap, Profile

if TYPE_CHECKING:
    from roadscan.fit import SelfAffineFit
    from roadscan.spectrum_types import Spectrum, Spectrum2D
    from roadscan.texture_depth import MpdSegments

__all__ = [
    "SurfaceAnalysis",
    "analyse_surface",
    "surface_psd",
    "default_velocities",
    "friction_curve",
    "spectrum_of",
]


@dataclass(eq=False)
class SurfaceAnalysis:
    """Everything derived from one scan (area or line profile).

    ``filled`` (levelled and inpainted: what the FFT saw) is rebuilt from ``levelled`` and
    the filled values when first read, so that a big scan is not held three times over.

    Attributes
    ----------
    source : HeightMap or Profile
        The scan as read.
    levelled : HeightMap or Profile
        Levelled scan.
    fill : tuple
        Filled values.
    filled_fraction : float
        Share of points filled.
    spectrum : roadscan.Spectrum
        The spectrum.
    spec2d : Spectrum2D or None
        2D spectrum (areas).
    psd1d : tuple or None
        1D spectrum (profiles).
    fit : SelfAffineFit or None
        The fit.
    roughness : dict
        Roughness figures.
    mpd_m : float or None
        Mean profile depth [m].
    mpd_note : str
        How it was computed.
    anisotropy : dict or None
        Directional distribution.
    mpd_segments : MpdSegments or None
        The MPD's per-segment table (ISO 13473-1), lines along x.
    """

    source: HeightMap | Profile  # as read
    levelled: HeightMap | Profile  # levelled, unmeasured points still unmeasured
    fill: tuple  # (values at the unmeasured points in raster order, meta) or
    # (the filled HeightMap/Profile, None)
    filled_fraction: float
    spectrum: Spectrum  # isotropic 2D C(q) [m^4]
    spec2d: Spectrum2D | None = None  # for areas, None for profiles
    psd1d: tuple | None = None  # (q_per_m, C1_m3) for profiles
    fit: SelfAffineFit | None = None
    roughness: dict = field(default_factory=dict)
    mpd_m: float | None = None
    mpd_note: str = ""
    anisotropy: dict | None = None
    mpd_segments: MpdSegments | None = None  # the MPD's segments (source's rows)

    @property
    def filled(self):
        """The levelled map with its unmeasured points filled (a HeightMap or Profile)."""
        values, meta = self.fill
        if meta is None:
            return values
        lev = self.levelled
        h = lev.heights_m.copy()
        h[lev.unmeasured] = values
        filled = lev._adopt(h, unmeasured=np.zeros_like(lev.unmeasured), meta=dict(meta))
        self.fill = (filled, None)
        return filled

    @property
    def is_profile(self):
        return isinstance(self.source, Profile)

    @property
    def name(self):
        return self.source.name


def spectrum_of(obj, window_alpha=0.25):
    """PSD of an already levelled, fully measured HeightMap/Profile -> (Spectrum, spec2d, psd1d).

    Parameters
    ----------
    obj : HeightMap or Profile
        Levelled, fully measured scan.
    window_alpha : float, optional
        Tukey window.

    Returns
    -------
    tuple
        (Spectrum, spec2d or None, psd1d or None).
    """
    from roadscan import spectrum as sp

    if isinstance(obj, Profile):
        q1, c1, spec = sp.psd_profile(obj, window_alpha=window_alpha)
        return spec, None, (q1, c1)
    spec, spec2d = sp.psd_area(obj, window_alpha=window_alpha)
    return spec, spec2d, None


def analyse_surface(
    obj,
    window_alpha=0.25,
    level_degree=1,
    despike=False,
    fit_band=None,
    mpd_settings=None,
    on_levelled=None,
    on_spectrum2d=None,
    fit=True,
):
    """Run the metrology chain on a HeightMap or Profile (see module docstring).

    ``mpd_settings`` overrides :data:`roadscan.roughness.MPD_SETTINGS` (e.g. ``spike_alpha``).
    ``on_levelled(levelled)``, when given, is called as soon as the levelled scan exists, before
    the spectrum (``roadscan analyse`` hands the height map to its figure process there), and
    ``on_spectrum2d(spec2d)`` as soon as a map's 2D spectrum exists (before the fit and the
    anisotropy). ``fit=False`` leaves ``fit`` None (:func:`pipelines.chain.steps.measure` fits once,
    inside the reliable band).

    Parameters
    ----------
    obj : HeightMap or Profile
        The scan [m].
    window_alpha : float, optional
        Tukey window.
    level_degree : int, optional
        Form removed.
    despike : bool, optional
        Replace spikes.
    fit_band : tuple of float, optional
        Fit band [1/m].
    mpd_settings : dict, optional
        ISO 13473-1 settings.
    on_levelled, on_spectrum2d : callable, optional
        Hooks.
    fit : bool, optional
        Fit the self-affine model.

    Returns
    -------
    SurfaceAnalysis
    """
    from roadscan import fit as fitmod
    from roadscan import inpaint, level, roughness
    from roadscan.spectrum import anisotropy
    from roadscan.trim import road_section

    if not isinstance(obj, (HeightMap, Profile)):
        raise TypeError(f"expected HeightMap or Profile, got {type(obj).__name__}")
    if isinstance(obj, Profile):
        obj = road_section(obj)  # a profiler's reference plates are not road
    work = level.remove_spikes(obj) if despike else obj
    levelled = level.level(work, degree=level_degree)
    if on_levelled is not None:
        from pipelines.jobs.texture.prefetch import levelled_from

        with levelled_from(levelled, obj, mpd_settings):  # the source of a texture prefetch
            on_levelled(levelled)
    from roadscan.texture_depth import mpd_and_segments

    if isinstance(obj, Profile):
        rough = roughness.profile_parameters(levelled)
    else:
        rough = roughness.area_parameters(levelled)
    # the MPD and its segment table from one pass (mean_profile_depth(_area)'s values)
    mpd_m, mpd_note, mpd_seg = mpd_and_segments(obj, **(mpd_settings or {}))
    undefined = [k for k in ("Sdq", "Sdr", "Rdq") if k in rough and rough[k] is None]
    if undefined:
        from pipelines.checks.validate import warn

        warn(
            f"{obj.name}: {', '.join(undefined)} undefined (no measured neighbours to take a slope "
            f"from): null in the outputs"
        )
    if isinstance(obj, Profile):
        filled, filled_fraction = inpaint.fill_unmeasured(levelled)
        fill = (filled, None)
        spec, spec2d, psd1d = spectrum_of(filled, window_alpha)
    else:
        # a big scan is not copied for the fill: the FFT step reads the levelled map with the
        # filled values put in band by band; ``filled`` is rebuilt when asked for
        from roadscan.spectrum import psd_area

        values = inpaint.unmeasured_fill(levelled)
        filled_fraction = float(levelled.unmeasured.mean())
        fill = (values, dict(levelled.meta, fill_method="biharmonic", filled_fraction=filled_fraction))
        spec, spec2d = psd_area(levelled, window_alpha=window_alpha, fill_values=values)
        psd1d = None
        if on_spectrum2d is not None:
            on_spectrum2d(spec2d)
    fit = fitmod.fit_self_affine(spec, band=fit_band) if fit else None
    aniso = anisotropy(spec2d) if spec2d is not None else None
    return SurfaceAnalysis(
        obj,
        levelled,
        fill,
        float(filled_fraction),
        spec,
        spec2d,
        psd1d,
        fit,
        rough,
        mpd_m,
        mpd_note,
        aniso,
        mpd_segments=mpd_seg,
    )


def surface_psd(spectrum, fit=None, q1_per_m=None):
    """The friction engine's PSD for a measured spectrum.

    Integrates the measured angular average from its lowest ring to its highest (the Nyquist
    wave vector pi/a), with q0 (for the macro-asperity wave vector q_m = zeta_m q0) at the
    detected roll-off, else the lowest wave vector (docs: Theory). With ``q1_per_m``
    beyond the measured band, the spectrum is continued by the fitted self-affine power law
    (:func:`roadscan.fit.extend_spectrum`) up to q1: roughness below the scan's resolution;
    with q1 inside the band the spectrum is cut at its first ring at or above q1 (``apply_band``
    then cuts at q1 exactly); q1 at or below the lowest measured wave
    vector is refused (:func:`pipelines.checks.validate.check_q1`).

    Parameters
    ----------
    spectrum : roadscan.Spectrum
        The measured spectrum.
    fit : SelfAffineFit, optional
        Its fit.
    q1_per_m : float, optional
        Extension [1/m].

    Returns
    -------
    friction.TabulatedPSD
    """
    from friction import TabulatedPSD
    from pipelines.checks.validate import check_q1
    from roadscan.fit import extend_spectrum

    check_q1(q1_per_m, float(np.min(spectrum.q_per_m)))
    if q1_per_m is not None and q1_per_m > spectrum.q_max_per_m:
        if fit is None:
            raise ValueError("extending a spectrum beyond its band needs its self-affine fit")
        spectrum = extend_spectrum(spectrum, fit, q1_per_m)
    q = np.asarray(spectrum.q_per_m, dtype=float)
    C = np.asarray(spectrum.C_m4, dtype=float)
    ok = np.isfinite(C) & (C > 0) & np.isfinite(q) & (q > 0)
    if q1_per_m is not None and np.any(ok & (q >= q1_per_m)):  # q1 inside the measured band:
        q_end = np.min(q[ok & (q >= q1_per_m)])  # cut at the first ring >= q1
        ok &= q <= q_end
    q, C = q[ok], C[ok]
    if q.size < 2:
        from roadscan.errors import InputError

        raise InputError(None, f"--q1 {q1_per_m:g} 1/m leaves {q.size} wave vector(s) of the spectrum")
    q0 = None
    if fit is not None and getattr(fit, "q_roll_per_m", None):
        q0 = float(np.clip(fit.q_roll_per_m, q[0], q[-1]))
    return TabulatedPSD(q, C, q0_per_m=q0)


def default_velocities(lo=1e-4, hi=1e2, per_decade=10):
    """Default sliding speeds: 1e-4 to 1e2 m/s at 10 per decade (61 points), the range tyres
    slide at on roads (the thesis's range was 1e-8..1e4, still one ``--velocities
    1e-8:1e4:121`` away).

    Parameters
    ----------
    lo, hi : float, optional
        Range [m/s].
    per_decade : int, optional
        Speeds per decade.

    Returns
    -------
    ndarray
    """
    n = int(round(np.log10(hi / lo) * per_decade)) + 1
    return np.logspace(np.log10(lo), np.log10(hi), n)


def friction_curve(
    psd,
    rubber=None,
    v_m_per_s=None,
    sigma0_Pa=0.2e6,
    T0_C=None,
    flash=False,
    nu=0.5,
    contact_gamma=None,
    warn_high=True,
    tol=None,
):
    """mu(v) from the shared engine (Persson's theory; :func:`friction.mu_isothermal`,
    :func:`friction.mu_flash`) with the defaults nu = 0.5, S = 1, the thesis rubber at its
    T_ref, and the engine's accuracy target ``tol`` (relative, 1e-3) unless given.

    Parameters
    ----------
    psd : spectrum
        The spectrum.
    rubber : rubber model, optional
        Default the thesis rubber.
    v_m_per_s : array_like, optional
        Speeds [m/s].
    sigma0_Pa : float, optional
        Nominal pressure [Pa].
    T0_C : float, optional
        Temperature [C].
    flash : bool, optional
        Flash-temperature model.
    nu : float, optional
        Poisson's ratio.
    contact_gamma : float, optional
        Persson's gamma.
    warn_high : bool, optional
        Warn when mu > 5.
    tol : float, optional
        Relative tolerance.

    Returns
    -------
    friction.FrictionResult

    References
    ----------
    B.N.J. Persson, J. Chem. Phys. 115, 3840 (2001), doi:10.1063/1.1388626.
    """
    import friction
    from pipelines.checks.validate import check_mu, check_temperature

    rubber = friction.thesis_rubber() if rubber is None else rubber
    check_temperature(T0_C, rubber)
    v = default_velocities() if v_m_per_s is None else np.asarray(v_m_per_s, float)
    kw = dict(sigma0_Pa=sigma0_Pa, T0_C=T0_C, nu=nu, contact_gamma=contact_gamma)
    if tol is not None:
        kw["tol"] = tol
    from friction.flash import FlashBandError, FlashConvergenceError
    from roadscan.errors import InputError

    try:
        with np.errstate(all="ignore"):
            if flash:
                res = friction.mu_flash(psd, rubber, v, **kw)
            else:
                res = friction.mu_isothermal(psd, rubber, v, **kw)
    except FlashConvergenceError as exc:  # one line naming the speeds (as `friction` says)
        raise InputError(None, f"friction: {exc}") from None
    except FlashBandError as exc:  # the band is an input (the scan's, or --q1)
        raise InputError(
            None,
            f"friction: the flash-temperature model needs the band to reach the macro-asperity "
            f"wave vector q_m = {exc.zeta_m:g} q0 = {exc.q_m_per_m:.3g} 1/m, but it ends at "
            f"q1 = {exc.q1_per_m:.3g} 1/m (a band shorter than its factor in q): widen the band "
            "({q1}) or leave out {flash}",
            hint_option=("q1", "flash"),
        ) from None
    check_mu(res.mu, warn_high=warn_high)
    return res
