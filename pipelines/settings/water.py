"""The options of ``roadscan rain-fill`` and ``roadscan dry-vs-wet`` in one place: the flags
(:func:`add_rain_fill_options`, :func:`add_dry_vs_wet_options`, both built on
:func:`add_water_options`) that the commands parse and that :func:`pipelines.rain_fill`
and :func:`pipelines.dry_vs_wet` take as keywords (a long flag with dashes as
underscores), so that the command and the API read the same definitions.

The water model is the morphological reconstruction of Soille, *Morphological Image
Analysis*, 2003, sec. 6.3.7 (:mod:`roadscan.rain`).
"""

from __future__ import annotations

import math

from roadscan.errors import InputError

__all__ = [
    "add_water_options",
    "check_water",
    "check_water_options",
    "add_rain_fill_options",
    "add_dry_vs_wet_options",
    "add_wet_model_options",
    "wet_conditions",
]


def add_water_options(p):
    """``--connectivity 4|8`` and ``--max-depth M`` / ``--water-film M`` [m] (at most one).

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser to extend.

    Returns
    -------
    None
    """
    p.add_argument(
        "--connectivity",
        type=int,
        choices=(4, 8),
        default=4,
        help="connectivity of the fill (default 4, as Matlab's imfill)",
    )
    g = p.add_mutually_exclusive_group()
    g.add_argument(
        "--max-depth",
        type=float,
        default=None,
        metavar="M",
        help="water at most this deep above each depression's lowest point [m]",
    )
    g.add_argument(
        "--water-film",
        type=float,
        default=None,
        metavar="M",
        help="water available per area [m^3/m^2 = m]; fills to the smallest depth cap holding it",
    )


def check_water(max_depth_m=None, water_film_m=None):
    """Refuse a negative or non-finite depth cap or water film (one-line InputError naming the
    flag).

    Parameters
    ----------
    max_depth_m, water_film_m : float, optional
        Depth cap and water film [m].

    Returns
    -------
    None
    """
    for flag, val in (("--max-depth", max_depth_m), ("--water-film", water_film_m)):
        if val is not None and not (math.isfinite(val) and val >= 0):
            raise InputError(None, f"{flag} {val}: must be a non-negative length in metres")


def check_water_options(args):
    """``--max-depth`` / ``--water-film`` checked (:func:`check_water`:
    one-line InputError naming the flag).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    None
    """
    if args.max_depth is not None and args.water_film is not None:  # the flags' either-or
        raise InputError(None, "give --max-depth or --water-film, not both")
    check_water(args.max_depth, args.water_film)


def add_rain_fill_options(p):
    """Every option of ``roadscan rain-fill``: how the scan is read, the water, ``--no-level``.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser to extend.

    Returns
    -------
    None
    """
    from pipelines.settings.scan_input import add_scan_options

    add_scan_options(p)
    add_water_options(p)
    p.add_argument(
        "--no-level",
        action="store_true",
        help="fill the heights as read (default: remove the least-squares plane first)",
    )


def add_dry_vs_wet_options(p):
    """Every option of ``roadscan dry-vs-wet``: how the scan is read, the water, the spectrum
    (``--window-alpha``, ``--fit-band``, ``--despike``, ``--resolution``) and friction.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser to extend.

    Returns
    -------
    None
    """
    from pipelines.settings.analyse import add_spectrum_options
    from pipelines.settings.friction import add_friction_options
    from pipelines.settings.scan_input import add_scan_options

    add_scan_options(p)
    add_water_options(p)
    add_wet_model_options(p)
    add_spectrum_options(p)  # --window-alpha, --fit-band, --despike, --resolution
    add_friction_options(p)
    p.add_argument(
        "--no-figures",
        action="store_true",
        help="skip the PNG figures and the 3D view (every CSV/JSON number is the same; report.html "
        "keeps its tables)",
    )


def add_wet_model_options(p):
    """``--wet-model persson|fill`` and the wet model's water and tyre, SI flags whose defaults
    and sources are :data:`friction.wet.water.DEFAULT_SOURCES` (``--water-depth M``,
    ``--water-temperature C``, ``--footprint M``, ``--block-size M``, ``--shear-stress PA``).

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser to extend.

    Returns
    -------
    None
    """
    p.add_argument(
        "--wet-model",
        choices=("persson", "fill"),
        default="persson",
        help="persson (default): sealing, squeeze-out, adhesion lost (Persson 2005, "
        "Lorenz & Persson 2010); fill: every basin filled (the thesis)",
    )
    p.add_argument(
        "--water-depth",
        type=float,
        default=None,
        metavar="M",
        help="water on the road per area [m] (default 5e-4, ASTM E274's film)",
    )
    p.add_argument(
        "--water-temperature",
        type=float,
        default=None,
        metavar="C",
        help="water temperature [C], sets its viscosity (default 20)",
    )
    p.add_argument(
        "--footprint",
        type=float,
        default=None,
        metavar="M",
        help="tyre contact length along the sliding [m] (default 0.12)",
    )
    p.add_argument(
        "--block-size",
        type=float,
        default=None,
        metavar="M",
        help="tread block size, the squeeze-out length [m] (default 0.025)",
    )
    p.add_argument(
        "--shear-stress",
        type=float,
        default=None,
        metavar="PA",
        help="frictional shear stress of the adhesive term [Pa] (default: none, adhesion left out)",
    )


def wet_conditions(args):
    """The parsed wet-model flags -> :class:`friction.wet.WetConditions` (defaults for the
    flags not given); a value the model refuses is an InputError naming its flag.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    friction.wet.WetConditions
    """
    from friction.wet.water import WetConditions

    given = {
        "water_depth_m": ("--water-depth", args.water_depth),
        "water_temperature_C": ("--water-temperature", args.water_temperature),
        "footprint_m": ("--footprint", args.footprint),
        "block_size_m": ("--block-size", args.block_size),
        "shear_stress_Pa": ("--shear-stress", args.shear_stress),
    }
    kw = {}
    for key, (flag, val) in given.items():
        if val is None:
            continue
        try:
            WetConditions(**{key: val})
        except ValueError as err:
            raise InputError(None, f"{flag} {val}: {err}") from None
        kw[key] = float(val)
    return WetConditions(**kw)
