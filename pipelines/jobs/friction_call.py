"""``roadscan friction`` as one call: :func:`friction` and the command's options
(:func:`add_friction_command_options`), which the command parses and the function takes as
keywords, so that the two cannot disagree. The job itself is :mod:`pipelines.jobs.friction`.
"""
from __future__ import annotations

__all__ = ["friction", "add_friction_command_options"]


def add_friction_command_options(p):
    """Every option of ``roadscan friction`` but ``--out``: the spectrum (``--psd`` or
    ``--self-affine``, exactly one), the rubber, contact and speed options
    (:func:`pipelines.settings.friction.add_friction_options`), ``--magnifications`` and
    ``--tol``.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser to extend.

    Returns
    -------
    None
    """
    from pipelines.settings.friction import add_friction_options

    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--psd", metavar="FILE", help="psd.csv with header q_per_m,C_m4 [1/m, m^4]")
    src.add_argument("--self-affine", metavar="H=..,h0=..,q0=..,q1=..",
                     help="self-affine model (thesis appendix A): Hurst H, h0 [m], q0, q1 [1/m], "
                          "optional qroll [1/m]")
    add_friction_options(p, master_curve=True, optional=False, q1_help=None)
    p.add_argument("--magnifications", default="", metavar="Z1,Z2,...",
                   help="with --flash: also report T at these magnifications zeta = q/q0")
    p.add_argument("--tol", type=float, default=1e-3, help="relative accuracy target for mu (1e-3)")


def friction(out, **options):
    """``roadscan friction`` as one call: mu(v) and the real contact area A/A0 = P(q1) from a
    spectrum and a rubber (Persson, J. Chem. Phys. 115, 3840 (2001); with ``flash=True`` the
    flash temperature of Persson, J. Phys.: Condens. Matter 18, 7789 (2006)), written as
    ``out`` (mu.csv), ``<stem>_summary.json`` and ``<stem>.png`` beside it, all or none
    (:func:`pipelines.jobs.friction.run_friction`).

    ``options`` are the command's long flags with dashes as underscores, taking what the flag
    takes: exactly one of ``psd="psd.csv"`` or ``self_affine="H=0.8,h0=1e-4,q0=1e3,q1=1e6"``,
    and ``rubber="r.toml"``, ``sigma0="0.25MPa"``, ``nu=0.45``, ``velocities="1e-3:10:9"``,
    ``flash=True``..., parsed by the command's own option definitions
    (:func:`add_friction_command_options`).

    Parameters
    ----------
    out : str or Path
        The output CSV, as ``--out`` (the command's default is ``mu.csv``).
    **options
        ``roadscan friction``'s long flags with dashes as underscores.

    Returns
    -------
    dict
        The ``<stem>_summary.json`` content, as written: ``model``, ``sigma0_Pa`` [Pa], ``nu``,
        ``pressure_in_P_Pa``, ``contact_gamma``, ``T0_C``, ``rubber``, ``band`` (the integration
        band [1/m]), ``q_nodes``, ``mu_peak`` and ``v_peak_m_per_s`` (refined by a parabola in
        ln v), ``peak_at_edge``, ``peak_note``, ``area_fraction_range``, ``rubber_checks``,
        ``rubber_label``, ``extrapolated_share`` (one per speed), ``extrapolated_share_at_peak``,
        ``extrapolated_from_per_m``, ``warnings`` and, with flash, ``T_flash_max_C``.

    Raises
    ------
    TypeError
        An unknown keyword.
    roadscan.errors.InputError
        A value the flag refuses, or a spectrum or rubber the job cannot use (one line).
    """
    import json
    import os
    from pathlib import Path

    from pipelines.settings.analyse import options_from_kwargs
    from pipelines.jobs.friction import run_friction
    from pipelines.checks.validate import collecting

    args = options_from_kwargs(options, "friction", add_friction_command_options)
    args.out = os.fspath(out)
    with collecting():
        _, _, _, written = run_friction(args)
    summary = Path(written).with_name(Path(written).stem + "_summary.json")
    return json.loads(summary.read_text())
