"""``roadscan combine`` keeps the coarse end (issue 37): the flat part of a spectrum below the
surface's roll-off is the surface, not an instrument limit. Three simulated instruments of one
surface (:func:`roadscan.synth_measure.measure_synthetic`) merged stay within 25 % of the true
C(q) from 8 x 2 pi / L of the largest field to 2 pi / 1 um, with a roll-off inside the coarse
field and without one; q0 is reported where the surface has one and nowhere else. The judge of
:mod:`roadscan.rolloff_origin` on exact spectra: a knee near the field of view alone is the
instrument's, one another instrument bends at is the surface's, one another measures straight
across is the instrument's."""

import csv
import json

import numpy as np
import pytest

from pipelines.cli.app import main
from roadscan.reliable_band import gaussian_response
from roadscan.rolloff_origin import RollOffView, judge_roll_offs, surface_q0
from roadscan.synth import model_psd
from roadscan.synth_measure import measure_synthetic

H, K = 0.8, 2e-5
#: (label, points per side, spacing [m], resolution [m], where the white noise's C equals the
#: blurred surface's, as a fraction of Nyquist): a 51 mm road laser, a 1.3 mm confocal, a
#: 26 um AFM whose band reaches past 2 pi / 1 um
INSTRUMENTS = [
    ("road laser", 256, 200e-6, 400e-6, 0.9),
    ("confocal", 256, 5e-6, 10e-6, 0.8),
    ("afm", 256, 0.1e-6, 0.3e-6, 0.7),
]
L_MAX = 256 * 200e-6
Q_A, Q_B = 8 * 2 * np.pi / L_MAX, 2 * np.pi / 1e-6


def _combine(d, q_roll, seed):
    rows = ["file,spacing_m,resolution_m,label"]
    for i, (label, n, dx, res, at) in enumerate(INSTRUMENTS):
        q = at * np.pi / dx
        c = model_psd(q, H, K, q_roll_per_m=q_roll) * gaussian_response(q, res) ** 2
        sigma = float(np.sqrt(c * (2 * np.pi) ** 2 / dx**2))  # C_white = s^2 a^2 / (2 pi)^2
        hm = measure_synthetic(
            n, dx, H, K, q_roll_per_m=q_roll, resolution_m=res, noise_rms_m=sigma, seed=seed * 10 + i
        )
        np.save(d / f"i{i}.npy", hm.heights_m)
        rows.append(f"i{i}.npy,{dx!r},{res!r},{label}")
    (d / "m.csv").write_text("\n".join(rows) + "\n")
    assert main(["combine", str(d / "m.csv"), "--out", str(d / "out"), "--no-figures"]) == 0
    with open(d / "out" / "psd.csv") as fh:
        t = np.array(list(csv.reader(fh))[1:], float)
    return t, json.loads((d / "out" / "combine.json").read_text())


def _window_check(t, q_roll):
    q, C = t[:, 0], t[:, 1]
    assert q[0] <= Q_A and q[-1] >= Q_B, (q[0], Q_A, q[-1], Q_B)
    sel = (q >= Q_A) & (q <= Q_B)
    err = np.abs(C[sel] / model_psd(q[sel], H, K, q_roll_per_m=q_roll) - 1)
    assert np.all(err <= 0.25), np.c_[q[sel], 1 + err][err > 0.25]


@pytest.mark.parametrize("seed", [1, 2])
def test_a_surface_with_a_roll_off_keeps_its_plateau_and_q0(tmp_path, seed):
    """Roll-off at 1050 1/m (8.6 x 2 pi / L of the laser): the laser's band reaches down into
    the plateau (it started at the roll-off, and the merged curve at 1.66e3 1/m, before), the
    curve starts by 8 x 2 pi / L, and q0 is the roll-off."""
    q_roll = 1050.0
    t, info = _combine(tmp_path, q_roll, seed)
    _window_check(t, q_roll)
    laser = info["inputs"][0]
    assert laser["roll_off"]["origin"] == "surface"
    assert laser["reliable_band_per_m"][0] < 0.8 * q_roll  # the plateau is in
    assert info["q0_per_m"] == pytest.approx(q_roll, rel=0.15)
    assert "road laser" in info["q0_how"]
    assert info["fit"]["roll_off_per_m"] == pytest.approx(info["q0_per_m"])
    # the rows on the plateau (below q0) hold the truth within their 5-95 % band widened by
    # the 10 % bias a band's end tolerates
    plateau = t[t[:, 0] < 0.9 * q_roll]
    assert plateau.size
    assert np.all(
        (plateau[:, 2] / 1.1 <= model_psd(plateau[:, 0], H, K, q_roll_per_m=q_roll))
        & (model_psd(plateau[:, 0], H, K, q_roll_per_m=q_roll) <= 1.1 * plateau[:, 3])
    )


@pytest.mark.parametrize("seed", [1, 2])
def test_a_surface_without_a_roll_off_gets_no_q0(tmp_path, seed):
    t, info = _combine(tmp_path, None, seed)
    _window_check(t, None)
    assert info["q0_per_m"] is None
    assert "no roll-off" in info["q0_how"]


# ----------------------------------------------------------------- the judge on exact spectra
def _rings(lo, hi, per_decade=20):
    j = np.arange(np.floor(per_decade * np.log10(lo)), np.ceil(per_decade * np.log10(hi)))
    return 10 ** ((j + 0.5) / per_decade)


def _view(label, q_roll, L, band, knee_of_surface=None):
    q = _rings(*band)
    C = np.maximum(q, knee_of_surface or 0.0) ** -3.6
    return RollOffView(label, q_roll, 2 * np.pi / L, 6 * 2 * np.pi / L, band, q, C, np.full(q.size, 1e3))


def test_a_knee_alone_near_the_field_of_view_is_the_instruments():
    L = 0.05
    q_fov = 2 * np.pi / L
    near = judge_roll_offs(views=[_view("laser", 4 * q_fov, L, (4 * q_fov, 100 * q_fov))])
    far = judge_roll_offs(views=[_view("laser", 20 * q_fov, L, (6 * q_fov, 100 * q_fov))])
    top = judge_roll_offs(views=[_view("laser", 90 * q_fov, L, (6 * q_fov, 100 * q_fov))])
    assert judge_roll_offs(views=[_view("laser", None, L, (6 * q_fov, 100 * q_fov))]) == [None]
    assert [v.origin for v in near + far + top] == ["instrument", "surface", "instrument"]
    assert "field-of-view end" in near[0].reason and "top" in top[0].reason
    assert surface_q0(verdicts=near)[0] is None
    assert surface_q0(verdicts=far)[0] == pytest.approx(20 * q_fov)


def test_a_knee_another_instrument_bends_at_is_the_surfaces():
    """The small field's knee sits at 3.5 x its 2 pi / L (alone, that would be its own); the
    large field, whose own knee test found nothing (its band's middle is the plateau), bends
    there: the surface's, seen by both (the large field's bend found from its rings' slope)."""
    q_r = 4000.0
    small = _view("confocal", q_r, 5.12e-3, (q_r, 9e4), knee_of_surface=q_r)
    large = _view("laser", None, 0.0512, (500.0, 9e3), knee_of_surface=q_r)
    bend, v = judge_roll_offs(views=[large, small])
    assert v.origin == "surface" and v.seen_by == ("confocal", "laser")
    assert bend.origin == "surface" and bend.q_roll_per_m == pytest.approx(q_r, rel=0.13)
    assert surface_q0(verdicts=[bend, v])[0] == pytest.approx(q_r, rel=0.1)
    # the same knee where the large field's spectrum runs straight across it: the instrument's
    straight = _view("laser", None, 0.0512, (500.0, 9e3))
    none, w = judge_roll_offs(views=[straight, small])
    assert none is None and w.origin == "instrument" and w.refuted_by == ("laser",)
    assert surface_q0(verdicts=[none, w])[0] is None
