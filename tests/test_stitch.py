"""Stitching (roadscan.stitch) and the ``roadscan stitch`` command.

Tiles are cut from a known synthetic surface (roadscan.synth), given a random height offset,
tilt and a little measurement noise each, and nominal positions wrong by up to 10 samples;
the mosaic must reproduce the surface (issue 4 item 1)."""

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from roadscan.errors import InputError
from roadscan.heightmap import HeightMap
from roadscan.level import level
from roadscan.spectrum import psd_area
from roadscan.stitch import grid_positions, read_manifest, stitch
from roadscan.synth import self_affine_surface

DX = 50e-6
RMS = 1e-4
REPO = Path(__file__).resolve().parents[1]


def make_tiles(
    surface, rows=3, cols=3, n=160, step=120, pad=12, noise=1e-3, dropouts=0.0, jitter=10.0, seed=0
):
    """Cut tiles from ``surface`` (a 2D array) on a jittered grid.

    Returns tiles, nominal positions [m], true (row, col) of each tile's first sample, and the
    true measured mask of every tile (for the expected coverage).
    """
    rng = np.random.default_rng(seed)
    tiles, nominal, true = [], [], []
    yy, xx = np.mgrid[0:n, 0:n] * DX
    for r in range(rows):
        for c in range(cols):
            r0 = pad + r * step + int(rng.integers(-6, 7))
            c0 = pad + c * step + int(rng.integers(-6, 7))
            z = surface[r0 : r0 + n, c0 : c0 + n].copy()
            slope = 3 * RMS / (n * DX)
            z += rng.normal(0, 3 * RMS) + rng.normal(0, slope) * xx + rng.normal(0, slope) * yy
            z += noise * RMS * rng.standard_normal(z.shape)
            if dropouts:
                z[rng.random(z.shape) < dropouts] = np.nan
                z[20:26, 30:33] = np.nan  # a small cavity dropout in every tile
            tiles.append(HeightMap(z, DX, DX, name=f"tile_r{r}_c{c}"))
            true.append((r0, c0))
            err = rng.uniform(-jitter, jitter, 2)
            nominal.append(((c0 + err[1]) * DX, (r0 + err[0]) * DX))
    return tiles, nominal, np.array(true)


def truth_window(res, surface, true):
    """The part of the original surface under the mosaic (the gauge is tile 0's true place)."""
    hm = res.heightmap
    ox, oy = hm.meta["origin_xy_m"]
    # mosaic sample (0,0) relative to tile 0's first sample, in samples
    rel = np.array([(oy - res.positions_m[0, 1]) / DX, (ox - res.positions_m[0, 0]) / DX])
    start = true[0] + rel
    assert np.allclose(start, np.rint(start), atol=1e-6)
    r0, c0 = np.rint(start).astype(int)
    return surface[r0 : r0 + hm.ny, c0 : c0 + hm.nx]


def coverage(res, tiles):
    """Points of the mosaic inside at least one tile footprint, and measured by some tile."""
    hm = res.heightmap
    inside = np.zeros(hm.shape, bool)
    measured = np.zeros(hm.shape, bool)
    ox, oy = hm.meta["origin_xy_m"]
    for t, (x, y) in zip(tiles, res.positions_m):
        r, c = int(round((y - oy) / DX)), int(round((x - ox) / DX))
        inside[r : r + t.ny, c : c + t.nx] = True
        measured[r : r + t.ny, c : c + t.nx] |= ~t.unmeasured
    return inside, measured


def plane_residual(d):
    ok = np.isfinite(d)
    yy, xx = np.nonzero(ok)
    A = np.column_stack([np.ones(yy.size), xx, yy])
    coef, *_ = np.linalg.lstsq(A, d[ok], rcond=None)
    out = np.full(d.shape, np.nan)
    out[ok] = d[ok] - A @ coef
    return out


@pytest.fixture(scope="module")
def surface():
    return self_affine_surface(520, 520, dx_m=DX, hurst=0.8, rms_height_m=RMS, seed=11).heights_m


@pytest.fixture(scope="module")
def mosaic_3x3(surface):
    tiles, nominal, true = make_tiles(surface, dropouts=0.005, seed=1)
    return tiles, nominal, true, stitch(tiles, nominal)


def test_positions_recovered_exactly(mosaic_3x3):
    _, nominal, true, res = mosaic_3x3
    nominal_px = np.array(nominal)[:, ::-1] / DX
    assert np.max(np.abs(nominal_px - true - (nominal_px[0] - true[0]))) > 5  # really wrong
    refined_px = res.positions_m[:, ::-1] / DX
    np.testing.assert_allclose(refined_px - refined_px[0], true - true[0], atol=0.05)
    # tile 0 is the gauge: keeps its nominal position
    np.testing.assert_allclose(res.positions_m[0], nominal[0], atol=1e-12)
    # every registered shift is the true relative position minus the nominal one
    for o in res.overlaps:
        i, j = o["i"], o["j"]
        expect = (true[j] - true[i]) - (nominal_px[j] - nominal_px[i])
        np.testing.assert_allclose(o["shift_px"], expect, atol=0.05)
        assert o["registered"]


def test_mosaic_matches_original_within_1_percent(mosaic_3x3, surface):
    tiles, _, true, res = mosaic_3x3
    hm = res.heightmap
    ref = truth_window(res, surface, true)
    err = plane_residual(hm.heights_m - ref)  # absolute offset and tilt are a gauge
    inside, measured = coverage(res, tiles)
    # unmeasured exactly where no tile measured
    np.testing.assert_array_equal(hm.unmeasured, ~measured)
    # away from the outer border of the covered area
    from scipy import ndimage

    interior = ndimage.binary_erosion(inside, iterations=10) & measured
    e = err[interior]
    assert np.sqrt(np.mean(e**2)) < 0.01 * RMS
    assert np.max(np.abs(e)) < 0.01 * RMS
    # 3x3 grid: 12 edge and 8 diagonal overlaps, each matched to about the noise level
    assert len(res.overlaps) == 20
    for o in res.overlaps:
        assert o["n_points"] > 100
        assert o["rms_mismatch_m"] < 3 * math.sqrt(2) * 1e-3 * RMS


def ring_psd(h):
    hm = level(HeightMap(h, DX, DX), degree=1)
    s, _ = psd_area(hm, rings_per_decade=20)
    return s.q_per_m, s.C_m4


def test_no_seam_in_spectrum(surface):
    tiles, nominal, true = make_tiles(surface, noise=1e-3, seed=2)
    res = stitch(tiles, nominal)
    ref = truth_window(res, surface, true)
    # fully covered interior rectangle
    sl = (slice(20, 360), slice(20, 360))
    m = res.heightmap.heights_m[sl]
    assert np.isfinite(m).all()
    q, C_mos = ring_psd(m)
    _, C_ref = ring_psd(ref[sl])
    ratio = C_mos / C_ref
    high = q > 0.1 * q.max()
    assert np.all(np.abs(ratio[high] - 1) < 0.03), ratio[high]
    assert np.all(np.abs(ratio - 1) < 0.03)  # including the tile period 2 pi / (120 dx)

    # the same metric sees seams: tiles laid at their true places without height correction
    naive = ref.copy()
    ox, oy = res.heightmap.meta["origin_xy_m"]
    for t, (x, y) in zip(tiles, res.positions_m):
        r, c = int(round((y - oy) / DX)), int(round((x - ox) / DX))
        naive[r : r + t.ny, c : c + t.nx] = t.heights_m
    _, C_naive = ring_psd(naive[sl])
    assert np.max(np.abs(C_naive / C_ref - 1)) > 0.5


def test_subpixel_offsets(surface):
    # periodic surface shifted by a fraction of a sample (exact Fourier shift)
    n = 240
    H = self_affine_surface(n, n, dx_m=DX, hurst=0.8, rms_height_m=RMS, seed=5).heights_m
    ky = np.fft.fftfreq(n)[:, None]
    kx = np.fft.fftfreq(n)[None, :]
    frac = np.array([0.3, -0.35])
    Hs = np.fft.ifft2(np.fft.fft2(H) * np.exp(-2j * np.pi * (ky * frac[0] + kx * frac[1]))).real
    a = HeightMap(H[10:130, 10:130], DX, DX, name="a")
    b = HeightMap(Hs[14:134, 100:220], DX, DX, name="b")  # b[u] = H[u + (14, 100) - frac]
    true_rel = np.array([4.0, 90.0]) - frac
    res = stitch([a, b], [(0.0, 0.0), ((true_rel[1] + 6) * DX, (true_rel[0] - 5) * DX)])
    rel = (res.positions_m[1] - res.positions_m[0])[::-1] / DX
    np.testing.assert_allclose(rel, true_rel, atol=0.05)
    # the resampled tile b still matches the surface in the overlap to ~1 % of rms
    o = res.overlaps[0]
    assert o["rms_mismatch_m"] < 0.01 * RMS


def test_disconnected_tile_is_refused(surface):
    a = HeightMap(surface[:100, :100], DX, DX, name="left.npy")
    b = HeightMap(surface[:100, 80:180], DX, DX, name="middle.npy")
    c = HeightMap(surface[300:400, 300:400], DX, DX, name="far_away.npy")
    with pytest.raises(InputError, match=r"tile far_away\.npy does not overlap any other tile"):
        stitch([a, b, c], [(0, 0), (80 * DX, 0), (300 * DX, 300 * DX)])
    d = HeightMap(surface[300:400, 380:480], DX, DX, name="far_pair.npy")
    with pytest.raises(InputError, match="do not overlap"):
        stitch([a, b, c, d], [(0, 0), (80 * DX, 0), (300 * DX, 300 * DX), (380 * DX, 300 * DX)])


def test_spacing_mismatch_is_refused(surface):
    a = HeightMap(surface[:100, :100], DX, DX, name="a")
    b = HeightMap(surface[:100, 80:180], 2 * DX, DX, name="b")
    with pytest.raises(InputError, match="spacing"):
        stitch([a, b], [(0, 0), (80 * DX, 0)])


def test_grid_positions():
    pos = grid_positions(2, 3, (100, 200), 1e-5, 2e-5, 0.25)
    assert len(pos) == 6
    assert pos[0] == (0.0, 0.0)
    assert pos[1] == pytest.approx((150 * 1e-5, 0.0))
    assert pos[5] == pytest.approx((2 * 150 * 1e-5, 75 * 2e-5))
    with pytest.raises(ValueError):
        grid_positions(2, 2, (10, 10), 1, 1, 1.0)


def test_read_manifest(tmp_path):
    (tmp_path / "tiles").mkdir()
    np.save(tmp_path / "tiles" / "a.npy", np.zeros((4, 4)))
    good = tmp_path / "m.csv"
    good.write_text("file,x_m,y_m\ntiles/a.npy,0.001,-2e-3\n")
    assert read_manifest(good) == [(tmp_path / "tiles" / "a.npy", 0.001, -0.002)]
    bad = tmp_path / "bad.csv"
    bad.write_text("name,x,y\ntiles/a.npy,0,0\n")
    with pytest.raises(InputError, match="header must be exactly 'file,x_m,y_m'"):
        read_manifest(bad)
    missing = tmp_path / "missing.csv"
    missing.write_text("file,x_m,y_m\ntiles/b.npy,0,0\n")
    with pytest.raises(InputError, match=r"line 2: tile file 'tiles/b\.npy' not found"):
        read_manifest(missing)
    nonnum = tmp_path / "nonnum.csv"
    nonnum.write_text("file,x_m,y_m\ntiles/a.npy,zero,0\n")
    with pytest.raises(InputError, match="line 2"):
        read_manifest(nonnum)
    with pytest.raises(InputError, match="not found"):
        read_manifest(tmp_path / "nope.csv")


# --- the command ------------------------------------------------------------------------------


def best_match(m, truth, search):
    """rms of mosaic - truth (plane removed) at the integer offset (|r|, |c| <= search) that
    matches best; the offset is chosen on a central patch, the rms taken over the whole overlap."""

    def aligned(r, c):
        a = m[max(0, -r) :, max(0, -c) :]
        b = truth[max(0, r) :, max(0, c) :]
        ny, nx = min(a.shape[0], b.shape[0]), min(a.shape[1], b.shape[1])
        return a[:ny, :nx] - b[:ny, :nx]

    def patch_rms(r, c):
        d = aligned(r, c)
        cy, cx = d.shape[0] // 2, d.shape[1] // 2
        return np.nanstd(plane_residual(d[cy - 32 : cy + 32, cx - 32 : cx + 32]))

    r, c = min(
        ((r, c) for r in range(-search, search + 1) for c in range(-search, search + 1)),
        key=lambda rc: patch_rms(*rc),
    )
    return np.nanstd(plane_residual(aligned(r, c)))


def run_cli(argv):
    from pipelines.cli.app import main

    return main(argv)


def test_cli_sample_manifest_reproduces_truth(tmp_path, capsys):
    out = tmp_path / "mosaic.npy"
    rc = run_cli(["stitch", str(REPO / "sample_scans" / "tiles_manifest.csv"), "--out", str(out)])
    assert rc == 0
    table = capsys.readouterr().out
    assert "rms mismatch" in table and "tile_r0_c0.npz" in table
    m = np.load(out)
    truth = np.load(REPO / "sample_scans" / "tiles_truth.npy").astype(float)
    rms = np.nanstd(truth)
    # the mosaic's origin is tile 0's nominal place: find the small integer offset to the truth
    assert best_match(m, truth, 5) < 0.01 * rms
    with open(out.with_name("mosaic_overlaps.csv")) as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) >= 7 and all(float(r["rms_mismatch_m"]) < 0.01 * rms for r in rows)


def test_cli_grid_and_x3p(tmp_path, surface):
    from roadscan.io import read

    tiles, _, true = make_tiles(surface, rows=1, cols=2, n=100, step=75, jitter=0.0, noise=0.0, seed=3)
    # the grid's nominal overlap is 25 %; the real one differs by the random cut offsets (< 7 px)
    files = []
    for k, t in enumerate(tiles):
        f = tmp_path / f"t{k}.npy"
        np.save(f, t.heights_m * 1e6)  # micrometres, no spacing in the file
        files.append(str(f))
    out = tmp_path / "m.x3p"
    rc = run_cli(
        [
            "stitch",
            *files,
            "--grid",
            "1x2",
            "--overlap",
            "0.25",
            "--out",
            str(out),
            "--spacing",
            str(DX),
            "--units",
            "um",
        ]
    )
    assert rc == 0
    hm = read(out)
    assert hm.dx_m == pytest.approx(DX)
    assert 100 < hm.nx < 200 and hm.ny >= 100
    assert np.isfinite(hm.heights_m).mean() > 0.9
    truth = surface[true[0][0] :, true[0][1] :]
    assert best_match(hm.heights_m, truth, 8) < 0.01 * RMS


def test_cli_bad_inputs(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("file;x;y\n")
    assert run_cli(["stitch", str(bad), "--out", str(tmp_path / "o.npy")]) == 2
    assert "file,x_m,y_m" in capsys.readouterr().err
    assert (
        run_cli(
            [
                "stitch",
                str(bad),
                str(bad),
                "--grid",
                "3x1",
                "--overlap",
                "0.2",
                "--out",
                str(tmp_path / "o.npy"),
            ]
        )
        == 2
    )
    assert "needs 3 tiles" in capsys.readouterr().err


def test_nominal_overlap_without_common_texture_is_refused():
    """Two tiles placed side by side on paper whose overlap strips show unrelated texture."""
    from pathlib import Path

    from roadscan.io import read

    d = Path(__file__).resolve().parents[1] / "sample_scans" / "tiles"
    a, b = read(d / "tile_r0_c0.npz"), read(d / "tile_r1_c2.npz")  # far apart in truth
    with pytest.raises(InputError, match="texture matches"):
        stitch([a, b], [(0.0, 0.0), (288 * a.dx_m, 0.0)])
    # the same two tiles where they really are (no overlap at all) are refused as well
    with pytest.raises(InputError, match="does not overlap any other tile"):
        stitch([a, b], [(0.0, 0.0), (512 * a.dx_m, 256 * a.dy_m)])
