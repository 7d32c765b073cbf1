"""DEM inside LAMMPS (pair viscontact, fix viscontact/wall) against the exact single collision.

Every collision is set up as a user would: ``viscontact.dem.contact_law`` and
``viscontact.dem.coeff_lines`` give the ``pair_coeff * *`` line and the
``fix vcwall all viscontact/wall zplane 0.0 NULL ...`` line pasted unchanged into the input
(``scripts/dem_collide.py`` runs and measures; it knows nothing of the force law).

1. Every law, clamp on (``end force``) and off (``end overlap``), two equal spheres head-on and
   a sphere on a wall, three speeds (0.5, 1, 2 x vref): DEM e, t_c, F_max against
   ``viscontact.impact`` with the same m*, k_Hertz, c0, tau (computed in Python from the law's
   closed form, docs/pair_viscontact.md) within 1e-3 relative at dt = t_c / 1000 (t_c the
   exact contact time), at four phases of the contact start on the step grid; and the order of convergence,
   regression of log|error| on log dt over dt = t_c/50, t_c/100, t_c/200, at least 0.9 (the
   scheme is first order: LAMMPS's velocity Verlet evaluates the damping force with the
   half-step velocity).  For the order the start and the exact end of the contact fall at
   mid-step at every dt: a law whose force jumps where the contact begins or ends (LH; Ts
   steeply) has an O(dt) error that depends on those phases, which would otherwise scatter the
   regression (its size at dt = t_c/1000 is covered by the four phases of test 1).
2. Chung & Ooi (2011) tests 1-4 (Y.C. Chung and J.Y. Ooi, Granular Matter 13 (2011) 643).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from dem_util import needs_lammps

pytestmark = needs_lammps

import viscontact as vc  # noqa: E402
from viscontact import dem  # noqa: E402

import dem_collide as dc  # noqa: E402  (scripts/dem_collide.py, shared with scripts/dem_exact_table.py)
from dem_collide import (  # noqa: E402  the cases, the same in the table script
    ALOX, ANGLES, CASES, E4, ELASTIC, LAWS, MAT, MU, R4, RADIUS, SPEEDS, V4, law_for,
)

TOL = 1e-3
MIN_ORDER = 0.9


def errors(setup: dc.Setup) -> np.ndarray:
    """Relative errors (e, t_c, F_max) of every shot of the setup against the exact solver."""
    out = []
    for m in dc.run(setup):
        ex = dc.exact(setup, m.shot)
        assert ex.separated
        out.append([m.e / ex.e - 1, m.tc / ex.tc - 1, m.fmax / ex.fmax - 1])
    return np.array(out)


@pytest.mark.parametrize("name,end", CASES)
def test_dem_matches_exact_at_tc_over_1000(name, end):
    law = law_for(name, end)
    shots = [dc.Shot(g, v, phase=ph) for g in ("pair", "wall") for v in SPEEDS
             for ph in (0.125, 0.375, 0.625, 0.875)]
    setup = dc.Setup(law, MAT, RADIUS, shots, steps_per_tc=1000, exact_grid=True)
    err = np.abs(errors(setup))
    worst = err.max(axis=0)
    assert np.all(worst < TOL), f"{name} end {end}: max |rel err| e, t_c, F_max = {worst}"


@pytest.mark.parametrize("name,end", CASES)
def test_dem_converges_at_least_linearly(name, end):
    law = law_for(name, end)
    levels = (50, 100, 200)
    shots = [dc.Shot(g, v) for g in ("pair", "wall") for v in SPEEDS]
    err = np.array([[errors(dc.Setup(law, MAT, RADIUS, [s], steps_per_tc=n, exact_grid=True))[0]
                     for s in shots] for n in levels])          # level x shot x quantity
    err = np.abs(err)
    assert np.all(err > 1e-12), "an error at rounding level cannot show an order"
    logdt = -np.log(levels)
    order = np.array([[np.polyfit(logdt, np.log(err[:, s, q]), 1)[0] for q in range(3)]
                      for s in range(len(shots))])
    assert np.all(order >= MIN_ORDER), (
        f"{name} end {end}: orders (shot x e, t_c, F_max) =\n{np.round(order, 2)}")


# ---- Chung & Ooi (2011), Granular Matter 13, 643 ----------------------------------------------


def hertz_errors(setup: dc.Setup) -> np.ndarray:
    """Relative errors (delta_max, F_max, t_c) against the elastic Hertz closed forms, and e - 1."""
    out = []
    for m in dc.run(setup):
        tc, dmax, fmax = vc.dimensional.hertz_limit(m.m_eff, m.k_hertz, m.shot.v)
        out.append([m.dmax / dmax - 1, m.fmax / fmax - 1, m.tc / tc - 1, m.e - 1])
    return np.array(out)


@pytest.mark.parametrize("material", [dc.Material(48e9, 0.20, 2800), dc.Material(20e9, 0.25, 2500)],
                         ids=["glass", "limestone"])
def test_chung_ooi_1_two_spheres_elastic(material):
    # R = 10 mm at +-10 m/s; velocity Verlet is second order for the elastic contact: at
    # t_c/1000 delta_max, F_max, t_c within 1e-5 (measured 4e-7 to 7e-7), e = 1 to 1e-9
    err = hertz_errors(dc.Setup(ELASTIC, material, 0.010, [dc.Shot("pair", 20.0)],
                                steps_per_tc=1000))[0]
    assert np.all(np.abs(err[:3]) < 1e-5) and abs(err[3]) < 1e-9, err


@pytest.mark.parametrize("material", [dc.Material(70e9, 0.30, 2699), dc.Material(40e9, 0.35, 1800)],
                         ids=["Al-alloy", "Mg-alloy"])
def test_chung_ooi_2_sphere_on_rigid_plane(material):
    err = hertz_errors(dc.Setup(ELASTIC, material, 0.10, [dc.Shot("wall", 0.2)], wall="rigid",
                                steps_per_tc=1000))[0]
    assert np.all(np.abs(err[:3]) < 1e-5) and abs(err[3]) < 1e-9, err


@pytest.mark.parametrize("material", [dc.Material(380e9, 0.23, 4000),
                                      dc.Material(100e9, 0.25, 7000)], ids=["Al-oxide", "cast-iron"])
@pytest.mark.parametrize("name", list(LAWS))
def test_chung_ooi_3_measured_e_is_input_e(name, material):
    # R = 2.5 mm at 3.9 m/s on a plane of the same material; each law calibrated exactly to
    # e at vref = 3.9 m/s.  |e - e_in| <= 1e-3 (absolute: e is a ratio of speeds; the DEM's
    # first-order error grows with the damping, 3e-4 at e = 0.2 for LH at t_c/1000)
    for e_in in (0.2, 0.5, 0.8, 1.0):
        law = dem.contact_law(name, e=e_in, vref=3.9, **LAWS[name])
        m = dc.run(dc.Setup(law, material, 0.0025, [dc.Shot("wall", 3.9)], steps_per_tc=1000))[0]
        assert abs(m.e - e_in) < TOL, f"{name}: e in {e_in}, measured {m.e}"




@pytest.fixture(scope="module")
def oblique():
    law = dem.contact_law("Ts", e=E4, vref=V4)
    shots = [dc.Shot("wall", V4 * math.cos(math.radians(a)), angle=a) for a in ANGLES]
    return dc.run(dc.Setup(law, ALOX, R4, shots, friction=MU, steps_per_tc=1000))


def test_chung_ooi_4_normal_restitution(oblique):
    for m in oblique:
        assert abs(m.e - E4) < TOL, (m.shot.angle, m.e)


def test_chung_ooi_4_gross_sliding_matches_impulse_theory(oblique):
    # tan(theta) >= 3.5 mu (1 + e): the contact slides throughout, J_t = mu J_n; rigid-body
    # theory: e_t = 1 - mu (1 + e) cot(theta), w = 5 mu (1 + e) v cos(theta) / (2 R).
    # Mindlin's spring reaches the Coulomb limit within a tiny part of the contact (its ratio to
    # the elastic normal force, 6 (G*/E*) tan(theta), exceeds mu; only the damping term, large
    # at the first instant, holds it back), so J_t = mu J_n up to that instant and the time
    # step: asserted 1e-4 (measured: e_t within 8e-7, spin within 3e-6 relative, normal e
    # within 9e-7); a torque arm of R - delta/2 instead of R would be off by ~1e-3.
    sliding = [m for m in oblique if math.tan(math.radians(m.shot.angle)) >= 3.5 * MU * (1 + E4)]
    assert len(sliding) >= 10
    for m in sliding:
        th = math.radians(m.shot.angle)
        et = 1 - MU * (1 + E4) / math.tan(th)
        w = 5 * MU * (1 + E4) * V4 * math.cos(th) / (2 * R4)
        assert abs(m.vt_out / m.vt_in - et) < 1e-4, (m.shot.angle, m.vt_out / m.vt_in, et)
        # the sphere moves in +x on the plane z = 0: friction spins it about +y
        assert abs(m.spin_out / w - 1) < 1e-4, (m.shot.angle, m.spin_out, w)


def test_chung_ooi_4_sticking_regime(oblique):
    # tan(theta) < 3.5 mu (1 + e): rigid-body theory ends in rolling, e_t = 5/7; with Mindlin's
    # tangential elasticity the contact point's velocity reverses during the impact (Maw,
    # Barber & Fawcett 1976), so e_t is not 5/7 and no closed form applies.  What must hold:
    # the Coulomb bound |J_t| <= mu J_n, i.e. 1 - e_t <= mu (1 + e) cot(theta), and the angular
    # momentum about the contact point: w R = (5/2) (v_t - v_t') (torque arm R), to rounding.
    stick = [m for m in oblique if math.tan(math.radians(m.shot.angle)) < 3.5 * MU * (1 + E4)]
    assert len(stick) >= 5
    for m in stick:
        th = math.radians(m.shot.angle)
        et = m.vt_out / m.vt_in
        assert 1 - et <= MU * (1 + E4) / math.tan(th) * (1 + 1e-9), (m.shot.angle, et)
        assert abs(m.spin_out * R4 - 2.5 * (m.vt_in - m.vt_out)) <= 1e-9 * m.vt_in


def test_chung_ooi_4_sticking_regime_converges():
    """Below the sliding threshold the answer is Mindlin's (no closed form): the DEM converges
    to it as dt halves (t_c/125 ... t_c/1000: the largest change over the angles, of e_t and of
    the spin ratio w R / v_t, shrinks at least linearly, measured order 1.2), and at
    t_c/1000 it is within 1e-4 of the limit (first-order Richardson estimate: the last change;
    measured 1.6e-5 and 4.0e-5).  E.g. e_t = 0.6201 at 20 degrees, against 5/7 for rolling."""
    law = dem.contact_law("Ts", e=E4, vref=V4)
    angles = [a for a in ANGLES if math.tan(math.radians(a)) < 3.5 * MU * (1 + E4)]
    shots = [dc.Shot("wall", V4 * math.cos(math.radians(a)), angle=a) for a in angles]
    levels = (125, 250, 500, 1000)
    out = []
    for n in levels:
        res = dc.run(dc.Setup(law, ALOX, R4, shots, friction=MU, steps_per_tc=n))
        out.append([[m.vt_out / m.vt_in, m.spin_out * R4 / (V4 * math.sin(math.radians(a)))]
                    for m, a in zip(res, angles)])
    out = np.array(out)                                       # level x angle x (e_t, spin)
    change = np.abs(np.diff(out, axis=0)).max(axis=1)         # per halving, largest over angles
    for q in range(2):
        order = np.polyfit(-np.log(levels[1:]), np.log(change[:, q]), 1)[0]
        assert order >= MIN_ORDER, (q, change[:, q], order)
        assert change[-1, q] < 1e-4, (q, change[:, q])
