"""The ``roadscan rubber master`` job: raw DMA frequency sweeps -> master curve by
time-temperature superposition (:mod:`friction.mastercurve`; Williams, Landel and Ferry,
J. Am. Chem. Soc. 77, 3701, 1955), written as a rubber TOML with its data files.

Writes, beside ``out`` (stem S of the TOML): the rubber TOML (loadable by ``--rubber``:
``model = "master_curve"`` with the shift table; the fitted Prony series and the WLF constants
are in it too), ``S_master.csv`` (``f_Hz,E_storage_Pa,E_loss_Pa``, the smoothed master curve
at T_ref), ``S_shift.csv`` (``T_C,log10_aT``), ``S_shifted.csv`` (every raw point at its shifted
frequency: ``f_Hz,E_storage_Pa,E_loss_Pa,T_C,sweep``), ``S_master.json`` (shift table, how each
shift was found, WLF fit and its rms in decades, Prony fit) and ``S_master.png`` (raw sweeps,
the shifted master curve, aT(T) with the WLF fit).
"""

from __future__ import annotations

import math
from pathlib import Path

from pipelines.output.units import sig3
from roadscan.errors import InputError

__all__ = ["MASTER_SUFFIXES", "build_rubber_master"]

#: the files written beside the TOML (stem + suffix)
MASTER_SUFFIXES = ("_master.csv", "_shift.csv", "_shifted.csv", "_master.json", "_master.png")


def _toml_list(a):
    return "[" + ", ".join(f"{x:.10g}" for x in a) + "]"


def _plot(res, raw, path):
    import matplotlib.pyplot as plt
    import numpy as np

    from pipelines.output.report import save_figure

    f, E1, E2, T = raw
    fig, axs = plt.subplots(1, 3, figsize=(15, 4.6))
    cmap = plt.get_cmap("coolwarm")
    Tn = (T - T.min()) / max(np.ptp(T), 1e-9)
    ax = axs[0]
    ax.scatter(f, E1, c=cmap(Tn), s=8, marker="o", label="E' (raw)")
    ax.scatter(f, E2, c=cmap(Tn), s=8, marker="^", label="E'' (raw)")
    ax.set_xscale("log"), ax.set_yscale("log")
    ax.set_xlabel("frequency f [Hz]"), ax.set_ylabel("modulus [Pa]")
    ax.set_title(f"raw sweeps, {T.min():.0f} to {T.max():.0f} °C (blue cold, red hot)", fontsize=9)
    ax.legend(fontsize=8)
    ax = axs[1]
    s = res.shifted
    Ts = (s["T_C"] - T.min()) / max(np.ptp(T), 1e-9)
    ax.scatter(s["f_Hz"], s["E_storage_Pa"], c=cmap(Ts), s=6)
    ax.scatter(s["f_Hz"], s["E_loss_Pa"], c=cmap(Ts), s=6, marker="^")
    m = res.master
    ax.loglog(m.f_Hz, m.E_storage_Pa, "k-", lw=1.2, label="master E' (smoothed)")
    ax.loglog(m.f_Hz, m.E_loss_Pa, "k--", lw=1.2, label="master E''")
    Ep = res.prony.modulus_ref(2 * np.pi * m.f_Hz)
    ax.loglog(m.f_Hz, Ep.real, color="C2", lw=0.8, label=f"Prony ({res.prony.E_i_Pa.size} terms)")
    ax.loglog(m.f_Hz, Ep.imag, color="C2", lw=0.8, ls="--")
    ax.set_xlabel(f"reduced frequency f aT [Hz] at T_ref = {res.T_ref_C:g} °C"), ax.set_ylabel("modulus [Pa]")
    ax.set_title("shifted sweeps and master curve", fontsize=9)
    ax.legend(fontsize=8)
    ax = axs[2]
    methods = [i["method"] for i in res.sweep_info]
    for meth, mk in (("reference", "s"), ("overlap", "o"), ("trend", "x")):
        k = [j for j, mm in enumerate(methods) if mm == meth]
        if k:
            ax.plot(res.T_sweep_C[k], res.log10_aT[k], mk, label=f"shift: {meth}")
    Tg = np.linspace(res.T_sweep_C.min(), res.T_sweep_C.max(), 200)
    w = res.wlf
    ax.plot(
        Tg,
        w.log10_aT(Tg),
        "k-",
        lw=1,
        label=f"WLF C1 = {sig3(w.C1)}, C2 = {sig3(w.C2_K)} K (rms {res.wlf_rms_decades:.2f} dec)",
    )
    ax.set_xlabel("temperature T [°C]"), ax.set_ylabel("log10 aT")
    ax.set_title("shift factors aT(T)", fontsize=9)
    ax.grid(alpha=0.3), ax.legend(fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)


def build_rubber_master(raw, reference_temperature_C, out, prony_per_decade=1.5):
    """Build the master curve of the sweeps in ``raw`` and write the files of the module
    docstring (all or none).

    Parameters
    ----------
    raw : str or Path
        Raw sweeps CSV: f [Hz], E_stor, E_loss, T [C] (+ units line), optional Set.
    reference_temperature_C : float
        T_ref of the master curve [C] (within the sweeps' range).
    out : str or Path
        The rubber TOML to write.
    prony_per_decade : float
        Prony terms per decade of the master curve, in [0.2, 5].

    Returns
    -------
    :class:`friction.mastercurve` result
        With ``master``, ``shift table``, ``wlf``, ``prony``, ``sweep_info``...
    """
    import numpy as np

    import friction
    from friction.mastercurve import build_master
    from pipelines.output.report import write_csv, write_json
    from pipelines.settings.rubber_file import load_rubber, read_dma_sweeps_csv
    from roadscan.io.atomic import atomic_file_set, atomic_write_text
    from roadscan.io.overwrite_guard import refuse_overwrite

    if not (math.isfinite(prony_per_decade) and 0.2 <= prony_per_decade <= 5):
        raise InputError(None, "--prony-per-decade must lie in [0.2, 5]")
    out = Path(out)
    if out.suffix.lower() != ".toml":
        raise InputError(out, "--out must name a .toml file")
    refuse_overwrite([out] + [out.with_name(out.stem + s) for s in MASTER_SUFFIXES], [raw])
    f, E1, E2, T, sid = read_dma_sweeps_csv(raw)
    try:
        with np.errstate(all="ignore"):
            res = build_master(
                f, E1, E2, T, reference_temperature_C, set_id=sid, prony_per_decade=prony_per_decade
            )
    except ValueError as exc:  # the sweeps cannot be superposed: friction's own checks
        raise InputError(raw, str(exc)) from None
    with atomic_file_set(out) as d:  # the TOML and its data files: all or none
        stem = out.stem
        mc_name, sh_name = f"{stem}_master.csv", f"{stem}_shift.csv"
        m = res.master
        write_csv(d / mc_name, ["f_Hz", "E_storage_Pa", "E_loss_Pa"], [m.f_Hz, m.E_storage_Pa, m.E_loss_Pa])
        write_csv(d / sh_name, ["T_C", "log10_aT"], [res.T_sweep_C, res.log10_aT])
        s = res.shifted
        write_csv(
            d / f"{stem}_shifted.csv",
            ["f_Hz", "E_storage_Pa", "E_loss_Pa", "T_C", "sweep"],
            [s["f_Hz"], s["E_storage_Pa"], s["E_loss_Pa"], s["T_C"], s["sweep"]],
        )
        w, p = res.wlf, res.prony
        toml = (
            f"# Master curve at T_ref = {res.T_ref_C:g} C from the raw DMA sweeps {Path(raw).name}\n"
            f"# by time-temperature superposition (roadscan rubber master; friction/mastercurve.py).\n"
            f"# WLF fit to the shift table: C1 = {w.C1:.6g}, C2_K = {w.C2_K:.6g}, T_s_C = {w.T_s_C:g}\n"
            f"# (rms {res.wlf_rms_decades:.3f} decades, max {res.wlf_max_decades:.3f}); to use it, replace\n"
            f'# [shift] by kind = "wlf" with those constants. The Prony series below fits the master\n'
            f'# curve (rms relative misfit {res.prony_rms:.3f}); to use it, set model = "prony".\n'
            f'model = "master_curve"\nT_ref_C = {res.T_ref_C!r}\n'
            f'source = "roadscan rubber master {Path(raw).name} --reference-temperature {res.T_ref_C:g}"\n\n'
            f'[master_curve]\nfile = "{mc_name}"   # f_Hz, E_storage_Pa, E_loss_Pa (smoothed)\n\n'
            f'[shift]\nkind = "table"\nfile = "{sh_name}"   # T_C, log10_aT\n\n'
            f"[prony]\nE_inf_Pa = {p.E_inf_Pa:.10g}\nE_i_Pa = {_toml_list(p.E_i_Pa)}\n"
            f"tau_i_s = {_toml_list(p.tau_i_s)}\n"
        )
        atomic_write_text(d / out.name, toml)
        check = load_rubber(d / out.name)  # the TOML must load as --rubber does
        assert isinstance(check, friction.MasterCurve)
        summary = {
            "raw": str(raw),
            "T_ref_C": res.T_ref_C,
            "sweeps": len(res.T_sweep_C),
            "shift_table": [
                {"T_C": float(t), "log10_aT": float(a), **i}
                for t, a, i in zip(res.T_sweep_C, res.log10_aT, res.sweep_info)
            ],
            "wlf_fit": {
                "C1": w.C1,
                "C2_K": w.C2_K,
                "T_s_C": w.T_s_C,
                "rms_decades": res.wlf_rms_decades,
                "max_abs_decades": res.wlf_max_decades,
            },
            "master_curve_f_Hz": [float(m.f_Hz[0]), float(m.f_Hz[-1])],
            "prony": {"terms": int(p.E_i_Pa.size), "rms_relative_misfit": res.prony_rms},
            "files": {
                "toml": out.name,
                "master": mc_name,
                "shift": sh_name,
                "shifted": f"{stem}_shifted.csv",
                "plot": f"{stem}_master.png",
            },
        }
        write_json(d / f"{stem}_master.json", summary)
        _plot(res, (f, E1, E2, T), d / f"{stem}_master.png")
    return res
