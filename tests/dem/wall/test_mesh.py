"""``fix viscontact/wall ... mesh FILE``: a triangle-mesh wall against the analytic walls it
must reproduce, and the contact rule at edges and vertices (docs/fix_viscontact_mesh.md);
bad meshes and keywords are in test_mesh_errors.py.

* Flat meshes (2 triangles; a 16 x 16 grid of 512 triangles, six around each inner vertex)
  against ``zplane``: spheres sliding and rolling along a grid line (across the shared edges
  and the six-triangle vertices on it), along the split diagonals (along shared edges) and on
  a generic path, for every sub-model (tangential kinds, rolling, twisting, dmt, jkr, KK, Ts):
  positions, velocities, forces, torques and the energy columns equal the plane's to 1e-12 of
  the largest after each of three chunks (a history that differed would change the forces).
* Convex edge and vertex (a roof, a pyramid): a sphere rolling over them feels one contact;
  the largest step-to-step change of its wall force is at most twice the largest on the flat
  mesh at the same speed (naively summing the faces would double the force at the ridge).
* A polygonal tube of N faces against ``zcylinder``: the distance from a pressed sphere to the
  mesh converges to the cylinder's as N^-2 (the faces' corners lie on the circle; the gap is
  R (1 - cos(pi/N))).  The force converges to the flat-face value: the faces are flat
  (R* = r) where zcylinder takes native's curvature radius -2R.
* A closed box of 12 triangles against six plane walls: a settle of 27 spheres (pair forces,
  concave corners with three contacts) agrees.
* The energy balance closes with spheres thrown over the roof and the pyramid: the residual
  of kinetic + rotational + gravitational + elastic + dissipated shrinks at least twofold when
  dt halves.

Real LAMMPS, in-process (few starts, short runs).
"""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import needs_lammps
from mesh_util import box, grid, pyramid, roof, sphere_lines, tube, write_stl

pytestmark = needs_lammps

from viscontact.dem import plugin as _plugin  # noqa: E402

E, NU, RHO, R = 1.0e7, 0.3, 2500.0, 0.005
C0 = 0.05
DT = 1e-6
M = 4.0 / 3.0 * np.pi * R**3 * RHO
TOL = 1e-12


def _models() -> dict[str, str]:
    """name -> our wall model words (every sub-model family)."""
    lh = f"damping LH c0 {C0}"
    out = {}
    for tang in ("linear_nohistory 0.5 0.4", "linear_history 2000 0.5 0.4",
                 "mindlin NULL 0.5 0.4", "mindlin_rescale NULL 0.5 0.4",
                 "mindlin/force NULL 0.5 0.4", "mindlin_rescale/force 8e6 0.5 0.05"):
        out[tang] = f"{lh} end force tangential {tang}"
    spin = "tangential mindlin NULL 0.5 0.4 rolling sds 50 0.02 0.1"
    out["rolling twisting marshall"] = f"{lh} end force {spin} twisting marshall"
    out["slipping rolling twisting sds"] = (
        f"{lh} end overlap tangential linear_history 2000 0.5 0.05 rolling sds 5000 0.02 0.001 "
        "twisting sds 1 1e-6 1e-5")
    out["dmt"] = f"normal dmt 0.05 {lh} tangential mindlin NULL 0.5 0.4 rolling sds 50 0.02 0.1"
    out["jkr"] = f"normal jkr 0.05 {lh} tangential mindlin NULL 0.5 0.4 rolling sds 50 0.02 0.1"
    out["KK"] = (f"damping KK c0 {float(3000.0 * M * np.sqrt(R))!r} tangential linear_history "
                 "2000 0.5 0.4 twisting marshall")
    out["Jian"] = "damping Jian c0 0.05 tau 1e-4 tangential mindlin NULL 0.5 0.4"
    return out


#: (x, v, omega) of the spheres on the flat meshes: along the grid line y = 0 (rolling), along
#: the split diagonal y = x (sliding), a generic path (rolling and spinning), and one lifting
#: off (jkr: until pull-off); z a little below R (pressed by gravity)
PATHS = [((-0.0123, 0.0, R - 2e-6), (1.5, 0.0, 0.0), (0.0, 1.5 / R, 0.0)),
         ((-0.011, -0.011, R - 1e-6), (1.0, 1.0, 0.0), (0.0, 0.0, 0.0)),
         ((0.0031, -0.0047, R - 3e-6), (0.7, 1.2, 0.0), (-1.2 / R, 0.7 / R, 40.0)),
         ((0.0072, 0.0093, R - 1e-6), (-0.4, 0.3, 0.2), (10.0, 0.0, 0.0))]
GRAVITY = 200.0


def _head() -> list[str]:
    return ["units si", "atom_style sphere", "atom_modify map array sort 0 0.0", "boundary f f f",
            "region box block -0.1 0.1 -0.1 0.1 -0.05 0.1", "create_box 1 box",
            "pair_style zero 0.02", "pair_coeff * *", "neighbor 0.001 bin",
            "neigh_modify exclude type 1 1"]


def _atoms(first: int, paths) -> list[str]:
    return sphere_lines(first, paths, R, RHO)


def _state(lmp, n: int) -> dict[str, np.ndarray]:
    out = {}
    for name in ("x", "v", "f", "omega", "torque"):
        out[name] = np.array(lmp.numpy.extract_atom(name)[:n], dtype=float)
    return out


def _groups(lmp, walls: list[tuple[str, str]], paths, steps: list[int], extra=()) -> list[dict]:
    """One in-process LAMMPS: each wall line (``fix ID GROUP viscontact/wall ...`` with GROUP
    a placeholder ``{g}``) acts on its own copy of the spheres of ``paths`` (no forces between
    spheres); after each chunk of ``steps``: the state of every copy and the energy columns."""
    cmds = _head()
    for j in range(len(walls)):
        cmds += _atoms(j * len(paths) + 1, paths)
        cmds.append(f"group g{j} id {j * len(paths) + 1}:{(j + 1) * len(paths)}")
    for j, (name, line) in enumerate(walls):
        cmds.append(line.format(g=f"g{j}", id=f"w{j}"))
        cmds.append(f"compute e{j} g{j} viscontact/energy")
    cmds += [f"fix grav all gravity {GRAVITY} vector 0 0 -1", "fix nve all nve/sphere",
             f"timestep {DT!r}", "thermo 0", *extra]
    for c in cmds:
        lmp.command(c)
    n = len(walls) * len(paths)
    out = []
    for s in steps:
        lmp.command(f"run {s} post no")
        st = _state(lmp, n)
        st["energy"] = np.array([[lmp.extract_compute(f"e{j}", 0, 1)[k] for k in range(12)]
                                 for j in range(len(walls))])
        out.append(st)
    return out


def _assert_copies_equal(states, ncopies: int, nper: int, ref: int = 0, tol: float = TOL):
    for st in states:
        for name in ("x", "v", "f", "omega", "torque"):
            a = st[name].reshape(ncopies, nper, 3)
            scale = max(np.abs(a[ref]).max(), 1e-300)
            if name == "x":
                scale = R
            for j in range(ncopies):
                np.testing.assert_allclose(a[j], a[ref], rtol=0, atol=tol * scale,
                                           err_msg=f"{name} of copy {j}")
        e = st["energy"]
        np.testing.assert_allclose(e, np.broadcast_to(e[ref], e.shape), rtol=0,
                                   atol=tol * max(np.abs(e[ref]).max(), 1e-300))


def _line(geom: str, model: str) -> str:
    return (f"fix {{id}} {{g}} viscontact/wall {geom} wall_material {E!r} {NU} {model} "
            f"particle {E!r} {NU}")


@pytest.fixture(scope="module")
def flat_meshes(tmp_path_factory):
    d = tmp_path_factory.mktemp("flat")
    two = write_stl(d / "two.stl", [((-0.08, -0.08, 0.0), (0.08, -0.08, 0.0), (0.08, 0.08, 0.0)),
                                    ((-0.08, -0.08, 0.0), (0.08, 0.08, 0.0), (-0.08, 0.08, 0.0))],
                    binary=False)
    many = write_stl(d / "grid.stl", grid(-0.0625, -0.0625, 16, 0.0078125))
    return two, many


def test_flat_mesh_is_the_plane(flat_meshes):
    """Every sub-model (one LAMMPS, a copy of the spheres per model and wall): the
    two-triangle and the 512-triangle meshes give the plane's motion, forces, torques and
    energy to 1e-12 (three chunks of 1500 steps: every sphere crosses several edges, the first
    and second along edges and through six-triangle vertices)."""
    two, many = flat_meshes
    models = list(_models().items())
    n = len(PATHS)
    for batch in (models[:6], models[6:]):    # at most 32 groups in one LAMMPS
        walls = []
        for _, words in batch:
            walls += [("plane", _line("zplane 0.0 NULL", words)),
                      ("two", _line(f"mesh {two}", words)), ("grid", _line(f"mesh {many}", words))]
        lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
        try:
            states = _groups(lmp, walls, PATHS, [1500, 1500, 1500])
        finally:
            lmp.close()
        for k, (model, _) in enumerate(batch):
            sub = [{name: (st[name][3 * k * n:3 * (k + 1) * n] if name != "energy"
                           else st[name][3 * k:3 * k + 3]) for name in st} for st in states]
            _assert_copies_equal(sub, 3, n)
            assert np.abs(sub[-1]["torque"]).max() > 0, model


# ---- convex edge and vertex: one continuous contact; the energy balance -----------------------

SLOPE = 0.05
#: a rolling sphere's start on each surface: (wall, x0 of the contact point, direction in xy)
ROLLERS = {"flat": (-0.004, (1.0, 0.0)), "roof": (-0.004, (1.0, 0.0)),
           "pyramid": (-0.004, (1.0, 0.3))}
SPEED = 0.45


def _surface(name: str, x: float, y: float) -> tuple[float, np.ndarray]:
    """Height and unit normal of the roof / pyramid / flat surface at (x, y), x < 0 side."""
    if name == "flat":
        return 0.0, np.array([0.0, 0.0, 1.0])
    if name == "roof":
        z = SLOPE * (0.03 + x)
    else:    # the pyramid face x < -|y| (half 0.02, apex height 0.02 SLOPE)
        z = SLOPE * (0.02 + x)
    n = np.array([-SLOPE, 0.0, 1.0])
    return z, n / np.linalg.norm(n)


def _roll_over(d, dt: float, steps: int, every: int) -> dict[str, np.ndarray]:
    """A sphere rolling (gravity 200 m/s^2 keeps it on the surface) on the flat mesh, over the
    roof's ridge and over the pyramid's apex, from the same start (a face, 4 mm before the top,
    0.45 m/s, 80 % of the resting overlap), one LAMMPS, one copy each; every ``every``
    steps: forces on each sphere and the energy of each copy (total and dissipated)."""
    meshes = {"flat": write_stl(d / "flat.stl", grid(-0.0625, -0.0625, 16, 0.0078125)),
              "roof": write_stl(d / "roof.stl", roof(0.03, SLOPE, 0.05)),
              "pyramid": write_stl(d / "pyramid.stl", pyramid(0.02, 0.02 * SLOPE))}
    model = "damping LH c0 0.05 tangential mindlin NULL 0.5 0.4 twisting marshall"
    k_hertz = 4.0 / 3.0 * E / (2 * (1 - NU**2)) * np.sqrt(R)
    cmds = _head()
    for j, (name, (x0, direc)) in enumerate(ROLLERS.items(), 1):
        u = np.array([*direc, 0.0]) / np.hypot(*direc)
        y0 = x0 * u[1] / u[0]
        z, n = _surface(name, x0, y0)
        # 80 % of the resting overlap: the same small normal oscillation on every surface
        delta = 0.8 * (M * GRAVITY * n[2] / k_hertz) ** (2.0 / 3.0)
        x = np.array([x0, y0, z]) + (R - delta) * n
        t = u - np.dot(u, n) * n
        v = SPEED * t / np.linalg.norm(t)
        w = np.cross(n, v) / R
        cmds += _atoms(j, [tuple(tuple(map(float, a)) for a in (x, v, w))])
        cmds += [f"group g{j} id {j}",
                 _line(f"mesh {meshes[name]}", model).format(id=f"w{j}", g=f"g{j}"),
                 f"compute e{j} g{j} viscontact/energy"]
    cmds += [f"fix grav all gravity {GRAVITY} vector 0 0 -1", "fix nve all nve/sphere",
             f"timestep {dt!r}", "thermo 0", "run 0 post no"]
    lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
    forces, total, diss = [], [], []
    try:
        for c in cmds:
            lmp.command(c)
        for s in range(steps // every + 1):
            if s:
                lmp.command(f"run {every} pre no post no")
            forces.append(np.array(lmp.numpy.extract_atom("f")[:3], dtype=float))
            x = np.array(lmp.numpy.extract_atom("x")[:3], dtype=float)
            v = np.array(lmp.numpy.extract_atom("v")[:3], dtype=float)
            w = np.array(lmp.numpy.extract_atom("omega")[:3], dtype=float)
            e = np.array([[lmp.extract_compute(f"e{j}", 0, 1)[k] for k in (0, 7)]
                          for j in (1, 2, 3)])
            energy = (0.5 * M * np.sum(v * v, axis=1) + 0.2 * M * R**2 * np.sum(w * w, axis=1)
                      + M * GRAVITY * x[:, 2] + e[:, 0] + e[:, 1])
            total.append(energy)
            diss.append(e[:, 0])
            xs = x
    finally:
        lmp.close()
    return {"f": np.array(forces), "total": np.array(total), "diss": np.array(diss), "x": xs}


def test_convex_edge_and_vertex_are_continuous(tmp_path):
    """Rolling over the roof's ridge and the pyramid's apex: the largest step-to-step change
    of the wall force is at most twice the largest on the flat mesh; the spheres did cross."""
    run = _roll_over(tmp_path, 1e-5, 3000, 1)
    jump = np.linalg.norm(np.diff(run["f"], axis=0), axis=2).max(axis=0)
    assert run["x"][1, 0] > 0.004 and run["x"][2, 0] > 0.004, run["x"]    # over the top
    assert np.all(np.linalg.norm(run["f"][:, 1:], axis=2) > 0)             # never lost contact
    assert jump[1] <= 2 * jump[0], jump
    assert jump[2] <= 2 * jump[0], jump


def test_energy_balance_over_edges(tmp_path):
    """Kinetic + rotational + gravitational + elastic + dissipated over the roof and the
    pyramid: the end residual relative to the dissipated energy shrinks at least twofold when
    dt halves (a contact counted twice or lost at an edge would leave a residual that does
    not shrink)."""
    res = []
    for dt in (2e-5, 1e-5):
        run = _roll_over(tmp_path, dt, int(0.03 / dt), int(0.03 / dt) // 4)
        res.append(np.abs(run["total"][-1] - run["total"][0]) / run["diss"][-1])
    assert np.all(res[0][1:] < 1e-2), res
    assert np.all(res[1][1:] <= res[0][1:] / 2), res


# ---- a polygonal tube against zcylinder; a closed box against six planes ----------------------

CYL = 0.05
TUBE_FACES = (64, 128, 256, 512, 1024)


def test_tube_converges_to_zcylinder(tmp_path):
    """A sphere pressed 0.1 mm into the cylinder at a face centre: the distance from its centre
    to the mesh is the cylinder's less R (1 - cos(pi/N)) (to 1e-12), and the force converges as
    N^-2 (log-log slope in [-2.2, -1.8]; each value the Hertz force (1 + gap/delta)^1.5 of the
    limit to 1e-10) to the flat-face value, sqrt(r / R*) of zcylinder's with its
    R* = 2 R r / (2 R - r) (0.9747 for r/R = 0.1).  Measured relative force error against
    that limit: 1.03, 0.234, 0.0570, 0.0142, 0.00353 for N = 64, 128, 256, 512, 1024."""
    delta = 1e-4
    x = (CYL - R + delta, 0.0, 0.0)
    model = "damping LH c0 0.05 tangential none"
    walls = [("cyl", _line("zcylinder 0.05", model) + " contacts")]
    for n in TUBE_FACES:
        path = write_stl(tmp_path / f"tube{n}.stl", tube(CYL, n, -0.05, 0.05), binary=False)
        walls.append((f"tube{n}", _line(f"mesh {path}", model) + " contacts"))
    cmds = [c.replace("-0.05 0.1", "-0.1 0.1") for c in _head()]
    for j, (_, line) in enumerate(walls):
        cmds += _atoms(j + 1, [(x, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))])
        cmds += [f"group g{j} id {j + 1}", line.format(id=f"w{j}", g=f"g{j}")]
    cmds += ["run 0 post no"]
    lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
    try:
        for c in cmds:
            lmp.command(c)
        f = np.array(lmp.numpy.extract_atom("f")[:len(walls)], dtype=float)[:, 0]
        dist = []
        for j in range(len(walls)):
            contact = np.array(lmp.numpy.extract_fix(f"w{j}", 1, 2))[j]
            assert contact[0] == 1.0
            dist.append(float(np.linalg.norm(np.array(x) - contact[4:7])))
    finally:
        lmp.close()
    n = np.array(TUBE_FACES, dtype=float)
    gap = CYL * (1 - np.cos(np.pi / n))
    np.testing.assert_allclose(dist[0] - np.array(dist[1:]), gap, rtol=1e-6, atol=1e-12 * CYL)
    reff_cyl = 2 * CYL * R / (2 * CYL - R)
    limit = f[0] * np.sqrt(R / reff_cyl)
    err = np.abs(f[1:] / limit - 1)
    slope = np.polyfit(np.log(n), np.log(err), 1)[0]
    assert -2.2 <= slope <= -1.8, (err, slope)
    # Hertz at rest, closed form: the mesh's overlap is delta + gap
    np.testing.assert_allclose(f[1:] / limit, (1 + gap / delta) ** 1.5, rtol=1e-10)


def test_shallow_concave_crease_is_one_contact(tmp_path):
    """A sphere pressed into the 64-face tube (facets 5.6 degrees apart) at angles from a face
    centre across a crease to the next centre (81 samples): the force's size is largest at the
    centres, smallest on the crease, and its largest change between samples is at most twice
    the largest away from the crease (measured 1.1 x: continuous, with a kink; the two faces
    at the crease give one contact, the deepest).  With ``crease 0`` (every face its own
    contact) the force jumps there by more than 10 x the changes elsewhere."""
    path = write_stl(tmp_path / "tube64.stl", tube(CYL, 64, -0.05, 0.05), binary=False)
    rho = CYL - R + 2e-4
    phis = np.linspace(0.0, 2 * np.pi / 64, 81)
    sizes = {}
    for crease in ("", " crease 0"):
        lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
        try:
            for c in [*[c.replace("-0.05 0.1", "-0.1 0.1") for c in _head()],
                      *_atoms(1, [((rho, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))]),
                      _line(f"mesh {path}{crease}", "damping LH c0 0.05 tangential none")
                      .format(id="w", g="all")]:
                lmp.command(c)
            f = []
            for phi in phis:
                lmp.command(f"set atom 1 x {float(rho * np.cos(phi))!r} y {float(rho * np.sin(phi))!r}")
                lmp.command("run 0 post no")
                f.append(float(np.linalg.norm(lmp.numpy.extract_atom("f")[0])))
        finally:
            lmp.close()
        sizes[crease] = np.array(f)
    f = sizes[""]
    assert f.max() <= max(f[0], f[-1]) * (1 + 1e-12) and f[40] == f.min()
    steps = np.abs(np.diff(f))
    away = np.r_[steps[:35], steps[45:]]    # samples away from the crease
    assert steps.max() <= 2 * away.max(), (steps.max(), away.max())
    summed = np.abs(np.diff(sizes[" crease 0"]))
    assert summed.max() > 10 * np.r_[summed[:35], summed[45:]].max()


HALF = 0.03125


def _box_settle(tmp_path, steps: int) -> list[dict[str, np.ndarray]]:
    """27 spheres (pair viscontact, friction) settling in a closed cube of 12 triangles and
    in the same cube of three plane walls (lo and hi each): the same motion to 1e-12 after
    2000 steps (measured: bitwise equal; spheres in the floor's edges touch two faces)."""
    mesh = write_stl(tmp_path / "box.stl", box(-HALF, HALF))    # binary: exact in float32
    model = "damping LH c0 0.2 tangential mindlin NULL 0.5 0.4 rolling sds 50 0.02 0.1"
    pos = [(i * 0.012, j * 0.012, k * 0.012 - 0.005) for i in (-1, 0, 1) for j in (-1, 0, 1)
           for k in (-1, 0, 1)]
    rng = np.random.default_rng(3)
    out = []
    for walls in ([f"mesh {mesh}"], [f"{d}plane {-HALF!r} {HALF!r}" for d in "xyz"]):
        cmds = _head()[:6] + ["pair_style viscontact",
                              f"pair_coeff * * hertz/material {E!r} {NU} {model}",
                              "neighbor 0.001 bin", "comm_modify vel yes"]
        vel = rng.uniform(-0.5, 0.5, (len(pos), 3))
        rng = np.random.default_rng(3)
        cmds += _atoms(1, [(p, tuple(map(float, v)), (0.0, 0.0, 0.0)) for p, v in zip(pos, vel)])
        cmds += [_line(g, model).format(id=f"w{k}", g="all") for k, g in enumerate(walls)]
        cmds += [f"fix grav all gravity {GRAVITY} vector 0 0 -1", "fix nve all nve/sphere",
                 "timestep 1e-5", "thermo 0", f"run {steps} post no"]
        lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
        try:
            for c in cmds:
                lmp.command(c)
            out.append({k: np.array(lmp.numpy.extract_atom(k)[:len(pos)], dtype=float)
                        for k in ("x", "v", "omega")})
        finally:
            lmp.close()
    return out


def test_closed_box_is_six_planes(tmp_path):
    out = _box_settle(tmp_path, 2000)
    assert out[0]["x"][:, 2].min() < -HALF + R + 1e-4    # settled on the floor
    for k in ("x", "v", "omega"):
        scale = 2 * HALF if k == "x" else np.abs(out[1][k]).max()
        np.testing.assert_allclose(out[0][k], out[1][k], rtol=0, atol=TOL * scale, err_msg=k)
