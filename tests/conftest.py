import os
from pathlib import Path

import numpy as np
import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared"


def _shared_dir():
    for cand in (SHARED, ROOT / "shared", Path("/work/shared")):
        if (cand / "data").is_dir():
            return cand
    return None


@pytest.fixture(scope="session")
def shared_data():
    d = _shared_dir()
    if d is None:
        pytest.skip("shared/data not found beside the checkout")
    return d / "data"


IN_CI = os.environ.get("CI", "").lower() == "true"


def need_vendor():
    """SurfaceTopography for vendor formats: required in CI (the extra is installed there),
    a skip elsewhere."""
    if IN_CI:
        import SurfaceTopography  # noqa: F401  (CI installs the extra: an ImportError fails)

        return
    pytest.importorskip("SurfaceTopography")


@pytest.fixture(scope="session")
def formats_dir():
    """``shared/data/formats``: real instrument files with their ``expected.json``."""
    need_vendor()
    for cand in (SHARED, ROOT / "shared", Path("/work/shared")):
        d = cand / "data" / "formats"
        if (d / "expected.json").is_file():
            return d
    if IN_CI:
        pytest.fail("shared/data/formats not found beside the checkout")
    pytest.skip("shared/data/formats not found beside the checkout")


def unit_fourier_surface(n, hurst=0.8, seed=0):
    """Random-phase self-affine surface on an n x n grid of unit spacing, rms 1, mean 0."""
    h = fourier_surface(n, 1.0, hurst, 1.0, seed=seed)
    return h - h.mean()


def fourier_surface(n, dx, hurst, rms, seed=0, q_roll=None):
    """A small independent random-phase self-affine surface for pipeline tests (not roadscan.synth)."""
    rng = np.random.default_rng(seed)
    qx = 2 * np.pi * np.fft.fftfreq(n, dx)
    q = np.hypot(*np.meshgrid(qx, qx, indexing="xy"))
    q[0, 0] = 1.0
    qr = q_roll if q_roll else 2 * np.pi / (n * dx)
    amp = np.maximum(q, qr) ** (-(hurst + 1))
    amp[0, 0] = 0.0
    h = np.fft.ifft2(amp * np.exp(2j * np.pi * rng.random((n, n)))).real
    return h * (rms / h.std())
