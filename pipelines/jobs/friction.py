"""The ``roadscan friction`` job: mu(v) and A/A0 from a spectrum (a ``psd.csv`` or a
self-affine model) and a rubber (Persson's theory), and the files the command writes.

Outputs: ``--out mu.csv`` with columns ``v_m_per_s,mu,area_fraction`` (A/A0 = P(q1) at each
speed; with ``--flash`` also ``T_flash_max_C``, the hottest flash temperature over all length
scales, then ``T_C_zeta_1``, ``T_C_zeta_max`` and ``T_C_zeta_<z>`` per ``--magnifications``
value) and ``extrapolated_share``, a PNG plot beside it (same stem) and ``<stem>_summary.json``
(inputs, the integration band, the master-curve frequency coverage and the WLF fit of a shift
table). A ``psd.csv`` written by ``roadscan analyse`` is integrated over the band analyse used
(``psd_band.json`` beside it), so that the same flags give analyse's mu(v).
"""

from __future__ import annotations

import math
from pathlib import Path

from roadscan.errors import InputError

__all__ = ["run_friction"]


def _self_affine(text):
    from friction import SelfAffinePSD

    keys = {
        "h": "hurst",
        "hurst": "hurst",
        "h0": "h0_m",
        "q0": "q0_per_m",
        "q1": "q1_per_m",
        "qroll": "q_roll_per_m",
        "q_roll": "q_roll_per_m",
    }
    kw = {}
    for part in filter(None, (s.strip() for s in text.split(","))):
        k, sep, val = part.partition("=")
        if not sep or k.strip().lower() not in keys:
            raise InputError(None, f"--self-affine: bad item {part!r} (use H=..,h0=..,q0=..,q1=..)")
        try:
            kw[keys[k.strip().lower()]] = float(val)
        except ValueError:
            raise InputError(None, f"--self-affine: {k}={val!r} is not a number") from None
        if not math.isfinite(kw[keys[k.strip().lower()]]):
            raise InputError(None, f"--self-affine: {k.strip()}={val.strip()}: must be finite")
    missing = {"hurst", "h0_m", "q0_per_m", "q1_per_m"} - set(kw)
    if missing:
        raise InputError(None, "--self-affine: missing " + ", ".join(sorted(missing)))
    from pipelines.checks.validate import check_wave_vector

    for key in ("q0_per_m", "q1_per_m", "q_roll_per_m"):
        if key in kw:
            check_wave_vector(
                kw[key], f"--self-affine {key.split('_')[0] if key != 'q_roll_per_m' else 'qroll'}="
            )
    # the model's own conditions, checked here: a ValueError from SelfAffinePSD is then a bug
    if not 0 < kw["hurst"] < 1.5:
        raise InputError(None, f"--self-affine H={kw['hurst']:g}: must lie in (0, 1.5)")
    if not kw["h0_m"] > 0:
        raise InputError(None, f"--self-affine h0={kw['h0_m']:g}: must be a positive height in m")
    if not kw["q0_per_m"] < kw["q1_per_m"]:
        raise InputError(None, f"--self-affine q0={kw['q0_per_m']:g} must be below q1={kw['q1_per_m']:g}")
    if kw.get("q_roll_per_m") is not None and not kw["q_roll_per_m"] < kw["q0_per_m"]:
        raise InputError(
            None, f"--self-affine qroll={kw['q_roll_per_m']:g} must be below q0={kw['q0_per_m']:g}"
        )
    return SelfAffinePSD(**kw)


def _psd(args, settings=None):
    """(friction PSD, band dict). A ``psd.csv`` written by ``roadscan analyse`` carries its band
    beside it (``psd_band.json``): the spectrum is then integrated over the band analyse used,
    continued above its last row by analyse's self-affine fit (:func:`pipelines.chain.steps.friction_psd`),
    so that the same flags give analyse's mu(v)."""
    from pipelines.output.csv_files import read_psd_csv
    from pipelines.settings.friction import apply_band

    if args.psd:
        table = read_psd_csv(args.psd)
        from pipelines.chain.sidecar import read_band_sidecar
        from pipelines.chain.steps import friction_psd

        side = read_band_sidecar(args.psd) if settings is not None else None
        if side is not None:
            from roadscan.spectrum_types import Spectrum

            rb, fit, path = side
            spec = Spectrum(table.q_per_m, table.C_m4, kind="table", meta={"source": str(args.psd)})
            psd, band = friction_psd(spec, fit, rb, settings, say=True)
            from pipelines.chain.steps import judge_fine_end
            from pipelines.checks.run_warnings import note

            _, refused = judge_fine_end(psd, rb, settings)  # as analyse judged the band
            if refused is not None:
                raise InputError(args.psd, refused)
            band = dict(band or {}, band_from=str(path))
            note(
                f"note: {args.psd}: integrated over the band of {path.name} "
                f"({band['q0_per_m']:.6g} to {band['q1_per_m']:.6g} 1/m)"
            )
            return psd, band
        psd, band = apply_band(table, args.q0, args.q1)
        if band is None:
            band = dict(
                q0_per_m=psd.q_min_per_m,
                q1_per_m=psd.q1_per_m,
                q_table_min_per_m=psd.q_min_per_m,
                q_table_max_per_m=float(psd.q_per_m[-1]),
                extended_decades=0.0,
                tail_exponent=None,
            )
        return psd, band
    psd = _self_affine(args.self_affine)
    if args.q0 is not None:
        raise InputError(None, "--q0 with --self-affine: give q0= (and qroll=) inside --self-affine")
    if args.q1 is not None:
        from pipelines.checks.validate import check_q1

        psd = psd.with_q1(check_q1(args.q1, psd.q0_per_m))  # SelfAffinePSD needs q0 < q1
    return psd, dict(q0_per_m=psd.q_min_per_m, q1_per_m=psd.q1_per_m, extended_decades=0.0)


def run_friction(args):
    """``roadscan friction``'s job on its parsed flags: the spectrum (``--psd``, integrated over
    the band analyse wrote beside it when there is one, or ``--self-affine``), mu(v) through
    :func:`pipelines.chain.steps.friction_of`, its provenance, and the outputs of ``--out`` (mu.csv,
    ``<stem>_summary.json``, ``<stem>.png``), all or none. Returns (engine result, speeds [m/s],
    friction PSD, out path).

    Friction: Persson, J. Chem. Phys. 115, 3840 (2001); flash temperature: Persson, J. Phys.:
    Condens. Matter 18, 7789 (2006).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags of ``roadscan friction``.

    Returns
    -------
    tuple
        (FrictionResult, speeds [m/s], spectrum, outputs written).
    """
    import numpy as np

    import friction
    from pipelines.chain.surface import default_velocities
    from pipelines.settings.friction import run_checks, settings_from_args, with_extrapolation
    from roadscan.io.overwrite_guard import refuse_overwrite

    out = Path(args.out)  # mu.csv, its summary and plot never replace an input
    refuse_overwrite(
        [out, out.with_name(out.stem + "_summary.json"), out.with_suffix(".png")],
        [getattr(args, k, None) for k in ("psd", "rubber", "master_curve", "shift_table")],
    )
    settings = settings_from_args(args)  # checked: contact options, rubber, pressure, T0
    sigma0 = settings.sigma0_Pa
    v = settings.v_m_per_s if settings.v_m_per_s is not None else default_velocities()
    if not (0 < args.tol < 0.1):
        raise InputError(None, "--tol must lie in (0, 0.1)")
    psd, band = _psd(args, settings)
    rubber = with_extrapolation(
        settings.rubber if settings.rubber is not None else friction.thesis_rubber(), args.extrapolate
    )
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

    kw = dict(
        sigma0_Pa=sigma0, nu=args.nu, T0_C=args.temperature, tol=args.tol, contact_gamma=args.contact_gamma
    )
    from pipelines.chain.steps import friction_of

    try:  # the one engine call of every command (pipelines.chain.steps)
        res = friction_of(psd, settings, v, tol=args.tol)
    except RuntimeError as exc:
        raise InputError(None, f"friction: {exc}") from None
    # no `except ValueError`: the flags were checked above (settings_from_args, _psd), so a
    # ValueError from the engine is a bug (exit 1, "internal error"), not bad input
    prov = _provenance(args, psd, band, res, rubber, settings, v, kw)
    out = Path(args.out)
    if out.suffix.lower() == ".png":
        raise InputError(None, f"--out {out}: name the CSV (the plot is written beside it as {out.stem}.png)")
    area = res.P[:, -1]
    header, cols = ["v_m_per_s", "mu", "area_fraction"], [res.v_m_per_s, res.mu, area]
    T_max = None
    if args.flash:
        T_max = np.max(res.T_q_C, axis=1)
        header += ["T_flash_max_C", "T_C_zeta_1", "T_C_zeta_max"]
        cols += [T_max, res.temperature_at(1.0), res.temperature_at(zmax)]
        for z in zetas:
            header.append(f"T_C_zeta_{z:g}")
            cols.append(res.temperature_at(z))
    header.append("extrapolated_share")  # after the existing columns
    cols.append(prov["extrapolated_share"])
    checks = run_checks(
        rubber,
        v,
        psd.q_min_per_m,
        psd.q1_per_m,
        res.meta["T0_C"],
        None if T_max is None else float(T_max.max()),
        result=res,
    )
    from roadscan.io.atomic import atomic_file_set

    with atomic_file_set(out) as tmp:  # mu.csv, its summary and plot: all or none
        _write_outputs(tmp, out, header, cols, res, args, sigma0, rubber, band, area, checks, T_max, prov)
    return res, v, psd, out


def _provenance(args, psd, band, res, rubber, settings, v, kw):
    """extrapolated_share per speed (beyond a --psd table's last row; a --self-affine model
    measures nothing: 0), the rubber's label, and the implausible-mu warning naming its cause."""
    import numpy as np

    import friction
    from pipelines.chain import provenance as mp
    from pipelines.checks.validate import warn

    engine = friction.mu_flash if args.flash else friction.mu_isothermal
    q_meas = band.get("q_table_max_per_m") if args.psd else None

    def recompute(p):
        with np.errstate(all="ignore"):
            return engine(p, rubber, v, **kw).mu

    share = mp.extrapolated_share(psd, res.mu, q_meas, recompute)
    i = int(np.argmax(res.mu))
    default = settings.rubber is None and not getattr(args, "master_curve", None)
    label = mp.rubber_label(None if default else rubber, settings.sigma0_Pa, res.meta["T0_C"])
    cause = mp.implausible_cause(
        float(res.mu[i]),
        share_at_peak=float(share[i]),
        slope=mp.rms_slope(psd),
        default_rubber=default,
        q1_per_m=psd.q1_per_m,
    )
    if cause and args.psd:  # a spectrum file: its C may be in another normalisation
        from pipelines.checks.psd_plausibility import normalisation_cause

        cause = f"{cause}; {normalisation_cause()}"
    if cause:
        warn(f"{args.out}: {cause}")
    edge = mp.edge_warning(res.v_m_per_s, res.mu)  # no peak inside the speed range
    if edge:
        warn(f"{args.out}: {edge}")
    return {
        "extrapolated_share": share,
        "extrapolated_share_at_peak": float(share[i]),
        "rubber": label,
        "implausible": cause,
        "extrapolated_from_per_m": q_meas,
    }


def _write_outputs(tmp, out, header, cols, res, args, sigma0, rubber, band, area, checks, T_max, prov=None):
    from pipelines.output.headline import peak_keys
    from pipelines.output.report import plot_mu, write_csv, write_json

    write_csv(tmp / out.name, header, cols)
    mu_max, v_max = res.peak
    summary = {
        "model": "flash temperature" if args.flash else "isothermal",
        "sigma0_Pa": sigma0,
        "nu": args.nu,
        "pressure_in_P_Pa": (1 - args.nu**2) * sigma0,
        "pressure_note": "sigma0 is the nominal pressure; P(q), G(q) and M(q) use (1 - nu^2) sigma0",
        "contact_gamma": args.contact_gamma,
        "T0_C": res.meta["T0_C"],
        "rubber": {"T_ref_C": rubber.T_ref_C, "kind": type(rubber).__name__},
        "band": band,
        "q_nodes": res.meta.get("q_nodes"),
        "mu_peak": mu_max,
        "v_peak_m_per_s": v_max,
        # largest mu at the first or last speed: no peak in the range (pipelines.output.headline)
        **{k: x for k, x in peak_keys(res.v_m_per_s, res.mu).items() if k.startswith("peak_")},
        "area_fraction_range": [float(area.min()), float(area.max())],
        "rubber_checks": checks,
    }
    if prov is not None:  # where mu comes from
        summary["rubber_label"] = prov["rubber"]
        summary["extrapolated_share"] = [float(x) for x in prov["extrapolated_share"]]
        summary["extrapolated_share_at_peak"] = prov["extrapolated_share_at_peak"]
        summary["extrapolated_from_per_m"] = prov["extrapolated_from_per_m"]
        from pipelines.checks import validate

        summary["warnings"] = validate.warnings_list()
    if T_max is not None:
        summary["T_flash_max_C"] = float(T_max.max())
    write_json(tmp / (out.stem + "_summary.json"), summary)
    title = (
        "μ(v), "
        + ("flash temperature" if args.flash else "isothermal")
        + (
            f", {prov['rubber']}"
            if prov is not None
            else f", σ0 = {sigma0 / 1e6:g} MPa, T0 = {res.meta['T0_C']:g} °C"
        )
    )
    plot_mu(
        [("", res.v_m_per_s, res.mu)],
        tmp / (out.stem + ".png"),
        title=title,
        ylabel="friction coefficient μ [-]",
    )
