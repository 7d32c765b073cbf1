"""Physical units: effective properties, T, the alpha <-> c map, impact() in SI
(docs/reproduce.md, "Calibrating a particle in physical units")."""

import math

import pytest

import viscontact as vc
from viscontact.physics.pair import contact_pair, damping_unit

# the indoor lacrosse ball (the paper's Table 4, docs/reproduce.md)
M, K, V = 0.1547, 1.688e6, 1.716
T_UNDAMPED = 3.2180654597  # Hertz contact time / T of the undamped contact
X_MAX = 1.0933620739  # Hertz maximum overlap / (T v)


def test_time_scale_by_hand():
    # T = (m^2 / (k^2 v))^(1/5): 0.1547^2 = 0.02393209; 1.688e6^2 * 1.716 = 4.889474e12;
    # ratio 4.894614e-15; fifth root 1.373864e-3 s
    assert vc.time_scale(M, K, V) == pytest.approx(1.373864e-3, rel=1e-6)
    assert vc.time_scale(M, K, V) == pytest.approx(
        math.exp((2 * math.log(M) - 2 * math.log(K) - math.log(V)) / 5), rel=1e-14)


def test_hertz_stiffness_by_hand():
    # rubber-like sphere (E = 10 MPa, nu = 0.5, R = 31.75 mm) on a rigid wall:
    # E* = 1e7 / 0.75 = 1.3333e7 Pa, k = 4/3 * 1.3333e7 * sqrt(0.03175) = 3.16773e6 N/m^1.5
    e_eff = vc.effective_modulus(1e7, 0.5)
    assert e_eff == pytest.approx(1e7 / 0.75, rel=1e-14)
    assert vc.hertz_stiffness(e_eff, 0.03175) == pytest.approx(3.16773e6, rel=1e-5)


def test_two_identical_spheres():
    m, r, e, nu = 0.2, 0.01, 2e8, 0.3
    pair = contact_pair(m, radius=r, modulus=e, poisson=nu, mass2=m, radius2=r, modulus2=e,
                        poisson2=nu)
    assert pair.m_eff == pytest.approx(m / 2)
    assert pair.r_eff == pytest.approx(r / 2)
    assert pair.e_eff == pytest.approx(e / (2 * (1 - nu**2)))
    assert pair.k_hertz == pytest.approx(4 / 3 * e / (2 * (1 - nu**2)) * math.sqrt(r / 2))


def test_elastic_wall_softens_the_contact():
    rigid = contact_pair(0.1, radius=0.02, modulus=1e7, poisson=0.4)
    soft = contact_pair(0.1, radius=0.02, modulus=1e7, poisson=0.4, modulus2=1e7, poisson2=0.4)
    assert soft.k_hertz == pytest.approx(rigid.k_hertz / 2)


@pytest.mark.parametrize("model,closed_form", [
    ("LH", lambda a, T: a * M / T),  # c = gamma m*, gamma = alpha / T
    ("Ts", lambda a, T: a * math.sqrt(M * K)),
    ("KK", lambda a, T: a * K * T),
    ("Li", lambda a, T: a * K**2 * T**3 / M),
    ("Hunt", lambda a, T: a * K / V),  # lambda = alpha k_Hertz / v
    ("Jian", lambda a, T: a * K * T),
])
def test_damping_coefficient_closed_forms(model, closed_form):
    T = vc.time_scale(M, K, V)
    c = vc.damping_coefficient(model, 0.37, m_eff=M, k_hertz=K, v=V)
    assert c == pytest.approx(closed_form(0.37, T), rel=1e-12)


@pytest.mark.parametrize("model", ["LH", "Ts", "KK", "Li", "Hunt", "Jian", "power"])
@pytest.mark.parametrize("v", [0.3, 1.716, 5.0])
def test_alpha_c_round_trip(model, v):
    p = 0.7 if model == "power" else None
    tau = 2.5e-4 if model == "Jian" else None
    for alpha in (0.0, 0.05, 1.3, 20.0):
        c = vc.damping_coefficient(model, alpha, m_eff=M, k_hertz=K, v=v, p=p)
        a2, beta = vc.damping_constants(model, c, m_eff=M, k_hertz=K, v=v, tau=tau, p=p)
        assert a2 == pytest.approx(alpha, rel=1e-13, abs=1e-15)
        if model == "Jian":
            assert beta == pytest.approx(tau / vc.time_scale(M, K, v), rel=1e-14)
        else:
            assert beta is None


def test_damping_units():
    assert damping_unit(0) == "kg/s"
    assert damping_unit(0.5) == "N s/m^1.5"
    assert damping_unit(1.5) == "N s/m^2.5"


def test_undamped_impact_matches_hertz_closed_form():
    r = vc.impact("KK", m_eff=M, k_hertz=K, v=V, c=0.0)
    T = vc.time_scale(M, K, V)
    assert r.e == pytest.approx(1.0, abs=1e-9)
    assert r.tc == pytest.approx(T_UNDAMPED * T, rel=1e-8)
    # Hertz: delta_max = (5 m v^2 / (4 k))^(2/5), independent of T
    assert r.dmax == pytest.approx((5 * M * V**2 / (4 * K)) ** 0.4, rel=1e-8)
    assert r.dmax == pytest.approx(X_MAX * T * V, rel=1e-8)
    # peak force = k delta_max^(3/2) when undamped
    assert r.fmax == pytest.approx(K * r.dmax**1.5, rel=1e-7)


@pytest.mark.parametrize("model", ["LH", "Ts", "KK", "Li", "Hunt", "Jian"])
def test_impact_scales_the_nondimensional_result(model):
    T = vc.time_scale(M, K, V)
    beta = 0.5 if model == "Jian" else None
    c = vc.damping_coefficient(model, 0.3, m_eff=M, k_hertz=K, v=V)
    r = vc.impact(model, m_eff=M, k_hertz=K, v=V, c=c, tau=None if beta is None else beta * T)
    nd = vc.collide(model, 0.3, beta=beta)
    assert r.alpha == pytest.approx(0.3, rel=1e-13)
    assert r.e == pytest.approx(nd.e, rel=1e-12)
    assert r.tc == pytest.approx(nd.tc * T, rel=1e-12)
    assert r.fmax == pytest.approx(nd.fmax * M * V / T, rel=1e-12)
    assert r.dmax == pytest.approx(nd.xmax * T * V, rel=1e-12)
    # energy balance in joules: 1/2 m v^2 (1 - e^2) = damping work + elastic energy left
    left = 0.4 * K * r.residual**2.5
    assert 0.5 * M * V**2 * (1 - r.e**2) == pytest.approx(r.dissipated + left, rel=1e-8)
    assert r.t[-1] == pytest.approx(r.tc) and r.force.size == r.delta.size


def test_drop_speed():
    assert vc.drop_speed(0.15) == pytest.approx(1.7155, abs=1e-4)  # the study's 171.6 cm/s


@pytest.mark.parametrize("call", [
    lambda: vc.time_scale(-1, K, V),
    lambda: vc.time_scale(M, 0, V),
    lambda: vc.time_scale(M, K, 0),
    lambda: vc.time_scale(M, K, float("nan")),
    lambda: vc.effective_mass(0.1, 0),
    lambda: vc.effective_radius(-0.01),
    lambda: vc.effective_modulus(0, 0.3),
    lambda: vc.effective_modulus(1e6, 0.6),
    lambda: vc.effective_modulus(1e6, -1.0),
    lambda: vc.effective_modulus(1e6, float("nan")),
    lambda: vc.hertz_stiffness(1e6, 0),
    lambda: vc.drop_speed(-0.1),
    lambda: vc.damping_coefficient("KK", -0.1, m_eff=M, k_hertz=K, v=V),
    lambda: vc.damping_coefficient("nope", 0.1, m_eff=M, k_hertz=K, v=V),
    lambda: vc.damping_constants("Jian", 100.0, m_eff=M, k_hertz=K, v=V),
    lambda: vc.damping_constants("KK", 100.0, m_eff=M, k_hertz=K, v=V, tau=1e-3),
    lambda: vc.impact("KK", m_eff=M, k_hertz=K, v=-1, c=1.0),
    lambda: contact_pair(0.1, modulus=1e7, poisson=0.3),  # no radius
    lambda: contact_pair(0.1, radius=0.01),  # neither k nor E, nu
    lambda: contact_pair(0.1, radius=0.01, k_hertz=1e6, modulus=1e7),
])
def test_bad_input_is_a_value_error(call):
    with pytest.raises(ValueError):
        call()


def test_poisson_range_is_half_open():
    assert vc.effective_modulus(1e6, 0.5) == pytest.approx(1e6 / 0.75)
    assert vc.effective_modulus(1e6, -0.99) > 0


def test_hertz_limit_closed_form_matches_the_solver():
    from viscontact.physics.pair import HERTZ_TC, HERTZ_XMAX, hertz_limit

    assert HERTZ_TC == pytest.approx(T_UNDAMPED, abs=1e-10)
    assert HERTZ_XMAX == pytest.approx(X_MAX, abs=1e-10)
    tc, dmax, fmax = hertz_limit(M, K, 0.8)
    r = vc.impact("LH", m_eff=M, k_hertz=K, v=0.8, c=0.0)
    assert (r.tc, r.dmax, r.fmax) == pytest.approx((tc, dmax, fmax), rel=1e-7)
