"""Run inside Yade (``yade -n -x yade_collide.py CASES.json OUT.json``): head-on collisions.

Each case of CASES.json (written by scripts/engine_harness.py) gives the bodies (radius, density,
Young's modulus, Poisson ratio, position, velocity; a body with radius None is a wall at
x = 0), the typed ``en``, the time step and the number of steps.  For each case the script
writes the final velocities and the largest overlap seen (penetrationDepth), one process for
the whole batch (the peak overlap only for the undamped cases, e = 1).  Frictionless, no
gravity, no numerical (Newton) damping.
"""

import json
import sys

from yade import O, utils
from yade.wrapper import (FrictMat, ForceResetter, InsertionSortCollider, Bo1_Sphere_Aabb,
                          Bo1_Wall_Aabb, InteractionLoop, Ig2_Sphere_Sphere_ScGeom,
                          Ig2_Wall_Sphere_ScGeom, Ip2_FrictMat_FrictMat_MindlinPhys,
                          Law2_ScGeom_MindlinPhys_Mindlin, NewtonIntegrator, PyRunner)

PEAK = [0.0]


def _track() -> None:
    for i in O.interactions:
        if i.isReal:
            PEAK[0] = max(PEAK[0], i.geom.penetrationDepth)


def run(case: dict) -> dict:
    O.reset()
    ids = []
    for b in case["bodies"]:
        mat = O.materials.append(FrictMat(young=b["E"], poisson=b["nu"], density=b["rho"],
                                          frictionAngle=0.0))
        if b["R"] is None:
            ids.append(O.bodies.append(utils.wall(0.0, axis=0, material=mat)))
        else:
            ids.append(O.bodies.append(utils.sphere((b["x"], 0.0, 0.0), b["R"], material=mat)))
            O.bodies[ids[-1]].state.vel = (b["v"], 0.0, 0.0)
    ip2 = Ip2_FrictMat_FrictMat_MindlinPhys(en=case["e"]) if case["e"] < 1.0 else \
        Ip2_FrictMat_FrictMat_MindlinPhys()
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
        InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()], [ip2],
                        [Law2_ScGeom_MindlinPhys_Mindlin()]),
        NewtonIntegrator(damping=0.0, gravity=(0.0, 0.0, 0.0)),
    ]
    if case["e"] >= 1.0:  # the peak overlap, for the undamped cases only (a Python call a step)
        O.engines = O.engines + [PyRunner(iterPeriod=1, command="_track()")]
    O.dt = case["dt"]
    PEAK[0] = 0.0
    O.run(case["steps"], True)
    return {"v": [O.bodies[i].state.vel[0] for i in ids], "peak": PEAK[0]}


# Yade executes this file in its own namespace (__name__ is not "__main__" there)
with open(sys.argv[1]) as fh:
    _cases = json.load(fh)
with open(sys.argv[2], "w") as fh:
    json.dump([run(c) for c in _cases], fh)
