"""``pipelines.analyse``: one scan analysed from Python exactly as ``roadscan analyse`` does
(:func:`analyse`), its options keyword-only and typed, read into the same settings as the
command's flags (:func:`pipelines.settings.keywords.options_of`)."""
from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from pipelines.jobs.analyse.job import analyse_scan

if TYPE_CHECKING:  # numpy's typing only for checkers: the command's --help stays light
    from numpy.typing import ArrayLike

__all__ = ["analyse"]


def analyse(
        source: str | os.PathLike[str] | Any,
        *,
        out: str | os.PathLike[str] | None = None,
        no_figures: bool = False,
        spacing: float | str | tuple[float, float] | None = None,
        units: Literal['m', 'mm', 'um', 'nm'] | None = None,
        x_units: Literal['m', 'mm', 'um', 'nm'] | None = None,
        override_calibration: bool = False,
        channel: int | str | None = None,
        window_alpha: float = 0.25,
        fit_band: tuple[float, float] | str | None = None,
        despike: bool = False,
        mpd_spike_alpha: float | None = None,
        resolution: float | None = None,
        direction: Literal['x', 'y'] = 'x',
        friction_measurement: str | None = None,
        ifi_constants: str | None = None,
        form: Literal['plane', 'poly2', 'poly3'] = 'plane',
        s_filter: float | None = None,
        l_filter: float | None = None,
        rubber: str | os.PathLike[str] | Any | None = None,
        sigma0: float | str = 200000.0,
        temperature: float | None = None,
        flash: bool = False,
        velocities: ArrayLike | str | None = None,
        q0: float | None = None,
        q1: float | None = None,
        contact_gamma: float | None = None,
        nu: float = 0.5,
        extrapolate: Literal['powerlaw', 'hold'] = 'powerlaw',
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
    out : str or os.PathLike, optional
        Also write the command's files into this folder (as ``.write(out)``).
    no_figures : bool, default False
        ``--no-figures``: no PNG figures (and none in report.html) when written.
    spacing : float or str or tuple[float, float] or None, default None
        ``--spacing``: grid spacing in metres for formats that do not carry it (e.g. 5.54e-5 or
        5e-5,6e-5).
    units : Literal['m', 'mm', 'um', 'nm'] or None, default None
        ``--units``: units of the heights in files that carry no units, and of the x (and y)
        columns of text files without unit titles (default m).
    x_units : Literal['m', 'mm', 'um', 'nm'] or None, default None
        ``--x-units``: units of the x (and y) columns of an x,z or x,y,z text file without unit
        titles, when they differ from --units (e.g. x in m, heights in mm).
    override_calibration : bool, default False
        ``--override-calibration``: let --spacing/--units replace the spacing/units a file
        carries (X3P, vendor, .npz with dx/dy..; refused otherwise); recorded as
        calibration_override in summary.json.
    channel : int or str or None, default None
        ``--channel``: page of a multi-page TIFF, colour channel of an RGB/stack TIFF, or
        channel of an instrument file with several (index from 0 or name); recorded in
        summary.json.
    window_alpha : float, default 0.25
        ``--window-alpha``: Tukey window alpha (default 0.25).
    fit_band : tuple[float, float] or str or None, default None
        ``--fit-band``: self-affine fit band [1/m] (default: detected).
    despike : bool, default False
        ``--despike``: mark spikes as unmeasured before levelling.
    mpd_spike_alpha : float or None, default None
        ``--mpd-spike-alpha``: MPD spike criterion |dh| >= ALPHA x sampling interval (ISO
        13473-1 default 3; CAPTIF uses 6 on chip seals, whose stone edges are steep).
    resolution : float or None, default None
        ``--resolution``: the instrument's lateral resolution [m] (wavelength passed at 50 %
        amplitude; default: the file's metadata): the reliable band ends where it still passes
        80 %.
    direction : Literal['x', 'y'], default 'x'
        ``--direction``: driving direction of an area scan for the ISO 13473-4 texture spectrum
        (lines along it are analysed; default x).
    friction_measurement : str or None, default None
        ``--friction-measurement``: friction F measured at slip speed SPEED km/h (e.g. 0.45@30):
        with --ifi-constants gives the IFI F60 of ASTM E1960.
    ifi_constants : str or None, default None
        ``--ifi-constants``: the friction device's IFI calibration constants (ASTM E1960; C
        multiplies MPD in mm, default 0).
    form : Literal['plane', 'poly2', 'poly3'], default 'plane'
        ``--form``: form removed before the roughness figures: least-squares plane (default), or
        polynomial of degree 2 or 3 (ISO 25178-2 F-operator).
    s_filter : float or None, default None
        ``--s-filter``: S-filter nesting index [m]: Gaussian low-pass removing scales below it
        (ISO 16610-61 / -21, 50 % transmission at M) before the roughness figures.
    l_filter : float or None, default None
        ``--l-filter``: L-filter nesting index [m]: Gaussian high-pass removing scales above it
        (waviness), e.g. 0.008; the spectrum and friction stay unfiltered.
    rubber : str or os.PathLike[str] or Any or None, default None
        ``--rubber``: rubber model, friction/RUBBER_TOML.md (default: the thesis's standard
        linear solid, T_ref = 60 C).
    sigma0 : float or str, default 200000.0
        ``--sigma0``: nominal contact pressure sigma0 = load / nominal area, with a unit:
        0.3MPa, 300kPa, 3e5Pa; a bare number is Pa (>= 1 kPa). The engine uses (1 - nu^2) sigma0
        in P(q) (default 0.2MPa).
    temperature : float or None, default None
        ``--temperature``: background temperature T0 [C] (default: the rubber's reference
        temperature).
    flash : bool, default False
        ``--flash``: flash-temperature model (Persson 2006).
    velocities : ArrayLike or str or None, default None
        ``--velocities``: N log-spaced sliding speeds [m/s] from LO to HI, or a list V1,V2,..
        (e.g. another program's table; default 1e-4:1e2:61, where tyres slide).
    q0 : float or None, default None
        ``--q0``: lower end of the friction integrals [1/m], inside the spectrum (default: its
        lowest wave vector).
    q1 : float or None, default None
        ``--q1``: upper end of the friction integrals [1/m]; beyond the Nyquist wave vector the
        spectrum is extended by its self-affine fit.
    contact_gamma : float or None, default None
        ``--contact-gamma``: Persson's S(q) = G + (1 - G) P(q)^2 in the dissipation integrand
        (mu = 1/2 int q^3 C S P M dq); 0 <= G <= 1, e.g. 0.5 (default: off, S = 1).
    nu : float, default 0.5
        ``--nu``: Poisson ratio of the rubber, 0 <= nu <= 0.5 (default 0.5).
    extrapolate : Literal['powerlaw', 'hold'], default 'powerlaw'
        ``--extrapolate``: master curve beyond its measured frequencies: powerlaw (E' held, E''
        continues as the power law of its last decade; default) or hold (both held).
    no_friction : bool, default False
        ``--no-friction``: skip mu(v).

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
            raise TypeError(f"analyse() source must be a path, HeightMap or Profile, not "
                            f"{type(source).__name__}")
        result = analyse_scan(scan, settings, **kw)   # a ValueError here is a bug, not bad input
    result = replace(result, figures=not args.no_figures, source_path=path)
    if out is not None:
        result.write(out)
    return result
