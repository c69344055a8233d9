"""The command-line side of the friction-level diagnosis that :mod:`pipelines.cli.commands.diagnose`
delegates: the provenance hints of a run (which inputs the user gave, which files) and the
several-measurement run (``--measurements M.csv``, :mod:`.joint`)."""

from __future__ import annotations

from roadscan.errors import InputError

__all__ = ["provenance_hints", "run_measurements", "load_surface"]


def provenance_hints(args, uncertain, measured=True):
    """dict(files=[(role, path)], given=[inputs keys the user set]) for
    :mod:`pipelines.diagnosis.report.provenance`.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed ``roadscan diagnose`` flags (file paths, ``--q0``, ``--q1``, ``--temperature``).
    uncertain : dict
        Parsed ``--uncertain``; a ``psd_scale`` key marks the spectrum's level as given.
    measured : bool, optional
        A ``--measured`` run (False: the ``--measured`` path is not listed among the files).

    Returns
    -------
    dict
        files, given and, when the scan was read, scan_read (channel and calibration).
    """
    files = [
        ("measured", getattr(args, "measured", None) if measured else None),
        ("psd", args.psd),
        ("scan", args.scan),
        ("rubber", args.rubber),
        ("master_curve", getattr(args, "master_curve", None)),
        ("shift_table", getattr(args, "shift_table", None)),
        ("validate", getattr(args, "validate", None)),
        ("measurements", getattr(args, "measurements", None)),
    ]
    given = []
    if getattr(args, "sigma0_given", True):
        given.append("sigma0_Pa")
    if args.q0 is not None:
        given.append("q0_per_m")
    if args.q1 is not None:
        given.append("q1_per_m")
    if args.temperature is not None:
        given.append("temperature_C")
    if "psd_scale" in uncertain:
        given.append("psd_scale")
    hints = dict(files=[(r, p) for r, p in files if p], given=given)
    if getattr(args, "scan_read", None):
        hints["scan_read"] = args.scan_read  # how --scan was read (channel, calibration)
    return hints


def load_surface(args, say):
    """(psd, band, scan, spectrum, fit) of ``--psd`` or ``--scan`` with ``--q0/--q1`` applied.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags; for ``--scan`` it gains ``scan_read`` (how the file was read).
    say : callable
        Prints one progress or note line (str), e.g. the band ``--q0``/``--q1`` cut.

    Returns
    -------
    tuple
        (psd, band, scan, spectrum, fit); scan, spectrum and fit are None for ``--psd``.
    """
    from pipelines.diagnosis.inputs import read_psd_csv, scan_surface
    from pipelines.settings.friction import apply_band
    from pipelines.settings.scan_input import load_scan

    if args.psd:
        psd, scan, spec, fit = read_psd_csv(args.psd), None, None, None
    else:
        from pipelines.settings.scan_input import read_record

        obj = load_scan(args.scan, args)
        args.scan_read = read_record(obj)
        try:
            psd, scan, spec, fit = scan_surface(obj, args.q0, args.q1)  # the one chain
        except InputError as exc:  # too little spectrum to analyse: the scan's fault
            raise InputError(args.scan, f"cannot analyse the scan ({exc.problem})") from None
    psd, band = apply_band(psd, args.q0, args.q1, log=say)
    return psd, band, scan, spec, fit


def run_measurements(args, uncertain, settings_fn, say):
    """``roadscan diagnose --measurements M.csv (--psd P | --scan S) --out DIR``: every row's
    verdict with the shared inputs calibrated jointly; writes DIR/diagnosis.json (``joint``,
    ``measurements``) and DIR/report.html.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed ``roadscan diagnose`` flags.
    uncertain : dict
        Input name -> :class:`fit.calibration.Uncertain` (``--uncertain``), shared by every row.
    settings_fn : callable
        The engine settings of one measurement.
    say : callable
        Prints one progress or note line (str), e.g. the band ``--q0``/``--q1`` cut.

    Returns
    -------
    dict
        The ``diagnosis.json`` content.
    """
    from dataclasses import replace

    from pipelines.checks.validate import check_pressure, check_temperature
    from pipelines.diagnosis.inputs import build_context
    from pipelines.diagnosis.joint import read_measurements, run_joint
    from pipelines.diagnosis.report.joint import joint_json, write_joint_report
    from pipelines.output import report as rep
    from pipelines.settings.friction import with_extrapolation
    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    if args.measured or args.validate:
        raise InputError(args.measurements, "--measurements replaces --measured (and --validate)")
    if args.rubber or getattr(args, "master_curve", None):
        raise InputError(args.measurements, "with --measurements each row names its rubber (column rubber)")
    if (args.scan is None) == (args.psd is None):
        raise InputError(args.measurements, "--measurements needs exactly one of --scan FILE or --psd FILE")
    inputs = [f for f in (args.measurements, args.scan, args.psd) if f]
    check_output_dir(args.out, inputs=inputs)
    rows = read_measurements(args.measurements, sigma0_Pa=args.sigma0, T0_C=args.temperature)
    import numpy as np

    for r in rows:
        for t in np.unique(r.curve.T0_C[np.isfinite(r.curve.T0_C)]):
            check_temperature(float(t), r.rubber, flag=f"{r.label}: T0_C")
        for p in np.unique(r.curve.sigma0_Pa):
            check_pressure(float(p), flag=f"{r.label}: sigma0_Pa")
    psd, band, scan, spec, fit = load_surface(args, say)
    ctxs, settings = [], {}
    for r in rows:
        rub = with_extrapolation(r.rubber, args.extrapolate)
        c = build_context(r.curve, psd, rubber=rub, scan=scan, spectrum=spec, fit=fit)
        c.base = replace(c.base, contact_gamma=args.contact_gamma, nu=args.nu)
        ctxs.append(c)
        settings[r.label] = settings_fn(args, r.curve, None, psd, band, c.base.rubber)["engine_settings"]
    joint, results = run_joint(rows, ctxs, noise=args.noise, uncertain=uncertain, log=say)
    hints = provenance_hints(args, uncertain, measured=False)
    psd_files = [(k, p) for k, p in hints["files"] if k in ("psd", "scan", "measurements")]
    data = joint_json(joint, results, settings, dict(given=hints["given"]), psd_files)
    with atomic_output_dir(args.out, inputs=inputs) as tmp:
        rep.write_json(tmp / "diagnosis.json", data)
        write_joint_report(tmp, data, results)
    return data
