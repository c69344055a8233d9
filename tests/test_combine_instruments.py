"""``roadscan combine`` on one synthetic surface of known C(q) "measured" by three simulated
instruments (issue 20's acceptance check, on small grids): different spacing, field of view,
lateral resolution (Gaussian blur) and noise floor; area files plus a manifest giving
``spacing_m`` and ``resolution_m``."""

import csv
import json

import numpy as np
import pytest

from pipelines.cli.app import main
from roadscan.reliable_band import gaussian_response
from roadscan.synth import model_psd
from roadscan.synth_measure import measure_synthetic

H, K = 0.8, 2e-5  # C = K q^-3.6 [m^4], q in 1/m: rms 0.2 mm over the laser's view
N = 256
#: (name, spacing [m], lateral resolution [m], wave vector where the noise's C equals the
#: blurred surface's, as a fraction of Nyquist)
INSTRUMENTS = [("laser", 50e-6, 150e-6, 0.6), ("confocal", 2e-6, 5e-6, 0.5), ("afm", 0.1e-6, 0.3e-6, 0.7)]


def _noise_sigma(dx, res, at):
    q = at * np.pi / dx
    c_signal = model_psd(q, H, K) * gaussian_response(q, res) ** 2
    return float(np.sqrt(c_signal * (2 * np.pi) ** 2 / dx**2)), c_signal  # C_white = s^2 a^2/(2 pi)^2


def _gap(g):
    """A gap of combine.json as (q_a, q_b) [1/m]: a pair, or a record naming its ends."""
    if isinstance(g, dict):
        ends = [v for k, v in g.items() if k.endswith("per_m") and isinstance(v, (int, float))]
        if "q_per_m" in g:
            ends = g["q_per_m"]
        return min(ends), max(ends)
    return min(g), max(g)


@pytest.fixture(scope="module")
def combined(tmp_path_factory):
    d = tmp_path_factory.mktemp("three")
    rows = ["file,spacing_m,resolution_m,label"]
    for i, (name, dx, res, at) in enumerate(INSTRUMENTS):
        sigma, _ = _noise_sigma(dx, res, at)
        hm = measure_synthetic(N, dx, H, K, resolution_m=res, noise_rms_m=sigma, seed=11 + i)
        np.save(d / f"{name}.npy", hm.heights_m)
        rows.append(f"{name}.npy,{dx!r},{res!r},{name}")
    (d / "manifest.csv").write_text("\n".join(rows) + "\n")
    out = d / "out"
    assert main(["combine", str(d / "manifest.csv"), "--out", str(out)]) == 0
    with open(out / "psd.csv") as f:
        r = list(csv.reader(f))
    table = np.array(r[1:], float)
    return r[0], table, json.loads((out / "combine.json").read_text()), out


def test_psd_csv_header_and_reader(combined):
    head, table, _, out = combined
    assert head == ["q_per_m", "C_m4", "C_lo_m4", "C_hi_m4", "n_sources"]
    from pipelines.output.csv_files import read_psd_csv

    psd = read_psd_csv(out / "psd.csv")
    assert psd.q_min_per_m == pytest.approx(table[0, 0])
    assert np.all(table[:, 2] <= table[:, 1]) and np.all(table[:, 1] <= table[:, 3])
    for name in ("combine.json", "combine.png", "report.html"):
        assert (out / name).is_file()


def test_merged_within_25_percent_from_8_coarse_fov_to_1_um(combined):
    _, t, info, _ = combined
    q, C, lo, hi = t[:, 0], t[:, 1], t[:, 2], t[:, 3]
    L_coarse = N * INSTRUMENTS[0][1]
    q_a, q_b = 8 * 2 * np.pi / L_coarse, 2 * np.pi / 1e-6
    assert q[0] <= q_a and q[-1] >= q_b
    sel = (q >= q_a) & (q <= q_b)
    truth = model_psd(q[sel], H, K)
    err = np.abs(C[sel] / truth - 1)
    held = (lo[sel] <= truth) & (truth <= hi[sel])
    assert np.all((err <= 0.25) | ((err <= 0.5) & held)), np.c_[q[sel], C[sel] / truth][err > 0.25]
    assert np.mean(err <= 0.25) > 0.9
    gaps = [_gap(g) for g in info["gaps"]]
    assert all(b / a <= 6 for a, b in gaps), gaps


def test_merged_band_stops_before_finest_response_falls_to_0_3(combined):
    _, t, info, _ = combined
    res_fine = INSTRUMENTS[-1][2]
    assert info["merged_band_per_m"][1] == pytest.approx(t[-1, 0])
    assert gaussian_response(t[-1, 0], res_fine) > 0.3
    assert gaussian_response(t[-1, 0], res_fine) ** 2 > 0.3


def test_each_band_ends_before_resolution_or_noise_dominates(combined):
    _, _, info, _ = combined
    assert [s["label"] for s in info["inputs"]] == [i[0] for i in INSTRUMENTS]
    for s, (_, dx, res, at) in zip(info["inputs"], INSTRUMENTS):
        lo, hi = s["reliable_band_per_m"]
        assert s["resolution_m"] == pytest.approx(res)
        assert hi < 2 * np.pi / res  # before the resolution
        _, c_noise = _noise_sigma(dx, res, at)
        c_signal = model_psd(hi, H, K) * gaussian_response(hi, res) ** 2
        assert c_noise < c_signal  # before the noise dominates
        assert lo >= 2 * 2 * np.pi / (N * dx)
        assert set(s["reliable_band_reasons"]) == {"lo", "hi"}
    fit = info["fit"]
    assert fit["hurst"] == pytest.approx(H, abs=0.1)
