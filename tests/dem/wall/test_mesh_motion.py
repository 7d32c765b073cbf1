"""A moving ``fix viscontact/wall ... mesh FILE`` (``move`` and ``rotate`` as a LAMMPS
region's), its output, its history across ranks and restart files.

* Moving mesh against moving region: a flat grid mesh of 8192 triangles and a LAMMPS
  ``region plane`` with the same motion, side by side in one LAMMPS (each its own copy of the
  spheres): a turntable (rotation about a vertical axis off the origin while the plate
  oscillates up and down) and a seesaw (a tilt oscillating about x while the plate slides
  along x).  The wall's velocity at each contact (translation + omega x arm) enters the
  damping and tangential models: forces and torques equal the region wall's to 1e-10 of the
  largest, positions to 1e-8 of the largest displacement, after 1000, 2000 and 3000 steps.
* Output: the fix's global vector 4-6 is the torque of the spheres on the mesh about its
  rotation point, here compared with the sum of (x_c - P) x (-F) over the spheres' contacts;
  ``vtk N FILE`` writes the mesh with the force on each triangle, which sums to the total.
* 1 against 2 ranks (``processors 2 1 1``, spheres rolling across the boundary on the
  turning mesh) and a restart in the middle: the same motion to 1e-10 (each atom's wall force
  depends on that atom alone; the history travels with it and through the restart file).

Real LAMMPS: one in-process instance, four short ``lmp`` runs.
"""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import assert_ok, needs_lammps, needs_mpirun, plugin_line, read_atoms, run_lmp
from mesh_util import grid, sphere_lines, write_stl

pytestmark = needs_lammps

from viscontact.dem import plugin as _plugin  # noqa: E402

E, NU, RHO, R = 1.0e7, 0.3, 2500.0, 0.005
MODEL = ("damping LH c0 0.05 tangential mindlin NULL 0.5 0.4 rolling sds 50 0.02 0.1 "
         "twisting marshall")
GRID = (-0.0625, -0.0625, 64, 0.001953125)    # exact in float32
#: name -> (variables, motion words (region and mesh alike))
MOTIONS = {
    "turntable": (["variable spin equal 20*time", "variable dz equal 1e-5*sin(2*PI*time/2e-3)"],
                  "move NULL NULL v_dz rotate v_spin 0.003 -0.002 0 0 0 1"),
    "seesaw": (["variable tilt equal 0.2*sin(2*PI*time/4e-3)", "variable dx equal 0.5*time"],
               "move v_dx NULL NULL rotate v_tilt 0 0 0 1 0 0"),
}
SPHERES = [((-0.004, 0.0, R - 2e-6), (1.0, 0.0, 0.0), (0.0, 0.0, 0.0)),
           ((0.002, 0.003, R - 1e-6), (-0.3, 0.8, 0.0), (0.0, 0.0, 50.0)),
           ((0.006, -0.005, R - 3e-6), (0.0, -0.6, 0.0), (0.6 / R, 0.0, 0.0))]
COLUMNS = ("x", "v", "f", "omega", "torque")


def _sphere_lines(first: int) -> list[str]:
    return sphere_lines(first, SPHERES, R, RHO)


def _wall(fid: str, group: str, geom: str) -> str:
    return (f"fix {fid} {group} viscontact/wall {geom} wall_material {E!r} {NU} {MODEL} "
            f"particle {E!r} {NU}")


def test_moving_mesh_is_the_moving_region(tmp_path):
    mesh = write_stl(tmp_path / "grid.stl", grid(*GRID))
    vtk = tmp_path / "mesh_*.vtk"
    cmds = ["units si", "atom_style sphere", "atom_modify map array sort 0 0.0",
            "boundary f f f", "region box block -0.1 0.1 -0.1 0.1 -0.05 0.1",
            "create_box 1 box", "pair_style zero 0.02", "pair_coeff * *",
            "neigh_modify exclude type 1 1"]
    n = len(SPHERES)
    for j, (name, (variables, motion)) in enumerate(MOTIONS.items()):
        cmds += variables
        cmds += [f"region plate{j} plane 0 0 0 0 0 1 side in {motion}"]
        for impl, k in (("region", 2 * j), ("mesh", 2 * j + 1)):
            cmds += _sphere_lines(k * n + 1)
            cmds.append(f"group g{k} id {k * n + 1}:{(k + 1) * n}")
            geom = (f"region plate{j}" if impl == "region"
                    else f"mesh {mesh} {motion}" + (f" vtk 1000 {vtk}" if j == 0 else ""))
            cmds.append(_wall(f"w{k}", f"g{k}", geom))
    cmds += ["fix grav all gravity 200 vector 0 0 -1", "fix nve all nve/sphere",
             "timestep 1e-6", "thermo 0"]
    lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
    try:
        for c in cmds:
            lmp.command(c)
        x0 = np.array(lmp.numpy.extract_atom("x")[:4 * n], dtype=float)
        for chunk in range(3):
            # pre no: a second run's setup changes the region wall's motion by 1e-6 relative
            # (measured: one run of 2000 steps against two of 1000), the mesh's by 1e-9
            lmp.command("run 1000 post no" + (" pre no" if chunk else ""))
            st = {c: np.array(lmp.numpy.extract_atom(c)[:4 * n], dtype=float).reshape(2, 2, n, 3)
                  for c in COLUMNS}
            disp = np.abs(st["x"].reshape(-1, 3) - x0).max()
            for j in range(2):
                for c in COLUMNS:
                    ref, got = st[c][j, 0], st[c][j, 1]
                    scale = disp if c == "x" else np.abs(ref).max()
                    tol = 1e-8 if c == "x" else 1e-10
                    np.testing.assert_allclose(got, ref, rtol=0, atol=tol * scale,
                                               err_msg=f"{list(MOTIONS)[j]} {c} chunk {chunk}")
            assert np.abs(st["torque"]).max() > 0
            # output: the torque on the turntable mesh about P + d, from the spheres' forces
            tq = np.array([lmp.extract_fix("w1", 0, 1, k) for k in range(6)])
            f_wall = st["f"][0, 1] - np.array([0.0, 0.0, -200.0]) * _masses(lmp, n, n)[:, None]
            arm = st["x"][0, 1] - np.array([0.003, -0.002, 0.0])
            arm[:, 2] = 0.0    # the contact points lie in the horizontal plate, as P + d does
            np.testing.assert_allclose(tq[:3], f_wall.sum(axis=0), rtol=1e-12, atol=1e-15)
            np.testing.assert_allclose(tq[3:], -np.cross(arm, f_wall).sum(axis=0), rtol=0,
                                       atol=1e-10 * np.abs(tq[3:]).max())
    finally:
        lmp.close()
    frame = tmp_path / "mesh_3000.vtk"
    text = frame.read_text().split("CELL_DATA")[1].splitlines()[2:]
    load = np.array([[float(v) for v in ln.split()] for ln in text])
    assert load.shape == (2 * 64 * 64, 3)
    np.testing.assert_allclose(load.sum(axis=0), -tq[:3], rtol=1e-9)


def _masses(lmp, first: int, n: int) -> np.ndarray:
    return np.array(lmp.numpy.extract_atom("rmass")[first:first + n], dtype=float)


_RANKS = """{plugin}
units si
atom_style sphere
atom_modify map array
boundary f f f
comm_modify vel yes
processors * 1 1
{start}
pair_style zero 0.02
pair_coeff * *
neigh_modify exclude type 1 1
variable spin equal 3*time
variable dz equal 1e-5*sin(2*PI*time/2e-3)
{wall}
fix grav all gravity 200 vector 0 0 -1
fix nve all nve/sphere
timestep 1e-6
thermo 0
{body}
write_dump all custom {out} id x y z vx vy vz omegax omegay omegaz modify sort id format float %.17g
"""


def _ranks_run(d, out, body, *, np_=1, start=None):
    mesh = write_stl(d / "grid.stl", grid(*GRID))
    if start is None:
        lines = ["region box block -0.1 0.1 -0.1 0.1 -0.05 0.1", "create_box 1 box"]
        for k in range(12):    # rolling across x = 0 both ways, far apart
            side = 1 if k % 2 else -1
            x = (-side * 0.0015, -0.05 + 0.009 * k, R - 1e-6 * (1 + k % 3))
            v = (side * 0.8, 0.1 * (k % 3 - 1), 0.0)
            w = (0.0, side * 0.8 / R, 10.0 * (k % 4))
            lines += ["create_atoms 1 single {!r} {!r} {!r}".format(*x),
                      f"set atom {k + 1} diameter {2 * R!r} density {RHO!r}",
                      "set atom {} vx {!r} vy {!r} vz {!r}".format(k + 1, *v),
                      "set atom {} omega {!r} {!r} {!r}".format(k + 1, *w)]
        start = "\n".join(lines)
    wall = _wall("w", "all", f"mesh {mesh} move NULL NULL v_dz rotate v_spin 0 0 0 0 0 1")
    script = _RANKS.format(plugin=plugin_line(), start=start, wall=wall, body=body, out=out)
    proc = run_lmp(script, d, np=np_, name=f"in.{out}")
    assert_ok(proc)
    return read_atoms(d / out)


def _rel_diff(a, b) -> float:
    return max(float(np.max(np.abs(a[c] - b[c])) / max(np.max(np.abs(a[c])), 1e-300))
               for c in ("x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz"))


@needs_mpirun
def test_ranks_and_restart(tmp_path):
    """1 rank and 2 ranks: equal; two runs of 1000 steps, and the same with a restart file
    between them: equal (a run's setup re-evaluates the stored contacts, so the reference for
    the restart is the run split in two)."""
    one = _ranks_run(tmp_path, "one.dump", "run 2000")
    two = _ranks_run(tmp_path, "two.dump", "run 2000", np_=2)
    assert np.sum(np.sign(one["x"]) != np.sign(np.where(np.arange(12) % 2, -1.0, 1.0))) >= 10
    assert _rel_diff(one, two) < 1e-10
    _ranks_run(tmp_path, "half.dump", "run 1000\nwrite_restart half.restart")
    again = _ranks_run(tmp_path, "again.dump", "run 1000", start="read_restart half.restart")
    split = _ranks_run(tmp_path, "split.dump", "run 1000\nrun 1000")
    assert _rel_diff(split, again) < 1e-10
