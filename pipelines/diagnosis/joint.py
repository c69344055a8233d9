"""Several measurements at once (``roadscan diagnose --measurements M.csv``): compounds measured
on the same road share q1, the spectrum's level and the nominal pressure.

``M.csv``: header ``measured,rubber,label`` plus optional ``temperature_C`` and ``sigma0_Pa``;
``measured`` is a mu(v) CSV (:mod:`.measured`), ``rubber`` a rubber TOML (friction/RUBBER_TOML.md),
both relative to M.csv; ``label`` names the row (unique). A row's ``temperature_C`` and
``sigma0_Pa`` are the defaults of its curve's rows (as ``--temperature`` and ``--sigma0``).

Joint calibration: the shared uncertain inputs (q1, psd_scale, sigma0; q1 also by default where
mu is carried by the cut-off in some row) are fitted once on the training points of every row
together (bounded least squares in the unit cube from the three best separated points of a coarse
grid; one sigma0 for every row), with Gauss-Newton 95 % intervals (as
:func:`calibration.intervals`): ``joint.calibrated``. Each row is then diagnosed on its own
(:func:`run.diagnose_curve`) within the same ranges (not the joint interval: a local interval can
exclude the truth where the shared inputs trade off against one another, and a row forced
outside it would blame an effect); an ``--uncertain`` temperature range applies to every row.
``joint.effects``: every effect named in some row, with the rows naming it and whether it holds in every row.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pipelines.diagnosis.fit.calibration import KEYS, Uncertain, calibration_effect, default_q1, free_ranges
from roadscan.errors import InputError

__all__ = ["Row", "read_measurements", "joint_calibration", "run_joint", "SHARED"]

SHARED = ("q1", "psd_scale", "sigma0")


@dataclass(eq=False)
class Row:
    """One measurement of M.csv: its label, curve, rubber and files.

    Attributes
    ----------
    label : str
        The row's ``label`` cell, unique in M.csv; names the row in reports.
    curve : MeasuredCurve
        The measured mu(v) of the row's ``measured`` file, with the row's T0 and sigma0 defaults.
    rubber : rubber model
        The rubber loaded from the row's ``rubber`` file.
    measured_path, rubber_path : Path
        The two files, resolved against M.csv's folder.
    line : int
        Line number of the row in M.csv (the header is line 1).
    """

    label: str
    curve: object
    rubber: object
    measured_path: Path
    rubber_path: Path
    line: int


def read_measurements(path, sigma0_Pa=0.2e6, T0_C=None):
    """Read M.csv (see module docstring) -> list of :class:`Row` (InputError, one line, naming
    M.csv and the line, on a missing column, an empty or repeated label, or a bad row file).

    Parameters
    ----------
    path : str or Path
        M.csv: columns measured, rubber, label[, temperature_C, sigma0_Pa]; files relative to it.
    sigma0_Pa : float, optional
        Nominal pressure [Pa] where neither the row nor its measured file gives one (default 0.2 MPa).
    T0_C : float, optional
        Background temperature [C] where neither the row nor its file gives one; None: T_ref.

    Returns
    -------
    list of Row
        One per data line, in file order.
    """
    from pipelines.diagnosis.measured import read_measured
    from pipelines.output.csv_files import read_csv_rows
    from pipelines.settings.rubber_file import load_rubber

    path = Path(path)
    header, body = read_csv_rows(path, "a header measured,rubber,label")
    col = {h: i for i, h in enumerate(header)}
    for need in ("measured", "rubber", "label"):
        if need not in col:
            raise InputError(
                path,
                f"missing column {need!r} (header is {','.join(header)!r}; "
                "needs measured,rubber,label[,temperature_C,sigma0_Pa])",
            )
    if not body:
        raise InputError(path, "no measurement rows")
    rows, seen = [], set()
    for k, r in enumerate(body, start=2):
        r = r + [""] * (len(header) - len(r))
        label = r[col["label"]].strip()
        if not label:
            raise InputError(path, f"line {k}: empty label")
        if label in seen:
            raise InputError(path, f"line {k}: label {label!r} repeated")
        seen.add(label)
        T = _opt(r, col, "temperature_C", path, k)
        s = _opt(r, col, "sigma0_Pa", path, k)
        if s is not None and not s > 0:
            raise InputError(path, f"line {k}: sigma0_Pa {s:g} must be positive")
        mp = (path.parent / r[col["measured"]]).resolve()
        rp = (path.parent / r[col["rubber"]]).resolve()
        if not r[col["measured"]] or not r[col["rubber"]]:
            raise InputError(path, f"line {k}: measured and rubber must name files")
        try:
            curve = read_measured(mp, sigma0_Pa=sigma0_Pa if s is None else s, T0_C=T0_C if T is None else T)
            rubber = load_rubber(rp)
        except InputError as exc:
            raise InputError(path, f"line {k} ({label}): {exc}") from None
        rows.append(Row(label, curve, rubber, mp, rp, k))
    return rows


def _opt(r, col, name, path, k):
    if name not in col or not r[col[name]].strip():
        return None
    try:
        x = float(r[col[name]])
    except ValueError:
        raise InputError(path, f"line {k}: {name} {r[col[name]]!r} is not a number") from None
    if not np.isfinite(x):
        raise InputError(path, f"line {k}: {name} must be finite")
    return x


def joint_calibration(ctxs, mus, trains, ranges, noise, log=None):
    """Fit the shared inputs over every row. Returns dict PARAM name -> dict(value, interval,
    range) and the per-row calibration effects (None when no shared input is free).

    Parameters
    ----------
    ctxs : list of FrictionContext
        One per measurement (row of M.csv).
    mus : list of ndarray
        Measured mu of each measurement, one value per row of its context.
    trains : list of ndarray
        Boolean mask per measurement of the points the joint fit uses.
    ranges : dict
        Input name -> :class:`Uncertain` of the shared inputs (q1, psd_scale, sigma0).
    noise : float
        rms log10 noise: the floor of the residual scale in the Gauss-Newton intervals.
    log : callable, optional
        Called with one line (str) giving the calibrated values; None: silent.

    Returns
    -------
    calibrated : dict
        Parameter name -> dict(value, interval (95 %, sd at least 0.025 in the unit cube), range);
        empty when no shared input is free.
    effects : list or None
        The calibration effect of each context; None when no shared input is free.
    """
    from pipelines.diagnosis.fit.fitting import pack, unpack
    from pipelines.diagnosis.fit.stats import gauss_newton_cov, jacobian, multistart_lsq
    from pipelines.diagnosis.model import simulate

    effs = [calibration_effect(c, ranges) for c in ctxs]
    if any(e is None for e in effs):
        return {}, None
    e0 = effs[0]
    k = len(e0.params)
    ys = [np.log10(m)[t] for m, t in zip(mus, trains)]
    cache = {}

    def model(u):
        key = tuple(np.round(u, 10))
        if key not in cache:
            out = []
            for c, e, t in zip(ctxs, effs, trains):
                try:
                    p = unpack((e,), u)[0]
                    out.append(np.log10(simulate(e.modify(c.base, p, c), c))[t])
                except (ValueError, ArithmeticError, RuntimeError):
                    out.append(np.full(int(t.sum()), np.nan))
            cache[key] = np.concatenate(out)
        return cache[key]

    y = np.concatenate(ys)

    def resid(u):
        r = y - model(u)
        return np.where(np.isfinite(r), r, 1e3)

    axes = [np.linspace(0.05, 0.95, {1: 7, 2: 5}.get(k, 3))] * k
    grid = np.array(np.meshgrid(*axes, indexing="ij")).reshape(k, -1).T
    grid = np.vstack([pack((e0,), [e0.null_params(ctxs[0])]), grid])
    costs = np.array([float(np.sum(resid(g) ** 2)) for g in grid])
    best_u, best_c = grid[int(np.argmin(costs))], float(costs.min())
    starts = []
    for i in np.argsort(costs):
        if len(starts) < 3 and all(np.max(np.abs(grid[i] - s0)) > 0.2 for s0 in starts):
            starts.append(grid[i])
    best_u, best_c = multistart_lsq(
        resid,
        starts,
        u_best=best_u,
        c_best=best_c,
        diff_step=0.02,
        max_nfev=20 * k,
        x_scale=0.1,
        xtol=1e-4,
        ftol=1e-6,
    )
    r = resid(best_u)
    J = -jacobian(resid, best_u, f0=r)
    cov = gauss_newton_cov(J, r, noise)
    out = {}
    if log:
        log(
            f"joint calibration over {len(ctxs)} measurements: "
            + ", ".join(f"{p.name} = {p.from_unit(best_u[j]):.4g}" for j, p in enumerate(e0.params))
        )
    for j, p in enumerate(e0.params):
        sd = max(float(np.sqrt(max(cov[j, j], 0.0))), 0.025)
        out[p.name] = dict(
            value=p.from_unit(best_u[j]),
            interval=[p.from_unit(best_u[j] - 1.96 * sd), p.from_unit(best_u[j] + 1.96 * sd)],
            range=[p.lo, p.hi],
        )
    return out, effs


def run_joint(rows, ctxs, noise=None, uncertain=None, log=None):
    """Diagnose every row with the shared inputs calibrated jointly.

    Returns (joint dict, list of (row, Diagnosis, where, bm, bm_curves)).

    Parameters
    ----------
    rows : list of Row
        The measurements of M.csv.
    ctxs : list of FrictionContext
        One per row, in the same order.
    noise : float, optional
        rms log10 noise of every row; None: each row's own estimate (the joint fit: their median).
    uncertain : dict, optional
        Input name -> :class:`Uncertain` (``--uncertain``); None: only q1's default range, if any.
    log : callable, optional
        Called with one progress line (str) per step; None: silent.

    Returns
    -------
    joint : dict
        shared_inputs, calibrated, uncertain, effects (name, rows naming it), noise and method.
    results : list of tuple
        (row, Diagnosis, where, bm, bm_curves) per row, as :func:`run.diagnose_curve` returns.
    """
    from pipelines.diagnosis.fit.cv import holdout
    from pipelines.diagnosis.run import diagnose_curve

    say = log or (lambda *_: None)
    uncertain = dict(uncertain or {})
    shared = {k: u for k, u in uncertain.items() if k in SHARED}
    if "q1" not in shared:
        for c in ctxs:
            r, _ = default_q1(c, {})
            if "q1" in r:
                shared["q1"] = r["q1"]
                break
    from pipelines.diagnosis.gap import estimate_noise

    nz = (
        noise
        if noise is not None
        else float(np.median([estimate_noise(r.curve.v_m_per_s, r.curve.mu) for r in rows]))
    )
    joint_cal = {}
    if free_ranges(ctxs[0], shared):
        trains = [holdout(r.curve.n).train for r in rows]
        joint_cal, _ = joint_calibration(ctxs, [r.curve.mu for r in rows], trains, shared, nz, log=say)
    # each row keeps the full ranges: a joint interval from a local (Gauss-Newton) fit can exclude
    # the truth where the shared inputs trade off against one another (q1 against the spectrum's
    # level), and a row forced outside it would blame an effect
    per_row = dict(shared)
    if "temperature" in uncertain:
        per_row["temperature"] = uncertain["temperature"]
    if "q1" not in per_row:
        per_row["q1"] = Uncertain("q1", np.nan, np.nan, "known")  # q1 neither uncertain nor carried
    results = []
    for row, c in zip(rows, ctxs):
        say(f"== {row.label}")
        d, where, bm, bmc = diagnose_curve(row.curve, c, noise=noise, log=say, uncertain=per_row)
        results.append((row, d, where, bm, bmc))
    named = {}
    for row, d, *_ in results:
        e = d.verdict["effect"]
        for name in [e] if isinstance(e, str) else (e or []):
            if name != "calibration":
                named.setdefault(name, []).append(row.label)
    joint = dict(
        shared_inputs=[k for k in KEYS if k in shared],
        calibrated=joint_cal,
        uncertain={k: dict(range=[float(u.lo), float(u.hi)], source=u.source) for k, u in shared.items()},
        effects=[
            dict(name=n, rows=labels, all_rows=len(labels) == len(rows))
            for n, labels in sorted(named.items())
        ],
        noise=nz,
        method=(
            "shared inputs fitted on the training points of "
            "every row together (Gauss-Newton 95 % intervals); "
            "each row then diagnosed with them uncertain within the same ranges"
        ),
    )
    return joint, results
