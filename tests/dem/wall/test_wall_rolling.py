"""A sphere rolling on a plane wall with ``rolling sds KR GAMMAR MUR`` stops where the
spring-dashpot-slider says.

Model (rolling without slip, v = R w, flat wall: R* = R, F0 = m g): the rolling spring
displacement xi grows at v_R = R* w = v; the rolling force F = -KR xi - GAMMAR v is capped at
MUR F0 (slider), and its torque R* F is the only torque left once the tangential force keeps the
contact point at rest, so (I + m R^2) w' = R F, i.e. (7/5) m v' = F.

- Slip phase (cap binding): v' = -a, a = (5/7) MUR g; xi stays on the cap,
  xi = (MUR m g - GAMMAR v)/KR.  The slider sticks when KR v + GAMMAR v' <= 0 would keep
  |F| below the cap: at v* = GAMMAR a/KR, after x_s = (v0^2 - v*^2)/(2 a).
- Stick phase: x - xi is constant (both grow at v), and the damped spring brings xi to 0, so
  the sphere rests at x_s - xi_s, xi_s = (MUR m g - GAMMAR v*)/KR, provided the stick phase
  never reaches the cap again: checked by integrating (7/5) m v' = -(KR xi + GAMMAR v),
  xi' = v with SciPy.

So the stop distance is D = (v0^2 - v*^2)/(2 a) - (MUR m g - GAMMAR v*)/KR.  Real LAMMPS.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from dem_util import needs_lammps

pytestmark = needs_lammps

from viscontact.dem import plugin as _plugin  # noqa: E402

E, NU, RHO, R, G = 1.0e7, 0.3, 2500.0, 0.005, 9.81
KR, GAMMAR, MUR = 1.0, 0.05, 0.05
V0 = 0.1
DT = 4e-5


def stop_distance(m: float) -> float:
    """D of the module docstring; asserts that the stick phase stays below the cap."""
    cap = MUR * m * G
    a = 5.0 / 7.0 * cap / m
    vstar = GAMMAR * a / KR
    assert vstar < V0
    xs = (V0**2 - vstar**2) / (2 * a)
    xis = (cap - GAMMAR * vstar) / KR

    def rhs(_t, y):
        xi, v = y
        return [v, -(KR * xi + GAMMAR * v) / (1.4 * m)]

    sol = solve_ivp(rhs, (0.0, 5.0), [xis, vstar], rtol=1e-11, atol=1e-14, dense_output=True)
    t = np.linspace(0, 5.0, 20001)
    xi, v = sol.sol(t)
    force = np.abs(KR * xi + GAMMAR * v)
    assert force[1:].max() <= cap * (1 + 1e-9), "the stick phase would slip again"
    assert abs(xi[-1]) < 1e-6 * abs(xis) and abs(v[-1]) < 1e-6 * vstar    # at rest
    return xs - xis


def test_rolling_sds_stop_distance():
    """The sphere starts rolling (v0 = 0.1 m/s, w = v0/R) at the Hertz rest overlap; after it
    has stopped its displacement equals D to 5e-4 (measured: 3.1e-4, 1.4e-4, 6.1e-5 at
    dt = 8e-5, 4e-5, 2e-5 s: first order in dt; without rolling resistance it would roll on
    forever, with a pure slider, D = 7 v0^2/(10 MUR g), 1.5 % further).  The tangential spring
    is damped (XGAMMA 0.5): undamped, the sphere would rock between translation and rotation
    for ever and stop 1.5e-3 further on."""
    m = 4.0 / 3.0 * np.pi * R**3 * RHO
    estar = E / (2 * (1 - NU**2))
    k = 4.0 / 3.0 * estar * np.sqrt(R)
    z0 = float(R - (m * G / k) ** (2.0 / 3.0))
    want = stop_distance(m)
    model = (f"damping LH c0 0.5 end force tangential mindlin NULL 0.5 1.0 "
             f"rolling sds {KR} {GAMMAR} {MUR}")
    lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
    try:
        for c in ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f",
                  "region box block -0.05 0.1 -0.01 0.01 -0.01 0.02", "create_box 1 box",
                  f"create_atoms 1 single 0 0 {z0!r}",
                  f"set atom 1 diameter {2 * R!r} density {RHO!r}",
                  f"set atom 1 vx {V0!r}", f"set atom 1 omega 0 {V0 / R!r} 0",
                  "pair_style zero 0.02", "pair_coeff * *",
                  f"fix w all viscontact/wall zplane 0.0 NULL wall_material {E!r} {NU} {model} "
                  f"particle {E!r} {NU}",
                  f"fix g all gravity {G} vector 0 0 -1", "fix 1 all nve/sphere",
                  f"timestep {DT}", "thermo 0"]:
            lmp.command(c)
        t_stop = 7.0 * V0 / (5.0 * MUR * G)
        lmp.command(f"run {int(3 * t_stop / DT)}")
        x = float(lmp.numpy.extract_atom("x")[0, 0])
        v = float(lmp.numpy.extract_atom("v")[0, 0])
    finally:
        lmp.close()
    assert abs(v) < 1e-3 * V0
    assert abs(x / want - 1) < 5e-4, (x, want)
