"""The rubber's side of the friction options: ``--rubber`` or ``--master-curve``/``--shift-table``/
``--reference-temperature`` (a measured rubber without a TOML), ``--extrapolate`` on a master
curve, and the rubber checks of a run (frequency coverage of the master curve, the WLF fit of a
shift table). :mod:`pipelines.settings.friction` re-exports every name here.
"""

from __future__ import annotations

import os

from roadscan.errors import InputError

__all__ = [
    "add_master_curve_options",
    "rubber_from_args",
    "coverage_note",
    "with_extrapolation",
    "run_checks",
]


def add_master_curve_options(g):
    """--master-curve, --shift-table, --reference-temperature (a measured rubber without a TOML).

    Parameters
    ----------
    g : argparse parser or group
        Where to add them.

    Returns
    -------
    None
    """
    g.add_argument(
        "--master-curve",
        metavar="FILE.csv",
        default=None,
        help="master curve CSV: f [Hz], E_stor, E_loss (units line 'Hz, MPa, MPa' or "
        "header E_stor_MPa; default Pa) at --reference-temperature",
    )
    g.add_argument(
        "--shift-table",
        metavar="FILE.csv",
        default=None,
        help="with --master-curve: shift factors, columns T_C and aT (linear) or log10_aT; "
        "or one row of WLF constants C1,C2_K,T_s_C",
    )
    g.add_argument(
        "--reference-temperature",
        type=float,
        default=None,
        metavar="C",
        help="with --master-curve: the temperature of the master curve T_ref [C] "
        "(default: where the shift table has aT = 1)",
    )


def rubber_from_args(args):
    """The rubber of ``--rubber FILE.toml`` or ``--master-curve/--shift-table/--reference-temperature``;
    None when neither is given (the caller's default). One-line InputErrors on bad combinations.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    rubber model or None
    """
    mc = getattr(args, "master_curve", None)
    shift = getattr(args, "shift_table", None)
    t_ref = getattr(args, "reference_temperature", None)
    if mc:
        if args.rubber:
            raise InputError(None, "give either --rubber FILE.toml or --master-curve FILE.csv, not both")
        if t_ref is None and not shift:
            raise InputError(
                mc,
                "--master-curve needs --reference-temperature C (its T_ref) "
                "or a --shift-table with aT = 1 at T_ref",
            )
        from pipelines.checks.validate import check_temperature
        from pipelines.settings.rubber_file import rubber_from_csv_files

        check_temperature(t_ref, flag="--reference-temperature")  # absolute zero .. 1000 C
        return rubber_from_csv_files(mc, shift, t_ref)
    if shift or t_ref is not None:
        raise InputError(
            None,
            "--shift-table and --reference-temperature go with --master-curve "
            "(with --rubber put them in the TOML)",
        )
    if args.rubber is not None and not isinstance(args.rubber, (str, os.PathLike)):
        return _rubber_object(args.rubber)  # a rubber model of friction, given from Python
    if args.rubber:
        from pipelines.settings.rubber_file import load_rubber

        return load_rubber(args.rubber)
    return None


def _rubber_object(rubber):
    """A rubber model given as an object (``friction.thesis_rubber()``, a master curve...):
    used as it is when it has the method the engine evaluates, ``modulus(omega, T)``; else a
    one-line InputError naming ``--rubber``."""
    if not callable(getattr(rubber, "modulus", None)):
        raise InputError(
            None,
            f"--rubber: {type(rubber).__name__} is neither a rubber file nor a "
            "rubber model of friction (friction.thesis_rubber(), a master curve)",
        )
    return rubber


def coverage_note(cov, flag_hint=True):
    """One warning line when a master curve is extrapolated by more than one decade, else None.

    Parameters
    ----------
    cov : dict
        Frequency coverage.
    flag_hint : bool, optional
        Name the flag.

    Returns
    -------
    str or None
    """
    if not cov or cov.get("extrapolated_decades") is None or cov["extrapolated_decades"] <= 1.0:
        return None
    lo, hi = cov["f_needed_Hz"]
    a, b = cov["f_curve_Hz"]
    parts = []
    if cov["extrapolated_decades_below"] > 1.0:
        parts.append(f"{cov['extrapolated_decades_below']:.1f} decades below")
    if cov["extrapolated_decades_above"] > 1.0:
        parts.append(f"{cov['extrapolated_decades_above']:.1f} decades above")
    return (
        f"warning: the speeds need {lo:.2g}..{hi:.2g} Hz on the master curve (shifted to the "
        f"temperature) but it covers {a:.2g}..{b:.2g} Hz: extrapolated {' and '.join(parts)} "
        f"(--extrapolate {cov.get('extrapolate', 'powerlaw')})"
    )


def with_extrapolation(rubber, mode):
    """The rubber with ``--extrapolate`` applied (master curves only; other models unchanged).

    Parameters
    ----------
    rubber : rubber model
        The rubber.
    mode : str
        ``"powerlaw"`` or ``"hold"``.

    Returns
    -------
    rubber model
    """
    from dataclasses import replace

    from friction import MasterCurve

    if isinstance(rubber, MasterCurve) and mode and rubber.extrapolate != mode:
        return replace(rubber, extrapolate=mode)
    return rubber


def run_checks(rubber, v, q0, q1, T0_C, T_max_C=None, log=None, result=None):
    """The ``rubber_checks`` of a run: frequency coverage (warned once, in one line, beyond
    one decade of extrapolation) and the WLF fit of a shift table. Returns a dict for JSON.

    Parameters
    ----------
    rubber : rubber model
        The rubber.
    v : ndarray
        Speeds [m/s].
    q0, q1 : float
        Band [1/m].
    T0_C : float or None
        Temperature [C].
    T_max_C : float, optional
        Hottest flash temperature [C].
    log : callable, optional
        Prints one line.
    result : FrictionResult, optional
        The engine's result.

    Returns
    -------
    dict
    """
    import warnings

    from friction.rubber_checks import frequency_coverage, wlf_fit_report

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        flash = result is not None and result.T_q_C is not None
        cov = frequency_coverage(
            rubber,
            v,
            q0,
            q1,
            T0_C,
            T_max_C,
            T_q_C=result.T_q_C if flash else None,
            q_per_m=result.q_per_m if flash else None,
        )
    msg = coverage_note(cov)
    if msg and log is not None:
        log(msg)
    elif msg:  # recorded for summary.json/reports too
        from pipelines.checks.validate import warn

        warn(msg.removeprefix("warning: "))
    cov["warning"] = msg
    out = {"frequency_coverage": cov}
    wlf = wlf_fit_report(getattr(rubber, "shift", None))
    if wlf is not None:
        out["wlf_fit_to_shift_table"] = wlf
    return out
