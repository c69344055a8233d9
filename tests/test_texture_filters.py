"""ISO 16610 Gaussian S- and L-filters, form removal, and their flags through analyse."""

import contextlib
import io
import json

import numpy as np
import pytest
from conftest import fourier_surface

from pipelines.cli.app import main
from roadscan.heightmap import HeightMap, Profile
from roadscan.iso_filters import ALPHA, apply_filters, gaussian_lowpass, gaussian_transmission


def _amplitude(z):
    return np.sqrt(2 * np.mean(z**2))


@pytest.mark.parametrize("ratio", [1.0, 0.5, 2.0])
def test_profile_transmission_is_the_gaussian(ratio):
    """A sine of wavelength lambda through the low-pass of nesting index lc keeps
    exp(-pi (alpha lc / lambda)^2) of its amplitude: 50 % at lambda = lc."""
    dx, lc = 1e-4, 8e-3
    x = np.arange(6000) * dx
    lam = lc * ratio
    low = gaussian_lowpass(np.sin(2 * np.pi * x / lam), (dx,), lc)
    mid = slice(1400, 4600)  # away from the ends, a whole number of periods
    want = np.exp(-np.pi * (ALPHA * lc / lam) ** 2)
    assert _amplitude(low[mid]) == pytest.approx(want, rel=1e-3)
    assert gaussian_transmission(lam, lc) == pytest.approx(want)
    if ratio == 1.0:
        assert want == pytest.approx(0.5)
        rough = apply_filters(Profile(np.sin(2 * np.pi * x / lam), dx), l_filter_m=lc).heights_m
        assert _amplitude(rough[mid]) == pytest.approx(0.5, rel=1e-3)


def test_areal_half_transmission_along_a_diagonal():
    dx, lc = 1e-4, 4e-3
    y, x = np.mgrid[0:400, 0:400] * dx
    k = 2 * np.pi / lc  # wave vector of length 2 pi / lc at 45 deg
    z = np.sin(k * (x + y) / np.sqrt(2))
    low = gaussian_lowpass(z, (dx, dx), lc)
    assert _amplitude(low[100:300, 100:300]) == pytest.approx(0.5, rel=5e-3)


def test_l_filter_matches_an_independent_gaussian_high_pass():
    """Sq of the L-filtered surface within 5 % of a high-pass by scipy.ndimage.gaussian_filter
    (sigma = alpha lc / sqrt(2 pi), mirror edges), compared away from the edges."""
    from scipy.ndimage import gaussian_filter

    dx, lc = 5e-5, 2e-3
    z = fourier_surface(512, dx, 0.8, 3e-4, seed=3)
    hm = HeightMap(z, dx, dx)
    ours = apply_filters(hm, l_filter_m=lc).heights_m
    sigma = ALPHA * lc / np.sqrt(2 * np.pi) / dx
    ref = z - gaussian_filter(z, sigma, mode="mirror", truncate=5)
    inner = (slice(80, -80), slice(80, -80))
    sq = np.sqrt(np.mean(ours[inner] ** 2))
    assert sq == pytest.approx(np.sqrt(np.mean(ref[inner] ** 2)), rel=0.05)
    # over the whole field too: the normalised filter's edges do not blow up
    assert np.sqrt(np.mean(ours**2)) == pytest.approx(np.sqrt(np.mean(ref**2)), rel=0.05)


def test_constant_stays_constant_with_holes_and_edges():
    z = np.full((120, 90), 3e-4)
    z[40:50, 10:30] = np.nan
    low = gaussian_lowpass(z, (1e-4, 1e-4), 5e-3)
    assert np.isnan(low[45, 20])
    ok = np.isfinite(z)
    assert np.allclose(low[ok], 3e-4, rtol=1e-9)
    out = apply_filters(HeightMap(z, 1e-4, 1e-4), l_filter_m=5e-3)
    assert out.unmeasured[45, 20] and np.nanmax(np.abs(out.heights_m)) < 1e-15


def test_s_filter_removes_the_short_wave():
    dx = 1e-4
    x = np.arange(5000) * dx
    z = np.sin(2 * np.pi * x / 0.02) + 0.2 * np.sin(2 * np.pi * x / 5e-4)
    out = apply_filters(Profile(z, dx), s_filter_m=2.5e-3, l_filter_m=0.08).heights_m
    mid = slice(1000, 4000)
    # the 0.5 mm wave is gone (transmission exp(-pi (alpha 5)^2) ~ 1e-16), the 20 mm one is
    # passed by the S-filter (0.986) and by the L-filter's high-pass (1 - 1e-7)
    resid = out[mid] - np.sin(2 * np.pi * x[mid] / 0.02) * gaussian_transmission(0.02, 2.5e-3) * (
        1 - gaussian_transmission(0.02, 0.08)
    )
    assert np.max(np.abs(resid)) < 2e-3


@pytest.mark.parametrize(
    "bad",
    [
        dict(s_filter_m=1e-2, l_filter_m=1e-3),
        dict(s_filter_m=1e-5),
        dict(l_filter_m=1.0),
        dict(l_filter_m=-1.0),
    ],
)
def test_filter_refusals(bad):
    with pytest.raises(ValueError):
        apply_filters(HeightMap(np.zeros((50, 50)), 1e-4, 1e-4), **bad)


def _run(argv):
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
        try:
            rc = main(argv)
        except SystemExit as exc:  # argparse's own refusals
            rc = exc.code
    return rc, buf.getvalue()


@pytest.fixture(scope="module")
def scan(tmp_path_factory):
    d = tmp_path_factory.mktemp("filt")
    dx = 5e-5
    y, x = np.mgrid[0:256, 0:256] * dx
    z = fourier_surface(256, dx, 0.8, 2e-4, seed=4) + 3e-3 * ((x - 6e-3) ** 2 + (y - 6e-3) ** 2) / 6e-3
    np.save(d / "bowl.npy", z)
    return d / "bowl.npy", dx, z


def test_analyse_records_filters_and_form(scan, tmp_path):
    path, dx, _ = scan
    rc, text = _run(
        [
            "analyse",
            str(path),
            "--spacing",
            str(dx),
            "--no-friction",
            "--no-figures",
            "--out",
            str(tmp_path / "plain"),
        ]
    )
    assert rc == 0, text
    plain = json.loads((tmp_path / "plain" / "summary.json").read_text())
    assert plain["filters"]["form"] == "plane" and plain["filters"]["l_filter_m"] is None
    rc, text = _run(
        [
            "analyse",
            str(path),
            "--spacing",
            str(dx),
            "--no-friction",
            "--no-figures",
            "--form",
            "poly2",
            "--l-filter",
            "0.004",
            "--out",
            str(tmp_path / "f"),
        ]
    )
    assert rc == 0, text
    s = json.loads((tmp_path / "f" / "summary.json").read_text())
    f = s["filters"]
    assert f["form"] == "poly2" and f["l_filter_m"] == 0.004 and f["s_filter_m"] is None
    assert "normalised" in f["end_effects"]
    # the bowl (about 1 mm deep) is gone from the roughness figures, not from rms_height_m
    assert s["roughness"]["Sq_m"] < 0.5 * plain["roughness"]["Sq_m"]
    assert s["rms_height_m"] == pytest.approx(plain["rms_height_m"])
    assert s["hurst"] == pytest.approx(plain["hurst"])  # spectrum unfiltered
    html = (tmp_path / "f" / "report.html").read_text()
    assert "form poly2" in html and "L-filter 4.00 mm" in html and "unfiltered" in html


@pytest.mark.parametrize(
    "flags, needle",
    [
        (["--s-filter", "0.01", "--l-filter", "0.001"], "--s-filter"),
        (["--l-filter", "5"], "--l-filter"),
        (["--l-filter", "nan"], "--l-filter"),
        (["--form", "poly9"], "--form"),
    ],
)
def test_bad_filter_flags_exit_2_in_one_line(scan, tmp_path, flags, needle):
    path, dx, _ = scan
    rc, text = _run(
        [
            "analyse",
            str(path),
            "--spacing",
            str(dx),
            "--no-friction",
            "--no-figures",
            "--out",
            str(tmp_path / "x"),
        ]
        + flags
    )
    assert rc == 2
    assert needle in text and "Traceback" not in text
