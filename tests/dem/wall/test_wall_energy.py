"""The energy of spheres against static walls closes: kinetic + rotational + gravitational +
elastic (``compute viscontact/energy``, the wall contacts counted fully on their atoms) +
dissipated stays constant as the spheres settle, the residual shrinking at least linearly as
dt halves (a mechanism the wall failed to count would leave a residual that does not shrink).

Measured (this file's cases, 0.3 s of settling): residual / dissipated = 1.2e-3 (bowl) and
3.0e-4 (jkr floor) at dt = t_c/50, 2.1e-4 and 7.0e-5 at t_c/100, 5.1e-5 and 1.3e-5 at t_c/200:
second order (each force's work counted as velocity Verlet does it).  The residual is taken at
the end, with the spheres at rest or nearly so (in the middle of a contact velocity Verlet's
energy oscillates by O(dt^2) of the contact's energy).

Cases: spheres thrown into a spherical bowl (a region; friction with tangential damping,
rolling and twisting resistance, KK), and spheres dropped with spin onto a floor plane with
JKR adhesion (LH; the snap-in loss counted as adhesion hysteresis, contacts that end release
their elastic energy).  Real LAMMPS.
"""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import needs_lammps

pytestmark = needs_lammps

from viscontact.dem import plugin as _plugin  # noqa: E402

E, NU, RHO, R, G = 1.0e7, 0.3, 2500.0, 0.005, 9.81
#: Hertz contact time at 1 m/s of one sphere on the wall of its own material
M = 4.0 / 3.0 * np.pi * R**3 * RHO
K = 4.0 / 3.0 * E / (2 * (1 - NU**2)) * np.sqrt(R)
TC = float(3.2180654597 * (M / K) ** 0.4)

CASES = {
    "bowl": ("region bowl sphere 0 0 0.05 0.05 side in",
             "region bowl",
             "damping KK c0 20.0 tangential linear_history 3000 0.5 0.3 rolling sds 20 0.01 0.3 "
             "twisting sds 1e-4 1e-6 0.01",
             [((0.02, 0.0, 0.03), (0.3, 0.4, -0.5), (0.0, 20.0, 40.0)),
              ((-0.01, 0.02, 0.02), (-0.4, 0.1, 0.2), (30.0, 0.0, -20.0))]),
    "jkr floor": ("", "zplane 0.0 NULL",
                  "normal jkr 0.5 damping LH c0 0.2 tangential mindlin_rescale NULL 0.5 0.3 "
                  "rolling sds 20 0.01 0.3 twisting sds 1e-4 1e-6 0.01",
                  [((0.0, 0.0, R + 0.002), (0.3, 0.0, -0.6), (0.0, 0.0, 30.0)),
                   ((0.03, 0.0, R + 0.004), (-0.2, 0.1, -0.9), (10.0, 0.0, 0.0))]),
}


def energies(case: str, dt: float, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """(total energy, dissipated energy) at each of 10 samples over ``steps`` steps."""
    region, geom, model, atoms = CASES[case]
    lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
    try:
        cmds = ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f",
                "comm_modify vel yes", "region box block -0.1 0.1 -0.1 0.1 -0.1 0.1",
                "create_box 1 box"]
        for k, (x, v, w) in enumerate(atoms, 1):
            cmds += ["create_atoms 1 single {!r} {!r} {!r}".format(*x),
                     f"set atom {k} diameter {2 * R!r} density {RHO!r}",
                     "set atom {} vx {!r} vy {!r} vz {!r}".format(k, *v),
                     "set atom {} omega {!r} {!r} {!r}".format(k, *w)]
        cmds += ["pair_style zero 0.02", "pair_coeff * *", region,
                 f"fix w all viscontact/wall {geom} wall_material {E!r} {NU} {model} "
                 f"particle {E!r} {NU}",
                 f"fix g all gravity {G} vector 0 0 -1", "fix 1 all nve/sphere",
                 "compute e all viscontact/energy", "thermo_style custom step c_e[1]",
                 f"timestep {dt!r}", "thermo 0", "run 0"]
        for c in cmds:
            if c:
                lmp.command(c)
        total, diss = [], []
        for _ in range(11):
            x = lmp.numpy.extract_atom("x")[:2]
            v = lmp.numpy.extract_atom("v")[:2]
            w = lmp.numpy.extract_atom("omega")[:2]
            m = lmp.numpy.extract_atom("rmass")[:2]
            e = np.array([lmp.extract_compute("e", 0, 1)[k] for k in range(12)])
            kin = 0.5 * np.sum(m * np.sum(v * v, axis=1))
            rot = 0.5 * np.sum(0.4 * m * R**2 * np.sum(w * w, axis=1))
            pot = np.sum(m * G * x[:, 2])
            assert abs(e[0] - e[1:7].sum()) <= 1e-12 * max(abs(e[0]), 1e-300)
            assert abs(e[7] - e[8:12].sum()) <= 1e-12 * max(abs(e[7]), 1e-300)
            total.append(kin + rot + pot + e[7] + e[0])
            diss.append(e[0])
            lmp.command(f"run {steps // 10} pre no post no")
    finally:
        lmp.close()
    return np.array(total), np.array(diss)


@pytest.mark.parametrize("case", list(CASES))
def test_wall_energy_balance(case):
    res = []
    for div in (50, 100):
        dt = TC / div
        total, diss = energies(case, dt, int(0.3 / dt))
        assert diss[-1] > 0.2 * total[0]    # a real loss (the energy is counted from z = 0)
        res.append(abs(total[-1] - total[0]) / diss[-1])
    assert res[0] < 1e-2, res
    assert res[1] <= res[0] / 2, res
