"""``pipelines.analyse(source, **options)``: the analysis of one scan as a Python call.

The very computation ``roadscan analyse`` runs for each file (the command parses its flags,
calls :func:`analyse_scan` and writes the result): the metrology chain, the reliable band, the
self-affine fit, the road-texture figures and Persson friction (:mod:`pipelines.chain`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["analyse", "analyse_scan", "AnalysisResult"]


@dataclass(frozen=True, eq=False)
class AnalysisResult:
    """One analysed scan (SI units).

    Attributes
    ----------
    name : str
        The scan's name (its file's stem).
    summary : dict
        Exactly the ``summary.json`` that ``roadscan analyse`` writes for the same options.
    warnings : list of str
        This run's warnings only (reading the file included).
    analysis : pipelines.spectrum_bridge.SurfaceAnalysis
        Levelled scan, spectrum (``analysis.spectrum``), roughness, MPD, anisotropy.
    reliable_band : roadscan.reliable_band.ReliableBand or None
        The band [lo, hi] [1/m] the scan measures without bias, and why each end is there.
    friction_outcome : pipelines.chain.FrictionOutcome or None
        mu(v), the integrated spectrum and band, provenance (None with ``no_friction``).
    texture : roadscan.texture_spectrum.TextureSpectrum
        The ISO 13473-4 texture spectrum.
    settings : pipelines.friction_options.FrictionSettings
        The friction options used.

    The arrays: :attr:`q_per_m`, :attr:`C_m4` (the spectrum, Persson's normalisation
    <h^2> = 2 pi int q C dq), :attr:`reliable_band_per_m`, :attr:`fit` (H, h0, C(q0), roll-off),
    :attr:`v_m_per_s`, :attr:`mu`, :attr:`area_fraction` (A/A0 = P(q1) per speed; None when
    friction was not computed or was refused).
    """

    name: str
    summary: dict
    warnings: list
    analysis: object
    reliable_band: object
    friction_outcome: object
    texture: object
    window_alpha: float = 0.25
    settings: object = None
    figures: bool = True
    source_path: object = None
    _extra: dict = field(default_factory=dict, repr=False)

    @property
    def spectrum(self):
        """The angular-averaged spectrum (:class:`roadscan.Spectrum`; a profile's 2D estimate)."""
        return self.analysis.spectrum

    @property
    def q_per_m(self):
        return self.analysis.spectrum.q_per_m

    @property
    def C_m4(self):
        return self.analysis.spectrum.C_m4

    @property
    def fit(self):
        """:class:`roadscan.fit.SelfAffineFit` (fitted inside the reliable band)."""
        return self.analysis.fit

    @property
    def reliable_band_per_m(self):
        rb = self.reliable_band
        return None if rb is None else (float(rb.lo_per_m), float(rb.hi_per_m))

    @property
    def friction(self):
        """The friction engine's result (``v_m_per_s``, ``mu``, ``P``, ``T_q_C``) or None."""
        return None if self.friction_outcome is None else self.friction_outcome.result

    @property
    def v_m_per_s(self):
        return None if self.friction is None else self.friction.v_m_per_s

    @property
    def mu(self):
        return None if self.friction is None else self.friction.mu

    @property
    def area_fraction(self):
        return None if self.friction is None else self.friction.P[:, -1]

    def write(self, out_dir, figures=None):
        """Write exactly the files ``roadscan analyse --out out_dir`` writes, all or none
        (an existing folder is replaced only when it holds an earlier run's outputs).
        ``figures`` (default: unless ``no_figures`` was given) draws the PNGs."""
        from roadscan.io.atomic import atomic_output_dir, check_output_dir

        from .analyse import write_outputs
        from .figure_process import InProcess

        figures = self.figures if figures is None else bool(figures)
        inputs = [self.source_path] if self.source_path is not None else []
        out = Path(out_dir)
        check_output_dir(out, inputs=inputs)
        with InProcess() as drawer, atomic_output_dir(out, inputs=inputs) as tmp:
            write_outputs(self, Path(tmp), figures=figures, drawer=drawer)
        return out


def analyse_scan(scan, settings=None, window_alpha=0.25, fit_band=None, despike=False,
                 mpd_settings=None, texture=None, resolution_m=None, on_levelled=None,
                 on_spectrum2d=None):
    """Analyse a read HeightMap/Profile with checked options -> :class:`AnalysisResult`.

    The warnings are those of the current scope (:func:`pipelines.validate.collecting`).

    Parameters
    ----------
    scan : HeightMap or Profile
        The scan [m].
    settings : FrictionSettings, optional
        Friction options (default: the defaults).
    window_alpha : float, optional
        Tukey window.
    fit_band : tuple of float, optional
        Fit band [1/m].
    despike : bool, optional
        Replace spikes first.
    mpd_settings : dict, optional
        ISO 13473-1 settings.
    texture : TextureSettings, optional
        Texture options.
    resolution_m : float, optional
        Lateral resolution [m].
    on_levelled, on_spectrum2d : callable, optional
        Hooks called with the levelled map and the 2D spectrum.

    Returns
    -------
    AnalysisResult
    """
    from . import analyse_band, texture_outputs
    from .analyse import summarise
    from .chain import measure, scan_friction
    from .friction_options import FrictionSettings
    from .validate import warnings_list

    settings = settings or FrictionSettings()
    an, rb = measure(scan, window_alpha, fit_band, despike, mpd_settings, resolution_m,
                     on_levelled, on_spectrum2d)
    out = scan_friction(an, rb, settings) if settings.enabled else None
    fr = None if out is None else out.result
    summary = summarise(an, fr, window_alpha=window_alpha)
    summary.update(analyse_band.summary_keys(rb, an.name))
    if fr is not None:
        summary["friction"].update(
            q0_per_m=float(fr.q_per_m[0]), sigma0_Pa=settings.sigma0_Pa, nu=settings.nu,
            contact_gamma=settings.contact_gamma,
            area_fraction_range=[float(fr.P[:, -1].min()), float(fr.P[:, -1].max())])
        if out.band is not None:
            summary["friction"]["band"] = out.band
        if out.checks is not None:
            summary["friction"]["rubber_checks"] = out.checks
    if out is not None:
        analyse_band.add_provenance(summary, out.provenance, out.psd.q_min_per_m, out.psd.q1_per_m)
    summary, tex = texture_outputs.add_to_summary(summary, an, texture, mpd_settings)
    summary["warnings"] = warnings_list()
    return AnalysisResult(an.name, _as_json(summary), list(summary["warnings"]), an, rb, out,
                          tex, window_alpha=window_alpha, settings=settings)


def _as_json(summary):
    """The dict as ``summary.json`` holds it (numpy numbers as floats, tuples as lists,
    non-finite numbers as null), so that ``.summary`` equals the file key for key."""
    import json

    from .report import _jsonable

    return json.loads(json.dumps(_jsonable(summary)))


def analyse(source, **options):
    """Analyse one scan as ``roadscan analyse`` does -> :class:`AnalysisResult`.

    Parameters
    ----------
    source : str, os.PathLike, HeightMap or Profile
        A height file (read as ``roadscan analyse`` reads it) or a scan in memory.
    **options
        ``roadscan analyse``'s long flags with dashes as underscores, taking what the flag
        takes: ``analyse("s.npy", spacing="2e-5", rubber="r.toml", sigma0="0.25MPa", nu=0.45,
        contact_gamma=0.6)``; switches take True (``no_friction=True``, ``flash=True``).

    Returns
    -------
    AnalysisResult
        ``.summary`` equals the ``summary.json`` of ``roadscan analyse`` with the same flags;
        ``.warnings`` are this call's only; ``.write(out_dir)`` writes the command's files.

    Raises
    ------
    TypeError
        An unknown keyword (named).
    roadscan.InputError
        A file or a value that cannot be analysed (one line naming the file or the flag).

    Notes
    -----
    Spectrum: Persson's normalisation <h^2> = 2 pi int q C(q) dq, Tukey window; friction:
    Persson, J. Chem. Phys. 115, 3840 (2001) with the flash temperature of Persson, J. Phys.:
    Condens. Matter 18, 7789 (2006).
    """
    import os

    from roadscan.heightmap import HeightMap, Profile

    from .analyse_options import analysis_kwargs, options_from_kwargs
    from .friction_options import settings_from_args
    from .validate import check_scan, collecting

    args = options_from_kwargs(options)
    path = None
    with collecting():
        kw = analysis_kwargs(args)
        settings = settings_from_args(args)
        if isinstance(source, (HeightMap, Profile)):
            scan = check_scan(source)
        elif isinstance(source, (str, os.PathLike)):
            from .scan_input import load_scan

            path = Path(source)
            scan = load_scan(path, args)
        else:
            raise TypeError(f"analyse() source must be a path, HeightMap or Profile, not "
                            f"{type(source).__name__}")
        try:
            result = analyse_scan(scan, settings, **kw)
        except ValueError as exc:
            from roadscan.errors import InputError

            if isinstance(exc, InputError):
                raise
            raise InputError(path, str(exc)) from None
    from dataclasses import replace

    return replace(result, figures=not args.no_figures, source_path=path)
