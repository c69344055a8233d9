"""The result of analysing one scan (:func:`pipelines.analyse`): the ``summary.json`` dict, this
run's warnings, the arrays, and :meth:`AnalysisResult.write`.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

__all__ = ["AnalysisResult"]


@dataclass(frozen=True, eq=False, repr=False)
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
    analysis : pipelines.chain.surface.SurfaceAnalysis
        Levelled scan, spectrum (``analysis.spectrum``), roughness, MPD, anisotropy.
    reliable_band : roadscan.reliable_band.ReliableBand or None
        The band [lo, hi] [1/m] the scan measures without bias, and why each end is there.
    friction_outcome : pipelines.chain.steps.FrictionOutcome or None
        mu(v), the integrated spectrum and band, provenance (None with ``no_friction``).
    texture : roadscan.texture_spectrum.TextureSpectrum
        The ISO 13473-4 texture spectrum.
    settings : pipelines.settings.friction.FrictionSettings
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

    def __repr__(self) -> str:
        """The key figures in one line (the whole summary is in ``.summary``)."""
        s = self.summary
        parts = [f"name={self.name!r}"]
        for key, label in (("hurst", "H"), ("rms_height_m", "rms_height_m")):
            if isinstance(s.get(key), (int, float)):
                parts.append(f"{label}={s[key]:.3g}")
        if self.reliable_band_per_m is not None:
            lo, hi = self.reliable_band_per_m
            parts.append(f"band_per_m=({lo:.3g}, {hi:.3g})")
        mu = self.mu
        if mu is not None and len(mu):
            k = int(max(range(len(mu)), key=lambda i: mu[i]))
            parts.append(f"mu_max={float(mu[k]):.3g} at v={float(self.v_m_per_s[k]):.3g} m/s")
        else:
            parts.append("mu=None")
        parts.append(f"warnings={len(self.warnings)}")
        return f"AnalysisResult({', '.join(parts)})"

    def write(self, out_dir, figures=None):
        """Write exactly the files ``roadscan analyse --out out_dir`` writes, all or none
        (an existing folder is replaced only when it holds an earlier run's outputs).
        ``figures`` (default: unless ``no_figures`` was given) draws the PNGs."""
        from roadscan.io.atomic import atomic_output_dir, check_output_dir

        from pipelines.jobs.analyse.outputs import write_outputs
        from pipelines.output.figure_process import InProcess

        figures = self.figures if figures is None else bool(figures)
        inputs = [self.source_path] if self.source_path is not None else []
        out = Path(out_dir)
        check_output_dir(out, inputs=inputs)
        with InProcess() as drawer, atomic_output_dir(out, inputs=inputs) as tmp:
            write_outputs(self, Path(tmp), figures=figures, drawer=drawer)
        return out
