"""``roadscan friction`` as one call: :func:`friction` and the command's options
(:func:`add_friction_command_options`), which the command parses and the function takes as
keywords, so that the two cannot disagree. The job itself is :mod:`pipelines.jobs.friction`.
"""
from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Literal

if TYPE_CHECKING:  # numpy's typing only for checkers: the command's --help stays light
    from numpy.typing import ArrayLike


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


def friction(
        out: str | os.PathLike[str],
        *,
        psd: str | os.PathLike[str] | None = None,
        self_affine: str | None = None,
        rubber: str | os.PathLike[str] | Any | None = None,
        master_curve: str | os.PathLike[str] | None = None,
        shift_table: str | os.PathLike[str] | None = None,
        reference_temperature: float | None = None,
        sigma0: float | str = 200000.0,
        temperature: float | None = None,
        flash: bool = False,
        velocities: ArrayLike | str | None = None,
        q0: float | None = None,
        q1: float | None = None,
        contact_gamma: float | None = None,
        nu: float = 0.5,
        extrapolate: Literal['powerlaw', 'hold'] = 'powerlaw',
        magnifications: str = '',
        tol: float = 0.001,
) -> dict[str, Any]:
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
    psd : str or os.PathLike[str] or None, default None
        ``--psd``: psd.csv with header q_per_m,C_m4 [1/m, m^4].
    self_affine : str or None, default None
        ``--self-affine``: self-affine model (thesis appendix A): Hurst H, h0 [m], q0, q1 [1/m],
        optional qroll [1/m].
    rubber : str or os.PathLike[str] or Any or None, default None
        ``--rubber``: rubber model, friction/RUBBER_TOML.md (default: the thesis's standard
        linear solid, T_ref = 60 C).
    master_curve : str or os.PathLike[str] or None, default None
        ``--master-curve``: master curve CSV: f [Hz], E_stor, E_loss (units line 'Hz, MPa, MPa'
        or header E_stor_MPa; default Pa) at --reference-temperature.
    shift_table : str or os.PathLike[str] or None, default None
        ``--shift-table``: with --master-curve: shift factors, columns T_C and aT (linear) or
        log10_aT; or one row of WLF constants C1,C2_K,T_s_C.
    reference_temperature : float or None, default None
        ``--reference-temperature``: with --master-curve: the temperature of the master curve
        T_ref [C] (default: where the shift table has aT = 1).
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
        ``--q1``: upper end (cut-off) of the friction integrals [1/m]; above the spectrum's last
        point C(q) continues as its fitted power law (default: the last point).
    contact_gamma : float or None, default None
        ``--contact-gamma``: Persson's S(q) = G + (1 - G) P(q)^2 in the dissipation integrand
        (mu = 1/2 int q^3 C S P M dq); 0 <= G <= 1, e.g. 0.5 (default: off, S = 1).
    nu : float, default 0.5
        ``--nu``: Poisson ratio of the rubber, 0 <= nu <= 0.5 (default 0.5).
    extrapolate : Literal['powerlaw', 'hold'], default 'powerlaw'
        ``--extrapolate``: master curve beyond its measured frequencies: powerlaw (E' held, E''
        continues as the power law of its last decade; default) or hold (both held).
    magnifications : str, default ''
        ``--magnifications``: with --flash: also report T at these magnifications zeta = q/q0.
    tol : float, default 0.001
        ``--tol``: relative accuracy target for mu (1e-3).

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

    from pipelines.checks.validate import collecting
    from pipelines.jobs.friction import run_friction
    from pipelines.settings.keywords import options_of
    from roadscan.errors import InputError

    args = options_of(friction, locals())
    if (psd is None) == (self_affine is None):   # the command's required either-or
        raise InputError(None, "give one spectrum: --psd PSD.csv or --self-affine H,h0,q0,q1[,qroll]")
    args.out = os.fspath(out)
    with collecting():
        _, _, _, written = run_friction(args)
    summary = Path(written).with_name(Path(written).stem + "_summary.json")
    return json.loads(summary.read_text())
