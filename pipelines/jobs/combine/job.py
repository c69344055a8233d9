"""The ``combine`` job: several measurements of one surface -> one C(q) over all their scales.

Each input is read, turned into its spectrum and reliable band
(:mod:`pipelines.jobs.combine.sources`) and dropped before the next is read: the memory is that of
the largest single input. The reliable parts are merged (:func:`roadscan.spectrum_merge.
merge_spectra`: lattice-point-weighted mean per ring of a common log-q grid, 5-95 % band from
the rings' counts and the sources' scatter, gaps bridged by a fitted power law) and the merged
curve gets the self-affine fit of :func:`roadscan.fit.fit_self_affine` (H, h0, roll-off).

Outputs, all written into a temporary folder swapped in at the end
(:func:`roadscan.io.atomic.atomic_output_dir`):

- ``psd.csv``: ``q_per_m,C_m4,C_lo_m4,C_hi_m4,n_sources`` (readable by ``--psd``: the PSD
  reader takes ``q_per_m`` and ``C_m4`` and ignores the other columns);
- ``combine.json``: per input (``inputs``) its ``reliable_band_per_m``, reasons, spacing,
  size and resolution; ``merged_band_per_m``; ``gaps`` ([lo, hi] [1/m] each: no input
  reliable there) with ``gap_details`` (factor, rows, how bridged); ``disagreements`` (pairs
  of inputs whose C differ where both measure beyond their scatter: ``labels``, ``factor``
  C_a / C_b, ``q_from_per_m``, ``q_to_per_m``, ``rows``, ``sigma_ln``; each also a line of
  ``warnings`` naming the two labels and the factor); ``widened_rows_per_m`` (rows whose band
  was widened to what their neighbours say); ``fit``; ``q0_per_m`` (the surface's roll-off,
  Persson's q0 [1/m], or null when no input shows one: :mod:`roadscan.rolloff_origin` tells a
  surface's knee, seen by every input measuring across it, from an instrument's, near its own
  field of view or resolution) and ``q0_how`` (one line: who found it and why it is the
  surface's, or why there is none); per input its knee's verdict (``roll_off``); ``warnings``;
- ``combine.png`` (unless ``--no-figures``) and a self-contained ``report.html``.

Reference: Sanner et al., Surf. Topogr.: Metrol. Prop. 10, 035014 (2022) (merging the spectra
of several instruments within their reliable ranges).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Literal

import numpy as np

from pipelines.output.job_result import returns_job_result
from pipelines.settings.option_docs import document_options
from roadscan.errors import InputError

__all__ = ["combine", "run_combine", "combine_sources", "PSD_HEADER"]

PSD_HEADER = ["q_per_m", "C_m4", "C_lo_m4", "C_hi_m4", "n_sources"]
#: the merged curve has a row by this many 2 pi / L of the largest field of view
START_FOV = 8.0


def _spectra(entries, args):
    """Read, analyse and forget each input in turn -> list of SourceSpectrum."""
    from pipelines.jobs.combine.sources import source_spectrum
    from pipelines.settings.scan_input import load_scan

    out = []
    for e in entries:
        obj = load_scan(e.path, args, spacing=e.spacing, units=e.units)
        try:
            out.append(source_spectrum(obj, e.path, e.label, e.resolution_m))
        except InputError as exc:  # the scan's spectrum cannot carry a band or fit: name it
            if exc.path:
                raise
            raise exc.reworded(e.path, "cannot compute its spectrum: ") from None
        del obj
    return out


def _edge_bias(band):
    """Bias the band tolerates at its (low, high) end: leakage about 10 %; at a noise floor
    :data:`roadscan.reliable_band.NOISE_EXCESS` - 1 (25 %), else 10 % (aliasing, resolution)."""
    from roadscan.reliable_band import NOISE_EXCESS
    from roadscan.spectrum_merge import EDGE_BIAS

    hi = NOISE_EXCESS - 1.0 if band.hi_reason.startswith("noise floor") else EDGE_BIAS
    return (EDGE_BIAS, max(EDGE_BIAS, hi))


def _fit(spec, band, q0=None):
    """Self-affine fit of the merged curve -> (dict or None, note): over the straight stretch
    :func:`roadscan.fit.detect_band` finds, else (a gap in the middle leaves it no rings to
    compare) over the whole measured band; its roll-off the surface's q0 when one was found
    (:func:`roadscan.rolloff_origin.surface_q0`), else its own test's."""
    import warnings

    from roadscan.fit import fit_self_affine

    for b in (None, tuple(band)):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                f = fit_self_affine(spec, band=b, roll_off=q0)
        except ValueError as exc:
            last = exc
            continue
        if np.isfinite(f.hurst):
            d = f.as_dict()
            d["roll_off_per_m"] = f.q_roll_per_m
            note = (
                None
                if b is None
                else (
                    "self-affine fit over the whole merged band (no "
                    "straight stretch detected around its middle)"
                )
            )
            return d, note
        last = ValueError("the fit gave no finite H")
    return None, f"no self-affine fit of the merged spectrum ({last})"


def _judge_roll_offs(sources):
    """Each input's knee judged the surface's or its instrument's
    (:func:`roadscan.rolloff_origin.judge_roll_offs`, on the bands as measured), then each
    input's band and bends set from its verdict
    (:func:`pipelines.jobs.combine.sources.with_roll_off_verdict`) -> the verdicts."""
    from pipelines.jobs.combine.sources import with_roll_off_verdict
    from roadscan.rolloff_origin import RollOffView, judge_roll_offs

    # an area's rings show where they bend; a profile's 2D estimate C1 / q x f(H) holds for a
    # power law only and scatters with 2 degrees of freedom per mode: its own knee test only
    views = [
        RollOffView(
            s.label,
            s.band.q_roll_per_m,
            s.q_fov_per_m,
            s.band.limits.get("field_of_view") or s.band.lo_per_m,
            tuple(s.band.band),
            *((s.q_per_m, s.C_m4, s.count * s.dof_per_count) if s.kind == "area" else ()),
        )
        for s in sources
    ]
    verdicts = judge_roll_offs(views=views)
    for s, v in zip(sources, verdicts):
        s.roll_off = v
        s.band, s.bends = with_roll_off_verdict(s, verdict=v)
    return [v for v in verdicts if v is not None]


def combine_sources(sources):
    """Merge the reliable parts of :class:`~pipelines.jobs.combine.sources.SourceSpectrum` s and fit
    the result -> (MergedSpectrum, fit dict or None, warnings).

    Parameters
    ----------
    sources : list of SourceSpectrum
        The inputs.

    Returns
    -------
    merged : MergedSpectrum
    fit : dict or None
    warnings : list of str
    """
    from pipelines.output.units import sig3, wavelength_of_q
    from roadscan.rolloff_origin import surface_q0
    from roadscan.spectrum_merge import SpectrumPart, merge_spectra
    from roadscan.spectrum_types import Spectrum

    notes = []
    verdicts = _judge_roll_offs(sources)
    q0, _ = surface_q0(verdicts=verdicts)
    for s in sources:
        if not s.band.valid:
            notes.append(
                f"{s.path}: left out: its reliable band [{sig3(s.band.lo_per_m)}, "
                f"{sig3(s.band.hi_per_m)}] 1/m is under a factor 2 wide (low end: "
                f"{s.band.lo_reason}; high end: {s.band.hi_reason})"
            )
    parts = [
        SpectrumPart(
            s.label,
            s.q_per_m,
            s.C_m4,
            s.count,
            tuple(s.band.band),
            s.dof_per_count,
            _edge_bias(s.band),
            s.bends,
        )
        for s in sources
        if s.band.valid
    ]
    if not parts:
        raise InputError(
            sources[0].path if len(sources) == 1 else None,
            f"no input has a reliable band at least a factor 2 wide: nothing to merge ({notes[0]})",
        )
    # the curve starts by START_FOV x 2 pi / L of the largest field: an area's band
    # starts by k x 2 pi / L, k <= 7 for spectra up to q^-4 (roadscan.reliable_band)
    q_fov = min(s.q_fov_per_m for s in sources if s.band.valid)
    # (0.1 % under it: the value psd.csv rounds to stays by it too)
    merged = merge_spectra(parts, start_per_m=0.999 * START_FOV * q_fov)
    for g in merged.gaps:
        notes.append(
            f"gap: no input measures {sig3(g['q_from_per_m'])} to {sig3(g['q_to_per_m'])} 1/m "
            f"(wavelengths {wavelength_of_q(g['q_to_per_m'])} to "
            f"{wavelength_of_q(g['q_from_per_m'])}, a factor {g['factor']:.3g}) reliably; "
            f"bridged by {g['bridged_by']} (n_sources = 0 in psd.csv)"
        )
    for c in merged.disagreements:
        a, b = c["labels"]
        notes.append(
            f"inputs {a!r} and {b!r} disagree where both measure ({sig3(c['q_from_per_m'])} "
            f"to {sig3(c['q_to_per_m'])} 1/m, wavelengths "
            f"{wavelength_of_q(c['q_to_per_m'])} to {wavelength_of_q(c['q_from_per_m'])}): "
            f"C of {a!r} is {c['factor']:.3g} x that of {b!r}, beyond their scatter "
            f"(x{np.exp(3 * c['sigma_ln']):.3g} at 3 standard deviations): not one "
            f"surface, or a unit or calibration error in one; the merged rows there "
            f"average the two"
        )
    if merged.widened_rows_per_m:
        at = ", ".join(f"{sig3(v)} 1/m (wavelength {wavelength_of_q(v)})" for v in merged.widened_rows_per_m)
        notes.append(
            f"{len(merged.widened_rows_per_m)} row(s) at {at}: their 5-95 % band "
            f"excluded what the neighbouring rows say and was widened to it"
        )
    for s in sources:
        if s.resolution_m is None:
            notes.append(
                f"{s.path}: no lateral resolution given nor in the file: its band ends "
                f"at Nyquist or its noise floor (give resolution_m in the manifest)"
            )
    spec = Spectrum(
        merged.q_per_m,
        merged.C_m4,
        count=np.rint(merged.count).astype(np.int64),
        kind="model",
        meta={"source": "roadscan combine"},
    )
    for v in verdicts:
        if v.origin == "instrument":
            notes.append(
                f"input {v.label!r}: its roll-off is taken for the instrument's, not "
                f"the surface's (not q0): {v.reason}"
            )
    fit, why = _fit(spec, merged.band_per_m, q0)
    if why:
        notes.append(why)
    return merged, fit, notes


def _summary(sources, merged, fit, warnings):
    from roadscan.rolloff_origin import surface_q0

    q0, q0_how = surface_q0(verdicts=[s.roll_off for s in sources if s.roll_off is not None])
    return {
        "inputs": [s.as_dict() for s in sources],
        "merged_band_per_m": [float(b) for b in merged.band_per_m],
        "q_range_per_m": [float(merged.q_per_m[0]), float(merged.q_per_m[-1])],
        "rows": int(merged.q_per_m.size),
        "gaps": [[g["q_from_per_m"], g["q_to_per_m"]] for g in merged.gaps],
        "gap_details": merged.gaps,
        "disagreements": merged.disagreements,
        "widened_rows_per_m": merged.widened_rows_per_m,
        "fit": fit,
        "q0_per_m": q0,
        "q0_how": q0_how,
        "method": (
            "C per ring of a common grid of 20 rings per decade: mean over the lattice "
            "points of every input measuring it reliably; C_lo/C_hi the 5-95 % band from "
            "chi-square counts and the inputs' scatter (roadscan.spectrum_merge)"
        ),
        "warnings": warnings,
    }


#: what this job's options mean where it narrows the shared text
_OPTION_TEXT = {
    "resolution": (
        "``--resolution``: lateral resolution [m] (wavelength passed at 50 % amplitude) of inputs "
        "given on the command line whose file does not carry one."
    ),
    "no_figures": ("``--no-figures``: skip combine.png."),
}


@returns_job_result("combine")
@document_options(overrides=_OPTION_TEXT)
def combine(
    inputs: Any,
    out: str | os.PathLike[str],
    *,
    resolution: float | None = None,
    no_figures: bool = False,
    spacing: float | str | tuple[float, float] | None = None,
    units: Literal["m", "mm", "um", "nm"] | None = None,
    x_units: Literal["m", "mm", "um", "nm"] | None = None,
    override_calibration: bool = False,
    channel: int | str | None = None,
) -> dict[str, Any]:
    """``roadscan combine`` as one call: several measurements of one surface merged into one
    C(q) over all their scales (see the module docstring; Sanner et al. 2022), written into
    ``out`` (``psd.csv``, ``combine.json``, ``combine.png`` unless ``no_figures=True``,
    ``report.html``; all or none).

    ``options`` are the command's long flags with dashes as underscores, taking what the flag
    takes (``resolution=5e-6``, ``spacing="5e-5"``, ``units="um"``, ``no_figures=True``),
    parsed by the command's own option definitions
    (:func:`pipelines.jobs.combine.inputs.add_combine_options`).

    Parameters
    ----------
    inputs : sequence of str or Path
        Height files, or a manifest CSV (header ``file[,spacing_m,units,resolution_m,label]``).
    out : str or Path
        Output folder, as ``--out``.
    {options}

    Returns
    -------
    dict
        The ``combine.json`` content: ``inputs`` (per input its reliable band, reasons,
        spacing, size, resolution), ``merged_band_per_m``, ``q_range_per_m`` [1/m], ``rows``,
        ``gaps``, ``gap_details``, ``disagreements``, ``widened_rows_per_m``, ``fit`` (H, h0,
        roll-off; or None), ``q0_per_m`` and ``q0_how`` (the surface's roll-off [1/m] or
        None, and how it was found), ``method`` and ``warnings``.

    Raises
    ------
    TypeError
        An unknown keyword.
    roadscan.errors.InputError
        A value the flag refuses, or inputs the job cannot merge (one line).
    """
    import os

    from pipelines.checks.validate import collecting
    from pipelines.settings.keywords import options_of

    args = options_of(combine, locals())
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    args.inputs = [os.fspath(p) for p in inputs]
    if not args.inputs:
        raise InputError(None, "combine needs at least one input")
    args.out = os.fspath(out)
    with collecting():
        return run_combine(args)


def run_combine(args):
    """``roadscan combine``'s job on its parsed flags (``inputs``, ``out`` and those of
    :func:`pipelines.jobs.combine.inputs.add_combine_options`): read, merge, fit and write (see
    the module docstring).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    dict
        The ``combine.json`` content.
    """
    from pipelines.checks import validate
    from pipelines.jobs.combine.inputs import collect_inputs
    from pipelines.jobs.combine.report import draw_combine, write_combine_report
    from pipelines.output import report
    from pipelines.settings.analyse import check_resolution
    from roadscan.io.atomic import atomic_output_dir, check_output_dir

    check_resolution(args.resolution)  # the bound every command shares
    entries = collect_inputs(args.inputs, args.spacing, args.units, args.resolution)
    inputs = [str(e.path) for e in entries] + [str(p) for p in args.inputs]
    check_output_dir(args.out, inputs=inputs)
    sources = _spectra(entries, args)
    merged, fit, notes = combine_sources(sources)
    for line in notes:
        validate.warn(line)
    summary = _summary(sources, merged, fit, validate.warnings_list())
    with atomic_output_dir(args.out, inputs=inputs) as tmp:
        tmp = Path(tmp)
        report.write_csv(
            tmp / "psd.csv",
            PSD_HEADER,
            [merged.q_per_m, merged.C_m4, merged.C_lo_m4, merged.C_hi_m4, merged.n_sources],
        )
        report.write_json(tmp / "combine.json", summary)
        fig = None if args.no_figures else draw_combine(sources, merged, fit, tmp / "combine.png")
        write_combine_report(tmp / "report.html", summary, fig)
    return summary
