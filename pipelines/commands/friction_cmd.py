"""``roadscan friction``: mu(v) from a spectrum and a rubber (Persson's theory).

Outputs: ``--out mu.csv`` with columns ``v_m_per_s,mu`` (with ``--flash`` also
``T_C_zeta_1``, ``T_C_zeta_max`` and ``T_C_zeta_<z>`` per ``--magnifications`` value), and a PNG
plot beside it (same stem). Defaults (DESIGN.md sec 5): sigma0 = 0.2 MPa, nu = 0.5, the thesis
rubber at T0 = T_ref, isothermal, speeds 1e-8 to 1e4 m/s at 10 per decade (121 points).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from roadscan.errors import InputError

from ..csv_files import read_psd_csv
from ..friction_options import parse_velocities
from ..spectrum_bridge import default_velocities

NAME = "friction"
HELP = "friction coefficient mu(v) from a spectrum (psd.csv or self-affine model) and a rubber"


def add_arguments(p):
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--psd", metavar="FILE", help="psd.csv with header q_per_m,C_m4 [1/m, m^4]")
    src.add_argument("--self-affine", metavar="H=..,h0=..,q0=..,q1=..",
                     help="self-affine model (thesis appendix A): Hurst H, h0 [m], q0, q1 [1/m], "
                          "optional qroll [1/m]")
    p.add_argument("--rubber", metavar="FILE.toml", default=None,
                   help="rubber model (friction/RUBBER_TOML.md; default: the thesis SLS, T_ref 60 C)")
    p.add_argument("--sigma0", type=float, default=0.2e6, metavar="PA", help="nominal pressure [Pa] (2e5)")
    p.add_argument("--nu", type=float, default=0.5, help="Poisson ratio of the rubber (0.5)")
    p.add_argument("--temperature", type=float, default=None, metavar="C",
                   help="background temperature T0 [C] (default: the rubber's T_ref)")
    p.add_argument("--flash", action="store_true", help="flash-temperature model (Persson 2006)")
    p.add_argument("--velocities", default=None, metavar="LO:HI:N",
                   help="N log-spaced sliding speeds [m/s] (default 1e-8:1e4:121)")
    p.add_argument("--magnifications", default="", metavar="Z1,Z2,...",
                   help="with --flash: also report T at these magnifications zeta = q/q0")
    p.add_argument("--tol", type=float, default=1e-3, help="relative accuracy target for mu (1e-3)")
    p.add_argument("--out", default="mu.csv", metavar="mu.csv", help="output CSV (PNG beside it)")


def _self_affine(text):
    from friction import SelfAffinePSD

    keys = {"h": "hurst", "hurst": "hurst", "h0": "h0_m", "q0": "q0_per_m", "q1": "q1_per_m",
            "qroll": "q_roll_per_m", "q_roll": "q_roll_per_m"}
    kw = {}
    for part in filter(None, (s.strip() for s in text.split(","))):
        k, sep, val = part.partition("=")
        if not sep or k.strip().lower() not in keys:
            raise InputError(None, f"--self-affine: bad item {part!r} (use H=..,h0=..,q0=..,q1=..)")
        try:
            kw[keys[k.strip().lower()]] = float(val)
        except ValueError:
            raise InputError(None, f"--self-affine: {k}={val!r} is not a number") from None
        if not np.isfinite(kw[keys[k.strip().lower()]]):
            raise InputError(None, f"--self-affine: {k.strip()}={val.strip()}: must be finite")
    missing = {"hurst", "h0_m", "q0_per_m", "q1_per_m"} - set(kw)
    if missing:
        raise InputError(None, "--self-affine: missing " + ", ".join(sorted(missing)))
    try:
        return SelfAffinePSD(**kw)
    except ValueError as exc:
        raise InputError(None, f"--self-affine: {exc}") from None


def run(args):
    import friction

    from ..report import plot_mu, write_csv

    v = parse_velocities(args.velocities) if args.velocities else default_velocities()
    psd = read_psd_csv(args.psd) if args.psd else _self_affine(args.self_affine)
    if args.rubber:
        from ..rubber_file import load_rubber
        rubber = load_rubber(args.rubber)
    else:
        rubber = friction.thesis_rubber()
    if not (np.isfinite(args.sigma0) and args.sigma0 > 0):
        raise InputError(None, f"--sigma0 {args.sigma0!r}: must be a positive pressure in Pa")
    if not (0 < args.tol < 0.1):
        raise InputError(None, "--tol must lie in (0, 0.1)")
    zetas = []
    if args.magnifications:
        try:
            zetas = [float(z) for z in args.magnifications.split(",") if z.strip()]
        except ValueError:
            raise InputError(None, f"--magnifications {args.magnifications!r}: expected numbers") from None
    zmax = psd.q1_per_m / psd.q0_per_m
    zmin = psd.q_min_per_m / psd.q0_per_m
    bad = [z for z in zetas if not (zmin <= z <= zmax)]
    if bad:
        raise InputError(None, f"--magnifications {bad}: outside the spectrum's range {zmin:g}..{zmax:g}")
    if zetas and not args.flash:
        raise InputError(None, "--magnifications needs --flash")
    from ..validate import check_mu, check_temperature

    check_temperature(args.temperature, rubber)
    kw = dict(sigma0_Pa=args.sigma0, nu=args.nu, T0_C=args.temperature, tol=args.tol)
    try:
        res = (friction.mu_flash if args.flash else friction.mu_isothermal)(psd, rubber, v, **kw)
    except RuntimeError as exc:
        raise InputError(None, f"friction: {exc}") from None
    except ValueError as exc:
        raise InputError(None, str(exc)) from None
    check_mu(res.mu)
    out = Path(args.out)
    header, cols = ["v_m_per_s", "mu"], [res.v_m_per_s, res.mu]
    if args.flash:
        header += ["T_C_zeta_1", "T_C_zeta_max"]
        cols += [res.temperature_at(1.0), res.temperature_at(zmax)]
        for z in zetas:
            header.append(f"T_C_zeta_{z:g}")
            cols.append(res.temperature_at(z))
    write_csv(out, header, cols)
    title = "mu(v), " + ("flash temperature" if args.flash else "isothermal") + \
        f", sigma0 = {args.sigma0 / 1e6:g} MPa, T0 = {res.meta['T0_C']:g} C"
    plot_mu([("", res.v_m_per_s, res.mu)], out.with_suffix(".png"), title=title,
            ylabel="friction coefficient mu [-]")
    mu_max, v_max = res.peak
    print(f"{out}: {v.size} speeds, peak mu {mu_max:.4g} at {v_max:.4g} m/s"
          + (f", {res.iterations} iterations, residual {res.residual:.2g} K" if args.flash else ""))
    return 0
