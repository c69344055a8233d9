"""The flash-temperature solver (friction.flash._solve_flash, issues 13 and 14): convergence at
every speed from 1e-10 to 1e4 m/s, bounded iteration counts (counts, not time), the returned T
is a fixed point of the engine's own map whatever the solver path, clear one-line failures, and
the heat_scale path to the isothermal model."""

import numpy as np
import pytest

import friction.flash as flash
from friction import SelfAffinePSD, mu_flash, mu_isothermal, thesis_rubber
from friction.flash import FlashConvergenceError

RUB = thesis_rubber()
FLASH_PSD = SelfAffinePSD(0.8, 6.67e-4, 1500.0, 6e5)  # DESIGN.md sec 6, flash set
ISO_PSD = SelfAffinePSD(0.85, 5e-4, 2000.0, 2e5)


def capture_map(monkeypatch):
    """Run the engine and keep its map Phi (rows, T) -> T, to check a result independently."""
    box = {}
    real = flash._solve_flash

    def spy(phi_map, *args, **kw):
        box["phi"] = phi_map
        return real(phi_map, *args, **kw)

    monkeypatch.setattr(flash, "_solve_flash", spy)
    return box


@pytest.mark.parametrize(
    "lo,hi,sigma0,limit", [(-8, 4, 0.4e6, 60), (2, 4, 0.4e6, 100), (-8, 4, 0.2e6, 60), (2, 4, 0.2e6, 100)]
)
def test_iteration_counts_bounded(lo, hi, sigma0, limit):
    """Issue 13: at most 60 map evaluations for 50 speeds over 1e-8..1e4 m/s and 100 over
    1e2..1e4 (the solver before took 572 and 282 on the 0.4 MPa set)."""
    res = mu_flash(FLASH_PSD, RUB, np.logspace(lo, hi, 50), sigma0_Pa=sigma0)
    assert 1 <= res.iterations <= limit
    assert np.all(np.isfinite(res.mu)) and np.all(res.mu > 0)
    assert res.residual <= 1e-5 * max(1.0, float(np.max(res.T_q_C - 60.0)))


@pytest.mark.parametrize("v", [1e-10, 1e4])
@pytest.mark.parametrize("psd,sigma0,hot", [(FLASH_PSD, 0.4e6, 500.0), (ISO_PSD, 0.2e6, 1.0)])
def test_converges_at_the_ends_of_the_speed_range(v, psd, sigma0, hot):
    res = mu_flash(psd, RUB, [v], sigma0_Pa=sigma0)
    rise = float(np.max(res.T_q_C - 60.0))
    assert res.iterations <= 60
    if v == 1e-10:  # no heating at all: the isothermal result
        assert rise < 1e-3
        iso = mu_isothermal(psd, RUB, [v], sigma0_Pa=sigma0).mu
        assert res.mu[0] == pytest.approx(iso[0], rel=2e-3)
    else:  # heating, finite and below the cap
        assert hot < rise < flash.T_RISE_MAX_K


def test_result_is_a_fixed_point_of_the_engine_map(monkeypatch):
    """Evaluate the engine's own map at the returned T: |Phi(T) - T| within the criterion."""
    box = capture_map(monkeypatch)
    v = np.logspace(-10, 4, 29)
    res = mu_flash(FLASH_PSD, RUB, v, sigma0_Pa=0.4e6)
    Tn, R = box["phi"](res.T_q_C, np.arange(v.size))
    rise = np.maximum(1.0, np.max(res.T_q_C - 60.0, axis=1))
    step = np.max(np.abs(Tn - res.T_q_C), axis=1)
    assert np.all(step <= 2e-5 * rise)  # one more map step barely moves it
    np.testing.assert_allclose(R, res.meta["R_m"], rtol=1e-4)


def test_solution_independent_of_solver_path():
    """Different damping and memory (different paths through the runaway region) reach the
    same temperatures and mu: the fixed point, not an artefact of the path."""
    v = np.logspace(0, 4, 9)
    a = mu_flash(FLASH_PSD, RUB, v, sigma0_Pa=0.4e6)
    b = mu_flash(FLASH_PSD, RUB, v, sigma0_Pa=0.4e6, beta=0.2, memory=3)
    c = mu_flash(FLASH_PSD, RUB, v, sigma0_Pa=0.4e6, memory=1)  # no Anderson: damped only
    rise = np.max(a.T_q_C - 60.0, axis=1, keepdims=True)
    for other in (b, c):
        assert np.max(np.abs(other.T_q_C - a.T_q_C) / rise) < 1e-4
        np.testing.assert_allclose(other.mu, a.mu, rtol=1e-4)
    assert a.iterations <= b.iterations and a.iterations < c.iterations


def test_undamped_two_cycle_case_converges():
    """R fixed at 1 mm: the undamped map falls into a 2-cycle (DESIGN.md sec 7)."""
    res = mu_flash(
        FLASH_PSD, RUB, np.logspace(-10, 4, 50), sigma0_Pa=0.4e6, asperity_abc=(1e-3 * 3 * 1500.0, 0.0, 0.0)
    )
    assert res.iterations <= 60
    assert res.temperature_at(400.0).max() > 500


def test_failure_is_one_line_runtime_error_naming_speeds():
    with pytest.raises(FlashConvergenceError) as e:
        mu_flash(FLASH_PSD, RUB, np.logspace(-2, 3, 6), sigma0_Pa=0.4e6, max_iter=3)
    msg = str(e.value)
    assert isinstance(e.value, RuntimeError) and "\n" not in msg
    assert "did not converge" in msg and "v = 0.01, 0.1, 1 (and 3 more) m/s" in msg


def test_runaway_heating_is_reported_as_such():
    """A heat balance with no solution in the model's range (a very rough, very hot case whose
    iterates climb thousands of kelvin) fails with a one-line 'runs away' error, not silently."""
    from dataclasses import replace

    from friction import Thermal

    rub = replace(RUB, thermal=Thermal(conductivity_W_mK=0.1))
    psd = SelfAffinePSD(0.65, 1.15e-3, 1776.0, 1776.0 * 960)
    with pytest.raises(FlashConvergenceError, match="runs away") as e:
        mu_flash(psd, rub, [3.3e3, 1e4], sigma0_Pa=2e6, T0_C=73.0, max_iter=150)
    assert "\n" not in str(e.value) and "m/s" in str(e.value)


def test_heat_scale_reaches_the_isothermal_model():
    v = np.logspace(-6, 4, 11)
    iso = mu_isothermal(FLASH_PSD, RUB, v, sigma0_Pa=0.4e6).mu
    off = mu_flash(FLASH_PSD, RUB, v, sigma0_Pa=0.4e6, heat_scale=0.0)
    assert off.iterations == 1 and np.all(off.T_q_C == 60.0)
    np.testing.assert_allclose(off.mu, iso, rtol=1e-3)
    rises = [
        np.max(mu_flash(FLASH_PSD, RUB, v, sigma0_Pa=0.4e6, heat_scale=s).T_q_C - 60.0)
        for s in (1e-3, 0.1, 1.0)
    ]
    assert 0 < rises[0] < rises[1] < rises[2]  # a continuous path
    with pytest.raises(ValueError, match="heat_scale"):
        mu_flash(FLASH_PSD, RUB, v, heat_scale=-1.0)
