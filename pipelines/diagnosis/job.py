"""The ``roadscan diagnose`` job: its options (:func:`add_diagnose_options`), the keyword call
:func:`diagnose` (``pipelines.diagnose``) and the job on parsed options
(:func:`run_diagnosis`): which level runs (surface, friction, several compounds), the checks
of its inputs, the engine settings it records, the atomic output folder.
:mod:`pipelines.cli.commands.diagnose` only parses, calls :func:`diagnose` and prints.
"""

from __future__ import annotations

import os
from typing import Any, Literal

from pipelines.output.job_result import returns_job_result
from pipelines.settings.friction import (
    check_contact_args,
    parse_pressure,
    rubber_from_args,
    run_checks,
    with_extrapolation,
)
from pipelines.settings.option_docs import document_options
from pipelines.settings.scan_input import load_scan
from roadscan.errors import InputError

__all__ = ["diagnose", "add_diagnose_options", "run_diagnosis"]


def _say(msg):
    from pipelines.checks.run_warnings import note

    note(msg)


def add_diagnose_options(p):
    """Every option of ``roadscan diagnose`` but ``--out``: the measurement(s), the surface
    (``--scan`` or ``--psd``), the rubber, contact and pressure options, ``--noise``,
    ``--validate``, ``--uncertain`` and how a scan is read.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser to extend.

    Returns
    -------
    None
        The options are added to ``p`` in place.
    """
    from pipelines.settings.friction import add_friction_options
    from pipelines.settings.scan_input import add_scan_options

    p.add_argument(
        "--measured",
        metavar="MU.csv",
        default=None,
        help="measured mu(v): CSV v_m_per_s,mu[,T0_C,sigma0_Pa,condition] (friction level); "
        "without it the scan itself is diagnosed (surface level)",
    )
    p.add_argument("--scan", metavar="FILE", default=None, help="height file (area scan or line profile)")
    p.add_argument(
        "--psd", metavar="FILE", default=None, help="spectrum CSV q_per_m,C_m4 (instead of --scan)"
    )
    add_friction_options(p, master_curve=True, sliding=False, optional=False, q1_help=None)
    p.add_argument(
        "--noise",
        type=float,
        default=None,
        metavar="RMS",
        help="measurement noise as rms of log10 (default: estimated from the data)",
    )
    p.add_argument(
        "--validate",
        metavar="OTHER.csv",
        default=None,
        help="a separate measurement predicted by the corrected model without refitting",
    )
    p.add_argument(
        "--uncertain",
        default=None,
        metavar="KEY=LO:HI,...",
        help="inputs known only within a range, calibrated on the training points: q1=LO:HI [1/m] "
        "(q1=known: q1 fixed), sigma0=LO:HI (units as --sigma0), psd_scale=LO:HI (factor on C(q)), "
        "temperature=LO:HI [C]; any subset",
    )
    p.add_argument(
        "--measurements",
        metavar="M.csv",
        default=None,
        help="several measurements at once: CSV measured,rubber,label[,temperature_C,sigma0_Pa] "
        "(paths relative to M.csv); q1, psd_scale and sigma0 shared",
    )
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        metavar="N",
        help="processes fitting the candidates side by side (default: one per core; 1: none); "
        "the verdict is the same to the last digit, only the wall time changes",
    )
    add_scan_options(p)
    p.set_defaults(sigma0=None)  # None: not given (the default 0.2MPa is then listed as assumed)


#: what this job's options mean where it narrows the shared text
_OPTION_TEXT = {
    "psd": ("``--psd``: spectrum CSV q_per_m,C_m4 (instead of --scan)."),
    "workers": (
        "``--workers``: processes fitting the candidates of one stage side by side, forked from "
        "this one (default: one per core available; 1: in this process). The diagnosis is the "
        "same to the last digit whatever the number; only the wall time changes."
    ),
    "q1": (
        "``--q1``: upper end (cut-off) of the friction integrals [1/m]; above the spectrum's last "
        "point C(q) continues as its fitted power law (default: the last point)."
    ),
}


@returns_job_result("diagnose")
@document_options(overrides=_OPTION_TEXT)
def diagnose(
    out: str | os.PathLike[str],
    *,
    measured: str | os.PathLike[str] | None = None,
    scan: str | os.PathLike[str] | None = None,
    psd: str | os.PathLike[str] | None = None,
    rubber: str | os.PathLike[str] | Any | None = None,
    master_curve: str | os.PathLike[str] | None = None,
    shift_table: str | os.PathLike[str] | None = None,
    reference_temperature: float | None = None,
    sigma0: float | str | None = None,
    temperature: float | None = None,
    q0: float | None = None,
    q1: float | None = None,
    contact_gamma: float | None = None,
    nu: float = 0.5,
    extrapolate: Literal["powerlaw", "hold"] = "powerlaw",
    noise: float | None = None,
    validate: str | os.PathLike[str] | None = None,
    uncertain: str | None = None,
    measurements: str | os.PathLike[str] | None = None,
    spacing: float | str | tuple[float, float] | None = None,
    units: Literal["m", "mm", "um", "nm"] | None = None,
    x_units: Literal["m", "mm", "um", "nm"] | None = None,
    override_calibration: bool = False,
    channel: int | str | None = None,
    workers: int | None = None,
) -> dict[str, Any]:
    """``roadscan diagnose`` as one call: the sim-to-real gap (where model and measurement
    disagree, which unmodelled effect explains it, how much adding it closes the gap), written
    into ``out`` (``diagnosis.json`` and ``report.html``, all or none).

    The level follows the options as on the command line: ``measured="mu.csv"`` with ``scan=``
    or ``psd=`` (friction level), ``measurements="m.csv"`` with ``scan=`` or ``psd=`` (several
    compounds, shared inputs calibrated jointly), ``scan=`` alone (surface level: the scan
    against its Gaussian self-affine twin). ``options`` are the command's long flags with
    dashes as underscores, taking what the flag takes (``sigma0="0.3MPa"``, ``nu=0.45``,
    ``noise=0.02``, ``uncertain="q1=1e5:1e7"``, ``rubber="r.toml"``), parsed by the command's own
    option definitions (:func:`add_diagnose_options`). Friction: Persson, J. Chem. Phys. 115,
    3840 (2001); the held-out verdict and the evidence as in :mod:`pipelines.diagnosis`.

    Parameters
    ----------
    out : str or Path
        Output folder, as ``--out``.
    {options}

    Returns
    -------
    dict
        The ``diagnosis.json`` content: for one measurement or a scan ``level``,
        ``baseline_gap``, ``noise``, ``verdict`` (``effect``, ``shrink``, ``confidence``...),
        the candidates, ``inputs`` (values, files with sha256, what was assumed) and the
        engine settings; with ``measurements``: ``joint`` and per label ``measurements``.

    Raises
    ------
    TypeError
        An unknown keyword.
    roadscan.errors.InputError
        A value the flag refuses, or inputs the diagnosis cannot use (one line).
    """
    import os

    from pipelines.checks.validate import collecting
    from pipelines.settings.keywords import options_of

    args = options_of(diagnose, locals())
    args.out = os.fspath(out)
    with collecting():
        return run_diagnosis(args, _say)


def run_diagnosis(args, say=_say):
    """Run ``roadscan diagnose`` on parsed options ``args`` (those of
    :func:`add_diagnose_options` and ``out``).

    Parameters
    ----------
    args : argparse.Namespace
        The options of ``roadscan diagnose``.
    say : callable, optional
        ``say(message)`` prints one progress or warning line.

    Returns
    -------
    dict
        The ``diagnosis.json`` content.
    """
    from pipelines.diagnosis.fit.parallel import use_workers

    if args.workers is not None and args.workers < 1:
        raise InputError(None, f"--workers {args.workers}: give at least 1 process")
    with use_workers(args.workers):
        return _run_diagnosis(args, say)


def _run_diagnosis(args, say):
    import numpy as np

    if args.noise is not None and not (np.isfinite(args.noise) and args.noise > 0):
        raise InputError(None, f"--noise {args.noise!r} must be a positive rms of log10")
    from pipelines.diagnosis.fit.calibration import parse_uncertain

    args.sigma0_given = args.sigma0 is not None
    args.sigma0 = parse_pressure(args.sigma0 if args.sigma0_given else "0.2MPa")
    check_contact_args(args)
    uncertain = parse_uncertain(args.uncertain)
    if args.q1 is not None and "q1" not in uncertain:
        # --q1 stated and not named by --uncertain: given, not calibrated (no default range)
        from pipelines.diagnosis.fit.calibration import Uncertain

        uncertain["q1"] = Uncertain("q1", float("nan"), float("nan"), "known")
    if args.measurements is not None:
        from pipelines.diagnosis.run_command import run_measurements

        return run_measurements(args, uncertain, _settings, say)
    if args.measured is None:
        if args.scan is None:
            raise InputError(
                None,
                "give --measured MU.csv with --scan/--psd (friction level) or --scan alone (surface level)",
            )
        if args.psd or args.validate or uncertain:
            raise InputError(
                None, "--psd, --validate and --uncertain need --measured or --measurements (friction level)"
            )
        from pipelines.diagnosis.surface.level import run_surface
        from roadscan.io.atomic import atomic_output_dir, check_output_dir

        check_output_dir(args.out, inputs=[args.scan])
        obj = load_scan(args.scan, args)
        _check_surface(obj, args.scan)
        try:
            with atomic_output_dir(args.out, inputs=[args.scan]) as tmp:
                data = run_surface(obj, tmp, log=say)
        except (ValueError, np.linalg.LinAlgError) as exc:
            raise InputError(args.scan, f"cannot diagnose the scan ({exc})") from None
        return data
    if (args.scan is None) == (args.psd is None):
        raise InputError(args.measured, "the friction level needs exactly one of --scan FILE or --psd FILE")
    from pipelines.diagnosis.inputs import build_context
    from pipelines.diagnosis.measured import read_measured
    from pipelines.diagnosis.run import run_friction

    curve = read_measured(args.measured, sigma0_Pa=args.sigma0, T0_C=args.temperature)
    other = (
        read_measured(args.validate, sigma0_Pa=args.sigma0, T0_C=args.temperature) if args.validate else None
    )
    rubber = rubber_from_args(args)
    _check_conditions(args, rubber, curve, other)
    from pipelines.diagnosis.run_command import load_surface

    psd, band, scan, spec, fit = load_surface(args, say)
    rubber = with_extrapolation(rubber, args.extrapolate)
    ctx = build_context(curve, psd, rubber=rubber, scan=scan, spectrum=spec, fit=fit)
    from dataclasses import replace

    # baseline S(q) and nu; the contact-correction effect may refit gamma
    ctx.base = replace(ctx.base, contact_gamma=args.contact_gamma, nu=args.nu)
    extra = _settings(args, curve, other, psd, band, ctx.base.rubber)
    from roadscan.io.atomic import atomic_output_dir

    inputs = [f for f in (args.measured, args.scan, args.psd, args.validate) if f]
    from pipelines.diagnosis.run_command import provenance_hints

    with atomic_output_dir(args.out, inputs=inputs) as tmp:
        data = run_friction(
            curve,
            ctx,
            tmp,
            noise=args.noise,
            other=other,
            log=say,
            extra=extra,
            uncertain=uncertain,
            inputs=provenance_hints(args, uncertain),
        )
    return data


def _settings(args, curve, other, psd, band, rubber):
    """The engine settings of a friction-level run for diagnosis.json, with the master curve's
    frequency coverage over the measured speeds and temperatures (warned once, in one line,
    beyond one decade of extrapolation) and the WLF fit of a shift table."""
    import numpy as np

    v = np.concatenate([curve.v_m_per_s] + ([other.v_m_per_s] if other is not None else []))
    T = np.concatenate([curve.T0_C] + ([other.T0_C] if other is not None else []))
    T = np.where(np.isfinite(T), T, rubber.T_ref_C)
    lo, hi = float(T.min()), float(T.max())
    checks = run_checks(rubber, v, psd.q_min_per_m, psd.q1_per_m, lo, hi if hi > lo else None, log=_say)
    if band is None:
        band = dict(q0_per_m=psd.q_min_per_m, q1_per_m=psd.q1_per_m, extended_decades=0.0)
    return {
        "engine_settings": {
            "nu": args.nu,
            "contact_gamma": args.contact_gamma,
            "extrapolate": args.extrapolate,
            "pressure_note": "sigma0 is the nominal pressure; P(q), G(q) and M(q) use (1 - nu^2) sigma0",
            "band": band,
            "rubber": {"T_ref_C": rubber.T_ref_C, "kind": type(rubber).__name__},
            "rubber_checks": checks,
        }
    }


def _check_surface(obj, path):
    """One-line errors for scans the surface level cannot use: too few points, or flat."""
    import numpy as np

    h = np.asarray(obj.heights_m, float)
    shape = " x ".join(str(n) for n in h.shape)
    if h.ndim == 2 and min(h.shape) < 48:
        raise InputError(
            path, f"a {shape} grid is too small for the surface level (needs at least 48 x 48 points)"
        )
    if h.ndim == 1 and h.size < 128:
        raise InputError(
            path, f"a profile of {h.size} points is too short for the surface level (needs at least 128)"
        )
    good = h[np.isfinite(h)]
    if good.size == 0 or float(np.ptp(good)) <= 1e-12 * max(1.0, float(np.max(np.abs(good)))):
        raise InputError(path, "the scan is flat (all heights equal): no texture to diagnose")


def _check_conditions(args, rubber, curve, other):
    """--temperature and every row's T0_C against the rubber's WLF pole, every row's sigma0_Pa
    as a pressure (:mod:`pipelines.checks.validate`), before any fit (``--temperature -400`` reached
    the shift factor as an OverflowError)."""
    from pathlib import Path

    import numpy as np

    import friction
    from pipelines.checks.validate import check_pressure, check_temperature

    rub = rubber if rubber is not None else friction.thesis_rubber()
    check_temperature(args.temperature, rub)
    for c, path in ((curve, args.measured), (other, args.validate)):
        if c is None:
            continue
        for t in np.unique(c.T0_C[np.isfinite(c.T0_C)]):
            check_temperature(float(t), rub, flag=f"{Path(path).name}: T0_C")
        for p in np.unique(c.sigma0_Pa):
            check_pressure(float(p), flag=f"{Path(path).name}: sigma0_Pa")
