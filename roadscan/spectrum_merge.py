"""Several measured spectra of one surface merged into one C(q) on a common log-q grid.

Every spectrum enters only within its reliable band (:mod:`roadscan.reliable_band`). The
common grid is the set of rings with edges 10^(j / n) [1/m] (n rings per decade): spectra
computed on rings aligned with it (:func:`aligned_range`) contribute whole rings to one bin.
In bin j, with rings i of the sources (mean wave vector q_i, mean C_i over n_i lattice points
or 1D modes),

    C_j = sum_i n_i C_i (q_j / q_i)^s_j / sum_i n_i,    ln q_j = sum_i n_i ln q_i / sum_i n_i,

the mean over every lattice point of every source that falls in the bin: each source weighs by
its statistical weight; s_j is the local log-log slope (line through the rings within
:data:`SLOPE_REACH` decade, weighted by their degrees of freedom, so that the many-point rings
above a band's start set it), which moves each ring to q_j without bias for a power law. Where
a bin holds few lattice points (the lowest rings of a field of view), consecutive bins are
pooled into one row until it holds :data:`MIN_ROW_DOF` degrees of freedom (at most
:data:`MAX_ROW_BINS` bins). A *bend* (a source's detected roll-off, ``bends_per_m``) splits the
grid into segments: no row pools rings across one and no slope is taken across one (a straight
move across a roll-off puts the plateau's row far above it). The first row of each stretch
sits at its lowest ring (the curve starts where the band does), unless a bend lies within
:data:`SLOPE_REACH` decade above or :data:`BEND_AHEAD` decade below it, or the stretch spans
under :data:`MIN_STRETCH_DECADES`; the others sit at the count-weighted mean of ln q (where a
slope error cancels to first order). With ``start_per_m`` given (combine: 8 x 2 pi / L of the
largest field), a first row sitting above it whose rings reach it sits at it: the curve starts
there, not up to 0.6 decade above where its bands do. Uncertainty: a periodogram value of a
Gaussian surface is C times an exponential variable (2 degrees of freedom per independent
mode, reduced by the window's equivalent noise bandwidth); the mean of k degrees of freedom is C chi2_k / k,
so the 5-95 % band of the truth is [C k / chi2_k(0.95), C k / chi2_k(0.05)].
Where several sources overlap, the weighted rms scatter s of their ln C_i about ln C_j is added
in quadrature to each side (as 1.645 s), and so is ln(1 + b) times the share of the bin's
lattice points lying within 0.15 decade of their source's band ends, b the bias the reliable
band tolerates there (``SpectrumPart.edge_bias``: about 10 % for leakage, aliasing, resolution,
25 % at a noise floor; :mod:`roadscan.reliable_band`), and so is the slope's standard error
times the row's mean lever |ln(q_j / q_i)| (a row at its lowest ring moves rings far). Bins inside the union
of the bands that no source covers are *gaps* (a bin inside some band that holds no ring, as 1D modes sparser
than the grid at low q, gets no row): bridged (:mod:`roadscan.spectrum_gaps`) by the power law fitted
(inverse-variance weights) to the covered rows within 0.5 decade on either side, flagged
``n_sources = 0`` and listed.

Inputs whose C disagree where both measure beyond their scatter are listed
(``MergedSpectrum.disagreements``), and a measured row whose band excludes the line through its
neighbours gets a band reaching it (``widened_rows_per_m``): :mod:`roadscan.spectrum_agreement`.

Reference: Jacobs, Junge, Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017), sec. 3
(periodogram statistics, windows); Sanner et al., Surf. Topogr.: Metrol. Prop. 10, 035014
(2022) (merging the spectra of several instruments, reliability cut-offs).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .spectrum_agreement import Z95, disagreements, widen_outliers  # Z95, disagreements re-exported
from .spectrum_gaps import bridge, find_gaps, gap_edges

__all__ = [
    "SpectrumPart",
    "MergedSpectrum",
    "merge_spectra",
    "aligned_range",
    "disagreements",
    "chi2_quantile",
    "RINGS_PER_DECADE",
    "Z95",
]

RINGS_PER_DECADE = 20
#: rings this close (decades) to either end of their source's band carry the bias the reliable
#: band tolerates there (leakage at lo, noise or resolution at hi: about 10 %)
EDGE_DECADES = 0.15
EDGE_BIAS = 0.10
#: rings are pooled into a row until it holds this many degrees of freedom (C within about
#: +-7 % at one standard deviation, sqrt(2 / 400)), over at most MAX_ROW_BINS grid bins
MIN_ROW_DOF = 400.0
#: 0.6 decade: a field of view's first row (about 200 dof over 0.4 decade from 6 x 2 pi / L)
#: scattered by 9 % rms about the truth over 40 synthetic views, by 6-8 % over 0.6 decade
MAX_ROW_BINS = 12
#: decades either side of a row whose rings set its local slope
SLOPE_REACH = 1.0
#: a row starting within this many decades above a bend sits at its mean ln q: the window
#: rounds the bend over a few 2 pi / L and the bend's place, chosen from the data, favours
#: high rings above it
BEND_AHEAD = 0.2
#: a stretch of rows (between gaps) spanning less than this (decades) starts at its first
#: row's mean ln q, not its lowest ring: its own rings cannot show the slope to move them by
MIN_STRETCH_DECADES = 0.5


@dataclass(frozen=True)
class SpectrumPart:
    """One source's spectrum for :func:`merge_spectra`.

    ``q_per_m``, ``C_m4``, ``count`` are its rings (2D C, an area's or a profile's estimate),
    ``band_per_m`` its reliable band [lo, hi] [1/m], ``dof_per_count`` the degrees of freedom
    one unit of ``count`` carries (an area's full-lattice count: 1 / ENBW^2; profiles' 1D
    modes: 2 / ENBW).

    Attributes
    ----------
    label : str
    q_per_m, C_m4, count : ndarray
    band_per_m : tuple of float
    dof_per_count : float
    edge_bias : tuple of float
    bends_per_m : tuple of float
    """

    label: str
    q_per_m: np.ndarray
    C_m4: np.ndarray
    count: np.ndarray
    band_per_m: tuple
    dof_per_count: float = 1.0
    #: bias the band tolerates at its (low, high) end (fractions of C)
    edge_bias: tuple = (EDGE_BIAS, EDGE_BIAS)
    #: wave vectors [1/m] where the spectrum bends (a detected roll-off): no row pools rings
    #: across one, nor takes its slope from rings on the other side
    bends_per_m: tuple = ()


@dataclass(frozen=True)
class MergedSpectrum:
    """Result of :func:`merge_spectra`: rows of the merged C(q) and the gaps bridged.

    Attributes
    ----------
    q_per_m, C_m4 : ndarray
    C_lo_m4, C_hi_m4 : ndarray
    n_sources : ndarray of int
    count : ndarray
    band_per_m : tuple of float
    gaps : list
    disagreements : list
    widened_rows_per_m : list
    """

    q_per_m: np.ndarray
    C_m4: np.ndarray
    C_lo_m4: np.ndarray
    C_hi_m4: np.ndarray
    n_sources: np.ndarray  # sources measuring each row reliably (0: bridged)
    count: np.ndarray  # lattice points / modes behind each row (0: bridged)
    band_per_m: tuple  # [first, last] row measured reliably
    gaps: list = field(default_factory=list)
    #: pairs of sources whose overlap disagrees beyond their scatter (:func:`disagreements`)
    disagreements: list = field(default_factory=list)
    #: rows whose 5-95 % band was widened to what their neighbours say
    #: (:func:`roadscan.spectrum_agreement.widen_outliers`)
    widened_rows_per_m: list = field(default_factory=list)


def aligned_range(q_min_per_m, q_max_per_m, per_decade=RINGS_PER_DECADE):
    """(q_lo, q_hi) on the common grid 10^(j / per_decade) enclosing [q_min, q_max]: rings
    :func:`roadscan.rings._ring_edges` lays from q_lo to q_hi are then grid bins.

    Parameters
    ----------
    q_min_per_m, q_max_per_m : float
    per_decade : int, optional

    Returns
    -------
    tuple of float
        (q_lo, q_hi) [1/m].
    """
    j0 = np.floor(per_decade * np.log10(q_min_per_m) + 1e-9)
    j1 = np.ceil(per_decade * np.log10(q_max_per_m) - 1e-9)
    j1 = max(j1, j0 + 1)
    return float(10 ** (j0 / per_decade)), float(10 ** (j1 / per_decade))


def chi2_quantile(p, k):
    """Quantile p of the chi-square law with k degrees of freedom: 2 P^-1(k / 2, p), P the
    regularised lower incomplete gamma function (scipy.special.gammaincinv).

    Parameters
    ----------
    p : float
    k : array_like

    Returns
    -------
    ndarray
    """
    from scipy.special import gammaincinv

    return 2.0 * gammaincinv(np.asarray(k, float) / 2.0, p)


def _bins(q, per_decade):
    return np.floor(per_decade * np.log10(q) + 1e-9).astype(np.int64)


def merge_spectra(parts, per_decade=RINGS_PER_DECADE, *, start_per_m=None):
    """Merge the reliable parts of several spectra (see module docstring).

    Parameters
    ----------
    parts : sequence of SpectrumPart
    per_decade : int
        Rings per decade of the common grid.
    start_per_m : float, optional
        Where a band starts below this wave vector [1/m], the merged curve's first row sits at
        it or below (None: at its lowest ring or its rings' mean, as the rules above say).

    Returns
    -------
    MergedSpectrum

    Raises
    ------
    ValueError
        When no source has a reliable ring.
    """
    rows = []  # (bin, q, C, n, dof, source index, edge ring)
    lows, highs = [], []
    bends = sorted(
        {
            float(x)
            for p in parts
            for x in p.bends_per_m
            if x and p.band_per_m[0] / 10**BEND_AHEAD <= x < p.band_per_m[1]
        }
    )
    for s, p in enumerate(parts):
        q, C = np.asarray(p.q_per_m, float), np.asarray(p.C_m4, float)
        n = np.asarray(p.count, float)
        lo, hi = p.band_per_m
        keep = (q >= lo * (1 - 1e-9)) & (q <= hi * (1 + 1e-9)) & (C > 0) & np.isfinite(C) & (n > 0)
        if keep.any():
            lows.append(float(lo))
            highs.append(float(hi))
            qk = q[keep]
            b_lo, b_hi = p.edge_bias
            edge = np.where(qk < lo * 10**EDGE_DECADES, np.log(1 + b_lo) ** 2, 0.0)
            edge = np.maximum(edge, np.where(qk > hi / 10**EDGE_DECADES, np.log(1 + b_hi) ** 2, 0.0))
            rows.append(
                np.column_stack(
                    [
                        _bins(qk, per_decade),
                        qk,
                        C[keep],
                        n[keep],
                        n[keep] * p.dof_per_count,
                        np.full(keep.sum(), s),
                        edge,
                    ]
                )
            )
    if not rows:
        raise ValueError("no input has a reliable part of its spectrum: nothing to merge")
    r = np.vstack(rows)
    b = r[:, 0].astype(np.int64)
    j0 = b.min()
    n, dof = r[:, 3], r[:, 4]
    # segments between bends: a bend's grid bin starts a new segment (rows never straddle one)
    bend_bins = (
        np.unique(_bins(np.asarray(bends, float), per_decade)) - j0 if bends else np.zeros(0, np.int64)
    )
    seg_of_bin = np.searchsorted(bend_bins, np.arange(b.max() - j0 + 1), side="right")
    row_of_bin, first_bin = _group_bins(np.bincount(b - j0, dof), MIN_ROW_DOF, MAX_ROW_BINS, seg_of_bin)
    idx = row_of_bin[b - j0]
    N = np.bincount(idx, n, first_bin.size)
    q = _place_rows(r[:, 1], n, idx, first_bin, N > 0, bend_bins, per_decade)
    if start_per_m is not None:
        # the curve's first row moved down to start_per_m when its rings reach there (its
        # rings are moved along the local slope as any row's; their lever grows, and so does
        # the slope error's share of its band)
        i0 = int(np.argmax(N > 0))
        if q[i0] > start_per_m and r[idx == i0, 1].min() <= start_per_m:
            q[i0] = float(start_per_m)
    nb = first_bin.size
    seg_row, seg_ring = seg_of_bin[first_bin], seg_of_bin[b - j0]
    covered = N > 0
    Nc = np.where(covered, N, 1.0)
    # each ring's C moved to its row's q along the local slope (exact for a power law)
    slopes, slope_se = _row_slopes(r[:, 1], r[:, 2], dof, q, covered, seg_ring, seg_row)
    lever = np.log(q[idx] / r[:, 1])
    Cr = r[:, 2] * np.exp(slopes[idx] * lever)
    C = np.bincount(idx, n * Cr, nb) / Nc
    clash = disagreements(idx, r[:, 5].astype(np.int64), n, dof, Cr, r[:, 6], q, [p.label for p in parts])
    # a slope error ds shifts ln C of a row by ds times its rings' mean distance in ln q
    moved = np.bincount(idx, n * Cr * lever, nb) / np.maximum(np.bincount(idx, n * Cr, nb), 1e-300)
    k = np.bincount(idx, dof, nb)
    nsrc = np.array([np.unique(r[idx == i, 5]).size for i in range(nb)])
    # between-source scatter of ln C about the merged value (weighted rms)
    dev = np.log(Cr / np.where(covered, C, 1.0)[idx])
    s2 = np.bincount(idx, n * dev**2, nb) / Nc
    s2 = np.where(nsrc >= 2, s2, 0.0)
    s2 = s2 + (np.bincount(idx, n * r[:, 6], nb) / Nc) / Z95**2 + (slope_se * moved) ** 2
    kk = np.maximum(k, 1.0)
    d_lo = np.log(chi2_quantile(0.95, kk) / kk)
    d_hi = np.log(kk / chi2_quantile(0.05, kk))
    d_lo = np.sqrt(d_lo**2 + Z95**2 * s2)
    d_hi = np.sqrt(d_hi**2 + Z95**2 * s2)
    # gaps: bins no source's band covers, bridged in ln C vs ln q; an empty bin inside a band
    # (1D modes or lattice points sparser than the grid at low q) is no gap: no row
    centre = 10 ** ((first_bin + j0 + 0.5) / per_decade)
    lo_edge, hi_edge = 10 ** ((first_bin + j0) / per_decade), 10 ** ((first_bin + j0 + 1) / per_decade)
    in_band = np.zeros(nb, bool)
    for lo, hi in zip(lows, highs):
        in_band |= (hi_edge > lo) & (lo_edge < hi)
    row = covered | ~in_band
    q, C, N, covered, d_lo, d_hi, nsrc, seg = (
        a[row] for a in (np.where(covered, q, centre), C, N, covered, d_lo, d_hi, nsrc, seg_row)
    )
    gaps = find_gaps(covered, q)
    lnC = np.log(np.where(covered, C, 1.0))
    widened = widen_outliers(q, lnC, d_lo, d_hi, covered, seg)
    for g in gaps:
        bridge(g, q, lnC, d_lo, d_hi, covered, seg)
    gap_edges(gaps, lows, highs)
    Cm = np.exp(lnC)
    return MergedSpectrum(
        q,
        Cm,
        Cm * np.exp(-d_lo),
        Cm * np.exp(d_hi),
        nsrc.astype(np.int64),
        np.where(covered, N, 0.0),
        (float(q[covered][0]), float(q[covered][-1])),
        gaps,
        clash,
        widened,
    )


def _place_rows(q_ring, n, idx, first_bin, covered, bend_bins, per_decade):
    """Each row's wave vector [1/m]: the count-weighted mean of its rings' ln q (an error in the
    slope below cancels to first order in the moved rings' mean), but the first of each stretch
    at its lowest ring (the curve starts where the band does); not so near a bend, below one
    (its few rings' slope is uncertain) or at one (the bend's place, chosen from the data,
    favours high rings above it), nor in a stretch too short to show its own slope beyond its
    first row (a single row at its lowest ring over a roll-off was 9 x the truth)."""
    nb = first_bin.size
    Nc = np.where(covered, np.bincount(idx, n, nb), 1.0)
    q = np.exp(np.bincount(idx, n * np.log(q_ring), nb) / Nc)
    q_first = np.full(nb, np.inf)
    np.minimum.at(q_first, idx, q_ring)
    reach = int(round(SLOPE_REACH * per_decade))
    ahead = int(round(BEND_AHEAD * per_decade))
    near_bend = np.zeros(nb, bool)
    for bb in bend_bins:
        near_bend |= (first_bin <= bb + ahead) & (first_bin >= bb - reach)
    starts = covered & ~np.r_[False, covered[:-1]]
    stretch = np.cumsum(starts)
    ln_top = np.full(stretch.max() + 1, -np.inf)
    np.maximum.at(ln_top, stretch[idx], np.log10(q_ring))
    ln_bot = np.full(stretch.max() + 1, np.inf)
    np.minimum.at(ln_bot, stretch[idx], np.log10(q_ring))
    with np.errstate(invalid="ignore"):  # a stretch index without rings: -inf - inf
        long_enough = (ln_top - ln_bot)[stretch] >= MIN_STRETCH_DECADES
    return np.where(starts & ~near_bend & long_enough, q_first, q)


def _group_bins(dof, min_dof, max_bins, segment=None):
    """Rows of the merged curve from grid bins: consecutive covered bins of one segment (between
    bends) are pooled until a row holds ``min_dof`` degrees of freedom (at most ``max_bins``
    bins); an uncovered bin is a row of its own. -> (row index of each bin, first bin of each
    row)."""
    row = np.empty(dof.size, np.int64)
    seg = np.zeros(dof.size, np.int64) if segment is None else segment
    first = []
    acc, width, prev = 0.0, 0, False
    for j, d in enumerate(dof):
        cov = d > 0
        if not (cov and prev) or acc >= min_dof or width >= max_bins or (j and seg[j] != seg[j - 1]):
            first.append(j)
            acc, width = 0.0, 0
        row[j] = len(first) - 1
        acc += d
        width += 1
        prev = cov
    return row, np.asarray(first, np.int64)


def _row_slopes(q, C, dof, q_row, covered, seg_ring=None, seg_row=None, reach=None):
    """d ln C / d ln q at each row and its standard error: the line through the rings within
    ``reach`` decades of the row's q and in its segment (no bend between), weighted by their
    inverse variance dof / 2 (a ring's ln C scatters by sqrt(2 / dof)); slope 0 and error 0
    where fewer than 3 rings. -> (slopes, standard errors)."""
    reach = SLOPE_REACH if reach is None else reach
    x, y = np.log(q), np.log(C)
    out, se = np.zeros(q_row.size), np.zeros(q_row.size)
    for i in np.flatnonzero(covered):
        near = np.abs(x - np.log(q_row[i])) <= reach * np.log(10)
        if seg_ring is not None:
            near &= seg_ring == seg_row[i]
        if near.sum() >= 3 and np.ptp(x[near]) > 0:
            w = dof[near] / 2.0
            xm, ym = np.average(x[near], weights=w), np.average(y[near], weights=w)
            sxx = w @ (x[near] - xm) ** 2
            out[i] = (w @ ((x[near] - xm) * (y[near] - ym))) / sxx
            se[i] = 1.0 / np.sqrt(sxx)
    return out, se
