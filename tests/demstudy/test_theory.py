"""The DEM study's theory (viscontact.demstudy.theory) against independent closed forms."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from viscontact import impact
from viscontact.demstudy import theory as th

SIGMA, M, T0, PHI = 1e-3, 2e-6, 3e-9, 0.1
N_DENS = 6 * PHI / (math.pi * SIGMA ** 3)


def test_g2_is_carnahan_starling():
    # g2 = (Z - 1) / (4 phi) with the Carnahan-Starling Z = (1 + phi + phi^2 - phi^3) / (1 - phi)^3
    for phi in (0.01, 0.05, 0.1, 0.3, 0.5):
        z = (1 + phi + phi ** 2 - phi ** 3) / (1 - phi) ** 3
        assert th.enskog_g2(phi) == pytest.approx((z - 1) / (4 * phi), rel=1e-13)
    assert th.enskog_g2(0.0) == 1.0
    with pytest.raises(ValueError, match="phi"):
        th.enskog_g2(1.0)


def test_haff_rate_is_the_energy_loss_per_collision():
    # d(3T/2)/dt = -(omega/2) (1 - e^2) (m/4) <g_n^2>_coll with <g_n^2>_coll = 4 T / m for a
    # Maxwellian (flux-weighted normal relative speed): dT/dt = -(1 - e^2) omega T / 3
    e = 0.8
    tau0 = th.haff_tau0(e, n=N_DENS, sigma=SIGMA, m=M, T0=T0)
    omega = th.collision_frequency(T0, n=N_DENS, sigma=SIGMA, m=M, phi=PHI)
    rate_kinetic = -(1 - e * e) * omega * T0 / 3
    h = tau0 * 1e-6
    rate_haff = (th.haff_temperature(h, T0, tau0) - th.haff_temperature(-h, T0, tau0)) / (2 * h)
    assert rate_haff == pytest.approx(rate_kinetic, rel=1e-8)
    # phi defaults to pi n sigma^3 / 6
    assert th.haff_tau0(e, n=N_DENS, sigma=SIGMA, m=M, T0=T0, phi=PHI) == pytest.approx(tau0)
    assert th.haff_tau0(1.0, n=N_DENS, sigma=SIGMA, m=M, T0=T0) == math.inf


def test_haff_law_solves_the_cooling_equation():
    # dT/dt = -(1 - e^2) omega(T) T / 3 with omega ~ sqrt(T), integrated numerically
    e = 0.9
    tau0 = th.haff_tau0(e, n=N_DENS, sigma=SIGMA, m=M, T0=T0)

    def rhs(_t, y):
        return [-(1 - e * e) * th.collision_frequency(y[0], n=N_DENS, sigma=SIGMA, m=M,
                                                      phi=PHI) * y[0] / 3]

    t = np.linspace(0, 50 * tau0, 40)
    sol = solve_ivp(rhs, (0, t[-1]), [T0], t_eval=t, rtol=1e-11, atol=0)
    assert np.allclose(sol.y[0], th.haff_temperature(t, T0, tau0), rtol=1e-8)


def test_mean_loss_closed_forms():
    # constant e: 1 - e^2; 1 - e^2 = A v^q: A v_T^q Gamma(2 + q/2) (the energy-flux average),
    # to the quadrature's stated 1e-4 (u^(q/2) is not smooth at u = 0)
    assert th.mean_loss(lambda v: np.full_like(v, 0.8), 3.0) == pytest.approx(0.36, rel=1e-13)
    for q in (-0.2, 0.2, 0.6, 1.0):
        A, vt = 0.01, 1.7
        got = th.mean_loss(lambda v, q=q: np.sqrt(1 - A * v ** q), vt)
        assert got == pytest.approx(A * vt ** q * math.gamma(2 + q / 2), rel=1e-4), q
    assert th.mean_loss(lambda v: np.sqrt(1 - 1e-4 * v * v), 1.7) == pytest.approx(
        1e-4 * 1.7 ** 2 * 2, rel=1e-12)  # a loss polynomial in v^2: exact


def test_kinetic_temperature_is_haff_for_constant_e():
    e = 0.8
    tau0 = th.haff_tau0(e, n=N_DENS, sigma=SIGMA, m=M, T0=T0, phi=PHI)
    t = np.concatenate([[0.0], np.logspace(-3, 4, 60)]) * tau0
    T = th.kinetic_temperature(lambda v: np.full_like(v, e), t, T0=T0, n=N_DENS, sigma=SIGMA,
                               m=M, phi=PHI)
    assert np.allclose(T, th.haff_temperature(t, T0, tau0), rtol=1e-9, atol=0)
    # a different e is seen
    T9 = th.kinetic_temperature(lambda v: np.full_like(v, 0.9), t, T0=T0, n=N_DENS,
                                sigma=SIGMA, m=M, phi=PHI)
    assert abs(T9[-1] / T[-1] - 1) > 1


@pytest.mark.parametrize("q", [-0.2, 0.2, 0.6, 1.0])
def test_kinetic_temperature_power_law_closed_form(q):
    # 1 - e^2 = A v^q: dT/dt = -C T^((3+q)/2), T = T0 (1 + t / tau_q)^(-2/(1+q)),
    # C = (4 sqrt(pi)/3) g2 n sigma^2 m^(-1/2) A (2 / sqrt(m))^q Gamma(2 + q/2)
    loss0 = 0.05  # at v_T of T0; the loss must stay below 1 at every node and time
    A = loss0 / (2 * math.sqrt(T0 / M)) ** q
    C = (4 * math.sqrt(math.pi) / 3) * th.enskog_g2(PHI) * N_DENS * SIGMA ** 2 / math.sqrt(M) \
        * A * (2 / math.sqrt(M)) ** q * math.gamma(2 + q / 2)
    tau_q = 2 / ((1 + q) * C * T0 ** ((1 + q) / 2))
    t = np.logspace(-2, 3 if q > 0 else 1.5, 40) * tau_q

    def e_of_v(v):
        loss = A * v ** q
        assert np.all(loss < 1)  # the closed form holds only without clipping
        return np.sqrt(1 - loss)

    T = th.kinetic_temperature(e_of_v, t, T0=T0, n=N_DENS, sigma=SIGMA, m=M, phi=PHI)
    exact = T0 * (1 + t / tau_q) ** (-2 / (1 + q))
    assert np.allclose(T, exact, rtol=1e-4, atol=0)  # the quadrature's accuracy
    if q > 0:  # by 1000 tau_q the local exponent is within 0.3 % of -2 / (1 + q)
        slope, _ = th.log_slope(t, T, t[-1] / 10)
        assert slope == pytest.approx(-2 / (1 + q), rel=5e-3)


def test_kk_gas_approaches_five_thirds():
    # KK's exact e(v) (the solver, not its small-damping series): the local exponent of the
    # kinetic theory leaves Haff's -2 behind and approaches -5/3 as e -> 1 at late times
    from viscontact import alpha_from_e, damping_coefficient, velocity_sweep

    m_eff, k, v0 = 1e-6, 1e6, 500.0  # fast enough for ten decades of speed inside the domain
    c = damping_coefficient("KK", alpha_from_e("KK", 0.8), m_eff=m_eff, k_hertz=k, v=v0)
    speeds = np.geomspace(1e-6, 1e4, 400)
    ln_v = np.log(speeds)
    e = np.asarray(velocity_sweep("KK", speeds, m_eff=m_eff, k_hertz=k, c=c).e)
    assert np.interp(math.log(v0), ln_v, e) == pytest.approx(0.8, abs=1e-6)
    assert e[0] > 0.99  # e -> 1 at low speed

    def e_of_v(v):
        return np.interp(np.log(v), ln_v, e)

    m = 2 * m_eff
    T_0 = m * (v0 / 2) ** 2  # v_T = 2 sqrt(T0 / m) = v0
    tau0 = th.haff_tau0(0.8, n=N_DENS, sigma=SIGMA, m=m, T0=T_0, phi=PHI)
    t = np.logspace(-2, 7, 300) * tau0
    T = th.kinetic_temperature(e_of_v, t, T0=T_0, n=N_DENS, sigma=SIGMA, m=m, phi=PHI)
    slopes = [th.log_slope(t, T, a * tau0, 3 * a * tau0)[0] for a in (1e2, 1e4, 1e6 / 3)]
    assert all(abs(s + 5 / 3) < 0.03 for s in slopes), slopes
    assert abs(slopes[-1] + 5 / 3) < abs(slopes[0] + 5 / 3)  # closer and closer


def test_log_slope():
    t = np.logspace(0, 2, 50)
    assert th.log_slope(t, 3 * t ** -1.7, 10)[0] == pytest.approx(-1.7, rel=1e-12)
    assert math.isnan(th.log_slope(t[:3], t[:3], 0)[0])


def test_late_exponents():
    assert th.late_exponent("Ts") == pytest.approx(-2.0)
    assert th.late_exponent("KK") == pytest.approx(-5.0 / 3.0)
    assert th.late_exponent("Jian") == th.late_exponent("KK")
    assert th.late_exponent("LH") == pytest.approx(-2.5)
    assert th.late_exponent("Hunt") == pytest.approx(-1.0)
    assert th.late_exponent("power", p=0.75) == pytest.approx(-2 / 1.4)
    assert th.q_exponent("Li") == pytest.approx(0.6)


def test_constant_e_sequence_is_geometric():
    # Ts keeps e constant: v_k = v0 e^k, apex v^2 / (2 g), flights summing to 2 v0 e (1 - e^n) / (g (1 - e))
    m, k = 0.1547, 1.688e6
    c = 300.0  # any c: Ts's e does not depend on the speed
    e = impact("Ts", m_eff=m, k_hertz=k, v=1.0, c=c).e
    seq = th.bounce_sequence("Ts", m=m, k_hertz=k, c=c, height=0.15, h_min=1e-6)
    v0 = math.sqrt(2 * 9.81 * 0.15)
    v = seq.column("v_in")
    assert v == pytest.approx(v0 * e ** np.arange(seq.n), rel=1e-8)
    assert seq.column("apex") == pytest.approx(seq.column("v_out") ** 2 / (2 * 9.81))
    assert seq.stopped == "apex" and (v0 * e ** (seq.n + 1)) ** 2 / (2 * 9.81) < 1e-6 <= seq.bounces[-1].apex
    n = seq.n
    flights = seq.column("flight").sum()
    assert flights == pytest.approx(2 * v0 * e * (1 - e ** n) / (9.81 * (1 - e)), rel=1e-10)
    assert flights < th.constant_e_rest_time(e, v0)
    contact = sum(b.tc_overlap for b in seq.bounces)
    assert seq.t_rest == pytest.approx(v0 / 9.81 + flights + contact, rel=1e-12)


def test_elastic_ball_never_rests():
    seq = th.bounce_sequence("KK", m=0.15, k_hertz=1.7e6, c=0.0, height=0.1, n_max=5)
    assert seq.stopped == "n_max" and seq.n == 5
    assert seq.column("apex") == pytest.approx(0.1, rel=1e-9)


def test_series_scaling_is_the_continuum_of_the_recursion():
    # v_{k+1} = v_k (1 - A v_k^q) for small A: the continuum solution within 0.5 %
    for q, A in ((0.2, 2e-3), (0.6, 1e-3), (1.0, 1e-3), (0.0, 1e-3), (-0.2, 1e-3)):
        v = [1.0]
        for _ in range(3000):
            v.append(v[-1] * (1 - A * v[-1] ** q))
        k = np.arange(0, 3001, 300)
        assert th.series_scaling(q, A, 1.0, k) == pytest.approx(np.array(v)[k], rel=5e-3), q


def test_gravity_ratio_scaling():
    r1, r2 = th.gravity_ratio(np.array([1.0, 0.1]), m=0.15, k_hertz=1.7e6)
    assert r2 / r1 == pytest.approx(10 ** 1.2, rel=1e-12)


def test_bad_input():
    with pytest.raises(ValueError, match="exactly one"):
        th.bounce_sequence("KK", m=0.1, k_hertz=1e6, c=1.0)
    with pytest.raises(ValueError, match="restitution"):
        th.haff_tau0(1.2, n=1.0, sigma=1.0, m=1.0, T0=1.0)


def _collapse_study(law_eff, seed_eff, noise, rng):
    from dataclasses import replace

    from viscontact.demstudy.flow import CollapseRun, FlowStudy, QUICK_FLOW

    setup = replace(QUICK_FLOW, seeds=tuple(seed_eff), compare=2.0)
    runs = [CollapseRun(m, s, 1.0, 2.0, 2.0 + law_eff[m] + seed_eff[s] + noise * rng.normal(),
                        20.0, 0.3, None, aspect=2.0) for m in law_eff for s in seed_eff]
    return FlowStudy(setup, runs)


def test_law_differences_cover_and_detect():
    # each law's difference from KK over the same seeds: the 95 % interval covers the true
    # difference in about 95 % of repetitions whatever the seed effects, and a true difference
    # equal to the stated smallest detectable one is found (interval excludes 0) in about 80 %
    rng = np.random.default_rng(3)
    seeds = {1: 0.0, 2: 0.7, 3: -0.4, 4: 1.1}
    law_eff = {"LH": 0.3, "Ts": -0.2, "KK": 0.0}
    cover, trials = 0, 600
    for _ in range(trials):
        diffs, mdd = _collapse_study(law_eff, seeds, 0.05, rng).law_differences("runout")
        d = {x.model: x for x in diffs}
        cover += abs(d["LH"].diff - 0.3) <= d["LH"].half95
        assert set(d) == {"LH", "Ts"} and mdd > d["LH"].half95
    assert 0.92 < cover / trials < 0.98
    # the detectable difference: calibrate on one draw of the noise level, then test power
    _, mdd = _collapse_study({"LH": 0, "Ts": 0, "KK": 0}, seeds, 0.05, rng).law_differences(
        "runout")
    # mdd from one draw scatters; use the expected one: (t975 + t80) sqrt(2 s^2 / b)
    from scipy.stats import t as tdist

    nu = 2 * 3
    se = math.sqrt(2 * 0.05 ** 2 / 4)
    mdd = (tdist.ppf(0.975, nu) + tdist.ppf(0.8, nu)) * se
    found = 0
    for _ in range(trials):
        diffs, _ = _collapse_study({"LH": mdd, "Ts": 0.0, "KK": 0.0}, seeds, 0.05,
                                   rng).law_differences("runout")
        d = next(x for x in diffs if x.model == "LH")
        found += abs(d.diff) > d.half95
    assert 0.70 < found / trials < 0.90  # 80 % power (a t-based power is approximate)
    # too few seeds: NaN, no crash
    diffs, mdd = _collapse_study(law_eff, {1: 0.0}, 0.05, rng).law_differences("runout")
    assert math.isnan(mdd) and all(math.isnan(x.diff) for x in diffs)


def test_rest_time_interpolates_between_samples():
    # kinetic energy decaying exponentially, sampled every 5 ms: interpolation in ln KE finds
    # the crossing of the threshold exactly, far finer than the sampling
    from viscontact.demstudy.flow import rest_time

    t = np.arange(0.0, 0.5, 5e-3)
    ke = np.exp(-t / 0.03)
    thr = math.exp(-0.2321 / 0.03)
    assert rest_time(t, ke, thr, 0.1) == pytest.approx(0.2321, rel=1e-12)
    # a threshold never reached: the last sample; a rise before t_min is ignored
    assert rest_time(t, ke, 1e-30, 0.1) == t[-1]
    ke2 = ke.copy()
    ke2[2] = 1e-40
    assert rest_time(t, ke2, thr, 0.1) == pytest.approx(0.2321, rel=1e-12)


def test_a2_of_the_homogeneous_cooling_state():
    # zeros at e = 1 and e = 1/sqrt(2), negative between, positive below; the 3D closed form
    # 16 (1 - e)(1 - 2 e^2) / (81 - 17 e + 30 e^2 (1 - e)) (Brilliantov & Poschel, eq. 7.5)
    assert th.a2_homogeneous_cooling(1.0) == 0.0
    assert th.a2_homogeneous_cooling(1 / math.sqrt(2)) == pytest.approx(0.0, abs=1e-15)
    for e in (0.3, 0.5, 0.8, 0.95):
        ref = 16 * (1 - e) * (1 - 2 * e * e) / (81 - 17 * e + 30 * e * e * (1 - e))
        assert th.a2_homogeneous_cooling(e) == pytest.approx(ref, rel=1e-13)
    assert th.a2_homogeneous_cooling(0.8) == pytest.approx(-0.01258, abs=1e-5)
    assert th.a2_homogeneous_cooling(0.5) > 0 > th.a2_homogeneous_cooling(0.9)
    with pytest.raises(ValueError, match="restitution"):
        th.a2_homogeneous_cooling(1.2)


def test_sonine_a2_measures_the_fourth_moment():
    # a Maxwellian sample: a2 = 0 within its noise (sd about sqrt(8 / (15 N)) ... measured);
    # all speeds equal (directions random): <v^4> = <v^2>^2, a2 = 3/5 - 1 = -0.4
    rng = np.random.default_rng(5)
    v = rng.normal(size=(200000, 3))
    assert th.sonine_a2(v) == pytest.approx(0.0, abs=0.01)
    u = v / np.linalg.norm(v, axis=1, keepdims=True) * 2.5
    assert th.sonine_a2(u) == pytest.approx(-0.4, rel=1e-12)


def test_ideal_gas_band_matches_multinomial_counts():
    # n points in M cells: E[var/mean of counts] (population variance) = 1 - 1/M exactly; the
    # flow ratio of independent velocities is about 1; a2 of a Maxwellian about 0
    from viscontact.demstudy.gas import ideal_gas_band

    band = ideal_gas_band(2000, 6, draws=300)
    assert band["density"][1] == pytest.approx(1 - 1 / 216, abs=0.03)
    lo, _, hi = band["density"]
    # the 95 % band of a var/mean over 216 cells: about +- 1.96 sqrt(2 / 215)
    assert hi - lo == pytest.approx(2 * 1.96 * math.sqrt(2 / 215), rel=0.2)
    assert band["flow"][0] < 1 < band["flow"][2]
    assert band["a2"][0] < 0 < band["a2"][2]


def test_shear_instability_length_balances_viscosity_and_cooling():
    # nu k^2 = zeta / 2 at k = 2 pi / L_c with nu = eta / (n m), eta = 5/(16 sigma^2)
    # sqrt(m T / pi), zeta = -d ln T / dt of Haff's law at t = 0 (2 / tau0)
    e = 0.8
    L = th.shear_instability_length(e, n=N_DENS, sigma=SIGMA, phi=PHI)
    eta = 5 / (16 * SIGMA ** 2) * math.sqrt(M * T0 / math.pi)
    nu = eta / (N_DENS * M)
    zeta = 2 / th.haff_tau0(e, n=N_DENS, sigma=SIGMA, m=M, T0=T0, phi=PHI)
    assert nu * (2 * math.pi / L) ** 2 == pytest.approx(zeta / 2, rel=1e-12)
    # more inelastic: unstable in smaller boxes
    assert th.shear_instability_length(0.5, n=N_DENS, sigma=SIGMA) < L
    with pytest.raises(ValueError, match="restitution"):
        th.shear_instability_length(1.0, n=N_DENS, sigma=SIGMA)


def test_published_collapse_scaling():
    # Lube et al. 2005 branches at their stated values
    assert th.collapse_runout([1.0, 2.0]) == pytest.approx([1.2, 2.4])
    assert th.collapse_runout(8.0) == pytest.approx(1.9 * 4.0)
    assert th.collapse_height([0.5, 1.0]) == pytest.approx([0.5, 1.0])
    assert th.collapse_height(32.0) == pytest.approx(32.0 ** 0.4)


def test_series_local_exponent_and_asymptote():
    from viscontact.demstudy.figures import asymptote_reached, series_local_exponent

    k = np.arange(1, 40)
    v = 3.0 * k ** -5.0
    kk, s = series_local_exponent(v)
    assert s == pytest.approx(np.full(len(kk), -5.0), rel=1e-12)
    assert asymptote_reached("KK", v)  # q = 1/5: -1/q = -5
    assert not asymptote_reached("KK", 3.0 * k ** -3.0)
    assert not asymptote_reached("Ts", v)  # no power law for a constant e
