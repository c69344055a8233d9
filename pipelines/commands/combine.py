"""``roadscan combine INPUTS... --out DIR``: several measurements of one surface, one spectrum.

INPUTS are height files (areas or profiles, any format :func:`roadscan.io.read` reads) or a
manifest CSV with the header ``file`` plus optional ``spacing_m,units,resolution_m,label``
(paths relative to the manifest). Each measurement's C(q) is kept within its reliable band
(:mod:`roadscan.reliable_band`); the bands are merged on a common log-q grid weighted by the
lattice points per ring (:mod:`pipelines.combine_merge`). Outputs (written atomically):
``psd.csv``, ``combine.json``, ``combine.png``, ``report.html``.
"""
from __future__ import annotations

from ..scan_input import add_inputs_and_out, add_scan_options

NAME = "combine"
HELP = "merge the spectra of several measurements of one surface (instruments, scales) into one C(q)"


def add_arguments(p):
    add_inputs_and_out(p, "height files, or a manifest CSV (header: file[,spacing_m,units,"
                          "resolution_m,label]; paths relative to the manifest)", "output folder")
    p.add_argument("--resolution", type=float, default=None, metavar="M",
                   help="lateral resolution [m] (wavelength passed at 50 %% amplitude) of inputs "
                        "given on the command line whose file does not carry one")
    p.add_argument("--no-figures", action="store_true", help="skip combine.png")
    add_scan_options(p)


def run(args):
    from ..combine import run_combine

    return run_combine(args)
