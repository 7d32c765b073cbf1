"""Bonded partners (``special_bonds``) as native ``pair_style granular`` treats them: a pair
whose special_lj factor is 0 is skipped (no force, its contact history left alone), any other
factor scales the pair's forces and torques (not its heat flow).  Ours and native side by side on a small cluster of
touching spheres, three of them bonded in a chain (1-2, 2-3: 1-2 partners; 1-3: 1-3 partners),
with jkr cohesion, tangential, rolling and twisting history and heat conduction (heat area,
fix heat/flow): positions, forces, torques, temperatures and heat flows after
a few steps equal native's to 1e-10 (measured <= 8e-16, from the order of sums), for factors 1,
0.5 and 0 (0 both excluded from the neighbour list, coul 0, and listed, coul 1).
"""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import assert_ok, needs_lammps, plugin_line, read_atoms, run_lmp
from test_dem_contact_native import CASES

pytestmark = needs_lammps

D, RHO = 0.01, 2500.0
TOL = 1e-10
STEPS = 40
OURS, NATIVE = CASES["jkr_LH_linear_history_rolling_twist"]
SPECIAL = {
    "one": "lj 1 1 1 coul 1 1 1",
    "half": "lj 0.5 0.5 1",
    "zero_listed": "lj 0 0.5 1 coul 1 1 1",
    "zero_excluded": "lj 0 0.5 1",
}

_SCRIPT = """{plugin}
units si
atom_style hybrid sphere bond
atom_modify map array
boundary f f f
comm_modify vel yes
region box block -0.05 0.05 -0.05 0.05 -0.05 0.05
create_box 1 box bond/types 1 extra/bond/per/atom 2 extra/special/per/atom 4
fix p all property/atom temperature heatflow
create_atoms 1 single 0 0 0
create_atoms 1 single 0.0098 0 0
create_atoms 1 single 0.0049 0.0085 0.0003
create_atoms 1 single -0.0099 0.0004 0
create_atoms 1 single 0.0049 -0.0086 -0.0004
set group all diameter {d!r}
set group all density {rho!r}
set atom 1 vx 0.02 omega 5 -3 8
set atom 2 vy -0.03 omega -4 6 2
set atom 3 vz 0.01 omega 7 1 -5
set atom 4 vx 0.05 omega 0 9 -2
set atom 5 vy 0.04 omega 3 -6 4
set group all temperature 300
set atom 1 temperature 400
set atom 5 temperature 350
bond_style zero
bond_coeff 1
special_bonds {special}
create_bonds single/bond 1 1 2
create_bonds single/bond 1 2 3
pair_style {style}
pair_coeff * * {coeff} heat area 3.0
neighbor 0.002 bin
timestep 2e-6
fix 1 all nve/sphere
fix h all heat/flow constant 1.0
compute hf all property/atom temperature heatflow
run {steps}
write_dump all custom {out} id x y z fx fy fz tqx tqy tqz c_hf[1] c_hf[2] modify sort id format float %.17g
"""
COLS = ("x", "y", "z", "fx", "fy", "fz", "tqx", "tqy", "tqz", "c_hf[1]", "c_hf[2]")


def _run(d, case: str, style: str) -> dict:
    out = f"{case}.{style}"
    script = _SCRIPT.format(plugin=plugin_line() if style == "viscontact" else "", d=D, rho=RHO,
                            special=SPECIAL[case], style=style,
                            coeff=OURS if style == "viscontact" else NATIVE, steps=STEPS, out=out)
    proc = run_lmp(script, d, name=f"in.{out}")
    assert_ok(proc)
    return read_atoms(d / out)


def _diff(a: dict, b: dict) -> float:
    """max over quantities of max |a - b| / max |a| (positions: displacement from the start
    would hide nothing here, the forces and torques carry the comparison)."""
    return max(float(np.abs(a[c] - b[c]).max() / np.abs(a[c]).max()) for c in COLS)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    d = tmp_path_factory.mktemp("special")
    return {(case, style): _run(d, case, style) for case in SPECIAL
            for style in ("viscontact", "granular")}


@pytest.mark.parametrize("case", list(SPECIAL))
def test_special_bonds_as_native(runs, case):
    ours, native = runs[case, "viscontact"], runs[case, "granular"]
    assert _diff(native, ours) <= TOL, (case, {c: float(np.abs(native[c] - ours[c]).max())
                                               for c in COLS})


def test_special_factor_matters(runs):
    """The factors change the run (the comparison above can fail): 0.5 and 0 against 1, and the
    two ways to give 0 agree with each other."""
    one = runs["one", "viscontact"]
    for case in ("half", "zero_listed"):
        assert _diff(one, runs[case, "viscontact"]) > 1e-3, case
    assert _diff(runs["zero_excluded", "viscontact"], runs["zero_listed", "viscontact"]) <= TOL
