"""The options of ``roadscan analyse`` (and ``roadscan batch``, which takes the very same), in
one place: the flags (:func:`add_analysis_options`), their checked values
(:func:`analysis_kwargs`, :func:`pipelines.settings.friction.settings_from_args`) and the
keyword-only parameters of :func:`pipelines.analyse`, one per long flag with underscores, read
into the same settings (:func:`pipelines.settings.keywords.options_of`).
"""

from __future__ import annotations

import argparse

from roadscan.errors import InputError

__all__ = [
    "add_analysis_options",
    "analysis_kwargs",
    "parse_fit_band",
    "add_resolution_option",
    "check_resolution",
    "add_spectrum_options",
    "spectrum_kwargs",
    "add_compare_options",
    "unique_stems",
]


def add_analysis_options(p):
    """Every per-scan option of ``analyse``, friction included (``roadscan batch`` takes the
    very same).

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser to extend.

    Returns
    -------
    None
    """
    from pipelines.jobs.texture.outputs import add_texture_options
    from pipelines.settings.friction import add_friction_options
    from pipelines.settings.scan_input import add_scan_options

    add_scan_options(p)
    add_spectrum_options(p, resolution=False)
    p.add_argument(
        "--mpd-spike-alpha",
        type=float,
        default=None,
        metavar="ALPHA",
        help="MPD spike criterion |dh| >= ALPHA x sampling interval (ISO 13473-1 "
        "default 3; CAPTIF uses 6 on chip seals, whose stone edges are steep)",
    )
    add_resolution_option(p)
    add_texture_options(p)  # --direction, --friction-measurement, --ifi-constants
    add_friction_options(p)


def add_spectrum_options(p, resolution=True):
    """--window-alpha, --fit-band, --despike (and --resolution): how a scan becomes its
    spectrum, band and fit (:func:`pipelines.chain.steps.measure`); analyse, batch, compare and
    dry-vs-wet take the very same.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser.
    resolution : bool, optional
        Add ``--resolution`` too.

    Returns
    -------
    None
    """
    p.add_argument("--window-alpha", type=float, default=0.25, help="Tukey window alpha (default 0.25)")
    p.add_argument(
        "--fit-band", default=None, metavar="QLO,QHI", help="self-affine fit band [1/m] (default: detected)"
    )
    p.add_argument("--despike", action="store_true", help="mark spikes as unmeasured before levelling")
    if resolution:
        add_resolution_option(p)


def spectrum_kwargs(args):
    """Checked keyword arguments of :func:`pipelines.chain.steps.measure` from
    :func:`add_spectrum_options` (one-line InputError naming the flag).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    dict
    """
    if not 0 <= args.window_alpha <= 1:
        raise InputError(None, f"--window-alpha {args.window_alpha}: must be within [0, 1]")
    return {
        "window_alpha": args.window_alpha,
        "fit_band": parse_fit_band(args.fit_band),
        "despike": bool(args.despike),
        "resolution_m": check_resolution(args.resolution),
    }


def add_resolution_option(p):
    """``--resolution M``: the lateral resolution of the reliable band (analyse, batch,
    compare, dry-vs-wet: every command that takes its friction from a scan's band).

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser to extend.

    Returns
    -------
    None
    """
    p.add_argument(
        "--resolution",
        type=float,
        default=None,
        metavar="M",
        help="the instrument's lateral resolution [m] (wavelength passed at 50 %% "
        "amplitude; default: the file's metadata): the reliable band ends where "
        "it still passes 80 %%",
    )


def check_resolution(res):
    """``--resolution`` [m] checked: None, or 0 < r <= 1 m
    (:data:`roadscan.resolution.RESOLUTION_MAX_M`; one-line InputError).

    Parameters
    ----------
    res : float or None
        ``--resolution`` [m].

    Returns
    -------
    float or None
    """
    from roadscan.resolution import RESOLUTION_MAX_M, resolution_problem

    if res is not None and resolution_problem(res):
        raise InputError(
            None,
            f"--resolution {res!r}: must be a lateral resolution in metres "
            f"(0 < r <= {RESOLUTION_MAX_M:g} m, e.g. 5e-6)",
        )
    return res


def parse_fit_band(text):
    """``"QLO,QHI"`` [1/m] -> (lo, hi), or None; one-line InputError naming --fit-band.

    Parameters
    ----------
    text : str, pair of float or None
        ``"QLO,QHI"`` or ``(qlo, qhi)`` [1/m].

    Returns
    -------
    tuple of float or None
    """
    if text is None:
        return None
    try:
        parts = text.split(",") if isinstance(text, str) else list(text)
        lo, hi = (float(x) for x in parts)
    except ValueError:
        raise InputError(None, f"--fit-band {text!r}: expected QLO,QHI in 1/m") from None
    if not 0 < lo < hi:
        raise InputError(None, f"--fit-band {text!r}: need 0 < QLO < QHI")
    return lo, hi


def analysis_kwargs(args):
    """Checked keyword arguments of :func:`pipelines.jobs.analyse.job.run_analysis` from the options of
    :func:`add_analysis_options` (InputError naming the flag when one is out of range).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed flags.

    Returns
    -------
    dict
    """
    sk = spectrum_kwargs(args)
    mpd = None
    if args.mpd_spike_alpha is not None:
        if not args.mpd_spike_alpha > 0:
            raise InputError(None, f"--mpd-spike-alpha {args.mpd_spike_alpha}: must be positive")
        mpd = {"spike_alpha": args.mpd_spike_alpha}
    from pipelines.jobs.texture.outputs import texture_settings_from_args

    return {
        "window_alpha": sk["window_alpha"],
        "fit_band": sk["fit_band"],
        "despike": sk["despike"],
        "mpd_settings": mpd,
        "texture": texture_settings_from_args(args),
        "resolution_m": sk["resolution_m"],
    }


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # a bad value: one line, never an exit
        raise InputError(None, message)


def _parser(add_options=None):
    p = _Parser(prog="pipelines", add_help=False)
    if add_options is None:  # analyse's own
        p.add_argument("--no-figures", action="store_true")
        add_analysis_options(p)
    else:
        add_options(p)
    return p


def add_compare_options(p):
    """The per-scan options of ``roadscan compare`` (and :func:`pipelines.compare`): how a
    scan is read, its spectrum options and the friction options.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser.

    Returns
    -------
    None
    """
    from pipelines.settings.friction import add_friction_options
    from pipelines.settings.scan_input import add_scan_options

    add_scan_options(p)
    add_spectrum_options(p)  # --window-alpha, --fit-band, --despike, --resolution
    add_friction_options(p)
    p.add_argument(
        "--no-figures",
        action="store_true",
        help="skip the PNG figures (every CSV/JSON number is the same; report.html keeps its tables)",
    )


def unique_stems(paths):
    """Each path's stem, made unique in order (``a``, ``a_2``, ...): the per-scan folder names
    of a many-scan run.

    Parameters
    ----------
    paths : iterable of str or Path
        Input files.

    Returns
    -------
    list of str
    """
    from pathlib import Path

    seen, out = {}, []
    for p in paths:
        stem = Path(p).stem
        n = seen.get(stem, 0)
        seen[stem] = n + 1
        out.append(stem if n == 0 else f"{stem}_{n + 1}")
    return out
