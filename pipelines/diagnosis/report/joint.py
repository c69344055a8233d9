"""Outputs of a several-measurement diagnosis (``--measurements M.csv``): ``diagnosis.json`` with
``joint`` and ``measurements`` (keyed by label; each one a single diagnosis with the same keys as
``--measured``), and one ``report.html`` showing every compound."""

from __future__ import annotations

import tempfile
from pathlib import Path

from pipelines.output import report as rep

__all__ = ["joint_json", "write_joint_report"]


def joint_json(joint, results, settings, given, psd_files):
    """The diagnosis.json dict (``settings``: engine_settings per label; ``given``: provenance
    hints; ``psd_files``: [(role, path)] of the shared surface).

    Parameters
    ----------
    joint : dict
        The ``joint`` dict of :func:`joint.run_joint` (shared inputs, calibration, effects).
    results : list of tuple
        (row, Diagnosis, where, bm, bm_curves) per measurement, from :func:`joint.run_joint`.
    settings : dict
        Engine settings per label.
    given : dict
        ``given``: names of the inputs the user set (:func:`run_command.provenance_hints`).
    psd_files : list of tuple
        (role, path) of the surface.

    Returns
    -------
    dict
        level, mode ("measurements"), joint (with each row's verdict), measurements (label ->
        that row's friction diagnosis.json), inputs (the first row's, every file) and seconds.
    """
    from pipelines.diagnosis.report.provenance import inputs_json
    from pipelines.diagnosis.report.single import friction_json

    measurements = {}
    for row, d, where, bm, _ in results:
        data = friction_json(d, where, bm)
        data["engine_settings"] = dict(settings.get(row.label) or {})
        g = dict(
            given, files=list(psd_files) + [("measured", row.measured_path), ("rubber", row.rubber_path)]
        )
        data["inputs"] = inputs_json(d.ctx, d, g)
        data["engine_settings"]["sigma0_Pa"] = data["inputs"]["sigma0_Pa"]
        data["label"] = row.label
        measurements[row.label] = data
    first = next(iter(measurements.values()))
    verdicts = {k: m["verdict"]["effect"] for k, m in measurements.items()}
    return dict(
        level="friction",
        mode="measurements",
        joint=dict(joint, verdicts=verdicts),
        measurements=measurements,
        inputs=dict(first["inputs"], files=_files(measurements)),
        seconds=round(sum(m["seconds"] for m in measurements.values()), 2),
    )


def _files(measurements):
    seen, out = set(), []
    for m in measurements.values():
        for f in m["inputs"]["files"]:
            if f["path"] not in seen:
                seen.add(f["path"])
                out.append(f)
    return out


def write_joint_report(out_dir, data, results):
    """``report.html``: the shared inputs and their joint calibration, a verdict table, and per
    compound its μ(v) figure (band of the uncertain inputs, held-out points, corrected curve).

    Parameters
    ----------
    out_dir : str or Path
        Existing folder that receives report.html and its figures.
    data : dict
        The dict :func:`joint_json` made (the content of ``diagnosis.json``).
    results : list of tuple
        (row, Diagnosis, where, bm, bm_curves) per measurement, for the μ(v) figures.

    Returns
    -------
    None
        The report is written to ``out_dir``.
    """
    import matplotlib.pyplot as plt

    from pipelines.diagnosis.report.curves import report_curves
    from pipelines.diagnosis.report.single import _verdict_html, inputs_html, mu_axes

    j = data["joint"]
    cal = (
        rep.table_html(
            [
                (
                    k,
                    f"{x['value']:.4g}",
                    f"{x['interval'][0]:.4g} – {x['interval'][1]:.4g}",
                    f"{x['range'][0]:.4g} – {x['range'][1]:.4g}",
                )
                for k, x in j["calibrated"].items()
            ],
            header=["shared input", "joint fit", "95 % interval", "allowed range"],
        )
        if j["calibrated"]
        else rep.paragraph_html("no shared input was uncertain")
    )
    eff = (
        rep.table_html(
            [(e["name"], ", ".join(e["rows"]), "yes" if e["all_rows"] else "no") for e in j["effects"]],
            header=["effect", "named in", "holds in every row"],
        )
        if j["effects"]
        else rep.paragraph_html("no effect named in any row")
    )
    table = []
    for label, m in data["measurements"].items():
        v = m["verdict"]
        name = v["effect"] if not isinstance(v["effect"], list) else "+".join(v["effect"])
        if not name and v.get("inconclusive"):
            name = "inconclusive: " + ", ".join(v["inconclusive"])
        table.append(
            (
                label,
                name or "no effect",
                v.get("confidence") or "",
                v.get("shrink"),
                m["baseline_gap"],
                m["noise"],
                ", ".join(v.get("implausible") or []) or "",
            )
        )
    verdicts = rep.table_html(
        table,
        header=[
            "compound",
            "verdict",
            "confidence",
            "held-out shrink",
            "baseline gap",
            "noise",
            "implausible",
        ],
    )
    sections = [
        ("Shared model inputs", [inputs_html(data["inputs"])]),
        ("Joint calibration of the shared inputs", [cal, rep.paragraph_html(f"{j['method']}.")]),
        ("Verdict per compound", [verdicts, eff]),
    ]
    with tempfile.TemporaryDirectory() as t:
        for i, (row, d, *_) in enumerate(results):
            fig, ax = plt.subplots(figsize=rep.FIGSIZE)
            mu_axes(
                ax,
                row.curve,
                d,
                report_curves(d.ctx, d),
                title=f"{row.label}: measured, simulated, corrected μ(v)",
            )
            png = rep.save_figure(fig, Path(t) / f"mu_{i}.png", rep.fixed_margins(ax))
            m = data["measurements"][row.label]
            nxt = m.get("next_measurement")
            sections.append(
                (
                    f"Compound {row.label}",
                    [
                        _verdict_html(dict(m["verdict"], next=nxt and nxt["sentence"])),
                        inputs_html(data["measurements"][row.label]["inputs"]),
                        png,
                    ],
                )
            )
        rep.write_html(
            Path(out_dir) / "report.html",
            "Sim-to-real gap diagnosis of several compounds",
            sections,
            intro="Several measured μ(v) on one road: q1, the spectrum's level and the nominal pressure "
            "are shared and calibrated jointly; each compound then gets its own verdict.",
        )
