"""Friction options shared by the commands that compute mu(v) from a scan."""
from __future__ import annotations

import numpy as np

from roadscan.errors import InputError

__all__ = ["add_friction_options", "settings_from_args", "parse_velocities"]


def parse_velocities(text):
    """``"LO:HI:N"`` -> N log-spaced speeds [m/s] from LO to HI (InputError when malformed)."""
    try:
        lo, hi, n = text.split(":")
        lo, hi, n = float(lo), float(hi), int(n)
    except ValueError:
        raise InputError(None, f"--velocities {text!r}: expected LO:HI:N, e.g. 1e-8:1e4:121") from None
    if not (0 < lo < hi < np.inf) or n < 2:
        raise InputError(None, f"--velocities {text!r}: need 0 < LO < HI and N >= 2")
    return np.logspace(np.log10(lo), np.log10(hi), n)


def add_friction_options(parser):
    g = parser.add_argument_group("friction (Persson's theory; defaults as DESIGN.md section 5)")
    g.add_argument("--rubber", metavar="FILE.toml", default=None,
                   help="rubber model (default: the thesis's standard linear solid, T_ref = 60 C)")
    g.add_argument("--sigma0", type=float, default=0.2e6, metavar="PA",
                   help="nominal pressure [Pa] (default 2e5)")
    g.add_argument("--temperature", type=float, default=None, metavar="C",
                   help="background temperature T0 [C] (default: the rubber's reference temperature)")
    g.add_argument("--flash", action="store_true", help="include flash temperature")
    g.add_argument("--velocities", default=None, metavar="LO:HI:N",
                   help="log-spaced sliding speeds [m/s] (default 1e-8:1e4:121)")
    g.add_argument("--q1", type=float, default=None, metavar="PER_M",
                   help="extend the fitted spectrum beyond the Nyquist wave vector to q1 [1/m]")
    g.add_argument("--no-friction", action="store_true", help="skip mu(v)")


def settings_from_args(args):
    from .analyse import FrictionSettings

    rubber = None
    if getattr(args, "rubber", None):
        from .rubber_file import load_rubber

        rubber = load_rubber(args.rubber)
    if args.sigma0 is not None and not (args.sigma0 > 0 and np.isfinite(args.sigma0)):
        raise InputError(None, f"--sigma0 {args.sigma0!r} must be a positive pressure in Pa")
    v = parse_velocities(args.velocities) if args.velocities else None
    from .validate import check_temperature, finite_number

    if args.temperature is not None:
        import friction

        check_temperature(args.temperature, rubber if rubber is not None else friction.thesis_rubber())
    if args.q1 is not None and not finite_number(args.q1, "--q1") > 0:
        raise InputError(None, f"--q1 {args.q1:g} 1/m: must be a positive wave vector")
    return FrictionSettings(rubber=rubber, sigma0_Pa=args.sigma0, T0_C=args.temperature,
                            flash=args.flash, v_m_per_s=v, q1_per_m=args.q1,
                            enabled=not args.no_friction)
