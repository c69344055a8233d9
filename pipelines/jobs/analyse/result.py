"""The result of analysing one scan (:func:`pipelines.analyse`): the ``summary.json`` dict, this
run's warnings, the arrays, and :meth:`AnalysisResult.write`.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from friction.result import FrictionResult
    from pipelines.chain.steps import FrictionOutcome
    from pipelines.chain.surface import SurfaceAnalysis
    from pipelines.settings.friction import FrictionSettings
    from roadscan.fit import SelfAffineFit
    from roadscan.reliable_band import ReliableBand
    from roadscan.spectrum_types import Spectrum
    from roadscan.texture_spectrum import TextureSpectrum

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
    q_per_m : ndarray of float
        Wave vectors q of the angular-averaged spectrum [1/m] (ascending).
    C_m4 : ndarray of float
        The spectrum C(q) [m^4] at ``q_per_m``, in Persson's normalisation
        <h^2> = 2 pi int q C(q) dq (a profile's 2D estimate for a line scan).
    reliable_band_per_m : tuple of float or None
        (lo, hi): the band of q [1/m] that the scan measures without bias; None when no band was
        found.
    fit : roadscan.fit.SelfAffineFit
        The self-affine fit inside the reliable band: Hurst exponent H, rms height h0 [m],
        C(q0) [m^4], roll-off q0 [1/m].
    v_m_per_s : ndarray of float or None
        Sliding speeds v [m/s] of the friction curve; None when friction was not computed
        (``no_friction``) or was refused.
    mu : ndarray of float or None
        Friction coefficient mu(v) at ``v_m_per_s`` (dimensionless); None as ``v_m_per_s``.
    area_fraction : ndarray of float or None
        Relative contact area A/A0 = P(q1) at each speed (dimensionless, 0 to 1); None as
        ``v_m_per_s``.
    """

    name: str
    summary: dict[str, Any]
    warnings: list[str]
    analysis: SurfaceAnalysis
    reliable_band: ReliableBand | None
    friction_outcome: FrictionOutcome | None
    texture: TextureSpectrum
    window_alpha: float = 0.25
    settings: FrictionSettings | None = None
    figures: bool = True
    source_path: str | os.PathLike[str] | None = None

    @property
    def spectrum(self) -> Spectrum:
        """The angular-averaged spectrum (:class:`roadscan.Spectrum`; a profile's 2D estimate)."""
        return self.analysis.spectrum

    @property
    def q_per_m(self) -> NDArray[np.float64]:
        """Wave vectors q of the spectrum [1/m]."""
        return self.analysis.spectrum.q_per_m

    @property
    def C_m4(self) -> NDArray[np.float64]:
        """The spectrum C(q) [m^4] at :attr:`q_per_m` (Persson's normalisation)."""
        return self.analysis.spectrum.C_m4

    @property
    def fit(self) -> SelfAffineFit | None:
        """:class:`roadscan.fit.SelfAffineFit` (fitted inside the reliable band)."""
        return self.analysis.fit

    @property
    def reliable_band_per_m(self) -> tuple[float, float] | None:
        """(lo, hi) of the reliable band [1/m], or None."""
        rb = self.reliable_band
        return None if rb is None else (float(rb.lo_per_m), float(rb.hi_per_m))

    @property
    def friction(self) -> FrictionResult | None:
        """The friction engine's result (``v_m_per_s``, ``mu``, ``P``, ``T_q_C``) or None."""
        return None if self.friction_outcome is None else self.friction_outcome.result

    @property
    def v_m_per_s(self) -> NDArray[np.float64] | None:
        """Sliding speeds [m/s], or None without friction."""
        return None if self.friction is None else self.friction.v_m_per_s

    @property
    def mu(self) -> NDArray[np.float64] | None:
        """mu(v) at :attr:`v_m_per_s`, or None without friction."""
        return None if self.friction is None else self.friction.mu

    @property
    def area_fraction(self) -> NDArray[np.float64] | None:
        """A/A0 = P(q1) at each speed, or None without friction."""
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
        mu, v = self.mu, self.v_m_per_s
        if mu is not None and v is not None and len(mu):
            k = int(max(range(len(mu)), key=lambda i: mu[i]))
            parts.append(f"mu_max={float(mu[k]):.3g} at v={float(v[k]):.3g} m/s")
        else:
            parts.append("mu=None")
        parts.append(f"warnings={len(self.warnings)}")
        return f"AnalysisResult({', '.join(parts)})"

    def write(self, out_dir: str | os.PathLike[str], figures: bool | None = None) -> Path:
        """Write exactly the files ``roadscan analyse --out out_dir`` writes, all or none
        (an existing folder is replaced only when it holds an earlier run's outputs).
        ``figures`` (default: unless ``no_figures`` was given) draws the PNGs."""
        from pipelines.jobs.analyse.outputs import write_outputs
        from pipelines.output.figure_process import InProcess
        from roadscan.io.atomic import atomic_output_dir, check_output_dir

        figures = self.figures if figures is None else bool(figures)
        inputs = [self.source_path] if self.source_path is not None else []
        out = Path(out_dir)
        check_output_dir(out, inputs=inputs)
        with InProcess() as drawer, atomic_output_dir(out, inputs=inputs) as tmp:
            write_outputs(self, Path(tmp), figures=figures, drawer=drawer)
        return out
