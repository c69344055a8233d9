"""Properties of the friction engine: quadrature against closed forms, grid convergence,
limits and trends of Persson's theory, rubber models and fits."""

import numpy as np
import pytest
from scipy.integrate import quad

from friction import (
    WLF,
    MasterCurve,
    Prony,
    SelfAffinePSD,
    ShiftTable,
    StandardLinearSolid,
    TabulatedPSD,
    fit_prony,
    fit_wlf,
    mu_flash,
    mu_isothermal,
    rubber_from_dict,
    thesis_rubber,
)
from friction.contact import contact_P, p_weights
from friction.grids import phi_rule, phi_table

RUB = thesis_rubber()
PSD100 = SelfAffinePSD(0.85, 5e-4, 2000.0, 2e5)


def sls_phi_closed_form(x, E1=1e9, a1=1000.0, tau=1e-3):
    """m(x) = int_0^pi/2 cos(phi) Im E(x cos phi) dphi and w(x) = int |E|^2 dphi for the SLS."""
    b, k = 1 + a1, x * tau
    s = np.sqrt(b * b + k * k)
    m = E1 * a1 * np.pi / 2 * k / (s * (s + b))
    w = E1**2 * (np.pi / 2 - (b * b - 1) * np.pi / (2 * b * s))
    return m, w


def test_phi_quadrature_matches_sls_closed_form():
    x = np.logspace(-4, 14, 181)
    m_ex, w_ex = sls_phi_closed_form(x)
    c, wq = phi_rule()
    E = RUB.modulus_ref(x[:, None] * c)
    np.testing.assert_allclose((c * E.imag) @ wq, m_ex, rtol=1e-6)
    np.testing.assert_allclose((np.abs(E) ** 2) @ wq, w_ex, rtol=1e-6)
    # a coarse rule is visibly worse: the test can fail
    c4, w4 = phi_rule(n_gl=3)
    E4 = RUB.modulus_ref(x[:, None] * c4)
    assert np.max(np.abs((c4 * E4.imag) @ w4 / m_ex - 1)) > 1e-4
    tab = phi_table(RUB, 1e-4, 1e14)
    m, w = tab(x)
    np.testing.assert_allclose(m, m_ex, rtol=2e-6)
    np.testing.assert_allclose(w, w_ex, rtol=2e-6)


@pytest.mark.parametrize("Ga,Gb", [(0.0, 1e-3), (0.0, 40.0), (0.5, 3.0), (1e2, 1e4)])
def test_exact_P_weights(Ga, Gb):
    """Weights integrate f P exactly for f linear and G linear in s (vs scipy.quad)."""
    h = 0.3
    G = np.array([Ga, Gb])
    w, _ = p_weights(G, np.array([h]))
    f = lambda s: 2.0 + 5.0 * s / h  # noqa: E731
    P = lambda s: float(contact_P(Ga + (Gb - Ga) * s / h))  # noqa: E731
    ref = quad(lambda s: f(s) * P(s), 0, h, limit=200, epsrel=1e-12)[0]
    assert w @ np.array([f(0), f(h)]) == pytest.approx(ref, rel=1e-10)


@pytest.mark.parametrize("zeta", [10, 1000])
def test_halving_tol_changes_mu_less_than_0p1_percent(zeta):
    psd = SelfAffinePSD(0.85, 5e-4, 2000.0, 2000.0 * zeta)
    v = np.logspace(-8, 4, 121)
    a = mu_isothermal(psd, RUB, v, tol=1e-3).mu
    b = mu_isothermal(psd, RUB, v, tol=5e-4).mu
    assert a.size == 121 and np.max(np.abs(a / b - 1)) < 1e-3
    assert (
        mu_isothermal(psd, RUB, v, tol=1e-3).q_per_m.size < mu_isothermal(psd, RUB, v, tol=5e-4).q_per_m.size
    )


def test_mu_vanishes_at_low_speed_and_is_positive():
    v = np.logspace(-12, -6, 7)
    mu = mu_isothermal(PSD100, RUB, v).mu
    assert np.all(mu > 0) and np.all(np.diff(mu) > 0)
    assert mu[0] < 1e-7
    # linear response: mu proportional to v at very low speed (Im E ~ omega)
    assert mu[1] / mu[0] == pytest.approx(10.0, rel=0.01)


def test_sigma0_dependence():
    v = np.array([1e-6, 1e3])
    # P ~ 1 (high pressure on the rubbery plateau): mu ~ 1 / sigma0
    lo = mu_isothermal(PSD100, RUB, v[:1], sigma0_Pa=50e6)
    hi = mu_isothermal(PSD100, RUB, v[:1], sigma0_Pa=100e6)
    assert hi.P_at(100.0)[0] > 0.95 and hi.mu[0] / lo.mu[0] == pytest.approx(0.5, rel=0.03)
    lo = mu_isothermal(PSD100, RUB, v, sigma0_Pa=0.2e6)
    hi = mu_isothermal(PSD100, RUB, v, sigma0_Pa=0.4e6)
    # intermediate P: mu falls, but by less than 1/sigma0
    assert 0.5 < hi.mu[0] / lo.mu[0] < 1.0
    # P << 1 at high speed: P ~ sigma0 compensates, mu nearly independent of sigma0
    assert lo.P_at(100.0)[1] < 1e-3
    assert 0.9 < hi.mu[1] / lo.mu[1] < 1.1


def test_P_decreasing_in_q_and_G_increasing():
    res = mu_isothermal(PSD100, RUB, np.logspace(-8, 4, 25))
    assert np.all(np.diff(res.P, axis=1) <= 1e-15)
    assert np.all(np.diff(res.G, axis=1) >= 0)
    assert np.all(res.P[:, 0] == 1.0) and np.all((res.P > 0) & (res.P <= 1))


def test_contact_gamma_option():
    v = np.logspace(-4, 2, 7)
    base = mu_isothermal(PSD100, RUB, v).mu
    np.testing.assert_allclose(mu_isothermal(PSD100, RUB, v, contact_gamma=1.0).mu, base, rtol=1e-12)
    g = mu_isothermal(PSD100, RUB, v, contact_gamma=0.6).mu
    assert np.all(g < base) and np.all(g > 0.6 * base)


def test_background_temperature_shifts_speed_axis():
    v = np.logspace(-6, 2, 9)
    T0 = 80.0
    a = 10 ** (RUB.shift.log10_aT(T0) - RUB.shift.log10_aT(RUB.T_ref_C))
    hot = mu_isothermal(PSD100, RUB, v, T0_C=T0).mu
    ref = mu_isothermal(PSD100, RUB, v * a).mu
    np.testing.assert_allclose(hot, ref, rtol=1e-9)
    assert a < 1


def test_flash_heats_and_lowers_friction():
    psd = SelfAffinePSD(0.8, 6.67e-4, 1500.0, 6e5)
    v = np.logspace(-6, 2, 17)
    fl = mu_flash(psd, RUB, v, sigma0_Pa=0.4e6)
    iso = mu_isothermal(psd, RUB, v, sigma0_Pa=0.4e6)
    assert np.all(fl.T_q_C >= 60.0)
    assert np.all(fl.mu <= iso.mu * (1 + 1e-4))
    assert fl.peak[0] < 0.5 * iso.peak[0]
    # negligible heating at low speed: the two models agree
    assert fl.mu[0] == pytest.approx(iso.mu[0], rel=1e-3)
    with pytest.raises(RuntimeError, match="converge"):
        mu_flash(psd, RUB, v, sigma0_Pa=0.4e6, max_iter=3)


def test_rubber_models_sign_and_limits():
    w = np.logspace(-3, 12, 50)
    sls = StandardLinearSolid()
    for r in (sls, sls.as_prony()):
        E = r.modulus(w)
        assert np.all(E.imag > 0)
    np.testing.assert_allclose(sls.as_prony().modulus(w), sls.modulus(w), rtol=1e-12)
    assert sls.modulus(0.0).real == pytest.approx(1e9 / 1001)
    assert sls.modulus(1e15).real == pytest.approx(1e9, rel=1e-6)
    # temperature: the thesis WLF, aT(60 C) = 10^-2.504, relative to T_ref
    assert RUB.shift.log10_aT(60.0) == pytest.approx(-8.86 * 40 / 141.5)
    np.testing.assert_allclose(RUB.modulus(w, 60.0), RUB.modulus(w))
    a = 10 ** (RUB.shift.log10_aT(100.0) - RUB.shift.log10_aT(60.0))
    np.testing.assert_allclose(RUB.modulus(w, 100.0), RUB.modulus_ref(w * a))


def test_master_curve_that_is_a_prony_series_gives_same_mu():
    pr = Prony(1e6, [3e7, 2e8, 5e8], [1e-2, 1e-5, 1e-8], 60.0, WLF.thesis())
    f = np.logspace(-8, 16, 24 * 40 + 1)
    E = pr.modulus(2 * np.pi * f)
    mc = MasterCurve(f, E.real, E.imag, 60.0, WLF.thesis())
    v = np.logspace(-8, 4, 25)
    a = mu_isothermal(PSD100, pr, v).mu
    b = mu_isothermal(PSD100, mc, v).mu
    np.testing.assert_allclose(b, a, rtol=2e-3)
    psd = SelfAffinePSD(0.8, 6.67e-4, 1500.0, 6e5)
    fa = mu_flash(psd, pr, v[::3], sigma0_Pa=0.4e6)
    fb = mu_flash(psd, mc, v[::3], sigma0_Pa=0.4e6)
    np.testing.assert_allclose(fb.mu, fa.mu, rtol=5e-3)


def _pyvisco():
    from pathlib import Path

    from pipelines.settings.rubber_file import load_rubber

    here = Path(__file__).resolve().parents[1] / "sample_scans" / "rubbers"
    return load_rubber(here / "pyvisco_master_table.toml")


def test_real_master_curve_gives_finite_smooth_mu():
    mc = _pyvisco()
    v = np.logspace(-8, 4, 121)
    mu = mu_isothermal(PSD100, mc, v).mu
    assert np.all(np.isfinite(mu)) and np.all(mu > 0)
    d2 = np.diff(np.log(mu), 2)
    assert np.max(np.abs(d2)) < 0.05
    fl = mu_flash(PSD100, mc, v[::6], T0_C=20.0)
    assert np.all(np.isfinite(fl.mu)) and np.all(fl.T_q_C >= 20.0 - 1e-9)


def test_fit_prony_and_wlf_on_real_data():
    mc = _pyvisco()
    pr = fit_prony(mc)
    E = pr.modulus(2 * np.pi * mc.f_Hz)
    # this measured curve is not exactly Kramers-Kronig consistent with a Prony series:
    # the best non-negative fit is within about 16 % (E') and 12 % (E'') in the median
    assert np.all(E.imag > 0)
    assert np.median(np.abs(E.real / mc.E_storage_Pa - 1)) < 0.2
    assert np.median(np.abs(E.imag / mc.E_loss_Pa - 1)) < 0.15
    one = fit_prony(mc, n_terms=2).modulus(2 * np.pi * mc.f_Hz)
    assert np.median(np.abs(one.imag / mc.E_loss_Pa - 1)) > 0.3
    T, la = mc.shift.T_C, mc.shift.log10_aT_values
    w = fit_wlf(T, la)
    assert w.T_s_C == pytest.approx(-5.0) and w.C1 > 0 and w.C2_K > 0
    assert np.sqrt(np.mean((w.log10_aT(T) - la) ** 2)) < 0.6
    # exact recovery from WLF-generated data
    true = WLF(12.0, 80.0, 10.0)
    Tt = np.linspace(-20, 120, 15)
    got = fit_wlf(Tt, true.log10_aT(Tt))
    assert (got.C1, got.C2_K, got.T_s_C) == pytest.approx((12.0, 80.0, 10.0), rel=1e-6)
    st = ShiftTable(Tt, true.log10_aT(Tt))
    assert st.log10_aT(10.0) == pytest.approx(0.0, abs=1e-9)


def test_tabulated_psd_matches_model_and_extends():
    sa = SelfAffinePSD(0.85, 5e-4, 2000.0, 2e5)
    q = np.logspace(np.log10(2000.0), np.log10(2e5), 81)
    tab = TabulatedPSD(q, sa.C(q))
    assert tab.q0_per_m == pytest.approx(2000.0) and tab.tail_exponent == pytest.approx(-3.7, rel=1e-9)
    v = np.logspace(-6, 3, 10)
    np.testing.assert_allclose(mu_isothermal(tab, RUB, v).mu, mu_isothermal(sa, RUB, v).mu, rtol=2e-3)
    ext = tab.with_q1(2e6)
    np.testing.assert_allclose(ext.C([4e5, 1e6]), sa.with_q1(2e6).C([4e5, 1e6]), rtol=1e-9)
    roll = SelfAffinePSD(0.85, 5e-4, 2000.0, 2e5, q_roll_per_m=500.0)
    assert roll.C(1000.0) == roll.C(2000.0) and roll.C(400.0) == 0.0
    assert mu_isothermal(roll, RUB, [1.0]).mu[0] > mu_isothermal(sa, RUB, [1.0]).mu[0] * 0.5


def test_rubber_from_dict():
    r = rubber_from_dict(
        {"model": "sls", "T_ref_C": 60.0, "sls": {"E1_Pa": 1e9, "a1": 1000.0, "tau_s": 1e-3}}
    )
    np.testing.assert_allclose(r.modulus([1.0, 1e6]), RUB.modulus([1.0, 1e6]))
    assert r.shift.log10_aT(60.0) == pytest.approx(RUB.shift.log10_aT(60.0))
    p = rubber_from_dict(
        {
            "model": "prony",
            "prony": {"E_inf_Pa": 1e6, "E_i_Pa": [1e8], "tau_i_s": [1e-4]},
            "shift": {"kind": "none"},
            "thermal": {"rho_kg_m3": 1100.0},
        }
    )
    assert p.shift is None and p.thermal.rho_kg_m3 == 1100.0
    for bad, msg in [
        ({"model": "foo"}, "model"),
        ({"model": "sls", "sls": {"E1": 1}}, "unknown"),
        ({"model": "prony", "prony": {"E_inf_Pa": 1e6, "E_i_Pa": [1.0]}}, "tau_i_s"),
        ({"model": "sls", "sls": {}, "shift": {"kind": "arrhenius"}}, "kind"),
    ]:
        with pytest.raises(ValueError, match=msg):
            rubber_from_dict(bad)


def test_result_plot_and_temperature_at():
    import matplotlib

    matplotlib.use("Agg")
    res = mu_isothermal(PSD100, RUB, np.logspace(-4, 2, 7))
    ax = res.plot()
    assert ax.get_xscale() == "log" and "[m/s]" in ax.get_xlabel()
    with pytest.raises(ValueError):
        res.temperature_at(1.0)
