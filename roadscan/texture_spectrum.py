"""Texture spectrum of ISO 13473-4: texture profile levels in third-octave wavelength bands.

Bands (ISO 13473-4, ISO 266 base-ten series): exact centre wavelengths
lambda_c = 10^(k/10) mm, edges lambda_c x 10^(-1/20) and lambda_c x 10^(+1/20), labelled by the
nominal values of the preferred series (0.5, 0.63, 0.8, 1, 1.25, ..., 400, 500 mm).

Level of a band: L = 20 log10(a / a_ref) dB with a_ref = 1e-6 m and a the rms amplitude of the
profile in the band. A sine of amplitude A in a band has a = A / sqrt2.

How a is computed here (FFT method; ISO 13473-4 allows FFT or band-pass filters):

1. dropouts of a line are filled by linear interpolation between the nearest measured
   samples (ends held at the nearest measured height); a linear fill carries almost no power
   in the texture bands, so a line with a fraction f of dropouts reads about 10 log10(1 - f) dB
   low (-0.2 dB at 5 %);
2. the least-squares line is removed and a Tukey window w (alpha = 0.5: cosine tapers over
   the outer quarters) applied: it weights the profile's length more evenly than a Hann
   window (a single Hann window counts the middle of a long, non-stationary profile several
   times more than its ends), with sidelobes still falling as 1/d^3;
3. one-sided periodogram P_k = c_k |X_k|^2 / (n^2 <w^2>) (c_k = 2 except at 0 and Nyquist),
   so that sum_k P_k = <z^2> (the window's power loss corrected);
4. a^2 = sum_k P_k o_k, with o_k the fraction of the bin's frequency interval
   [f_k - df/2, f_k + df/2] (df = 1 / (n dx)) that lies inside the band's edges
   [1/lambda_hi, 1/lambda_lo];
5. an area: lines along the driving direction (rows for x, columns for y); a^2 is the mean over
   the lines (mean of squares, then dB).

Resolved bands only: a band is given when its shortest wavelength holds at least
:data:`MIN_SAMPLES_PER_WAVELENGTH` (4) samples (lambda_lo >= 4 dx) and its frequency width
spans at least :data:`MIN_BINS` (4) FFT bins of the evaluation length L, i.e.
0.2308 L / lambda_c >= 4 (lambda_c <= L / 17.3, lambda_hi <= L / 15.4): the window spreads a
sine over a few bins, so a narrower band would lose part of a sine at its centre to its
neighbours (with 4 bins: at most 0.1 dB, neighbouring bands 20 dB or more below; checked in
``tests/test_texture_spectrum.py``). A 100 mm lab scan thus gives bands up to 5 mm, a 1.8 m
CAPTIF profile up to 100 mm.

Reference: ISO 13473-4:2008, Characterization of pavement texture by use of surface profiles,
Part 4: Spectral analysis of surface profiles; ISO 266:1997 (preferred frequencies).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .bands import gap_neighbours
from .heightmap import HeightMap, Profile
from .windows import tukey

__all__ = [
    "NOMINAL_MM",
    "A_REF_M",
    "MIN_BINS",
    "MIN_SAMPLES_PER_WAVELENGTH",
    "TextureSpectrum",
    "third_octave_bands",
    "texture_spectrum",
    "line_band_power",
    "nominal_label",
]

#: Nominal centre wavelengths [mm] of the preferred series, k = -3 ... 27 (10^(k/10) mm).
NOMINAL_MM = (
    0.5,
    0.63,
    0.8,
    1,
    1.25,
    1.6,
    2,
    2.5,
    3.15,
    4,
    5,
    6.3,
    8,
    10,
    12.5,
    16,
    20,
    25,
    31.5,
    40,
    50,
    63,
    80,
    100,
    125,
    160,
    200,
    250,
    315,
    400,
    500,
)
_K0 = -3
A_REF_M = 1e-6  # reference rms amplitude of ISO 13473-4 [m]
MIN_BINS = 4  # FFT bins a band must span
MIN_SAMPLES_PER_WAVELENGTH = 4  # samples per shortest wavelength of a band
WINDOW_ALPHA = 0.5  # Tukey window: cosine tapers over the outer quarters
_HALF = 10 ** (1 / 20)  # band edge factor


def nominal_label(nominal_mm):
    """The label of a nominal centre wavelength: "0.63", "2.5", "80", "31.5" (as in the series).

    Parameters
    ----------
    nominal_mm : float
        Nominal centre wavelength [mm].

    Returns
    -------
    str
        The label.
    """
    return f"{nominal_mm:g}"


def third_octave_bands():
    """All bands of the series -> (nominal_mm, centre_m, lo_m, hi_m), arrays of 31.

    Parameters
    ----------
    None

    Returns
    -------
    nominal_mm, centre_m, lo_m, hi_m : ndarray
        Nominal centres [mm], exact centres and band edges [m].

    References
    ----------
    ISO 13473-4:2008, Characterization of pavement texture by use of surface profiles -- Part 4:
    Spectral analysis of surface profiles.
    """
    k = np.arange(len(NOMINAL_MM)) + _K0
    centre = 10.0 ** (k / 10.0) * 1e-3
    return np.array(NOMINAL_MM, float), centre, centre / _HALF, centre * _HALF


@dataclass(frozen=True)
class TextureSpectrum:
    """Third-octave texture levels of one profile or area (resolved bands only).

    ``nominal_mm``, ``centre_m``, ``lo_m``, ``hi_m``: the bands; ``rms_m``: a [m];
    ``level_dB``: 20 log10(a / 1e-6 m); ``note``: what was done (lines, dropouts filled,
    resolved range); ``dropout_fraction``: the share of unmeasured points filled.

    Attributes
    ----------
    nominal_mm, centre_m, lo_m, hi_m : ndarray
        The resolved bands.
    rms_m : ndarray
        Rms amplitude in each band [m].
    level_dB : ndarray
        Texture level [dB re 1 um].
    note : str
        What was done.
    dropout_fraction : float
        Share of unmeasured points filled.
    """

    nominal_mm: np.ndarray
    centre_m: np.ndarray
    lo_m: np.ndarray
    hi_m: np.ndarray
    rms_m: np.ndarray
    level_dB: np.ndarray
    note: str = ""
    dropout_fraction: float = 0.0

    def as_dict(self):
        """{nominal label: level dB} (the ``texture_level_dB`` object of summary.json)."""
        return {
            nominal_label(n): (float(v) if np.isfinite(v) else None)
            for n, v in zip(self.nominal_mm, self.level_dB)
        }


def _fill_lines(z):
    """Linear interpolation over NaN along each row (ends held at the nearest measured value;
    rows without a measured point stay NaN), vectorised over the unmeasured points only: for
    each, the previous and the next measured point of the flattened map (the points around
    its run of consecutive unmeasured points), kept where they lie on the same row."""
    bad = ~np.isfinite(z)
    if not bad.any():
        return z
    m, n = z.shape
    bi = np.flatnonzero(bad)
    out = np.array(z, dtype=np.float64)  # a copy, C-ordered
    flat = out.ravel()
    row = bi // n
    p, q = gap_neighbours(bi, m * n)  # previous and next measured point
    has_p = (p >= 0) & (p // n == row)
    has_q = (q < m * n) & (q // n == row)
    p = np.where(has_p, p, q)
    q = np.where(has_q, q, p)
    both = has_p | has_q
    zp, zq = flat[np.where(both, p, 0)], flat[np.where(both, q, 0)]
    w = np.where(q > p, (bi - p) / np.maximum(q - p, 1), 0.0)
    flat[bi] = np.where(both, zp + w * (zq - zp), np.nan)
    return out


def line_band_power(lines, dx_m, lo_m, hi_m):
    """Mean over lines of the band power a^2 [m^2] of each band (steps 1-4 of the module doc).

    Parameters
    ----------
    lines : (m, n) array
        Heights [m] along each line, NaN where unmeasured (lines with no data are skipped).
    dx_m : float
        Sample spacing along the lines [m].
    lo_m, hi_m : (b,) arrays
        Band edges (shortest, longest wavelength) [m].

    Returns
    -------
    a2 : ndarray, shape (b,)
        Band power a^2 [m^2] averaged over the lines with data.
    n_lines : int
        The number of such lines.
    """
    z = np.atleast_2d(np.asarray(lines, dtype=np.float64))
    n = z.shape[1]
    f = np.fft.rfftfreq(n, dx_m)
    df = 1.0 / (n * dx_m)
    f_lo, f_hi = 1.0 / np.asarray(hi_m)[:, None], 1.0 / np.asarray(lo_m)[:, None]
    overlap = np.clip(np.minimum(f + df / 2, f_hi) - np.maximum(f - df / 2, f_lo), 0.0, None) / df
    w = tukey(n, WINDOW_ALPHA)
    scale = np.full(f.size, 2.0)
    scale[0] = 1.0
    if n % 2 == 0:
        scale[-1] = 1.0
    scale /= n * n * np.mean(w * w)
    t = np.arange(n) - (n - 1) / 2.0
    total = np.zeros(f.size)
    used = 0
    step = max(1, (1 << 22) // max(n, 1))  # a few MB of lines at a time
    for s in range(0, z.shape[0], step):
        zc = _fill_lines(z[s : s + step])
        full = np.isfinite(zc).all(axis=1)
        if not full.all():  # no copy when every line has data
            zc = zc[full]
        if not zc.shape[0]:
            continue
        zc = zc - zc.mean(axis=1, keepdims=True)
        zc = zc - (zc @ t / (t @ t))[:, None] * t
        X = np.fft.rfft(zc * w, axis=1)
        total += (X.real**2 + X.imag**2).sum(axis=0)
        used += zc.shape[0]
    if not used:
        return np.full(len(lo_m), np.nan), 0
    return overlap @ (total * scale / used), used


def _lines(obj, direction):
    if isinstance(obj, Profile):
        return obj.heights_m[None, :], obj.dx_m, "profile"
    if not isinstance(obj, HeightMap):
        raise TypeError(f"expected a HeightMap or Profile, got {type(obj).__name__}")
    if direction == "x":
        return obj.heights_m, obj.dx_m, f"{obj.ny} lines along x"
    if direction == "y":
        return obj.heights_m.T, obj.dy_m, f"{obj.nx} lines along y"
    raise ValueError(f"direction must be 'x' or 'y', got {direction!r}")


def texture_spectrum(obj, direction="x"):
    """ISO 13473-4 third-octave texture levels of a Profile or HeightMap (see module doc).

    Parameters
    ----------
    obj : Profile or HeightMap
        Heights [m]; NaN / unmeasured points are filled linearly along each line.
    direction : {"x", "y"}
        Driving direction of an area (lines along it are analysed); ignored for profiles.

    Returns
    -------
    TextureSpectrum
        Resolved bands only (possibly none: then every array is empty and ``note`` says why).
    """
    z, dx, what = _lines(obj, direction)
    n = z.shape[1]
    L = n * dx
    nom, centre, lo, hi = third_octave_bands()
    ok = (lo >= MIN_SAMPLES_PER_WAVELENGTH * dx * (1 - 1e-9)) & (
        (1.0 / lo - 1.0 / hi) * L >= MIN_BINS * (1 - 1e-9)
    )
    drop = float(np.mean(~np.isfinite(z)))
    length = (f"{L:#.3g}".rstrip(".") + " m") if L >= 1 else (f"{L * 1e3:#.3g}".rstrip(".") + " mm")
    note = (
        f"ISO 13473-4 third-octave levels re 1 µm, FFT (Tukey 0.5 window) of {what} of "
        f"{length} at {dx * 1e3:.3g} mm; bands from {MIN_SAMPLES_PER_WAVELENGTH} "
        f"samples per shortest wavelength to {MIN_BINS} FFT bins per band"
    )
    if drop > 0:
        note += f"; {drop:.1%} dropouts filled linearly along the lines"
    if not ok.any():
        e = np.array([])
        return TextureSpectrum(e, e, e, e, e, e, note + "; no band resolved", drop)
    a2, _ = line_band_power(z, dx, lo[ok], hi[ok])
    with np.errstate(divide="ignore"):
        level = 10.0 * np.log10(a2 / A_REF_M**2)
    return TextureSpectrum(nom[ok], centre[ok], lo[ok], hi[ok], np.sqrt(a2), level, note, drop)
