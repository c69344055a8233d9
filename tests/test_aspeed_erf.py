"""The friction engine's error function (C library below a size, scipy.special above) against
scipy.special's, and the analytic values erf(0) = 0, erf(inf) = 1, erfc(-inf) = 2."""
import numpy as np
from scipy import special

from friction import contact


def test_erf_matches_scipy_on_both_paths(monkeypatch):
    x = np.concatenate([np.linspace(-8, 8, 4001), [0.0, np.inf, -np.inf]]).reshape(-1, 1)
    for threshold in (10**9, 1):                           # the C library's, then scipy's
        monkeypatch.setattr(contact, "_SCIPY_FROM", threshold)
        monkeypatch.delitem(__import__("sys").modules, "scipy.special", raising=False)
        e, c = contact.erf(x), contact.erfc(x)
        assert e.shape == x.shape and e.dtype == float
        np.testing.assert_allclose(e, special.erf(x), rtol=1e-13, atol=1e-300)
        np.testing.assert_allclose(c, special.erfc(x), rtol=1e-12, atol=1e-300)
        assert e[-3, 0] == 0.0 and e[-2, 0] == 1.0 and c[-1, 0] == 2.0
