"""``roadscan combine INPUTS... --out DIR``: several measurements of one surface, one spectrum.

INPUTS are height files (areas or profiles, any format :func:`roadscan.io.read` reads) or a
manifest CSV with the header ``file`` plus optional ``spacing_m,units,resolution_m,label``
(paths relative to the manifest). Each measurement's C(q) is kept within its reliable band
(:mod:`roadscan.reliable_band`); the bands are merged on a common log-q grid weighted by the
lattice points per ring (:mod:`roadscan.spectrum_merge`). Outputs (written atomically):
``psd.csv``, ``combine.json``, ``combine.png``, ``report.html``. The command parses, calls
:func:`pipelines.combine` and prints.
"""

from __future__ import annotations

from pipelines.jobs.combine.inputs import add_combine_options
from pipelines.settings.scan_input import add_inputs_and_out

NAME = "combine"
HELP = "merge the spectra of several measurements of one surface (instruments, scales) into one C(q)"


def add_arguments(p):
    add_inputs_and_out(
        p,
        "height files, or a manifest CSV (header: file[,spacing_m,units,"
        "resolution_m,label]; paths relative to the manifest)",
        "output folder",
    )
    add_combine_options(p)  # --resolution, --no-figures, scan options (pipelines.combine's too)


def run(args):
    from pipelines.jobs.combine.job import combine
    from pipelines.output.units import quantity
    from pipelines.settings.keywords import keywords_of

    s = combine(args.inputs, args.out, **keywords_of(args, combine))
    lo, hi = s["merged_band_per_m"]
    print(
        f"{len(s['inputs'])} inputs merged: C(q) from {quantity('q_per_m', lo)} to "
        f"{quantity('q_per_m', hi)}, "
        f"{len(s['gaps'])} gap(s) bridged"
        + (f", H = {s['fit']['hurst']:.3f}" if s["fit"] else "")
        + (
            f", q0 = {quantity('q_per_m', s['q0_per_m'])} (the surface's roll-off)"
            if s.get("q0_per_m")
            else ", no roll-off of the surface seen (q0 below the curve)"
        )
    )
    print(f"-> {args.out}/psd.csv, {args.out}/report.html")
    return 0
