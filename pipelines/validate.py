"""What roadscan does with input it cannot trust: the one policy, in one place.

Every number a user (a flag) or a file gives is checked here for *physical plausibility*
before it reaches the numerics. Each check either

- **refuses**: raises :class:`roadscan.InputError` whose text is one line naming the flag or
  file and the value (the CLI prints it and exits with code 2); used when no meaningful result
  can follow (a constant grid has no roughness, a temperature at the rubber's WLF pole has no
  shift factor, a PSD rising like q^3 is not a surface), or
- **warns**: :func:`warn` prints one line ``roadscan CMD: warning: ...`` on stderr and records it
  in the current run's :class:`Warnings` (:func:`collecting`); commands that write
  ``summary.json`` store that run's list under ``"warnings"``. Used when the result
  is still meaningful but the user should look (e.g. an unusual spacing, a small grid).

Limits (SI units; chosen wide, to refuse only what no road scan or rubber can be):

============================  =========================================================
quantity                      refused outside (warned outside)
============================  =========================================================
grid spacing [m]              [1e-9, 1] (warned outside [1e-7, 1e-2])
grid size                     fewer than 8 points along a side of an area, or fewer than
                              16 measured points, or under 1 % of the points measured
rms height [m] (synth)        outside [1e-12, 1e3] (not representable / not a road)
heights [m]                   all equal, to 12 digits (no roughness); any |h - median|
                              above 1e4 x the robust spread (a spike of another scale;
                              refused naming the value, unless it is under 1 m); |h| >= 1e3 m
nominal pressure sigma0 [Pa]  (0, 1e9]
Poisson ratio nu              [0, 0.5]
temperature T [C]             below -273.15, or within 5 K above the rubber's WLF pole
                              (T_g - C2, or T_s - C2; -81.5 C for the thesis rubber),
                              or above 1000 C
wave vectors q [1/m]          q1 not above the spectrum's q0 / lowest q; non-finite; any q
                              (flag or PSD row) above 1e11 1/m (a wavelength below 0.1 nm,
                              shorter than an atom) or below 1e-4 1/m (above 63 km)
PSD C(q) [m^4]                any row with C <= 0 or non-finite (refused naming the row);
                              a log-log slope of the whole spectrum above +1 (rises with q:
                              not a surface; self-affine surfaces fall as q^-2(1+H))
friction mu                   non-finite values, or mu > 100 (refused: no physical result);
                              warned when mu > 5
============================  =========================================================

Size limits on files are in :mod:`roadscan.io._common` (``check_declared_size``,
``--max-pixels``) since the readers apply them before allocating.
"""
from __future__ import annotations

import contextlib
import contextvars
import math
import sys

import numpy as np

from roadscan.errors import InputError

__all__ = [
    "warn", "warnings_list", "reset_warnings", "Warnings", "collecting", "current_warnings",
    "check_spacing", "check_spacing_option", "check_heights", "check_scan", "check_pressure", "check_poisson",
    "check_temperature", "check_rms_height", "check_wave_vector", "check_psd_rows", "check_psd_shape", "check_q1", "check_mu", "check_fit",
    "finite_number",
]

KELVIN = 273.15
SPACING_RANGE_M = (1e-9, 1.0)
SPACING_USUAL_M = (1e-7, 1e-2)
MIN_SIDE = 8
MIN_MEASURED = 16
MIN_MEASURED_FRACTION = 0.01
SPIKE_FACTOR = 1e4
MAX_ABS_HEIGHT_M = 1e3
MIN_RMS_HEIGHT_M = 1e-12
Q_MAX_PER_M = 1e11
#: the longest wavelength a surface spectrum may reach: 2 pi / 1e-4 = 63 km (a survey line)
Q_MIN_PER_M = 1e-4
PRESSURE_RANGE_PA = (0.0, 1e9)
POISSON_RANGE = (0.0, 0.5)
WLF_POLE_MARGIN_K = 5.0
T_MAX_C = 1000.0
MAX_PSD_SLOPE = 1.0
MU_MAX = 100.0
MU_WARN = 5.0

class Warnings:
    """The warnings of one run (one scan, one command): lines in the order first said, each
    once. :func:`warn` records into the collector of the innermost :func:`collecting` scope
    (a :mod:`contextvars` variable: each thread, task and nested run has its own), so two runs
    in one process, or many files in one call, never share a warning.

    Parameters
    ----------
    prefix : str, optional
        Program name printed before each line.
    """

    def __init__(self, prefix="roadscan"):
        self.prefix = prefix
        self.lines = []

    def add(self, line, echo=True):
        """Record ``line`` (once); ``echo`` prints ``PREFIX: warning: line`` on stderr."""
        if line in self.lines:
            return False
        self.lines.append(line)
        if echo:
            print(f"{self.prefix}: warning: {line}", file=sys.stderr)
        return True

    def __iter__(self):
        return iter(list(self.lines))

    def __len__(self):
        return len(self.lines)


_CURRENT = contextvars.ContextVar("roadscan_warnings", default=None)


def current_warnings():
    """The collector :func:`warn` records into (one is started in this context if none is).

    Parameters
    ----------
    None

    Returns
    -------
    Warnings
    """
    w = _CURRENT.get()
    if w is None:
        w = Warnings()
        _CURRENT.set(w)
    return w


@contextlib.contextmanager
def collecting(into=None, prefix=None):
    """A scope of its own for warnings: ``with collecting() as w: ...`` records every
    :func:`warn` inside into ``w`` (a :class:`Warnings`; ``into`` re-enters a given one). On
    leaving, the lines are also handed to the enclosing scope (not printed again), so a
    command that runs several scans still sees them all.

    Parameters
    ----------
    into : Warnings, optional
        Collector to re-enter.
    prefix : str, optional
        Program name.

    Yields
    ------
    Warnings
        The scope's collector.
    """
    parent = _CURRENT.get()
    w = into if into is not None else Warnings(prefix or (parent.prefix if parent else "roadscan"))
    token = _CURRENT.set(w)
    try:
        yield w
    finally:
        _CURRENT.reset(token)
        if parent is not None and parent is not w:
            for line in w.lines:
                parent.add(line, echo=False)


def reset_warnings(prefix="roadscan"):
    """Start a new collector in this context (the CLI calls this at the start of every command).

    Parameters
    ----------
    prefix : str, optional
        Program name.

    Returns
    -------
    None
    """
    _CURRENT.set(Warnings(prefix))


def warn(message):
    """Print one warning line on stderr and record it in this run's collector.

    Parameters
    ----------
    message : str
        One line.

    Returns
    -------
    None
    """
    current_warnings().add(" ".join(str(message).split()))


def warnings_list():
    """The warnings of the current scope (a new list).

    Parameters
    ----------
    None

    Returns
    -------
    list of str
    """
    return list(current_warnings().lines)


# ------------------------------------------------------------------------------ numbers
def _where(flag=None, path=None):
    return path, (f"{flag} " if flag else "")


def finite_number(value, flag=None, path=None, what="value"):
    """``float(value)``, refusing NaN, infinity and non-numbers (one line naming flag/file).

    Parameters
    ----------
    value : object
        The value.
    flag : str, optional
        Flag named in errors.
    path : str or Path, optional
        File named in errors.
    what : str, optional
        What it is.

    Returns
    -------
    float
    """
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise InputError(path, f"{flag or what} {value!r}: not a number") from None
    if not math.isfinite(v):
        raise InputError(path, f"{flag or what} {value!r}: must be finite")
    return v


def check_spacing(dx_m, dy_m=None, flag="--spacing", path=None):
    """Grid spacing [m]: refused outside [1e-9, 1] m, warned outside [1e-7, 1e-2] m.

    Parameters
    ----------
    dx_m : float
        Spacing [m].
    dy_m : float, optional
        Spacing along y [m].
    flag : str, optional
        Flag named.
    path : str or Path, optional
        File named.

    Returns
    -------
    None
    """
    for v in (dx_m,) if dy_m is None else (dx_m, dy_m):
        v = finite_number(v, flag, path, "spacing")
        lo, hi = SPACING_RANGE_M
        if not lo <= v <= hi:
            raise InputError(path, f"{flag} {v:g} m: implausible grid spacing (expected "
                                   f"{lo:g}..{hi:g} m; is the unit metres?)")
        ulo, uhi = SPACING_USUAL_M
        if not ulo <= v <= uhi:
            warn(f"{path + ': ' if path else ''}spacing {v:g} m is unusual for a road scan "
                 f"({ulo:g}..{uhi:g} m)")


def check_spacing_option(text, flag="--spacing"):
    """The CLI's ``--spacing DX[,DY]`` [m]: parsed by :func:`roadscan.io.resolve_spacing` and
    checked by :func:`check_spacing`; every refusal names the flag and the value given.

    Parameters
    ----------
    text : str
        ``DX[,DY]``.
    flag : str, optional
        Flag named.

    Returns
    -------
    tuple of float
    """
    from roadscan.io import resolve_spacing

    try:
        dx, dy = resolve_spacing(text, None)
    except InputError as exc:
        raise InputError(None, f"{flag} {text!r}: {exc.problem}") from None
    check_spacing(dx, dy, flag=flag)
    return dx, dy


def check_rms_height(rms_m, flag="--rms"):
    """An rms height [m] asked for (``roadscan synth``): within [1e-12, 1e3] m. Below a
    picometre the heights underflow to zeros on rescaling; above MAX_ABS_HEIGHT_M no road.

    Parameters
    ----------
    rms_m : float
        Rms height [m].
    flag : str, optional
        Flag named.

    Returns
    -------
    float
    """
    v = finite_number(rms_m, flag)
    if not MIN_RMS_HEIGHT_M <= v <= MAX_ABS_HEIGHT_M:
        raise InputError(None, f"{flag} {v:g} m: implausible rms height (expected "
                               f"{MIN_RMS_HEIGHT_M:g}..{MAX_ABS_HEIGHT_M:g} m; is the unit metres?)")
    return v


def check_pressure(sigma0_Pa, flag="--sigma0"):
    """Nominal contact pressure [Pa] in (0, 1e9].

    Parameters
    ----------
    sigma0_Pa : float
        Pressure [Pa].
    flag : str, optional
        Flag named.

    Returns
    -------
    float
    """
    v = finite_number(sigma0_Pa, flag)
    lo, hi = PRESSURE_RANGE_PA
    if not lo < v <= hi:
        raise InputError(None, f"{flag} {v:g} Pa: must be a pressure in ({lo:g}, {hi:g}] Pa")
    return v


def check_poisson(nu, flag="--nu"):
    """Poisson ratio in [0, 0.5] (rubber is nearly incompressible, 0.5).

    Parameters
    ----------
    nu : float
        Poisson's ratio.
    flag : str, optional
        Flag named.

    Returns
    -------
    float
    """
    v = finite_number(nu, flag)
    lo, hi = POISSON_RANGE
    if not lo <= v <= hi:
        raise InputError(None, f"{flag} {v:g}: a Poisson ratio lies in [{lo:g}, {hi:g}]")
    return v


def wlf_pole_C(rubber):
    """The temperature [C] where the rubber's WLF shift diverges, or None (no WLF shift).

    ``log10 aT = -C1 (T - T_s) / (C2 + T - T_d)`` with ``T_d = T_g`` (thesis form) or ``T_s``:
    the pole is ``T_d - C2`` (-81.5 C for the thesis rubber)."""
    wlf = getattr(rubber, "shift", None)
    c2 = getattr(wlf, "C2_K", None)
    td = getattr(wlf, "T_g_C", None)
    if td is None:
        td = getattr(wlf, "T_s_C", None)
    if c2 is None or td is None:
        return None
    return float(td) - float(c2)


def check_temperature(T_C, rubber=None, flag="--temperature"):
    """Temperature [C]: above absolute zero, below 1000 C, and more than 5 K above the
    rubber's WLF pole ``T_d - C2`` (at the pole log a_T diverges; below it WLF is meaningless).

    Parameters
    ----------
    T_C : float or None
        Temperature [C].
    rubber : rubber model, optional
        Its WLF pole is checked.
    flag : str, optional
        Flag named.

    Returns
    -------
    float or None
    """
    if T_C is None:
        return None
    v = finite_number(T_C, flag)
    if v <= -KELVIN:
        raise InputError(None, f"{flag} {v:g} C: below absolute zero (-273.15 C)")
    if v > T_MAX_C:
        raise InputError(None, f"{flag} {v:g} C: implausible for rubber (above {T_MAX_C:g} C)")
    pole = wlf_pole_C(rubber) if rubber is not None else None
    if pole is not None and v <= pole + WLF_POLE_MARGIN_K:
        raise InputError(None, f"{flag} {v:g} C: at or below the rubber's WLF pole "
                               f"(T_d - C2 = {pole:.4g} C); the shift factor diverges there")
    return v


# ------------------------------------------------------------------------------ scans
def check_heights(heights_m, path=None, unmeasured=None, area=True):
    """Plausibility of a height array [m] (see the module table); refuses with one line.

    Parameters
    ----------
    heights_m : ndarray
        Heights [m].
    path : str or Path, optional
        File named.
    unmeasured : ndarray of bool, optional
        Mask.
    area : bool, optional
        A map rather than a profile.

    Returns
    -------
    None
    """
    h = np.asarray(heights_m)
    if np.iscomplexobj(h):
        raise InputError(path, "heights are complex numbers")
    if area and h.ndim == 2 and min(h.shape) < MIN_SIDE:
        raise InputError(path, f"grid {h.shape[0]} x {h.shape[1]} is too small for a spectrum "
                               f"(need at least {MIN_SIDE} points along each side)")
    if not area and h.size < 2 * MIN_SIDE:
        raise InputError(path, f"profile of {h.size} points is too short (need {2 * MIN_SIDE})")
    n_ok, lo, hi = _measured_range(h, unmeasured)
    if n_ok < MIN_MEASURED or n_ok < MIN_MEASURED_FRACTION * h.size:
        raise InputError(path, f"only {n_ok} of {h.size} points are measured (need at least "
                               f"{max(MIN_MEASURED, int(np.ceil(MIN_MEASURED_FRACTION * h.size)))})")
    top = max(abs(lo), abs(hi))
    if top >= MAX_ABS_HEIGHT_M:
        raise InputError(path, f"height {top:.3g} m is implausible for a road scan (units? spike?)")
    spread = hi - lo
    if spread == 0.0 or spread <= 1e-12 * top:
        raise InputError(path, f"all measured heights are equal ({0.5 * (lo + hi):.6g}): a flat grid "
                               f"has no roughness")
    if spread <= 1.0:     # no point can lie more than 1 m from the median: no spike to look for
        return
    ok = np.isfinite(h)
    if unmeasured is not None:
        ok &= ~np.asarray(unmeasured, dtype=bool)
    vals = h[ok]
    med = float(np.median(vals))
    dev = np.abs(vals - med)
    mad = float(np.median(dev))
    far = float(np.max(dev))
    if far > 1.0 and far > SPIKE_FACTOR * 1.4826 * mad:
        spreads = f"{far / (1.4826 * mad):.3g} robust spreads" if mad else \
            f"{far:.3g} m (most heights are equal)"
        raise InputError(path, f"height {med + far:.3g} m lies {spreads} from the median: an "
                               f"implausible spike (mark it unmeasured)")


def _measured_range(h, unmeasured=None, chunk_bytes=4 << 20):
    """(number, min, max) of the finite heights not marked ``unmeasured``, band by band of rows
    (no copy of the measured points: the memory is one band's; :func:`roadscan.bands.measured_stats`)."""
    from roadscan.bands import measured_stats

    n, lo, hi, _ = measured_stats(h, unmeasured, chunk_bytes=chunk_bytes)
    return n, lo, hi


def check_scan(obj, path=None):
    """Check a read :class:`HeightMap` or :class:`Profile` (spacing and heights).

    Parameters
    ----------
    obj : HeightMap or Profile
        The scan.
    path : str or Path, optional
        File named.

    Returns
    -------
    HeightMap or Profile
    """
    from roadscan.heightmap import HeightMap

    area = isinstance(obj, HeightMap)
    if area:
        check_spacing(obj.dx_m, obj.dy_m, flag="spacing", path=str(path) if path else None)
    else:
        check_spacing(obj.dx_m, flag="spacing", path=str(path) if path else None)
    check_heights(obj.heights_m, path, getattr(obj, "unmeasured", None), area=area)
    return obj


# ------------------------------------------------------------------------------ spectra
def check_psd_rows(q, C, path=None):
    """Every row of a tabulated PSD must have finite q > 0 and finite C > 0; the first bad row
    is refused by its number among the data rows (1 = first row after the header).

    Parameters
    ----------
    q, C : ndarray
        Wave vectors [1/m] and C [m^4].
    path : str or Path, optional
        File named.

    Returns
    -------
    None
    """
    q = np.asarray(q, dtype=float)
    C = np.asarray(C, dtype=float)
    bad = ~(np.isfinite(q) & (q > 0) & np.isfinite(C) & (C > 0))
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError(path, f"data row {i + 1}: q = {q[i]:g}, C = {C[i]:g}: need finite q > 0 "
                               f"and C > 0 ({int(bad.sum())} such row{'s' if bad.sum() > 1 else ''})")
    out = (q < Q_MIN_PER_M) | (q > Q_MAX_PER_M)
    if out.any():
        i = int(np.argmax(out))
        raise InputError(path, f"data row {i + 1}: q = {q[i]:g} 1/m is outside {Q_MIN_PER_M:g} .. "
                               f"{Q_MAX_PER_M:g} 1/m (wavelengths 63 km .. 0.06 nm): units?")


def check_psd_shape(q, C, path=None):
    """A surface's PSD falls with q: refuse a spectrum whose least-squares log-log slope over
    its band is above +1 (e.g. rising as q^3).

    Parameters
    ----------
    q, C : ndarray
        Wave vectors [1/m] and C [m^4].
    path : str or Path, optional
        File named.

    Returns
    -------
    None
    """
    q = np.asarray(q, dtype=float)
    C = np.asarray(C, dtype=float)
    ok = np.isfinite(q) & np.isfinite(C) & (q > 0) & (C > 0)
    if ok.sum() < 3:
        raise InputError(path, f"the PSD has {int(ok.sum())} usable rows (need at least 3)")
    lq, lc = np.log(q[ok]), np.log(C[ok])
    if np.ptp(lq) == 0:
        raise InputError(path, "the PSD has a single wave vector")
    slope = float(np.polyfit(lq, lc, 1)[0])
    if slope > MAX_PSD_SLOPE:
        raise InputError(path, f"the PSD rises with q (log-log slope {slope:+.2f}): not the "
                               f"spectrum of a surface, which falls as q^-2(1+H)")


def check_wave_vector(q_per_m, flag):
    """A wave vector [1/m] given by a flag: finite, from 1e-4 1/m (2 pi / q = 63 km, longer
    than any surveyed line) to 1e11 1/m (0.06 nm: Persson's cut-offs stop at the atomic scale,
    about 1e10 1/m). Below, the self-affine C(q0) overflows (a fuzz finding: q0 = 2.2e-308).

    Parameters
    ----------
    q_per_m : float
        Wave vector [1/m].
    flag : str
        Flag named.

    Returns
    -------
    float
    """
    v = finite_number(q_per_m, flag)
    if not Q_MIN_PER_M <= v <= Q_MAX_PER_M:
        raise InputError(None, f"{flag}{'' if flag.endswith('=') else ' '}{v:g} 1/m: must be a wave vector from "
                               f"{Q_MIN_PER_M:g} 1/m (a wavelength of 63 km) to {Q_MAX_PER_M:g} 1/m "
                               f"(a wavelength of 0.06 nm)")
    return v


def check_q1(q1_per_m, q_lo_per_m, flag="--q1"):
    """q1 [1/m] must be finite and above the spectrum's lowest wave vector ``q_lo``.

    Parameters
    ----------
    q1_per_m : float or None
        q1 [1/m].
    q_lo_per_m : float
        Lowest wave vector of the spectrum [1/m].
    flag : str, optional
        Flag named.

    Returns
    -------
    float or None
    """
    if q1_per_m is None:
        return None
    v = finite_number(q1_per_m, flag)
    if not v > q_lo_per_m:
        raise InputError(None, f"{flag} {v:g} 1/m: must exceed the spectrum's lowest wave vector "
                               f"q0 = {q_lo_per_m:.4g} 1/m")
    return v


def check_fit(fit, name=""):
    """Warn when a self-affine fit is outside its meaning: Hurst exponent outside [0, 1]
    (e.g. a white-noise or a trend-dominated scan) or a non-finite h0.

    Parameters
    ----------
    fit : SelfAffineFit
        The fit.
    name : str, optional
        Scan name.

    Returns
    -------
    None
    """
    h = getattr(fit, "hurst", None)
    if h is None or not np.isfinite(h):
        raise InputError(name or None, "the self-affine fit failed (Hurst exponent not finite)")
    if not 0.0 <= h <= 1.0:
        undefined = " (h0 is undefined for H <= 0: null in summary.json)" if h <= 0 else ""
        warn(f"{name + ': ' if name else ''}Hurst exponent {h:.3g} lies outside [0, 1]: the spectrum "
             f"is not self-affine over the fitted band; H, h0 and mu(v) are not meaningful{undefined}")


def check_mu(mu, what="mu", warn_high=True):
    """Friction results: refuse non-finite values and mu > 100 (no physical meaning);
    warn when mu > 5 (unless ``warn_high`` is False: the caller diagnoses it, as analyse does
    with :mod:`pipelines.mu_provenance`).

    Parameters
    ----------
    mu : ndarray
        Friction coefficients.
    what : str, optional
        Name in messages.
    warn_high : bool, optional
        Warn above 5.

    Returns
    -------
    ndarray
    """
    mu = np.asarray(mu, dtype=float)
    if mu.size and not np.all(np.isfinite(mu)):
        n = int(np.count_nonzero(~np.isfinite(mu)))
        raise InputError(None, f"{what}: {n} of {mu.size} values are not finite (check h0, the "
                               f"PSD and the rubber model)")
    top = float(np.max(mu)) if mu.size else 0.0
    if top > MU_MAX:
        raise InputError(None, f"{what} reaches {top:.3g}: not physical (> {MU_MAX:g}); check the "
                               f"PSD (does it fall with q?) and the rubber model")
    if top > MU_WARN and warn_high:
        warn(f"{what} reaches {top:.3g}, unusually high for rubber on a road: likely the band "
             f"(its short end in the noise, or extended beyond the spectrum: --q1), the units "
             f"(--units) or the rubber (--rubber)")
    return mu
