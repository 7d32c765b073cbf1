"""The energy count (``compute viscontact/energy``) closes across a run's start: kinetic +
rotational + elastic + dissipated changes in the first step after a run start by no more than
in a step of an uninterrupted run.

The setup force call of a run (``run``, ``run N pre no``, after ``read_restart``) gives the
forces the integrator's first step starts from, so they are the first half of that step's work
(the trapezoid of velocity Verlet).  Each case follows the step-by-step change of the balance
(every step, ``fix ave/time``) of an oblique, spinning JKR collision (damping, Mindlin friction,
rolling and twisting resistance), or of the same sphere on a JKR wall:

* a contact present at the start (a plain run, and ``run 0`` then ``run N pre no``): its first
  step's change is at most the largest of a run in which the contact begins in a regular step;
* a contact going on (a second ``run``, and ``read_restart``): its first step's change is that
  of the same step of the uninterrupted run, to 10 %.

Measured (dt = t_c/50; pair, wall): the uninterrupted run's largest change 7.0e-10, 8.5e-10 J
and 1.04e-10, 6.2e-11 J in its step 51; after the start 1.06e-10, 3.0e-10 J (contact at the
start) and 1.03e-10, 6.1e-11 J (going on).  Before the setup wrote the energy slots: 3.1e-7,
3.1e-7 J and 4.0e-10, 4.6e-10 J (stale last forces: zero for a contact begun at setup, those of
the last regular step for one going on).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from dem_util import inprocess_lammps, needs_lammps, sphere_head  # noqa: F401 (fixture lmp)

pytestmark = needs_lammps

DT = 6.4e-4 / 50    # t_c/50 of this collision (Hertz estimate, 0.3 m/s, R = 1 cm, E = 10 MPa)
GOING_ON = 50       # steps before the second run: the contact began at step 33
MODEL = ("jkr 1e7 0.3 0.5 damping LH c0 0.5 tangential mindlin NULL 0.5 0.4 "
         "rolling sds 200 0.01 0.1 twisting sds 0.001 1e-6 0.05")
CASES = {    # atoms (x of the moving sphere: apart, the contact begins at step 33; touching)
    "pair": ("create_atoms 1 single 0 0 0\ncreate_atoms 1 single {x!r} 0.004 0.001\n"
             "set atom * diameter 0.02 density 2500\nset atom 2 vx -0.3 omega 5 0 20\n"
             "set atom 1 omega 0 -3 0\n",
             "pair_style viscontact\npair_coeff * * " + MODEL + "\n", 0.0197, 0.0195),
    "wall": ("create_atoms 1 single 0.01 0.004 {x!r}\nset atom * diameter 0.02 density 2500\n"
             "set atom 1 vx -0.1 vz -0.3 omega 5 0 20\n",
             "pair_style zero 0.03\npair_coeff * *\nfix w all viscontact/wall zplane 0.0 NULL "
             "wall_material 1e7 0.3 normal " + MODEL.replace("jkr 1e7 0.3", "jkr")
             + " particle 1e7 0.3\n", 0.0101, 0.00995),
}
_TAIL = """neighbor 0.002 bin
timestep {dt!r}
fix 1 all nve/sphere
compute e all viscontact/energy
compute ke all ke
compute rot all erotate/sphere
variable tot equal c_ke+c_rot+c_e[1]+c_e[8]
"""


def _changes(lmp, head: str, before: str, runs: str, out: Path) -> np.ndarray:
    """The balance's change in each step of ``runs`` (``fix ave/time`` from its first run on)
    after ``head``, the common tail and ``before``."""
    lmp.command("clear")
    lmp.commands_string(head + _TAIL.format(dt=DT) + before
                        + f'fix av all ave/time 1 1 1 v_tot file {out} format " %.17g"\n' + runs)
    lmp.command("unfix av")    # closes the file
    return np.abs(np.diff(np.loadtxt(out)[:, 1]))


@pytest.mark.parametrize("case", list(CASES))
def test_balance_across_run_start(lmp, tmp_path, case):
    atoms, model, apart, touching = CASES[case]
    head = sphere_head("f f f", "-0.1 0.1 -0.1 0.1 -0.1 0.1", plugin=False)
    body = atoms + model
    ref = _changes(lmp, head + body.format(x=apart), "", "run 100\n", tmp_path / "ref")
    begin = int(np.argmax(ref > 0))
    assert 10 < begin < GOING_ON - 5    # the contact begins in a regular step, before step 50
    worst = ref[begin:].max()
    # a contact present at the start: a plain run, and run 0 then run N pre no
    for runs in ("run 20\n", "run 0\nrun 20 pre no\n"):
        got = _changes(lmp, head + body.format(x=touching), "", runs, tmp_path / "start")
        assert got[0] > 0 and got[1] > 0    # touching from the start
        assert got[0] <= worst, (runs, got[:3], worst)
    # a contact going on: a second run, and read_restart
    second = _changes(lmp, head + body.format(x=apart), f"run {GOING_ON}\n", "run 20\n",
                      tmp_path / "second")
    assert second[0] == pytest.approx(ref[GOING_ON], rel=0.1)
    assert second[1:10] == pytest.approx(ref[GOING_ON + 1:GOING_ON + 10], rel=0.1)
    lmp.command("clear")
    lmp.commands_string(head + body.format(x=apart) + _TAIL.format(dt=DT)
                        + f"run {GOING_ON}\nwrite_restart {tmp_path / 'r.rst'}\n")
    restart_head = f"read_restart {tmp_path / 'r.rst'}\n" + model
    restarted = _changes(lmp, restart_head, "", "run 20\n", tmp_path / "restarted")
    assert restarted[0] == pytest.approx(ref[GOING_ON], rel=0.1)
