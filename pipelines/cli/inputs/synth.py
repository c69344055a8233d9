"""``roadscan synth --out FILE``: a Gaussian self-affine surface by Fourier filtering."""

from __future__ import annotations

from roadscan.errors import InputError

NAME = "synth"
HELP = "write a reproducible Gaussian self-affine synthetic surface (X3P, npy, npz or tif)"


def add_arguments(p):
    p.add_argument("--out", required=True, metavar="FILE", help="output height file (.x3p, .npy, .npz, .tif)")
    p.add_argument("--nx", type=int, default=1024, help="points along x (default 1024)")
    p.add_argument("--ny", type=int, default=None, help="points along y (default nx)")
    p.add_argument(
        "--spacing", type=float, default=5.54e-5, metavar="M", help="grid spacing [m] (default 5.54e-5)"
    )
    p.add_argument("--hurst", type=float, default=0.8, help="Hurst exponent, 0 < H < 1 (default 0.8)")
    p.add_argument("--rms", type=float, default=5e-4, metavar="M", help="rms height [m] (default 5e-4)")
    p.add_argument("--q-roll", type=float, default=None, metavar="PER_M", help="roll-off wave vector [1/m]")
    p.add_argument(
        "--q0",
        type=float,
        default=None,
        metavar="PER_M",
        help="lowest wave vector of the self-affine band [1/m] (default 2 pi / L)",
    )
    p.add_argument(
        "--q1",
        type=float,
        default=None,
        metavar="PER_M",
        help="highest wave vector [1/m] (default Nyquist pi / a)",
    )
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")


def run(args):
    from roadscan.io import write
    from roadscan.synth import self_affine_surface

    if not 0 < args.hurst < 1:
        raise InputError(None, f"--hurst {args.hurst}: must be within (0, 1)")
    if args.nx < 8 or (args.ny is not None and args.ny < 8):
        raise InputError(None, "--nx/--ny: need at least 8 points")
    from pipelines.checks.validate import check_rms_height, check_spacing
    from roadscan.io._common import check_declared_size

    check_declared_size("--nx/--ny", (args.ny or args.nx, args.nx))  # before allocating
    check_spacing(args.spacing, flag="--spacing")
    check_rms_height(args.rms, flag="--rms")
    if args.seed < 0:
        raise InputError(None, f"--seed {args.seed}: must be a non-negative whole number")
    hm = self_affine_surface(
        args.nx,
        args.ny,
        dx_m=args.spacing,
        hurst=args.hurst,
        rms_height_m=args.rms,
        q_roll_per_m=args.q_roll,
        q0_per_m=args.q0,
        q1_per_m=args.q1,
        seed=args.seed,
    )
    write(args.out, hm)
    from pipelines.output.units import length

    print(
        f"wrote {args.out}: {hm.ny} x {hm.nx} points at {length(args.spacing)}, H = {args.hurst}, "
        f"rms = {length(args.rms)}, seed {args.seed}"
    )
    return 0
