"""Cohesion with every damping law, where native has no counterpart (Jian, Li, Hunt, power):
two spheres in contact pulled apart slowly at constant speed lose contact at the pull-off force
of the theory (in native's cohesion parameter W, the work of adhesion being 2W):

    JKR (Johnson, Kendall, Roberts, Proc. R. Soc. A 324 (1971) 301):    F_po = 3 pi W R*
    DMT (Derjaguin, Muller, Toporov, J. Colloid Interface Sci. 53 (1975) 314): F_po = 4 pi W R*

At 2e-4 m/s the damping force is below 1e-4 of F_po for every law (c0 scaled by the law's
delta_a^p at pull-off), so the largest tensile force must equal F_po to 1e-3.  A JKR contact
also lives beyond zero overlap until -delta_c = -(3 pi^2/16)^(1/3) (R* W^2/E*^2)^(1/3): the
separation at which the force vanishes is checked against it.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from dem_util import inprocess_lammps, needs_lammps, sphere_head  # noqa: F401 (fixture lmp)

pytestmark = needs_lammps

E, NU, W, R = 1.0e7, 0.3, 0.5, 0.005
RSTAR = R / 2
ESTAR = E / (2 * (1 - NU**2))
V, DT, DELTA0 = 2e-4, 1e-6, 2e-6
LAWS = {"LH": 0.0, "Ts": 0.25, "KK": 0.5, "Li": 1.0, "Hunt": 1.5, "Jian": 0.5, "power": 0.75}

_SCRIPT = sphere_head("f f f", "-0.02 0.03 -0.02 0.02 -0.02 0.02", plugin=False) + """\
create_atoms 1 single 0 0 0
create_atoms 1 single {x2!r} 0 0
set type 1 diameter {d} density 2500
group two id 2
pair_style viscontact
pair_coeff * * {normal} {E} {NU} {W} damping {law} {params} tangential none
neighbor 0.0002 bin
neigh_modify every 1 delay 0 check no
timestep {dt}
fix mv two move linear {v} 0 0
variable f equal fx[2]
variable x equal x[2]
thermo_style custom step v_x v_f
thermo_modify format float %.15g
thermo {every}
log {log}
run {steps}
log none
"""


def _damping_params(law: str) -> str:
    p = LAWS[law]
    a_c = (9 * math.pi * W * RSTAR**2 / (4 * ESTAR)) ** (1 / 3)
    delta_a = a_c**2 / RSTAR
    c0 = 1e-2 / delta_a**p    # c0 delta_a^p v = 2e-6 N, F_po ~ 1e-2 N
    extra = " tau 1e-7" if law == "Jian" else ""
    pp = f"p {p} " if law == "power" else ""
    return f"{pp}c0 {c0!r}{extra}"


def _pull(lmp, tmp_path, normal: str, law: str) -> tuple[np.ndarray, np.ndarray]:
    log = tmp_path / f"log.{normal}.{law}"
    steps = int(round((DELTA0 + 2e-5) / (V * DT)))
    lmp.command("clear")
    lmp.commands_string(_SCRIPT.format(
        x2=2 * R - DELTA0, d=2 * R, normal=normal, E=E, NU=NU, W=W, law=law,
        params=_damping_params(law), dt=DT, v=V, every=5, log=log, steps=steps))
    rows = [ln.split() for ln in log.read_text().splitlines()
            if re.match(r"^\s*\d+\s+\S+\s+\S+\s*$", ln)]
    data = np.array([[float(c) for c in r[1:]] for r in rows])
    return data[:, 0], data[:, 1]


@pytest.mark.parametrize("law", list(LAWS))
@pytest.mark.parametrize("normal", ["jkr", "dmt"])
def test_pulloff_force_of_the_theory(lmp, tmp_path, normal, law):
    x, f = _pull(lmp, tmp_path, normal, law)
    f_po = (3 if normal == "jkr" else 4) * math.pi * W * RSTAR
    assert f.min() == pytest.approx(-f_po, rel=1e-3)
    # where the force vanishes for good: overlap -delta_c (jkr) or 0 (dmt)
    last = np.nonzero(f != 0.0)[0][-1]
    delta_end = 2 * R - x[last]
    if normal == "jkr":
        delta_c = (3 * math.pi**2 / 16) ** (1 / 3) * (RSTAR * W**2 / ESTAR**2) ** (1 / 3)
        assert delta_end == pytest.approx(-delta_c, abs=10 * V * DT * 5)
    else:
        assert 0.0 <= delta_end <= 5 * V * DT * 1.01
