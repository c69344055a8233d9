"""``roadscan friction`` as one call: :func:`friction` and the command's options
(:func:`add_friction_command_options`), which the command parses and the function takes as
keywords, so that the two cannot disagree. The job itself is :mod:`pipelines.jobs.friction`.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Literal

from pipelines.output.job_result import returns_job_result
from pipelines.settings.option_docs import document_options

if TYPE_CHECKING:  # numpy's typing only for checkers: the command's --help stays light
    from numpy.typing import ArrayLike

    from friction.rubber import Rubber


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
    src.add_argument(
        "--self-affine",
        metavar="H=..,h0=..,q0=..,q1=..",
        help="self-affine model (thesis appendix A): Hurst H, h0 [m], q0, q1 [1/m], optional qroll [1/m]",
    )
    add_friction_options(p, master_curve=True, optional=False, q1_help=None)
    p.add_argument(
        "--magnifications",
        default="",
        metavar="Z1,Z2,...",
        help="with --flash: also report T at these magnifications zeta = q/q0",
    )
    p.add_argument("--tol", type=float, default=1e-3, help="relative accuracy target for mu (1e-3)")


#: what this job's options mean where it narrows the shared text
_OPTION_TEXT = {
    "q1": (
        "``--q1``: upper end (cut-off) of the friction integrals [1/m]; above the spectrum's "
        "last point C(q) continues as its fitted power law (default: the last point)."
    ),
}


@returns_job_result("friction")
@document_options(overrides=_OPTION_TEXT)
def friction(
    out: str | os.PathLike[str],
    *,
    psd: str | os.PathLike[str] | None = None,
    self_affine: str | None = None,
    rubber: str | os.PathLike[str] | Rubber | None = None,
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
    extrapolate: Literal["powerlaw", "hold"] = "powerlaw",
    magnifications: str = "",
    tol: float = 0.001,
) -> dict[str, Any]:
    """``roadscan friction`` as one call: mu(v) and the real contact area A/A0 = P(q1) from a
    spectrum and a rubber, written as ``out`` (mu.csv) with ``<stem>_summary.json`` and
    ``<stem>.png`` beside it, all or none (:func:`pipelines.jobs.friction.run_friction`).

    Persson's theory: B.N.J. Persson, J. Chem. Phys. 115, 3840 (2001),
    doi:10.1063/1.1388626; with ``flash=True`` the flash temperature of Persson, J. Phys.:
    Condens. Matter 18, 7789 (2006), doi:10.1088/0953-8984/18/32/025.

    ``options`` are the command's long flags with dashes as underscores, taking what the flag
    takes: exactly one of ``psd="psd.csv"`` or ``self_affine="H=0.8,h0=1e-4,q0=1e3,q1=1e6"``,
    and ``rubber="r.toml"``, ``sigma0="0.25MPa"``, ``nu=0.45``, ``velocities="1e-3:10:9"``,
    ``flash=True``..., parsed by the command's own option definitions
    (:func:`add_friction_command_options`).

    Parameters
    ----------
    out : str or Path
        The output CSV, as ``--out`` (the command's default is ``mu.csv``).
    {options}

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
    if (psd is None) == (self_affine is None):  # the command's required either-or
        raise InputError(None, "give one spectrum: --psd PSD.csv or --self-affine H,h0,q0,q1[,qroll]")
    args.out = os.fspath(out)
    with collecting():
        _, _, _, written = run_friction(args)
    summary = Path(written).with_name(Path(written).stem + "_summary.json")
    return json.loads(summary.read_text())
