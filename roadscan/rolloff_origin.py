"""Whose roll-off is it: the surface's, or one instrument's? And q0, the one Persson's theory needs.

A roll-off (:func:`roadscan.rolloff.detect_roll_off`: the spectrum flattens below a knee q_r)
found in one instrument's spectrum has two possible causes:

- the **instrument**: the Tukey window and the levelling bend the lowest rings of every
  spectrum within a few 2 pi / L of its field of view L (below its band's field-of-view end,
  k(beta) x 2 pi / L, :func:`roadscan.reliable_band.leakage_factor`), and the lateral
  resolution and noise bend its top; such a knee moves with the instrument (it sits at the same
  multiple of 2 pi / L, or of the resolution, whatever the surface);
- the **surface** (the aggregate size of a road, Persson 2016): the knee sits at one wave
  vector, and every instrument that measures across that wave vector sees it there.

So a knee at q_r of instrument i is judged, in this order:

1. another instrument j *covers* q_r when its reliable band reaches from q_r / :data:`ROOM`
   up to q_r x :data:`SAME_Q`. j *sees* the bend there when it found a knee within a factor
   :data:`SAME_Q` of q_r, or when its own rings bend at q_r: the log-log slope s_below of its
   rings over [q_r / ROOM, q_r] exceeds s_above over [q_r, q_r x ROOM] (its band's top at
   most) by over :data:`BEND_SEEN` and by over 2 standard errors (lines weighted by
   the rings' degrees of freedom; a q^-3.6 spectrum over a plateau bends by about 3; j's own
   knee test can miss it when j's fitted line is the plateau itself). Seen by a covering j:
   the roll-off is the surface's (at the same q, far from j's field); every covering j
   straight across it (s_below - s_above + 2 standard errors under BEND_SEEN): i's own;
2. no other instrument covers q_r: it is the surface's when q_r lies at or above i's
   field-of-view end (where i measures a steep spectrum within about 10 %) and at least
   :data:`SAME_Q` below its band's top (resolution, noise, Nyquist: 3 rings above it show the
   line it departs from); below the field-of-view end
   it is taken for the instrument's (the window's leakage and the levelling can bend a
   spectrum there, and no other scan confirms it), near the top likewise.

q0 is the geometric mean of the knees judged the surface's within :data:`SAME_Q` of the lowest
(each instrument's estimate of one wave vector), or None when there is none: then the spectrum
shows no roll-off inside what was measured reliably, and q0 lies at or below the lowest wave
vector measured.

Reference: Persson, Tribol. Lett. 63, 42 (2016), doi:10.1007/s11249-016-0728-5 (roll-off of
road spectra, q0 in the friction integral); Jacobs, Junge, Pastewka, Surf. Topogr.: Metrol.
Prop. 5, 013001 (2017), doi:10.1088/2051-672X/aa51f8, sec. 3-4 (windows, reliability of
each instrument's scales).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .units import length as _len

__all__ = [
    "RollOffView",
    "RollOffVerdict",
    "judge_roll_offs",
    "surface_q0",
    "bend_at",
    "find_bend",
    "SAME_Q",
    "ROOM",
    "BEND_SEEN",
]

#: two knees within this factor (0.15 decade) are one wave vector: a knee found in a spectrum
#: of 20 rings per decade scatters by about 10 % over seeds at 8 x 2 pi / L and more nearer
SAME_Q = 10**0.15
#: the rings this factor (0.3 decade) below and above q_r give the slopes on either side
ROOM = 10**0.3
#: least drop of the log-log slope across q_r for an instrument's rings to bend there (half a
#: plateau-to-q^-3 bend; a straight spectrum's two slopes differ by their scatter only)
BEND_SEEN = 1.5


@dataclass(frozen=True)
class RollOffView:
    """What one instrument shows near a roll-off, for :func:`judge_roll_offs`.

    Attributes
    ----------
    label : str
        The instrument's name.
    q_roll_per_m : float or None
        Its detected knee [1/m], or None.
    q_fov_per_m : float
        2 pi / L of its field of view L [1/m].
    q_field_per_m : float
        Its band's field-of-view end k x 2 pi / L [1/m]: below it the window's leakage biases
        a steep spectrum by over about 10 %.
    band_per_m : tuple of float
        Its reliable band (lo, hi) [1/m], hi set by resolution, noise or Nyquist.
    q_per_m, C_m4, dof : ndarray, optional
        Its rings (wave vector [1/m], C, degrees of freedom), to see whether they bend at
        another instrument's knee (None: only its own knee counts).
    """

    label: str
    q_roll_per_m: float | None
    q_fov_per_m: float
    q_field_per_m: float
    band_per_m: tuple
    q_per_m: np.ndarray | None = None
    C_m4: np.ndarray | None = None
    dof: np.ndarray | None = None


@dataclass(frozen=True)
class RollOffVerdict:
    """One instrument's knee judged by :func:`judge_roll_offs`.

    Attributes
    ----------
    label : str
        The instrument that found it.
    q_roll_per_m : float
        The knee [1/m].
    origin : str
        ``"surface"`` or ``"instrument"``.
    reason : str
        One line: why.
    seen_by : tuple of str
        Every instrument seeing a bend at this knee (itself first).
    refuted_by : tuple of str
        The instruments measuring straight across it (then it is the instrument's).
    """

    label: str
    q_roll_per_m: float
    origin: str
    reason: str
    seen_by: tuple
    refuted_by: tuple = ()

    def as_dict(self):
        return {
            "label": self.label,
            "q_roll_per_m": self.q_roll_per_m,
            "origin": self.origin,
            "reason": self.reason,
            "seen_by": list(self.seen_by),
            "refuted_by": list(self.refuted_by),
        }


def _covers(view, q):
    """Does ``view``'s band reach from q / ROOM to q x SAME_Q (3 rings above q at least)?"""
    return view.band_per_m[0] <= q / ROOM * (1 + 1e-9) and view.band_per_m[1] >= q * SAME_Q * (1 - 1e-9)


def _slope(x, y, w):
    """Weighted least-squares slope of y on x and its standard error (weights: inverse
    variances), or None under 3 points."""
    if x.size < 3 or np.ptp(x) <= 0:
        return None
    xm = np.average(x, weights=w)
    sxx = np.sum(w * (x - xm) ** 2)
    s = np.sum(w * (x - xm) * (y - np.average(y, weights=w))) / sxx
    return float(s), float(1.0 / np.sqrt(sxx))


def bend_at(view, q):
    """How ``view``'s rings bend at q [1/m]: (s_below - s_above, its standard error), or None
    (too few rings on a side). Slopes of ln C on ln q over [q / ROOM, q] and [q, q x ROOM]
    inside the band, each ring weighted by its degrees of freedom / 2 (ln C of a ring of k
    degrees of freedom scatters by sqrt(2 / k))."""
    if view.q_per_m is None:
        return None
    qq, C, k = (np.asarray(a, float) for a in (view.q_per_m, view.C_m4, view.dof))
    lo, hi = view.band_per_m
    ok = (qq >= lo * (1 - 1e-9)) & (qq <= hi * (1 + 1e-9)) & (C > 0) & (k > 0)
    x, y, w = np.log(qq[ok]), np.log(C[ok]), k[ok] / 2.0
    below = (x >= np.log(q / ROOM)) & (x <= np.log(q))
    above = (x >= np.log(q)) & (x <= np.log(q * ROOM))
    a, b = _slope(x[below], y[below], w[below]), _slope(x[above], y[above], w[above])
    if a is None or b is None:
        return None
    return a[0] - b[0], float(np.hypot(a[1], b[1]))


def find_bend(view):
    """The sharpest bend of ``view``'s rings [1/m], or None: the ring q where s_below - s_above
    (:func:`bend_at`) is largest, when it exceeds :data:`BEND_SEEN` and 3 standard errors (the
    largest of some twenty tries: 2 would pass by chance).

    :func:`roadscan.rolloff.detect_roll_off` looks for rings falling under the line fitted to
    the middle of a band; a band whose middle is the plateau itself (a coarse scan whose field
    holds the plateau and only its top 0.3 decade of the power law) has no such rings, and its
    knee shows only as its slope dropping from about 0 to the power law's.

    Parameters
    ----------
    view : RollOffView
        One instrument, with its rings.

    Returns
    -------
    float or None
    """
    if view.q_per_m is None:
        return None
    lo, hi = view.band_per_m
    best = None
    for q in np.asarray(view.q_per_m, float):
        if not (lo * ROOM <= q <= hi / SAME_Q):
            continue
        bend = bend_at(view, q)
        if bend is None:
            continue
        drop, se = bend
        if drop > BEND_SEEN and drop > 3 * se and (best is None or drop > best[0]):
            best = (drop, float(q))
    return None if best is None else best[1]


def _sees(view, q):
    """True: ``view`` sees a bend at q (its own knee there, or its rings bend); False: its
    rings run straight across q; None: cannot tell."""
    if _same(view.q_roll_per_m, q):
        return True
    bend = bend_at(view, q)
    if bend is None:
        return None
    drop, se = bend
    if drop > BEND_SEEN and drop > 2 * se:
        return True
    if drop + 2 * se < BEND_SEEN:
        return False
    return None


def _same(a, b):
    return a is not None and b is not None and abs(np.log(a / b)) <= np.log(SAME_Q) * (1 + 1e-9)


def _wl(q):
    return _len(2 * np.pi / q)


def judge_roll_offs(*, views):
    """Judge every instrument's knee: the surface's or the instrument's (module docstring).

    Parameters
    ----------
    views : sequence of RollOffView
        Every instrument of one surface, with or without a knee.

    Returns
    -------
    list of RollOffVerdict or None
        One per view, in the order of ``views``: its knee (its own, or where its rings bend:
        :func:`find_bend`) judged, or None.
    """
    out = []
    for v in views:
        q, how = v.q_roll_per_m, "knee"
        if q is None:
            q, how = find_bend(v), "bend of its rings' slope"
        if q is None:
            out.append(None)
            continue
        where = (
            f"{how} at {q:.3g} 1/m (wavelength {_wl(q)}), {q / v.q_fov_per_m:.3g} x 2 pi / L of {v.label!r}"
        )
        others = [w for w in views if w is not v]
        covering = [w for w in others if _covers(w, q)]
        sees = [_sees(w, q) for w in covering]
        confirm = [w.label for w, x in zip(covering, sees) if x]
        covering = [w for w, x in zip(covering, sees) if x is not None]
        seen = tuple([v.label] + confirm)
        if confirm:
            out.append(
                RollOffVerdict(
                    v.label,
                    q,
                    "surface",
                    f"{where}: seen at the same wave vector by "
                    f"{', '.join(map(repr, confirm))}, whose rings bend "
                    f"there too",
                    seen,
                )
            )
        elif covering:
            names = ", ".join(repr(w.label) for w in covering)
            out.append(
                RollOffVerdict(
                    v.label,
                    q,
                    "instrument",
                    f"{where}: {names} measures straight across it (its "
                    f"rings' slope drops by under {BEND_SEEN:g} there): "
                    f"{v.label!r}'s own",
                    seen,
                    tuple(w.label for w in covering),
                )
            )
        elif q < v.q_field_per_m * (1 - 1e-9):
            out.append(
                RollOffVerdict(
                    v.label,
                    q,
                    "instrument",
                    f"{where}: below its field-of-view end {v.q_field_per_m / v.q_fov_per_m:.3g} x "
                    f"2 pi / L, where the window's leakage and the levelling bend a spectrum, and no "
                    f"other input measures there to confirm it",
                    seen,
                )
            )
        elif q * SAME_Q > v.band_per_m[1] * (1 + 1e-9):
            out.append(
                RollOffVerdict(
                    v.label,
                    q,
                    "instrument",
                    f"{where}: within a factor {SAME_Q:.2g} of its band's top "
                    f"({v.band_per_m[1]:.3g} 1/m: resolution, noise or Nyquist bend it there)",
                    seen,
                )
            )
        else:
            out.append(
                RollOffVerdict(
                    v.label,
                    q,
                    "surface",
                    f"{where}: inside its band, above its field-of-view end "
                    f"({v.q_field_per_m / v.q_fov_per_m:.3g} x 2 pi / L) and well below its top; "
                    f"no other input measures across it",
                    seen,
                )
            )
    return out


def surface_q0(*, verdicts):
    """q0 [1/m] from judged knees -> (q0 or None, how: one line).

    Parameters
    ----------
    verdicts : sequence of RollOffVerdict or None
        From :func:`judge_roll_offs` (None entries skipped).

    Returns
    -------
    q0 : float or None
        The geometric mean of the knees judged the surface's; None when there is none.
    how : str
        How it was found, or why there is none.
    """
    verdicts = [v for v in verdicts if v is not None]
    surf = [v for v in verdicts if v.origin == "surface"]
    if not surf:
        if verdicts:
            return None, (
                "no roll-off of the surface: every knee found is an instrument's "
                "(" + "; ".join(v.reason for v in verdicts) + "); q0 lies at or below "
                "the lowest wave vector measured"
            )
        return None, (
            "no roll-off found in any input's reliable band: q0 lies at or below the "
            "lowest wave vector measured"
        )
    # the lowest roll-off (a second bend above it is no q0): its knees within SAME_Q
    low = min(v.q_roll_per_m for v in surf)
    surf = [v for v in surf if _same(v.q_roll_per_m, low) or v.q_roll_per_m < low * SAME_Q]
    q0 = float(np.exp(np.mean([np.log(v.q_roll_per_m) for v in surf])))
    names = ", ".join(f"{v.label!r} at {v.q_roll_per_m:.3g} 1/m" for v in surf)
    return q0, (
        f"the surface's roll-off (Persson's q0, wavelength {_wl(q0)}): the knee of the "
        f"broken line (flat below, self-affine above) found by {names}"
        + (" (geometric mean)" if len(surf) > 1 else "")
        + f"; {surf[0].reason}"
    )
