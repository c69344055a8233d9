"""Inputs of the friction-level diagnosis: the surface (a scan or a psd.csv) and the rubber,
assembled into a :class:`model.FrictionContext`.

``psd.csv``: header with columns ``q_per_m`` [1/m] and ``C_m4`` [m^4] (Persson's normalisation,
as written by ``roadscan analyse``); rows with C <= 0 are dropped. The engine integrates it from
its lowest to its highest q (docs: Theory).
"""

from __future__ import annotations

from pipelines.diagnosis.model import FrictionContext, SimSpec
from pipelines.output.csv_files import read_psd_csv

__all__ = ["read_psd_csv", "write_psd_csv", "surface_from_scan", "scan_surface", "build_context"]


def write_psd_csv(path, q_per_m, C_m4):
    """Write ``q_per_m,C_m4`` (Persson's normalisation) to ``path``.

    Parameters
    ----------
    path : str or Path
        The CSV file to write (header ``q_per_m,C_m4``).
    q_per_m, C_m4 : array_like, shape (m,)
        Wave vectors q [1/m] and the isotropic PSD C(q) [m^4] at them.

    Returns
    -------
    Path
        The file written.
    """
    from pipelines.output.report import write_csv

    return write_csv(path, ["q_per_m", "C_m4"], [q_per_m, C_m4])


def surface_from_scan(obj):
    """Analyse a scan -> (friction PSD, filled HeightMap/Profile, Spectrum, fit).

    Parameters
    ----------
    obj : HeightMap or Profile
        The road scan, heights in m (as read by ``roadscan``).

    Returns
    -------
    tuple
        (psd, filled scan, Spectrum, fit).
    """
    from pipelines.chain.surface import analyse_surface, surface_psd

    an = analyse_surface(obj)
    return surface_psd(an.spectrum, an.fit), an.filled, an.spectrum, an.fit


def scan_surface(obj, q0_per_m=None, q1_per_m=None, resolution_m=None):
    """A measured scan's friction spectrum from the one chain (:mod:`pipelines.chain.steps`), as
    ``roadscan analyse`` integrates it -> (friction PSD, filled HeightMap/Profile, Spectrum, fit).

    The spectrum over the scan's reliable band (or ``--q0``/``--q1`` [1/m]; above the scan C(q)
    continues as the self-affine fit); a band whose fine end the measurement does not support
    (:func:`pipelines.chain.steps.judge_fine_end`) is refused in one line naming the flags.

    Parameters
    ----------
    obj : HeightMap or Profile
        The road scan, heights in m (as read by ``roadscan``).
    q0_per_m, q1_per_m : float, optional
        Ends of the friction band [1/m] (``--q0``/``--q1``); None: the scan's reliable band.
    resolution_m : float, optional
        The instrument's lateral resolution [m]; None: the scan file's metadata.

    Returns
    -------
    tuple
        (psd, filled scan, Spectrum, fit).
    """
    from pipelines.chain.steps import friction_psd, judge_fine_end, measure
    from pipelines.settings.friction import FrictionSettings
    from roadscan.errors import InputError

    an, rb = measure(obj, resolution_m=resolution_m)
    settings = FrictionSettings(q0_per_m=q0_per_m, q1_per_m=q1_per_m)
    psd, _ = friction_psd(an.spectrum, an.fit, rb, settings, an.name)
    _, refused = judge_fine_end(psd, rb, settings, an.name)
    if refused is not None:
        raise InputError(None, refused.replace("friction refused: ", "the scan's friction band is refused: "))
    return psd, an.filled, an.spectrum, an.fit


def build_context(curve, psd, rubber=None, scan=None, spectrum=None, fit=None, extra_inputs=()):
    """The baseline model (the engine's defaults, see Theory in the docs) on the rows of ``curve``.

    Parameters
    ----------
    curve : MeasuredCurve
        The measured rows: speeds [m/s], temperatures [C], pressures [Pa], wet flags.
    psd : spectrum
        The road's C(q) [m^4] the baseline integrates (TabulatedPSD or SelfAffinePSD).
    rubber : rubber model, optional
        Default the thesis rubber.
    scan : HeightMap, optional
        The levelled, filled scan; a HeightMap makes ``"scan"`` available (the water effect).
    spectrum, fit : optional
        The scan's measured Spectrum and its self-affine fit; None with a ``--psd`` file.
    extra_inputs : iterable of str, optional
        Input names added to ``{"psd", "rubber"}`` (e.g. ``"master_curve"``).

    Returns
    -------
    FrictionContext
        The rows of ``curve`` with ``SimSpec(psd, rubber)`` (engine defaults) as baseline.
    """
    import friction
    from roadscan.heightmap import HeightMap

    rubber = friction.thesis_rubber() if rubber is None else rubber
    inputs = {"psd", "rubber"} | set(extra_inputs)
    if isinstance(scan, HeightMap):
        inputs.add("scan")
    return FrictionContext.from_measured(
        curve, SimSpec(psd=psd, rubber=rubber), scan=scan, spectrum=spectrum, fit=fit, inputs=inputs
    )
