"""The friction engine's error function (C library below a size, scipy.special above) against
scipy.special's, and the analytic values erf(0) = 0, erf(inf) = 1, erfc(-inf) = 2."""

import numpy as np
from scipy import special

from friction import contact


def test_erf_matches_scipy_on_both_paths(monkeypatch):
    x = np.concatenate([np.linspace(-8, 8, 4001), [0.0, np.inf, -np.inf]]).reshape(-1, 1)
    for threshold in (10**9, 1):  # the C library's, then scipy's
        monkeypatch.setattr(contact, "_SCIPY_FROM", threshold)
        monkeypatch.delitem(__import__("sys").modules, "scipy.special", raising=False)
        e, c = contact.erf(x), contact.erfc(x)
        assert e.shape == x.shape and e.dtype == float
        np.testing.assert_allclose(e, special.erf(x), rtol=1e-13, atol=1e-300)
        np.testing.assert_allclose(c, special.erfc(x), rtol=1e-12, atol=1e-300)
        assert e[-3, 0] == 0.0 and e[-2, 0] == 1.0 and c[-1, 0] == 2.0


def test_erf_bits_do_not_depend_on_what_the_process_imported():
    """The same call gives the same bits before and after scipy.special is imported (batch and
    analyse of one scan must write byte-identical summaries)."""
    import subprocess
    import sys

    code = (
        "import numpy as np; from friction import contact; x = np.linspace(0.01, 4, 3001); "
        "a = contact.erf(x).tobytes(); import scipy.special; b = contact.erf(x).tobytes(); "
        "print(a == b)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "True"


def test_line_fill_equals_the_dense_per_row_interpolation():
    """roadscan.texture_spectrum's NaN fill of each line against np.interp row by row (ends held,
    all-NaN rows left NaN), on random maps with random dropout shares."""
    from roadscan.texture_spectrum import _fill_lines

    rng = np.random.default_rng(3)
    for _ in range(300):
        m, n = rng.integers(1, 7), rng.integers(1, 15)
        z = rng.standard_normal((m, n))
        z[rng.random(z.shape) < rng.random()] = np.nan
        want = z.copy()
        for r in range(m):
            ok = np.isfinite(z[r])
            if ok.any():
                want[r] = np.interp(np.arange(n), np.flatnonzero(ok), z[r, ok])
        np.testing.assert_allclose(_fill_lines(z), want, rtol=1e-14, atol=1e-15, equal_nan=True)
