"""The energy bookkeeping of ``compute viscontact/energy`` closes: an oblique, spinning collision
of two spheres with JKR cohesion, tangential damping and friction (linear_history and
mindlin_rescale), rolling and twisting resistance keeps kinetic + rotational + elastic +
dissipated energy constant, for every damping law:

* the residual shrinks at least linearly when dt halves and is below 1e-3 of the dissipated
  energy at dt = t_c/50 (measured: 1.5e-5 to 3e-5 over the laws and tangential models, 3.9 to
  6.3 times less at t_c/100: second order, each force's work counted as velocity Verlet does it,
  its two halves each in its own step's geometry);
* every mechanism column is non-negative where it must be and the per-atom array sums to the
  global vector (half of each contact's energy to each partner).
"""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import inprocess_lammps, needs_lammps, sphere_head  # noqa: F401 (fixture lmp)

pytestmark = needs_lammps

T_C = 6.4e-4    # contact time of this collision (Hertz estimate, 0.3 m/s, R = 1 cm, E = 10 MPa)
DAMPING = {
    "LH": "LH c0 0.5", "Ts": "Ts c0 5", "KK": "KK c0 50", "Li": "Li c0 5e3",
    "Hunt": "Hunt c0 5e5", "Jian": "Jian c0 50 tau 1e-5", "power": "power p 0.75 c0 500",
}
TANGENTIAL = ["linear_history 5e4 0.5 0.4", "mindlin_rescale NULL 0.5 0.4", "mindlin NULL 0.5 0.4",
              "mindlin/force NULL 0.5 0.4", "linear_nohistory 0.5 0.4"]

_SCRIPT = sphere_head("f f f", "-0.1 0.1 -0.1 0.1 -0.1 0.1", plugin=False) + """\
create_atoms 1 single 0 0 0
create_atoms 1 single 0.0201 0.004 0.001
set atom * diameter 0.02 density 2500
set atom 2 vx -0.3 omega 5 0 20
set atom 1 omega 0 -3 0
pair_style viscontact
pair_coeff * * jkr 1e7 0.3 0.5 damping {damping} tangential {tangential} rolling sds 200 0.01 0.1 twisting sds 0.001 1e-6 0.05
neighbor 0.002 bin
timestep {dt!r}
fix 1 all nve/sphere
compute e all viscontact/energy
compute ke all ke
compute rot all erotate/sphere
compute pa all reduce sum c_e[1] c_e[8]
variable tot equal c_ke+c_rot+c_e[1]+c_e[8]
thermo_style custom step v_tot c_e[1] c_pa[1] c_e[8] c_pa[2]
run {steps}
"""


def _balance(lmp, damping: str, tangential: str, dt: float) -> tuple[float, np.ndarray]:
    """(kinetic + rotational + elastic + dissipated at the end, the 12-vector)."""
    lmp.command("clear")
    lmp.commands_string(_SCRIPT.format(damping=damping, tangential=tangential, dt=dt,
                                       steps=int(round(0.012 / dt))))
    vec = np.array(lmp.numpy.extract_compute("e", 0, 1)[:12], dtype=float)
    pa = np.array(lmp.numpy.extract_compute("pa", 0, 1)[:2], dtype=float)
    # the per-atom columns sum to the global vector
    assert pa[0] == pytest.approx(vec[0], rel=1e-12) and pa[1] == pytest.approx(vec[7], abs=1e-18)
    return lmp.extract_variable("tot"), vec


@pytest.mark.parametrize("tangential", TANGENTIAL, ids=[t.split()[0] for t in TANGENTIAL])
@pytest.mark.parametrize("law", list(DAMPING))
def test_energy_balance_closes(lmp, law, tangential):
    m = 2500 * 4 / 3 * np.pi * 0.01**3
    start = 0.5 * m * 0.3**2 + 0.5 * (0.4 * m * 0.01**2) * (5**2 + 20**2 + 3**2)
    res = []
    for dt in (T_C / 50, T_C / 100):
        tot, vec = _balance(lmp, DAMPING[law], tangential, dt)
        diss = vec[0]
        assert diss > 0.05 * start                       # a real loss: the balance can fail
        assert vec[7] == pytest.approx(0.0, abs=1e-12 * start)    # apart again: no elastic left
        assert min(vec[1:7]) >= -1e-6 * diss             # mechanisms dissipate
        assert vec[6] > 0                                # JKR snap-in/pull-off hysteresis
        res.append(abs(tot - start) / diss)
    assert res[0] < 1e-3, res
    assert res[1] <= res[0] / 2, res
