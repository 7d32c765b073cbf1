"""Bonded partners (``special_bonds``) as native ``pair_style granular`` treats them: a pair
whose special_lj factor is 0 is skipped (no force, its contact history left alone), any other
factor scales the pair's forces and torques (not its heat flow).  Ours and native side by side on a small cluster of
touching spheres, three of them bonded in a chain (1-2, 2-3: 1-2 partners; 1-3: 1-3 partners),
with jkr cohesion, tangential, rolling and twisting history and heat conduction (heat area,
fix heat/flow): positions, forces, torques, temperatures and heat flows after
a few steps equal native's to 1e-10 (measured <= 8e-16, from the order of sums), for factors 1,
0.5 and 0 (0 both excluded from the neighbour list, coul 0, and listed, coul 1).

``compute pair/local`` through single() in the same runs: every pair with factor 1 gives
native's row (normal force, the 12 extras) to 1e-10 (measured <= 5.2e-16); a listed pair with
factor 0 a row of zeros, as native; and for factors 1, 0.5 and 0 the rows add up to the force
on each atom that the pair style applied (measured <= 1.6e-16).  Native's single() does not
apply a factor between 0 and 1 and does not find a bonded pair's history (its rows miss the
applied forces by more than 1e-3 there); ours applies it, as compute() and every other LAMMPS
pair style's single() do.
"""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import assert_ok, needs_lammps, plugin_line, read_atoms, run_lmp
from test_native_submodels import CASES

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
compute pl all pair/local dist force p1 p2 p3 p4 p5 p6 p7 p8 p9 p10 p11 p12
compute pi all property/local patom1 patom2
dump pl all local {steps} {out}.pairs c_pi[1] c_pi[2] c_pl[*]
dump_modify pl format float %.17g
run {steps}
write_dump all custom {out} id x y z fx fy fz tqx tqy tqz c_hf[1] c_hf[2] modify sort id format float %.17g
undump pl
compute pl0 all pair/local dist force p1 p2 p3 p4 p5 p6 p7 p8 p9 p10 p11 p12
compute pi0 all property/local patom1 patom2
dump pl0 all local 1 {out}.pairs0 c_pi0[1] c_pi0[2] c_pl0[*]
dump_modify pl0 format float %.17g
run 0
write_dump all custom {out}.setup id fx fy fz modify sort id format float %.17g
"""
COLS = ("x", "y", "z", "fx", "fy", "fz", "tqx", "tqy", "tqz", "c_hf[1]", "c_hf[2]")
#: the special_lj factor of each bonded pair per case (every other pair: 1); 1-2 partners are
#: (1, 2) and (2, 3), 1-3 partners (1, 3)
FACTORS = {
    "one": {},
    "half": {(1, 2): 0.5, (2, 3): 0.5, (1, 3): 0.5},
    "zero_listed": {(1, 2): 0.0, (2, 3): 0.0, (1, 3): 0.5},
    "zero_excluded": {(1, 2): 0.0, (2, 3): 0.0, (1, 3): 0.5},
}
#: columns of a pair/local row after the two atom ids: dist, force (= F_n: fforce r), then
#: single()'s extras 1-12 (F_t (3), |F_t|, F_R (3), |F_R|, tau_tw, x_i - x_j (3))
PAIR_COLS = 14


def _run(d, case: str, style: str) -> dict:
    out = f"{case}.{style}"
    script = _SCRIPT.format(plugin=plugin_line() if style == "viscontact" else "", d=D, rho=RHO,
                            special=SPECIAL[case], style=style,
                            coeff=OURS if style == "viscontact" else NATIVE, steps=STEPS, out=out)
    proc = run_lmp(script, d, name=f"in.{out}")
    assert_ok(proc)
    return {"atoms": read_atoms(d / out), "pairs": _pairs(d / f"{out}.pairs"),
            "setup": read_atoms(d / f"{out}.setup"), "pairs0": _pairs(d / f"{out}.pairs0")}


def _pairs(path) -> dict[tuple[int, int], np.ndarray]:
    """The last frame of a local dump of ``compute pair/local``: (id_i, id_j) -> the row."""
    lines = path.read_text().splitlines()
    start = max(k for k, ln in enumerate(lines) if ln.startswith("ITEM: ENTRIES")) + 1
    rows = {}
    for ln in lines[start:]:
        vals = [float(c) for c in ln.split()]
        assert len(vals) == 2 + PAIR_COLS, ln
        rows[int(vals[0]), int(vals[1])] = np.array(vals[2:])
    return rows


def _factor(case: str, pair: tuple[int, int]) -> float:
    return FACTORS[case].get(tuple(sorted(pair)), 1.0)


def _pair_forces(pairs: dict, n: int, unscale: str | None = None) -> np.ndarray:
    """Each atom's force as the sum of its pair/local rows: F = F_n (x_i - x_j)/r + F_t on i,
    its negative on j.  ``unscale``: a case whose bonded rows are first divided by their
    factor (what a single() that ignores the factor would report)."""
    f = np.zeros((n, 3))
    for (i, j), row in pairs.items():
        dist, fn, ft, dx = row[0], row[1], row[2:5], row[11:14]
        force = fn * dx / dist + ft
        if unscale is not None and 0.0 < _factor(unscale, (i, j)) < 1.0:
            force = force / _factor(unscale, (i, j))
        f[i - 1] += force
        f[j - 1] -= force
    return f


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
    ours, native = runs[case, "viscontact"]["atoms"], runs[case, "granular"]["atoms"]
    assert _diff(native, ours) <= TOL, (case, {c: float(np.abs(native[c] - ours[c]).max())
                                               for c in COLS})


def test_special_factor_matters(runs):
    """The factors change the run (the comparison above can fail): 0.5 and 0 against 1, and the
    two ways to give 0 agree with each other."""
    one = runs["one", "viscontact"]["atoms"]
    for case in ("half", "zero_listed"):
        assert _diff(one, runs[case, "viscontact"]["atoms"]) > 1e-3, case
    assert _diff(runs["zero_excluded", "viscontact"]["atoms"],
                 runs["zero_listed", "viscontact"]["atoms"]) <= TOL


@pytest.mark.parametrize("case", list(SPECIAL))
def test_single_as_native(runs, case):
    """``compute pair/local`` through single() at the last step of the run: the same pairs as
    native (a pair excluded from the
    neighbour list by factor 0 has no row; a listed one with factor 0 a row of zeros), and for
    every pair with factor 1 the same distance, normal force (elastic + damping, as native),
    tangential force, rolling pseudo-force, twisting torque and x_i - x_j as native's row, to
    1e-10 of each column's largest value.  Bonded pairs with 0 < factor < 1 are checked by the
    test below: native's single() neither applies the factor nor finds a bonded pair's history
    (it compares the neighbour entry, special bits included, with j)."""
    ours, native = runs[case, "viscontact"]["pairs"], runs[case, "granular"]["pairs"]
    assert set(ours) == set(native), (sorted(ours), sorted(native))
    assert ((1, 2) in ours) == (case != "zero_excluded")
    scale = np.max(np.abs(np.array(list(native.values()))), axis=0)
    compared = 0
    for pair, row in ours.items():
        f = _factor(case, pair)
        if f == 0.0:
            assert not np.any(row[1:]) and not np.any(native[pair][1:]), (pair, row, native[pair])
        elif f == 1.0:
            err = np.abs(row - native[pair]) / scale
            assert err.max() <= TOL, (pair, err)
            compared += 1
    assert compared >= 3, compared


@pytest.mark.parametrize("case", list(SPECIAL))
def test_single_rows_add_up_to_the_forces(runs, case):
    """The special_bonds factor in single() as in compute(): each atom's force summed from its
    pair/local rows equals the force the pair style applied, to 1e-10 of
    the largest force, for factors 1, 0.5 and 0.  Controls: our bonded rows divided by their
    factor (the unscaled contact, as native's single() reports it) miss by more than 1e-3,
    and so do native's own rows (pinned LAMMPS), except where every factor is 1.  Taken in a
    ``run 0`` after the run, where the forces and single() see the same (full-step)
    velocities and the same history; inside a run the forces saw the half-step velocities."""
    res = runs[case, "viscontact"]
    applied = np.stack([res["setup"][c] for c in ("fx", "fy", "fz")], axis=1)
    top = np.abs(applied).max()
    assert np.abs(_pair_forces(res["pairs0"], len(applied)) - applied).max() <= TOL * top
    nat = runs[case, "granular"]
    nat_applied = np.stack([nat["setup"][c] for c in ("fx", "fy", "fz")], axis=1)
    nat_err = np.abs(_pair_forces(nat["pairs0"], len(applied)) - nat_applied).max() / top
    if case == "one":
        assert nat_err <= TOL, nat_err
    else:
        assert nat_err > 1e-3, nat_err
    if case == "half":
        unscaled = _pair_forces(res["pairs0"], len(applied), unscale=case)
        assert np.abs(unscaled - applied).max() > 1e-3 * top
