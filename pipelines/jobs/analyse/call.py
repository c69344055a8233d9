"""``pipelines.analyse``: one scan analysed from Python exactly as ``roadscan analyse`` does
(:func:`analyse`), its options keyword-only and typed, read into the same settings as the
command's flags (:func:`pipelines.settings.keywords.options_of`)."""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from pipelines.jobs.analyse.job import analyse_scan
from pipelines.settings.option_docs import document_options

if TYPE_CHECKING:  # numpy's typing only for checkers: the command's --help stays light
    from numpy.typing import ArrayLike

    from friction.rubber import Rubber

__all__ = ["analyse"]


@document_options(
    overrides={
        "out": "Also write the command's files into this folder (as ``.write(out)``); default: write nothing."
    }
)
def analyse(
    source: str | os.PathLike[str] | Any,
    *,
    out: str | os.PathLike[str] | None = None,
    no_figures: bool = False,
    spacing: float | str | tuple[float, float] | None = None,
    units: Literal["m", "mm", "um", "nm"] | None = None,
    x_units: Literal["m", "mm", "um", "nm"] | None = None,
    override_calibration: bool = False,
    channel: int | str | None = None,
    window_alpha: float = 0.25,
    fit_band: tuple[float, float] | str | None = None,
    despike: bool = False,
    mpd_spike_alpha: float | None = None,
    resolution: float | None = None,
    direction: Literal["x", "y"] = "x",
    friction_measurement: str | None = None,
    ifi_constants: str | None = None,
    form: Literal["plane", "poly2", "poly3"] = "plane",
    s_filter: float | None = None,
    l_filter: float | None = None,
    rubber: str | os.PathLike[str] | Rubber | None = None,
    sigma0: float | str = 200000.0,
    temperature: float | None = None,
    flash: bool = False,
    velocities: ArrayLike | str | None = None,
    q0: float | None = None,
    q1: float | None = None,
    contact_gamma: float | None = None,
    nu: float = 0.5,
    extrapolate: Literal["powerlaw", "hold"] = "powerlaw",
    no_friction: bool = False,
) -> Any:
    """Analyse one scan as ``roadscan analyse`` does -> :class:`AnalysisResult`.

    The scan is levelled, windowed and Fourier-transformed into the angular-averaged PSD C(q)
    (Persson's normalisation <h^2> = 2 pi int q C(q) dq), its reliable band of wave vectors is
    found, the self-affine fit gives the Hurst exponent and rms height, the ISO 25178-2 and
    ISO 13473 texture figures are computed, and Persson's theory gives mu(v) (Persson, J. Chem.
    Phys. 115, 3840 (2001), doi:10.1063/1.1388626; with ``flash=True`` the flash temperature of
    Persson, J. Phys.: Condens. Matter 18, 7789 (2006), doi:10.1088/0953-8984/18/32/025).
    Every option is a long flag of ``roadscan analyse`` with underscores; numbers are SI.

    Parameters
    ----------
    source : str, os.PathLike, HeightMap or Profile
        A height file (read as ``roadscan analyse`` reads it) or a scan in memory [m].
    {options}

    Returns
    -------
    AnalysisResult
        ``.summary`` equals the ``summary.json`` of ``roadscan analyse`` with the same flags;
        ``.warnings`` are this call's only (each also issued as a
        :class:`roadscan.RoadscanWarning`); ``.write(out_dir)`` writes the command's files.

    Raises
    ------
    roadscan.InputError
        A file or a value that cannot be analysed (one line naming the file or the option).

    Examples
    --------
    >>> import pipelines
    >>> r = pipelines.analyse("sample_scans/asphalt.x3p", sigma0=2.5e5)   # doctest: +SKIP
    >>> r.summary["hurst"]                                                 # doctest: +SKIP
    """
    from pipelines.checks.validate import check_scan, collecting
    from pipelines.settings.analyse import analysis_kwargs
    from pipelines.settings.friction import settings_from_args
    from pipelines.settings.keywords import options_of
    from roadscan.blas_threads import single_threaded_blas
    from roadscan.heightmap import HeightMap, Profile

    args = options_of(analyse, locals())
    path = None
    # one BLAS thread for the call: the chain's own texture thread is its parallelism, and
    # OpenBLAS's pool beside it would spin on the second core (restored on return)
    with collecting(), single_threaded_blas():
        kw = analysis_kwargs(args)
        settings = settings_from_args(args)
        if isinstance(source, (HeightMap, Profile)):
            scan = check_scan(source)
        elif isinstance(source, (str, os.PathLike)):
            from pipelines.settings.scan_input import load_scan

            path = Path(source)
            scan = load_scan(path, args)
        else:
            raise TypeError(
                f"analyse() source must be a path, HeightMap or Profile, not {type(source).__name__}"
            )
        result = analyse_scan(scan, settings, **kw)  # a ValueError here is a bug, not bad input
    result = replace(result, figures=not args.no_figures, source_path=path)
    if out is not None:
        result.write(out)
    return result
