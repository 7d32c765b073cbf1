"""``pair_style viscontact`` next to native ``pair_style granular`` on the pinned LAMMPS: the
cutoff and neighbour rules (insertion fixes, frozen atoms), the effective mass (fix freeze,
rigid bodies), any units style, and the heat refusal (docs/pair_viscontact.md, "Cutoff and
neighbour lists", "Effective mass m*", "Units"; mixing: test_mixing.py; the damping and
sub-models: test_native_submodels.py).

Every reference is native LAMMPS run side by side, or a closed form: the laws' exact
equivalences (LH ``c0`` = native ``damping velocity``; Ts ``alpha A`` = native ``tsuji`` with
A = alpha_T(e), the polynomial of the pinned LAMMPS) make per-atom forces comparable to
rounding.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from dem_util import (
    MPIRUN, assert_ok, error_lines, needs_lammps, plugin_line, read_atoms, run_lmp, sphere_head,
)

pytestmark = needs_lammps

E, NU, RHO = 1.0e7, 0.3, 2500.0
#: equivalent pair lines (docs/pair_viscontact.md): LH c0 = native velocity damping, no friction
NATIVE_LH = "hertz/material {E} {c0} {nu} damping velocity tangential linear_nohistory 0 0 limit_damping"
OURS_LH = "hertz/material {E} {nu} damping LH c0 {c0} tangential none"


def _cutoffs(proc) -> tuple[float, float]:
    """(master list distance cutoff, ghost atom cutoff) as LAMMPS prints them."""
    master = re.search(r"master list distance cutoff = (\S+)", proc.stdout)
    ghost = re.search(r"ghost atom cutoff = (\S+)", proc.stdout)
    assert master and ghost, proc.stdout[-2000:]
    return float(master.group(1)), float(ghost.group(1))


def _pair_lines(style: str, c0: float = 0.05, e: float = E, nu: float = NU) -> str:
    form = NATIVE_LH if style == "granular" else OURS_LH
    return f"pair_style {style}\npair_coeff * * {form.format(E=e, nu=nu, c0=c0)}"


# ------------------------------------------------------------------------ cutoff (item 1)
_CUT = sphere_head("p p f", "0 {L} 0 {L} 0 {L}", 2) + """\
{atoms}
{pair}
neighbor 0.001 bin
fix 1 all nve/sphere
fix g all gravity 9.81 vector 0 0 -1
region slab block 0 {L} 0 {L} {zlo} {zhi}
{fixes}
run 0
"""
CUT_CASES = {
    "mono": ("create_atoms 1 single 0.01 0.01 0.01\ncreate_atoms 1 single 0.03 0.03 0.03\n"
             "set type 1 diameter 0.002", ""),
    "bidisperse": ("create_atoms 1 single 0.01 0.01 0.01\ncreate_atoms 2 single 0.03 0.03 0.03\n"
                   "set type 1 diameter 0.002\nset type 2 diameter 0.005", ""),
    # a frozen R = 0.1 next to a moving R = 0.01 (0.111 with skin 0.001: docs/pair_viscontact.md)
    "frozen": ("create_atoms 1 single 0.01 0.01 0.01\ncreate_atoms 2 single 0.03 0.03 0.03\n"
               "set type 1 diameter 0.02\nset type 2 diameter 0.2\ngroup fr type 2",
               "fix fz fr freeze"),
    "pour_larger": ("create_atoms 1 single 0.01 0.01 0.01\nset type 1 diameter 0.001",
                    "fix p all pour 5 1 4767 region slab diam range 0.002 0.005 dens 2500 2500"),
    "pour_empty": ("", "fix p all pour 5 2 4767 region slab diam one 0.004 dens 2500 2500"),
    # a deposited atom has diameter 1 (atom mode): a box of 10
    "deposit": ("create_atoms 1 single 1 1 1\nset type 1 diameter 0.002",
                "fix d all deposit 3 2 100 4767 region slab near 0.5"),
}


def _cut_script(atoms: str, pair: str, fixes: str, case: str = "") -> str:
    L = 10.0 if case == "deposit" else 0.1
    return _CUT.format(plugin=plugin_line(), atoms=atoms, pair=pair, fixes=fixes, L=L,
                       zlo=0.6 * L, zhi=0.9 * L)


@pytest.mark.parametrize("case", list(CUT_CASES))
def test_cutoff_as_native(tmp_path, case):
    """The printed master-list and ghost cutoffs equal native's: atoms present (mono,
    bidisperse), a frozen large type, fix pour announcing larger radii than present, a pour into
    an empty box, fix deposit (radius 0.5 in atom mode)."""
    atoms, fixes = CUT_CASES[case]
    got = {}
    for style in ("granular", "viscontact"):
        proc = run_lmp(_cut_script(atoms, _pair_lines(style), fixes, case), tmp_path,
                       name=f"in.{case}.{style}")
        assert_ok(proc)
        got[style] = _cutoffs(proc)
    assert got["viscontact"] == got["granular"], got
    assert got["granular"][0] > 0.001  # more than the skin: the rule was exercised


_POUR = sphere_head("p p f", "0 0.02 0 0.02 -0.005 0.15", 2) + """\
{pair}
neighbor 0.0002 bin
neigh_modify delay 0
fix 1 all nve/sphere
fix g all gravity 9.81 vector 0 0 -1
fix floor all wall/gran granular hertz/material 1e7 0.3 0.3 tangential linear_nohistory 0 0 zplane 0.0 NULL
region slab block 0 0.02 0 0.02 0.01 0.04
fix ins all pour 200 1 4767 region slab diam range 0.0015 0.0025 vel 0 0 0 0 0 dens 2500 2500
timestep 5e-6
run 20000
write_dump all custom {out} id x y z radius modify sort id format float %.17g
"""


def _max_overlap(at: dict, box: float = 0.02) -> float:
    """Largest pair overlap / (r_i + r_j) of a dump (periodic in x and y)."""
    x = np.stack([at["x"], at["y"], at["z"]], 1)
    r = at["radius"]
    d = x[:, None, :] - x[None, :, :]
    d[..., :2] -= box * np.round(d[..., :2] / box)
    dist = np.linalg.norm(d, axis=-1)
    rsum = r[:, None] + r[None, :]
    ov = (rsum - dist) / rsum
    np.fill_diagonal(ov, -1.0)
    return float(ov.max())


def test_pour_into_empty_box_packs_like_native(tmp_path):
    """200 spheres poured into an empty box (the cutoff comes only from fix pour's radius)
    settle into a bed like native's: the same cutoffs, every sphere kept, largest overlap at
    most twice native's (the old cutoff from the atoms present, none, let spheres pass through
    each other: overlaps up to 84 % and a bed ten times too high), bed top within 20 %; on 1
    and 2 ranks."""
    runs = [("granular", 1)] + [("viscontact", n) for n in (1, 2) if n == 1 or MPIRUN]
    res = {}
    for style, np_ in runs:
        out = f"pour.{style}.{np_}"
        proc = run_lmp(_POUR.format(plugin=plugin_line(), pair=_pair_lines(style), out=out),
                       tmp_path, np=np_, name=f"in.{out}")
        assert_ok(proc)
        at = read_atoms(tmp_path / out)
        res[(style, np_)] = (_cutoffs(proc), len(at["id"]), _max_overlap(at), at["z"].max())
    ref = res[("granular", 1)]
    assert ref[1] == 200 and ref[2] < 0.05, ref
    for key, got in res.items():
        assert got[0] == ref[0], (key, got, ref)
        assert got[1] == 200, (key, got)
        assert got[2] <= 2.0 * ref[2], (key, got, ref)
        assert abs(got[3] - ref[3]) <= 0.2 * ref[3], (key, got, ref)


def test_sphere_outgrowing_the_cutoff_is_an_error(tmp_path):
    """A sphere made larger between runs: a new run re-sizes the cutoff (runs); with `pre no`
    (no re-initialisation) the pair stops with one ERROR line instead of missing contacts."""
    base = _cut_script(CUT_CASES["mono"][0], _pair_lines("viscontact"), "")
    proc = run_lmp(base + "set atom 1 diameter 0.004\nrun 5\n", tmp_path, name="in.grow.ok")
    assert_ok(proc)
    assert _cutoffs(proc) != (0.005, 0.005)
    proc = run_lmp(base + "set atom 1 diameter 0.004\nrun 5 pre no\n", tmp_path, name="in.grow.bad")
    errs = error_lines(proc)
    assert proc.returncode != 0 and len(errs) == 1, errs
    assert "atom 1 (type 1) has radius 0.002" in errs[0] and "most 0.001" in errs[0], errs


# ------------------------------------------------------------------- effective mass (item 2)
R1, R2 = 0.001, 0.0015
_MASS = sphere_head("f f f", "-0.02 0.02 -0.02 0.02 -0.02 0.02") + """\
create_atoms 1 single 0 0 0
create_atoms 1 single {x2:.17g} 0 0
create_atoms 1 single {x3:.17g} 0 0
set atom 1 diameter {d1:.17g} density 2500 vx {v:.17g} vy {vt:.17g}
set atom 2*3 diameter {d2:.17g} density 2500
group a id 1
group b id 2
group c id 3
group bc id 2 3
{pair}
{fixes}
timestep 2e-7
thermo_modify norm no
dump f all custom 20 {out} id fx fy fz
dump_modify f format float %.17g sort id
run 400
"""
#: Ts alpha A == native tsuji with A = alpha_T(e) (docs/audit.md)
E_TSUJI = 0.7


def _tsuji_pair(style: str) -> str:
    from viscontact.audit.formulas import tsuji_polynomial

    if style == "granular":
        return (f"pair_style granular\npair_coeff * * hertz/material {E} {E_TSUJI} {NU} damping "
                f"tsuji tangential mindlin NULL 0 0.5")
    a = tsuji_polynomial(E_TSUJI)
    return (f"pair_style viscontact\npair_coeff * * hertz/material {E} {NU} damping Ts alpha "
            f"{a!r} vref 1 tangential mindlin 0.5")


def _frames(path) -> np.ndarray:
    """All frames of a dump of id fx fy fz as an array (frame, atom, 3)."""
    from viscontact import dem

    return np.array([np.stack([np.asarray(fr.columns[c]) for c in ("fx", "fy", "fz")], 1)
                     for fr in dem.read_dump(path)])


MASS_CASES = {
    # atom 1 hits atom 2, which is frozen (infinitely heavy: m* = m_1)
    "freeze": "fix fz b freeze\nfix 1 a nve/sphere",
    # atom 1 hits a rigid body of atoms 2 and 3 (m* with the body's mass)
    "rigid": "fix rb bc rigid single\nfix 1 a nve/sphere",
    "rigid_small": ("fix pa all property/atom i_body\nset group bc i_body 1\nset atom 1 i_body 2\n"
                    "fix rb bc rigid/small custom i_body\nfix 1 a nve/sphere"),
}


@pytest.mark.parametrize("case", list(MASS_CASES))
def test_effective_mass_as_native(tmp_path, case):
    """Ts alpha against native tsuji (sqrt(m*) enters the damping): forces of every dumped step
    of a sliding impact equal native's to 1e-10 of the peak force, with a frozen partner and a
    rigid body (fix rigid, rigid/small); the m* of both masses would be off by ~30 %."""
    fmt = dict(x2=R1 + R2 + 2e-5, x3=R1 + 3 * R2 + 2e-5, d1=2 * R1, d2=2 * R2, v=0.5, vt=0.1)
    forces = {}
    for style in ("granular", "viscontact"):
        out = f"mass.{case}.{style}"
        proc = run_lmp(_MASS.format(plugin=plugin_line(), pair=_tsuji_pair(style),
                                    fixes=MASS_CASES[case], out=out, **fmt), tmp_path,
                       name=f"in.{out}")
        assert_ok(proc)
        forces[style] = _frames(tmp_path / out)
    ref, got = forces["granular"], forces["viscontact"]
    peak = np.abs(ref).max()
    assert peak > 0 and np.count_nonzero(np.abs(ref[:, 0, 0]) > 0.1 * peak) >= 3  # in contact
    assert np.abs(got - ref).max() <= 1e-10 * peak, np.abs(got - ref).max() / peak


def test_wall_effective_mass_of_a_rigid_body_as_native(tmp_path):
    """A rigid body of two spheres falls onto a floor: fix viscontact/wall with Ts alpha (m* =
    the body's mass) against native fix wall/gran tsuji, forces on every dumped step to 1e-10
    of the peak (wall_material E NU particle E NU is native's one-material wall)."""
    from viscontact.audit.formulas import tsuji_polynomial

    walls = {
        "granular": (f"fix w all wall/gran granular hertz/material {E} {E_TSUJI} {NU} damping tsuji "
                     f"tangential mindlin NULL 0 0.5 zplane {-R2 - 1e-5!r} NULL"),
        "viscontact": (f"fix w all viscontact/wall zplane {-R2 - 1e-5!r} NULL wall_material {E} "
                       f"{NU} damping Ts alpha {tsuji_polynomial(E_TSUJI)!r} vref 1 tangential "
                       f"mindlin 0.5 particle {E} {NU}"),
    }
    forces = {}
    for style, wall in walls.items():
        out = f"wallmass.{style}"
        script = _MASS.format(plugin=plugin_line(), x2=0.005, x3=0.005 + 2 * R2, d1=2 * R1,
                              d2=2 * R2, v=0.0, vt=0.0, out=out,
                              pair="pair_style zero 0.01\npair_coeff * *",
                              fixes=("set group bc vz -0.5 vx 0.1\nfix rb bc rigid single\n"
                                     + wall))
        proc = run_lmp(script.replace("create_atoms 1 single 0 0 0\n",
                                      "create_atoms 1 single 0 0 0.01\n"), tmp_path,
                       name=f"in.{out}")
        assert_ok(proc)
        forces[style] = _frames(tmp_path / out)
    ref, got = forces["granular"], forces["viscontact"]
    peak = np.abs(ref).max()
    assert peak > 0 and np.count_nonzero(np.abs(ref[:, 1, 2]) > 0.1 * peak) >= 3
    assert np.abs(got - ref).max() <= 1e-10 * peak, np.abs(got - ref).max() / peak


_SHOT = sphere_head("f f f", "-0.02 0.02 -0.02 0.02 -0.02 0.02") + """\
create_atoms 1 single 0 0 {z1:.17g}
set atom 1 diameter {d:.17g} density {rho} vz {v:.17g}
{target}
pair_style viscontact
pair_coeff * * hertz/material {E} {nu} damping KK alpha {alpha!r} vref {vref} tangential none
group a id 1
fix 1 a nve/sphere
timestep {dt:.17g}
neighbor 0.0001 bin
run {steps}
print "VZ $(vz[1]:%.17g)"
"""


@pytest.mark.parametrize("target", ["frozen", "wall"])
def test_target_e_on_frozen_sphere_and_wall(tmp_path, target):
    """A sphere dropped at vref on a frozen sphere of the same size, and on a rigid wall,
    rebounds with the target e = 0.8 to 1e-3 (alpha from viscontact.alpha_from_e; m* = m of
    the moving sphere in both).  The m* of both masses gave e = 0.843 on the frozen sphere."""
    import viscontact

    e_target, vref, r = 0.8, 1.0, 0.001
    alpha = float(viscontact.alpha_from_e("KK", e_target))
    mass = 4 / 3 * math.pi * r**3 * RHO
    k = 4 / 3 * (E / (2 * (1 - NU**2)) if target == "frozen" else E / (1 - NU**2)) * math.sqrt(
        r / 2 if target == "frozen" else r)
    tc = 3.22 * (mass / k) ** 0.4 * vref**-0.2
    dt = tc / 2000
    if target == "frozen":
        tgt = ("create_atoms 1 single 0 0 0\nset atom 2 diameter {d} density {rho}\ngroup b id 2\n"
               "fix fz b freeze").format(d=2 * r, rho=RHO)
    else:
        tgt = f"fix w all viscontact/wall zplane {-r:.17g} NULL wall_material rigid damping KK alpha {alpha!r} vref {vref} tangential none"
    z1 = 2 * r + 1e-6 if target == "frozen" else 1e-6
    proc = run_lmp(_SHOT.format(plugin=plugin_line(), z1=z1, d=2 * r, rho=RHO, v=-vref,
                                target=tgt, E=E, nu=NU, alpha=alpha, vref=vref, dt=dt,
                                steps=int(3 * tc / dt)), tmp_path)
    assert_ok(proc)
    vz = float(re.search(r"^VZ (\S+)", proc.stdout, re.M).group(1))
    assert vz / vref == pytest.approx(e_target, abs=1e-3)


# ---------------------------------------------------------------------------- units (item 6)
#: one collision in SI, and the factors (length, mass, time) to another style's units
UNITS = {"si": (1.0, 1.0, 1.0), "cgs": (100.0, 1000.0, 1.0), "lj": (1 / 0.002, 1 / 1e-5, 1 / 1e-4),
         "micro": (1e6, 1e15, 1e6), "nano": (1e9, 1e21, 1e9)}
_UNIT_SHOT = sphere_head("f f f", "{lo:.17g} {hi:.17g} {lo:.17g} {hi:.17g} {lo:.17g} {hi:.17g}",
                         units="{units}") + """\
create_atoms 1 single 0 0 {z1:.17g}
create_atoms 1 single 0 {y2:.17g} {z1:.17g}
set group all diameter {d:.17g} density {rho:.17g}
set atom 1 vz {v:.17g}
set atom 2 vy {vneg:.17g}
create_atoms 1 single 0 {y3:.17g} {z1:.17g}
set atom 3 diameter {d:.17g} density {rho:.17g}
group moving id 1 2
group fixed id 3
pair_style viscontact
pair_coeff * * hertz/material {E:.17g} {nu} damping KK alpha 0.4 vref {vref:.17g} tangential none
fix w moving viscontact/wall zplane {zw:.17g} NULL wall_material rigid damping KK alpha 0.4 vref {vref:.17g} tangential none
fix fz fixed freeze
fix 1 all nve/sphere
neighbor {skin:.17g} bin
timestep {dt:.17g}
run {steps}
print "E $(vz[1]/{v:.17g}:%.17g) $(vy[2]/{vneg:.17g}:%.17g)"
"""


def test_same_collision_in_every_units_style(tmp_path):
    """A sphere on a rigid wall and a sphere on a frozen sphere, with inputs converted from SI
    to cgs, lj (sigma = 2 mm, m = 1e-5 kg, tau = 1e-4 s), micro and nano: the dimensionless
    rebound e = -v_out/v_in is the same to 1e-9 (the wall refused lj and cgs before)."""
    r, v, dt, steps = 0.001, -1.0, 1e-7, 8000
    res = {}
    for units, (L, M, T) in UNITS.items():
        fmt = dict(units=units, lo=-0.02 * L, hi=0.02 * L, z1=(r + 1e-5) * L,
                   y2=0.01 * L, y3=(0.01 + 2 * r + 1e-5) * L, d=2 * r * L, rho=RHO * M / L**3,
                   v=v * L / T, vneg=-v * L / T, E=E * M / (L * T**2), nu=NU, vref=1.0 * L / T, zw=0.0,
                   skin=1e-4 * L, dt=dt * T, steps=steps)
        proc = run_lmp(_UNIT_SHOT.format(plugin=plugin_line(), **fmt), tmp_path,
                       name=f"in.units.{units}")
        assert_ok(proc)
        res[units] = tuple(map(float, re.search(r"^E (\S+) (\S+)", proc.stdout, re.M).groups()))
    wall_e, pair_e = res["si"]
    assert 0.3 < -wall_e < 0.95 and 0.3 < -pair_e < 0.95, res  # rebounded, damped
    for units, got in res.items():
        assert got == pytest.approx(res["si"], rel=1e-9), (units, got, res["si"])


# ----------------------------------------------------------------------------- heat (item 7)
def test_heat_flow_with_the_pair_is_an_error(tmp_path):
    """fix heat/flow needs a pair that conducts heat: pair viscontact does not, so the input
    stops with one ERROR line (it used to run and conduct nothing)."""
    script = _cut_script(CUT_CASES["mono"][0], _pair_lines("viscontact"),
                         "fix p all property/atom temperature heatflow\n"
                         "set group all temperature 300\nfix h all heat/flow constant 1")
    proc = run_lmp(script, tmp_path)
    errs = error_lines(proc)
    assert proc.returncode != 0 and len(errs) == 1, errs
    assert "pair viscontact does not conduct heat; fix h (heat/flow)" in errs[0], errs
