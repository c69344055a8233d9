"""Friction options shared by the commands that compute mu(v) (analyse, compare, friction,
diagnose): flags, their parsing with units, and the one-line notes a run prints.

Pressure. ``--sigma0`` is the nominal contact pressure sigma0 (load / nominal area) with a unit:
``0.3MPa``, ``300kPa``, ``3e5Pa`` or a bare number in Pa (``3e5``). A bare number below 1 kPa
is refused (it cannot be a tyre or rubber-block pressure; ``0.3`` meant ``0.3MPa``). The engine
uses the plane-strain pressure ``(1 - nu^2) sigma0`` in P(q), G(q) and M(q) (Persson 2001;
:func:`friction.isothermal.contact_state`).

Band. ``--q0``/``--q1`` [1/m] set the integration range of Persson's integrals within the
spectrum (:func:`friction.band.integration_band`): log-log interpolation inside it, the fitted
power law above its last point (said in one line and in the outputs).

One parser. :func:`add_friction_options` puts the friction flags on every command that takes
them (analyse, batch, compare, dry-vs-wet; friction and diagnose with ``--master-curve``) and
:func:`settings_from_args` turns them into one :class:`FrictionSettings`. A new friction flag
goes into both, here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

from roadscan.errors import InputError

__all__ = [
    "FrictionSettings",
    "add_friction_options",
    "add_contact_options",
    "settings_from_args",
    "check_contact_args",
    "apply_band",
    "coverage_note",
    "EXTRAPOLATE_CHOICES",
    "PRESSURE_HELP",
    "with_extrapolation",
    "run_checks",
    "add_master_curve_options",
    "rubber_from_args",
]

# re-exported (documented once, in pipelines.settings.quantities)
from pipelines.settings.quantities import MIN_BARE_PA, parse_pressure, parse_velocities  # noqa: F401
from pipelines.settings.rubber import (
    add_master_curve_options,
    coverage_note,
    rubber_from_args,
    run_checks,
    with_extrapolation,
)

EXTRAPOLATE_CHOICES = ("powerlaw", "hold")
PRESSURE_HELP = (
    "nominal contact pressure sigma0 = load / nominal area, with a unit: 0.3MPa, 300kPa, "
    "3e5Pa; a bare number is Pa (>= 1 kPa). The engine uses (1 - nu^2) sigma0 in P(q) "
    "(default 0.2MPa)"
)
FRICTION_GROUP = "friction (Persson's theory; defaults: see Theory in the docs)"
RUBBER_GROUP = "rubber (one of --rubber or --master-curve; default: the thesis SLS, T_ref 60 C)"
SCAN_Q1_HELP = (
    "upper end of the friction integrals [1/m]; beyond the Nyquist wave vector the "
    "spectrum is extended by its self-affine fit"
)


@dataclass
class FrictionSettings:
    """How mu(v) is computed (defaults: docs: Theory); built from the flags by
    :func:`settings_from_args`. SI units: pressure [Pa], temperature [C], speeds [m/s], wave
    vectors [1/m].

    Attributes
    ----------
    rubber : rubber model or None
        None: the thesis rubber.
    sigma0_Pa : float
        Nominal pressure [Pa].
    T0_C : float or None
        Background temperature [C] (None: the rubber's reference).
    flash : bool
        Flash-temperature model.
    v_m_per_s : ndarray or None
        Speeds [m/s].
    q1_per_m, q0_per_m : float or None
        Band ends [1/m].
    enabled : bool
        Compute friction.
    nu : float
        Poisson's ratio.
    contact_gamma : float or None
        Persson's gamma of S(q).
    extrapolate : str
        Master-curve extrapolation.
    """

    rubber: object = None  # friction rubber; None -> thesis rubber
    sigma0_Pa: float = 0.2e6
    T0_C: float | None = None  # None -> the rubber's T_ref
    flash: bool = False
    v_m_per_s: np.ndarray | None = None  # None -> 1e-4..1e2 m/s, 10 per decade
    q1_per_m: float | None = None  # upper end; beyond Nyquist the self-affine fit extends C(q)
    enabled: bool = True
    q0_per_m: float | None = None  # lower end of the friction integrals (None: lowest ring)
    nu: float = 0.5
    contact_gamma: float | None = None  # Persson's S(q) = gamma + (1 - gamma) P^2 (None: S = 1)
    extrapolate: str = "powerlaw"  # master curve beyond its data: powerlaw | hold


def add_contact_options(g, q1_help=None, nu=True):
    """--q0, --q1, --contact-gamma, --nu and --extrapolate on a parser or argument group.

    Parameters
    ----------
    g : argparse parser or group
        Where to add them.
    q1_help : str, optional
        Help of --q1.
    nu : bool, optional
        Add --nu.

    Returns
    -------
    None
    """
    g.add_argument(
        "--q0",
        type=float,
        default=None,
        metavar="PER_M",
        help="lower end of the friction integrals [1/m], inside the spectrum "
        "(default: its lowest wave vector)",
    )
    g.add_argument(
        "--q1",
        type=float,
        default=None,
        metavar="PER_M",
        help=q1_help
        or "upper end (cut-off) of the friction integrals [1/m]; above the "
        "spectrum's last point C(q) continues as its fitted power law "
        "(default: the last point)",
    )
    g.add_argument(
        "--contact-gamma",
        type=float,
        default=None,
        metavar="G",
        help="Persson's S(q) = G + (1 - G) P(q)^2 in the dissipation integrand "
        "(mu = 1/2 int q^3 C S P M dq); 0 <= G <= 1, e.g. 0.5 (default: off, S = 1)",
    )
    if nu:
        g.add_argument(
            "--nu", type=float, default=0.5, help="Poisson ratio of the rubber, 0 <= nu <= 0.5 (default 0.5)"
        )
    g.add_argument(
        "--extrapolate",
        choices=EXTRAPOLATE_CHOICES,
        default="powerlaw",
        help="master curve beyond its measured frequencies: powerlaw (E' held, E'' "
        "continues as the power law of its last decade; default) or hold (both held)",
    )


def check_contact_args(args):
    """One-line InputErrors for --q0, --q1, --contact-gamma, --nu.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    None
    """
    from pipelines.checks.validate import check_wave_vector

    for flag, val in (("--q0", getattr(args, "q0", None)), ("--q1", getattr(args, "q1", None))):
        if val is not None and not (math.isfinite(val) and val > 0):
            raise InputError(None, f"{flag} {val!r}: must be a positive wave vector in 1/m")
        if val is not None:
            check_wave_vector(val, flag)
    if args.q0 is not None and args.q1 is not None and not args.q0 < args.q1:
        raise InputError(None, f"--q0 {args.q0:g} must be below --q1 {args.q1:g}")
    g = getattr(args, "contact_gamma", None)
    if g is not None and not (math.isfinite(g) and 0 <= g <= 1):
        raise InputError(None, f"--contact-gamma {g!r}: must lie in [0, 1] (Persson uses about 0.5 to 0.75)")
    nu = getattr(args, "nu", 0.5)
    if not (math.isfinite(nu) and 0 <= nu <= 0.5):
        raise InputError(None, f"--nu {nu!r}: the Poisson ratio of rubber must lie in [0, 0.5] (about 0.5)")


def apply_band(psd, q0, q1, log=None):
    """The spectrum restricted/extended to [q0, q1] (``friction.band.integration_band``) and its
    info dict; prints one line when C(q) is extended above the spectrum's last point.

    Parameters
    ----------
    psd : spectrum
        The spectrum.
    q0, q1 : float or None
        Band ends [1/m].
    log : callable, optional
        Prints one line.

    Returns
    -------
    psd : spectrum
    info : dict or None
    """
    from friction import TabulatedPSD
    from friction.band import band_problem, integration_band

    if not isinstance(psd, TabulatedPSD):
        return psd, None
    if q0 is None and q1 is None:
        return psd, None
    problem = band_problem(psd, q0, q1)  # bad input, checked before the computation
    if problem is not None:
        raise InputError(None, f"--q0/--q1: {problem}")
    out, info = integration_band(psd, q0, q1)
    if info["extended_decades"] > 0:
        from pipelines.output.units import quantity

        info["note"] = (
            f"q1 = {quantity('q1_per_m', info['q1_per_m'])} is above the spectrum's "
            f"last point {quantity('q_per_m', info['q_table_max_per_m'])}: C(q) extended "
            f"{info['extended_decades']:.2f} decades by the "
            f"fitted power law C ~ q^{info['tail_exponent']:.3f}"
        )
        (log or _say)("note: " + info["note"])
    return out, info


def _say(msg):
    from pipelines.checks.run_warnings import note

    note(msg)


def add_friction_options(p, master_curve=False, sliding=True, optional=True, q1_help=SCAN_Q1_HELP):
    """The friction flags, the one definition every command that computes mu(v) uses.

    Defaults (analyse, batch, compare, dry-vs-wet): one argument group with --rubber, --sigma0,
    --temperature, --flash, --velocities, the contact options (:func:`add_contact_options`) and
    --no-friction. ``master_curve=True`` (friction, diagnose): --rubber and the master-curve
    flags in a "rubber" group, the rest on ``p``; ``sliding=False`` drops --flash and
    --velocities (diagnose takes the measured speeds), ``optional=False`` drops --no-friction,
    ``q1_help=None`` the spectrum's (not the scan's) meaning of --q1.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser.
    master_curve : bool, optional
        Add the master-curve flags.
    sliding : bool, optional
        Add --velocities and --flash.
    optional : bool, optional
        Add --no-friction.
    q1_help : str, optional
        Help of --q1.

    Returns
    -------
    None
    """
    if master_curve:
        rub, g = p.add_argument_group(RUBBER_GROUP), p
    else:
        rub = g = p.add_argument_group(FRICTION_GROUP)
    rub.add_argument(
        "--rubber",
        metavar="FILE.toml",
        default=None,
        help="rubber model, friction/RUBBER_TOML.md (default: the thesis's standard "
        "linear solid, T_ref = 60 C)",
    )
    if master_curve:
        add_master_curve_options(rub)
    g.add_argument("--sigma0", default="0.2MPa", metavar="PRESSURE", help=PRESSURE_HELP)
    g.add_argument(
        "--temperature",
        type=float,
        default=None,
        metavar="C",
        help="background temperature T0 [C] (default: the rubber's reference temperature)",
    )
    if sliding:
        g.add_argument("--flash", action="store_true", help="flash-temperature model (Persson 2006)")
        g.add_argument(
            "--velocities",
            default=None,
            metavar="LO:HI:N|V1,V2,..",
            help="N log-spaced sliding speeds [m/s] from LO to HI, or a list V1,V2,... "
            "(e.g. another program's table; default 1e-4:1e2:61, where tyres slide)",
        )
    add_contact_options(g, q1_help=q1_help)
    if optional:
        g.add_argument("--no-friction", action="store_true", help="skip mu(v)")


def settings_from_args(args):
    """The flags of :func:`add_friction_options` -> :class:`FrictionSettings` [SI], checked:
    one-line InputErrors naming the flag (contact options, rubber files, pressure, speeds,
    temperature against the rubber's WLF pole). A flag the command lacks takes its default.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    FrictionSettings
    """
    check_contact_args(args)
    rubber = rubber_from_args(args)
    # a command that records whether --sigma0 was given (diagnose) defaults it to None
    sigma0 = FrictionSettings().sigma0_Pa if args.sigma0 is None else parse_pressure(args.sigma0)
    velocities = getattr(args, "velocities", None)
    v = (
        parse_velocities(velocities)
        if velocities is not None and not (isinstance(velocities, str) and not velocities)
        else None
    )
    from pipelines.checks.validate import check_temperature, finite_number

    if args.temperature is not None:
        import friction

        check_temperature(args.temperature, rubber if rubber is not None else friction.thesis_rubber())
    if args.q1 is not None and not finite_number(args.q1, "--q1") > 0:
        raise InputError(None, f"--q1 {args.q1:g} 1/m: must be a positive wave vector")
    return FrictionSettings(
        rubber=rubber,
        sigma0_Pa=sigma0,
        T0_C=args.temperature,
        flash=getattr(args, "flash", False),
        v_m_per_s=v,
        q1_per_m=args.q1,
        enabled=not getattr(args, "no_friction", False),
        q0_per_m=args.q0,
        nu=args.nu,
        contact_gamma=args.contact_gamma,
        extrapolate=args.extrapolate,
    )
