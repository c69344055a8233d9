"""friction.wet and roadscan.sealing against analytic limits and independent constructions."""

import itertools

import numpy as np
import pytest

import friction
from friction.contact import contact_P
from friction.wet.gap import J_function, contact_pressure, mean_separation
from friction.wet.model import wet_friction
from friction.wet.sealing import sealing_wave_vector
from friction.wet.squeeze import flow_factor, squeeze_film, stefan_time
from friction.wet.water import WetConditions, water_viscosity_Pa_s
from roadscan.heightmap import HeightMap
from roadscan.sealing import seal_pools


@pytest.mark.parametrize("T, eta_mPa_s", [(0, 1.7914), (20, 1.0016), (40, 0.6527), (80, 0.3544)])
def test_viscosity_against_iapws_2008(T, eta_mPa_s):
    assert water_viscosity_Pa_s(T) * 1e3 == pytest.approx(eta_mPa_s, rel=0.01)


def test_squeeze_of_a_rigid_flat_disk_is_stefans():
    t = np.array([1e-6, 1e-4, 1e-2, 1.0])
    h = squeeze_film(1e-3, t, p0_Pa=2e5, eta_Pa_s=1e-3, R_m=0.014, u_table=None, p_table=None)
    # closed form: t = 3 eta R^2 / (4 p) (1/h^2 - 1/h0^2)
    assert np.allclose(stefan_time(h, 1e-3, 2e5, 1e-3, 0.014), t, rtol=2e-3)
    assert np.all(np.diff(h) < 0)


def test_flow_factor_two_phase_bruggeman():
    assert flow_factor(0.0) == pytest.approx(1.0)
    assert flow_factor(0.5) == 0.0 and flow_factor(0.7) == 0.0
    c = 0.2  # s_e = (1 - 2c) s_open and s_open = (u / (1 - c))^3: solve Bruggeman's equation
    se = (1 - 2 * c) / (1 - c) ** 3
    so = 1 / (1 - c) ** 3
    assert c * (-1) + (1 - c) * (so - se) / (so + se) == pytest.approx(0.0, abs=1e-12)
    assert flow_factor(c) == pytest.approx(se)


def test_full_contact_squeezes_without_a_floating_point_warning():
    """A very smooth band is in full contact at p0 (u(p0) = 0, contact fraction 1): the film
    squeezes to the dry separation without a divide-by-zero (found by the long fuzz run)."""
    u_tab, p_tab = np.array([1e-3, 1e-5, 0.0]), np.array([1e3, 1e5, 1e6])
    with np.errstate(all="raise"):
        assert flow_factor(1.0) == 0.0
        u = squeeze_film(
            1e-4, 1e-3, p0_Pa=2e5, eta_Pa_s=1e-3, R_m=0.014, u_table=u_tab, p_table=p_tab, contact_area=1.0
        )
    assert 0.0 <= float(u) < 1e-4


def test_J_small_argument_slope_is_gamma():
    y = np.array([1e-9, 1e-8])
    J = J_function(y, 0.4)
    assert (J[0] - J[1]) / np.log(10) == pytest.approx(0.4, rel=1e-3)
    assert J_function(10.0) == 0.0


def _elastic_case():
    psd = friction.SelfAffinePSD(0.8, 3e-4, 300, 3e4, q_roll_per_m=100)
    rub = friction.StandardLinearSolid(E1_Pa=1e7, a1=1.0, tau_s=1e-3, T_ref_C=20.0)
    return psd, rub


def test_separation_is_logarithmic_at_small_pressure_and_inverts():
    psd, rub = _elastic_case()
    r = friction.mu_isothermal(psd, rub, [1e-9])
    q, C = r.q_per_m, psd.C(r.q_per_m)
    p = 2e5 * np.logspace(-10, 0, 41)
    u = mean_separation(q, C, r.G, 2e5, p)[0]
    assert np.all(np.diff(u) < 0)
    # Persson: du/d ln p -> -sqrt(pi) gamma int q^2 C w dq as p -> 0 (independent quadrature)
    qq = np.geomspace(q[0], q[-1], 200001)
    f3 = qq**3 * psd.C(qq)
    I3 = np.concatenate([[0], np.cumsum(0.5 * np.diff(qq) * (f3[1:] + f3[:-1]))])
    w = np.where(I3 > 0, 1 / np.sqrt(np.pi * np.maximum(I3, 1e-300)), 0)
    slope = np.sqrt(np.pi) * 0.4 * np.trapezoid(qq**2 * psd.C(qq) * w, qq)
    assert -(u[1] - u[0]) / np.log(p[1] / p[0]) == pytest.approx(slope, rel=0.03)
    assert contact_pressure(u[20], u, p) == pytest.approx(p[20], rel=1e-6)


def test_sealing_wave_vector_against_the_elastic_contact_area():
    psd, rub = _elastic_case()
    r = friction.mu_isothermal(psd, rub, [1e-9])  # relaxed: E = E1 / (1 + a1)
    E_star = 1e7 / 2 / (1 - 0.25)
    qc = sealing_wave_vector(r.q_per_m, r.P[0], 0.42)
    qq = np.geomspace(100, 3e4, 400001)
    f3 = qq**3 * psd.C(qq)
    I3 = np.concatenate([[0], np.cumsum(0.5 * np.diff(qq) * (f3[1:] + f3[:-1]))])
    P = contact_P(np.pi / 4 * (E_star / 2e5) ** 2 * I3)
    assert qc == pytest.approx(qq[np.argmax(P <= 0.42)], rel=0.02)


def test_pools_whose_places_are_known():
    h = np.zeros((100, 100))
    h[20:30, 20:30] = -1e-3  # closed pit
    h[60:70, 50:65] = -2e-3  # closed, deeper
    h[0:10, 80:90] = -1e-3  # touches the border: open
    hm = HeightMap(h, 1e-4, 1e-4)
    s = seal_pools(hm, q_seal_per_m=1e9, contact_fraction=0.42)
    assert s.pool_count == 2
    assert s.sealed_fraction == pytest.approx(250 / 1e4)
    assert s.volume_m3_per_m2 == pytest.approx((100 * 1e-3 + 150 * 2e-3) / 1e4)
    assert np.all(s.wet.heights_m[20:30, 20:30] == 0) and np.all(s.wet.heights_m[0:10, 80:90] == -1e-3)
    inside = seal_pools(hm, q_seal_per_m=1e9, contact_fraction=0.42, open_border=False)
    assert inside.pool_count == 3 and np.all(inside.wet.heights_m[0:10, 80:90] == 0)  # inside a footprint
    assert inside.volume_m3_per_m2 == pytest.approx((200 * 1e-3 + 150 * 2e-3) / 1e4)
    lim = seal_pools(hm, q_seal_per_m=1e9, contact_fraction=0.42, water_film_m=1e-5)
    assert lim.volume_m3_per_m2 == pytest.approx(1e-5, rel=1e-6)
    assert lim.level_m == pytest.approx(-2e-3 + 1e-5 * 1e4 / 150, rel=1e-6)


def _wet(psd, rub, v, **cond):
    dry = friction.mu_isothermal(psd, rub, v)
    eng = lambda p, vv, s: friction.mu_isothermal(p, rub, vv, sigma0_Pa=s)  # noqa: E731
    return wet_friction(dry=dry, psd=psd, engine=eng, sigma0_Pa=2e5, conditions=WetConditions(**cond))


def _measured_rubber():
    from pipelines.settings.rubber_file import load_rubber

    return load_rubber("sample_scans/rubbers/pyvisco_master_wlf.toml")


def test_more_or_colder_water_never_more_grip_and_falls_with_speed():
    rub = _measured_rubber()
    psd = friction.SelfAffinePSD(0.8, 8e-6, 314, 2e4, q_roll_per_m=150)  # a polished road: films matter
    v = np.concatenate([[1e-3], np.linspace(20, 100, 9) / 3.6])
    runs = {d: _wet(psd, rub, v, water_depth_m=d) for d in (0.1e-3, 0.5e-3, 2e-3, 4e-3)}
    mus = [runs[d].mu_wet for d in sorted(runs)]
    for a, b in itertools.pairwise(mus):
        assert np.all(b <= a * (1 + 1e-9))
    assert mus[-1][-1] < 0.9 * runs[4e-3].mu_dry[-1]  # the film left bites at 100 km/h
    assert runs[4e-3].contact_lost_v_m_per_s is None
    cold, warm = (_wet(psd, rub, v, water_depth_m=0.5e-3, water_temperature_C=T) for T in (2.0, 30.0))
    hi = v > 10
    assert np.all(cold.mu_wet[hi] <= warm.mu_wet[hi] * (1 + 1e-9))
    assert np.any(cold.mu_wet[hi] < 0.9 * warm.mu_wet[hi])
    base = runs[0.5e-3].mu_wet[1:]
    assert np.all(np.diff(base) < 0)  # falls over 20-100 km/h
    sh = runs[4e-3].shares
    d = runs[4e-3].mu_dry - runs[4e-3].mu_wet
    ok = d > 0
    assert np.allclose((sh["sealing"] + sh["squeeze_out"] + sh["adhesion"])[ok], 1.0)


def test_horne_dreher_speed_in_their_units_and_ours():
    from friction.wet.inertia import horne_dreher_speed, implied_lift_coefficient

    knot, psi = 1852.0 / 3600.0, 6894.757  # m/s and Pa
    assert horne_dreher_speed(30 * psi) == pytest.approx(9 * np.sqrt(30) * knot, rel=1e-12)
    assert horne_dreher_speed(200e3) * 3.6 == pytest.approx(6.35 * np.sqrt(200), rel=5e-4)
    # dynamic pressure 1/2 rho v^2 C_L = p: one lift coefficient at every pressure
    assert implied_lift_coefficient(100e3) == pytest.approx(implied_lift_coefficient(400e3), rel=1e-12)


def test_dynamic_lift_is_horne_dreher_where_water_cannot_drain():
    from friction.wet.inertia import dynamic_lift_share, horne_dreher_speed

    vp = float(horne_dreher_speed(2e5))
    v = vp * np.array([0.2, 0.5, 0.9, 1.0, 1.3])
    undrained = dynamic_lift_share(v, p_Pa=2e5, front_time_s=np.inf, footprint_m=0.12)
    assert np.allclose(undrained, np.minimum(1.0, (v / vp) ** 2), rtol=1e-12)
    assert undrained[3] == 1.0 and undrained[2] < 1.0  # lifted at v_p, not before
    assert np.all(dynamic_lift_share(v, p_Pa=2e5, front_time_s=0.0, footprint_m=0.12) == 0)
    part = dynamic_lift_share(v, p_Pa=2e5, front_time_s=1e-3, footprint_m=0.12)  # front zone v t_1 / L
    assert np.allclose(part, np.minimum(1, v * 1e-3 / 0.12) * np.minimum(1, (v / vp) ** 2))


def test_squeeze_time_inverts_the_film_and_is_stefans_for_a_flat_disk():
    from friction.wet.squeeze import squeeze_time

    kw = dict(p0_Pa=2e5, eta_Pa_s=1e-3, R_m=0.014, u_table=None, p_table=None)
    t_stefan = stefan_time(2e-5, 1e-3, 2e5, 1e-3, 0.014)
    assert squeeze_time(1e-3, 2e-5, **kw) == pytest.approx(t_stefan, rel=2e-3)
    t = squeeze_time(1e-3, 3e-5, **kw)
    assert squeeze_film(1e-3, t, **kw)[()] == pytest.approx(3e-5, rel=2e-3)
    assert squeeze_time(1e-4, 2e-4, **kw) == 0.0


def test_in_the_model_undrained_water_lifts_the_tyre_at_horne_dreher_speed():
    # a smooth tyre (one 0.15 m block: no grooves to drain to) on a polished road, 5 mm of water
    from friction.wet.inertia import horne_dreher_speed

    rub = _measured_rubber()
    psd = friction.SelfAffinePSD(0.8, 8e-6, 314, 2e4, q_roll_per_m=150)
    vp = float(horne_dreher_speed(2e5))
    v = vp * np.array([0.4, 0.8, 0.95, 1.05])
    wf = _wet(psd, rub, v, water_depth_m=5e-3, block_size_m=0.15)
    zone = np.minimum(1, v * wf.meta["front_time_s"] / 0.12)
    assert np.all(zone == 1.0)  # the front zone is the whole footprint
    assert np.allclose(wf.lift_share, np.minimum(1, (v / vp) ** 2), rtol=1e-9)
    assert wf.contact_lost[-1] and wf.contact_lost_v_m_per_s <= v[-1]
