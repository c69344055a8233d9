"""The example commands every ``roadscan COMMAND --help`` ends with.

One or two commands per command (and per sub-action, ``rubber master``), each runnable from
the repository root as written (the sample scans, or the public data in ``../shared/data/``
for the instrument and road-profile formats) and writing only into ``out/``. They are the
argparse epilog of each parser, kept verbatim by :class:`argparse.RawDescriptionHelpFormatter`.
"""

from __future__ import annotations

import argparse

__all__ = ["EXAMPLES", "epilog", "add_examples"]

#: command (or "command action") -> example command lines
EXAMPLES = {
    "roadscan": [
        "roadscan analyse sample_scans/asphalt.x3p --out out/asphalt",
        "roadscan compare --help    # each command's options, ending with its examples",
    ],
    "analyse": [
        "roadscan analyse sample_scans/asphalt.x3p --out out/asphalt",
        "roadscan analyse sample_scans/captif_station_1_excerpt.dat --mpd-spike-alpha 6 --out out/captif",
    ],
    "batch": [
        "roadscan batch sample_scans/asphalt.x3p "
        "sample_scans/coarse_asphalt.x3p --out out/campaign --workers 2",
        "roadscan batch '../shared/data/profiles/captif/*.dat' --mpd-spike-alpha 6 --section-length 0.25 "
        "--out out/sections",
    ],
    "compare": [
        "roadscan compare sample_scans/asphalt.x3p sample_scans/coarse_asphalt.x3p --out out/compare",
    ],
    "dry-vs-wet": [
        "roadscan dry-vs-wet sample_scans/asphalt.x3p --out out/wet",
        "roadscan dry-vs-wet sample_scans/asphalt.x3p --water-film 1e-4 --out out/wet_film",
    ],
    "rain-fill": [
        "roadscan rain-fill sample_scans/asphalt.x3p --out out/rain",
        "roadscan rain-fill sample_scans/asphalt.x3p --max-depth 2e-4 --out out/rain_capped",
    ],
    "friction": [
        "roadscan friction --psd sample_scans/asphalt_psd.csv --out out/mu.csv",
        "roadscan friction --psd sample_scans/asphalt_psd.csv --flash --sigma0 0.3MPa --out out/mu_hot.csv",
    ],
    "combine": [
        "roadscan combine sample_scans/asphalt.x3p sample_scans/coarse_asphalt.x3p --out out/combine",
    ],
    "diagnose": [
        "roadscan diagnose --measured sample_scans/measured_mu_example.csv "
        "--psd sample_scans/asphalt_psd.csv --out out/diag",
    ],
    "stitch": [
        "roadscan stitch sample_scans/tiles_manifest.csv --out out/mosaic.x3p",
    ],
    "synth": [
        "roadscan synth --hurst 0.8 --rms 5e-4 --nx 1024 --out out/synth.x3p",
    ],
    "convert": [
        "roadscan convert ../shared/data/formats/plu-1.plu out/plu-1.x3p    # needs the [vendor] extra",
        "roadscan convert sample_scans/asphalt.x3p out/asphalt.npz",
    ],
    "rubber": [
        "roadscan rubber master ../shared/data/rubber/pyvisco/freq_user_raw.csv "
        "--reference-temperature -5 --out out/rubber.toml",
    ],
    "rubber master": [
        "roadscan rubber master ../shared/data/rubber/pyvisco/freq_user_raw.csv "
        "--reference-temperature -5 --out out/rubber.toml",
    ],
}


def epilog(name):
    """The epilog of ``name``'s help: "example(s):" and the commands, indented; None when
    ``name`` has none.

    Parameters
    ----------
    name : str
        Command name, or "command action".

    Returns
    -------
    str or None
    """
    lines = EXAMPLES.get(name)
    if not lines:
        return None
    head = "example:" if len(lines) == 1 else "examples:"
    return "\n".join([head, *(f"  {c}" for c in lines)])


def add_examples(parser, name):
    """Give ``parser`` the examples of ``name`` as its epilog, printed as written.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The command's parser.
    name : str
        Its name (as in :data:`EXAMPLES`).

    Returns
    -------
    None
    """
    text = epilog(name)
    if text is None:
        return
    parser.epilog = text
    if parser.formatter_class is argparse.HelpFormatter:
        parser.formatter_class = argparse.RawDescriptionHelpFormatter
