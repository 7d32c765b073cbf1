"""``fix viscontact/wall ... region ID`` where native ``fix wall/gran/region`` has behaviour that
the plane and cylinder walls do not: a region whose shape changes in time, and a sphere that
touches more faces of a region than the region allows.

* Shape in time: a sphere (side in and side out) and a z cylinder whose radius is an
  equal-style variable of time breathe against a few pressed, sliding and spinning spheres.
  The wall's velocity at a contact includes the rate of change of its size there
  (Region::velocity_contact_shape: the radius's change over the last step).  Native
  (pinned LAMMPS) adds that term only for a region that also rotates: Region::velocity_contact
  computes the contact point only when the region rotates, so a breathing region that does
  not rotate gets no shape velocity.  Ours adds it for every breathing region, so native's
  copy of the region gets a rotation by a zero angle (``rotate v_zero``), which makes native
  compute the contact point and changes nothing else.  Native and ours run side by side in
  one LAMMPS (each its own copy of the spheres and of the region; no pair forces): forces and
  torques equal native's to 1e-10 of the largest, positions and velocities to 1e-8 of the
  largest displacement and velocity, after 100, 200 and 300 steps.
* Too many faces: a sphere larger than a block (or prism) touches all 6 faces where the region
  allows 3 (native: ``Too many wallgran/region contacts for one particle``): one ``ERROR``
  line naming the atom, the region and its limit; no crash.
"""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import error_lines, needs_lammps, plugin_line, run_lmp, sphere_head

pytestmark = needs_lammps

from viscontact.dem import plugin as _plugin  # noqa: E402

E, NU, RHO, R = 1.0e7, 0.3, 2500.0, 0.005
C0, MU = 0.05, 0.4
DT, STEPS, CHUNKS = 1e-6, 100, 3
TOL_FORCE, TOL_PATH = 1e-10, 1e-8
#: the wall's radius: 50 mm breathing by 20 um with a period of 200 steps (wall speed up to
#: 0.63 m/s, faster than the spheres)
RADIUS = "0.05+2e-5*sin(2*PI*time/2e-4)"
NATIVE = (f"hertz/material {E!r} {C0} {NU} damping velocity tangential mindlin NULL 0.5 {MU} "
          "rolling sds 50 0.02 0.1 twisting marshall limit_damping")
OURS = (f"wall_material {E!r} {NU} damping LH c0 {C0} end force tangential mindlin NULL 0.5 "
        f"{MU} rolling sds 50 0.02 0.1 twisting marshall particle {E!r} {NU}")
#: name -> (region arguments after the ID, sphere centres: just inside the breathing wall)
SHAPES = {
    "sphere in": ("sphere 0 0 0 v_r side in",
                  [(0.05 - R + 1e-5, 0.0, 0.0), (0.0, -(0.05 - R + 2e-5), 0.0),
                   tuple(float(c) * (0.05 - R + 1.5e-5) for c in (0.0, 0.6, 0.8))]),
    "sphere out": ("sphere 0 0 0 v_r side out",
                   [(0.05 + R - 1e-5, 0.0, 0.0), (0.0, 0.0, -(0.05 + R - 2e-5))]),
    "cylinder in": ("cylinder z 0 0 v_r -0.1 0.1 side in",
                    [(0.05 - R + 1e-5, 0.0, 0.01), (0.0, 0.05 - R + 2e-5, -0.02)]),
}
VELOCITIES = [(0.1, 0.3, -0.05), (-0.2, 0.0, 0.1), (0.0, -0.1, 0.2)]
SPINS = [(0.0, 0.0, 5.0), (3.0, 1.0, 0.0), (0.0, -4.0, 2.0)]
COLUMNS = ("x", "v", "f", "omega", "torque")


def _side_by_side() -> list[dict[str, np.ndarray]]:
    """One in-process LAMMPS: for each shape, the spheres twice (native's copy, our copy) and
    the region twice; after each chunk of steps, per copy: positions, velocities, forces,
    spins, torques."""
    lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
    try:
        cmds = ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f",
                "comm_modify vel yes", "region box block -0.2 0.2 -0.2 0.2 -0.2 0.2",
                "create_box 1 box", f"variable r equal {RADIUS}", "variable zero equal 0*time"]
        groups = []    # (shape, first id, count)
        nid = 0
        for shape, (region, centres) in SHAPES.items():
            tag = shape.replace(" ", "_")
            for impl in ("nat", "our"):
                first = nid + 1
                for k, x in enumerate(centres):
                    nid += 1
                    cmds += ["create_atoms 1 single {!r} {!r} {!r}".format(*x),
                             f"set atom {nid} diameter {2 * R!r} density {RHO!r}",
                             "set atom {} vx {!r} vy {!r} vz {!r}".format(nid, *VELOCITIES[k]),
                             "set atom {} omega {!r} {!r} {!r}".format(nid, *SPINS[k])]
                turn = " rotate v_zero 0 0 0 0 0 1" if impl == "nat" else ""
                cmds += [f"group {impl}_{tag} id {first}:{nid}",
                         f"region {impl}_{tag} {region}{turn}"]
                line = (f"fix w{impl}_{tag} {impl}_{tag} wall/gran/region granular {NATIVE} "
                        f"region {impl}_{tag}" if impl == "nat" else
                        f"fix w{impl}_{tag} {impl}_{tag} viscontact/wall region {impl}_{tag} "
                        f"{OURS}")
                cmds.append(line)
            groups.append((shape, nid - 2 * len(centres) + 1, len(centres)))
        cmds += ["pair_style zero 0.05", "pair_coeff * *", "fix 1 all nve/sphere",
                 f"timestep {DT!r}", "run 0"]
        for c in cmds:
            lmp.command(c)
        n = nid
        frames = []
        for _ in range(CHUNKS):
            lmp.command(f"run {STEPS} pre no post no")
            order = np.argsort(np.array(lmp.numpy.extract_atom("id")[:n]))
            cols = {c: np.array(lmp.numpy.extract_atom(c)[:n])[order] for c in COLUMNS}
            frames.append({(shape, impl): {c: cols[c][first - 1 + k * cnt:first - 1 + (k + 1) * cnt]
                                           for c in COLUMNS}
                           for shape, first, cnt in groups
                           for k, impl in enumerate(("native", "ours"))})
        return frames
    finally:
        lmp.close()


@pytest.fixture(scope="module")
def frames():
    return _side_by_side()


def _start(shape: str) -> np.ndarray:
    return np.array(SHAPES[shape][1])


@pytest.mark.parametrize("shape", list(SHAPES))
def test_variable_shape_region_as_native(frames, shape):
    for k, frame in enumerate(frames, 1):
        nat, our = frame[shape, "native"], frame[shape, "ours"]
        for c in ("f", "torque"):
            peak = np.abs(nat[c]).max()
            assert peak > 0, (shape, c)
            assert np.abs(our[c] - nat[c]).max() <= TOL_FORCE * peak, (shape, k * STEPS, c)
        moved = np.abs(nat["x"] - _start(shape)).max()
        assert np.abs(our["x"] - nat["x"]).max() <= TOL_PATH * moved, (shape, k * STEPS)
        for c in ("v", "omega"):
            peak = np.abs(nat[c]).max()
            assert np.abs(our[c] - nat[c]).max() <= TOL_PATH * peak, (shape, k * STEPS, c)


def test_the_wall_velocity_is_the_shape_rate():
    """The comparison above can fail: the breathing wall's contact velocity is the rate of
    change of its radius.  Two spheres held still (no integrator) against the side-in sphere
    wall, the same overlap, one with c0 = 0: the difference of their normal forces is the
    LH damping force alone, c0 d(delta)/dt = -c0 (r_n - r_{n-1})/dt along the inward normal,
    r_n the radius at step n (LAMMPS's finite difference of the shape over one step; zero at
    the first step of the run).  A region that does not rotate (native gives it no shape
    velocity, see above)."""
    d = 0.05 - R + 4e-5    # overlap 40 um: the force stays compressive as the wall recedes
    lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
    try:
        cmds = ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f",
                "region box block -0.2 0.2 -0.2 0.2 -0.2 0.2", "create_box 1 box",
                f"variable r equal {RADIUS}", f"create_atoms 1 single {d!r} 0 0",
                f"create_atoms 1 single {d!r} 0 0",
                f"set group all diameter {2 * R!r} density {RHO!r}",
                "group a id 1", "group b id 2",
                "region ra sphere 0 0 0 v_r side in", "region rb sphere 0 0 0 v_r side in",
                f"fix wa a viscontact/wall region ra {OURS}",
                f"fix wb b viscontact/wall region rb {OURS.replace(f'c0 {C0}', 'c0 0.0')}",
                "pair_style zero 0.05", "pair_coeff * *", f"timestep {DT!r}", "run 0"]
        for c in cmds:
            lmp.command(c)
        got = []
        for _ in range(20):
            lmp.command("run 1 pre no post no")
            f = np.array(lmp.numpy.extract_atom("f")[:2])
            got.append(f[0, 0] - f[1, 0])
    finally:
        lmp.close()
    t = DT * np.arange(0, 21)
    r = 0.05 + 2e-5 * np.sin(2 * np.pi * t / 2e-4)
    want = C0 * np.diff(r) / DT    # F_x = c0 (r_n - r_{n-1})/dt: inwards while r shrinks
    assert np.abs(want).max() > 0.02
    np.testing.assert_allclose(got, want, rtol=1e-6, atol=1e-9 * np.abs(want).max())


# ---- too many faces ---------------------------------------------------------------------------

_SMALL = sphere_head("f f f", "-0.1 0.1 -0.1 0.1 -0.1 0.1") + f"""\
create_atoms 1 single 0 0 0
set atom 1 diameter {2 * R!r} density {RHO!r}
pair_style zero 0.05
pair_coeff * *
region c {{region}} side in
fix w all viscontact/wall region c {OURS}
fix 1 all nve/sphere
timestep 1e-7
run 2
"""


@pytest.mark.parametrize("region", ["block -0.004 0.004 -0.004 0.004 -0.004 0.004",
                                    "prism -0.004 0.004 -0.004 0.004 -0.004 0.004 0.001 0 0"])
def test_too_many_faces_one_error_line(tmp_path, region):
    proc = run_lmp(_SMALL.format(plugin=plugin_line(), region=region), tmp_path)
    errs = error_lines(proc)
    assert proc.returncode == 1, (proc.returncode, proc.stderr[-500:])
    assert len(errs) == 1, errs
    assert "atom 1 touches 6 faces of region c, more than the 3 it allows" in errs[0], errs
