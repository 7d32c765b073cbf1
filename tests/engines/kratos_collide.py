"""Run with Kratos DEM (``python3 kratos_collide.py CASES.json OUT.json``): head-on collisions.

Same cases and output as yade_collide.py: the final velocities and the largest overlap.
Each case is one DEMAnalysisStage in this one process: spheres made in code (no .mdpa
files), a rigid face (two RigidFace3D3N triangles) at x = 0 for the wall,
DEM_D_Hertz_viscous_Coulomb with COEFFICIENT_OF_RESTITUTION = the typed e, frictionless,
no rotation, no gravity, velocity Verlet, a fixed time step, no output files.
"""

import json
import os
import sys

import KratosMultiphysics as KM
import KratosMultiphysics.DEMApplication as DEM
from KratosMultiphysics.DEMApplication.DEM_analysis_stage import DEMAnalysisStage

KM.Logger.GetDefaultOutput().SetSeverity(KM.Logger.Severity.WARNING)

_PARAMS = {
    "Dimension": 3, "BoundingBoxOption": False, "dem_inlet_option": False,
    "GravityX": 0.0, "GravityY": 0.0, "GravityZ": 0.0, "RotationOption": False,
    "CleanIndentationsOption": False, "do_print_results_option": False,
    "solver_settings": {"strategy": "sphere_strategy", "RemoveBallsInitiallyTouchingWalls": False,
                        "material_import_settings": {"materials_filename": "MaterialsDEM.json"}},
    "DeltaOption": "Absolute", "SearchTolerance": 0.0, "CoordinationNumber": 10,
    "TranslationalIntegrationScheme": "Velocity_Verlet", "RotationalIntegrationScheme": "Direct_Integration",
    "AutomaticTimestep": False, "DeltaTimeSafetyFactor": 1.0, "NeighbourSearchFrequency": 1,
    "ElementType": "SphericPartDEMElement3D", "OutputTimeStep": 1e9, "GraphExportFreq": 1e9,
    "ControlTime": 1e9, "problem_name": "collide",
}


def _materials(case):
    mats, names = [], []
    for b in case["bodies"]:
        name = f"mat{b['type']}"
        if name in names:
            continue
        names.append(name)
        var = {"YOUNG_MODULUS": b["E"], "POISSON_RATIO": b["nu"]}
        if b["R"] is not None:
            var["PARTICLE_DENSITY"] = b["rho"]
        mats.append({"material_name": name, "material_id": b["type"], "Variables": var})
    rel = []
    for i, a in enumerate(names):
        for b in names[i:]:
            rel.append({"material_names_list": [a, b],
                        "material_ids_list": [int(a[3:]), int(b[3:])],
                        "Variables": {"COEFFICIENT_OF_RESTITUTION": case["e"], "STATIC_FRICTION": 0.0,
                                      "DYNAMIC_FRICTION": 0.0, "FRICTION_DECAY": 500.0,
                                      "ROLLING_FRICTION": 0.0, "ROLLING_FRICTION_WITH_WALLS": 0.0,
                                      "DEM_DISCONTINUUM_CONSTITUTIVE_LAW_NAME": "DEM_D_Hertz_viscous_Coulomb"}})
    table = []
    for b in case["bodies"]:
        part = "RigidFacePart" if b["R"] is None else f"SpheresPart.s{b['type']}"
        if [part, f"mat{b['type']}"] not in table:
            table.append([part, f"mat{b['type']}"])
    return {"materials": mats, "material_relations": rel, "material_assignation_table": table}


class _Collide(DEMAnalysisStage):
    def __init__(self, model, params, case):
        self.case = case
        self.peak = 0.0
        super().__init__(model, params)

    def GetMainPath(self):
        return os.getcwd()

    def ReadModelParts(self, max_node_Id=0, max_elem_Id=0, max_cond_Id=0):
        sp = self.spheres_model_part
        props = {}
        for b in self.case["bodies"]:
            if b["R"] is not None and b["type"] not in props:
                t = b["type"]
                props[t] = KM.Properties(t)
                # the element reads its integration schemes from its properties at creation
                DEM.VelocityVerletScheme().SetTranslationalIntegrationSchemeInProperties(props[t], True)
                DEM.VelocityVerletScheme().SetRotationalIntegrationSchemeInProperties(props[t], True)
                sp.AddProperties(props[t])
                sp.CreateSubModelPart(f"s{t}")
        DEM.PropertiesProxiesManager().CreatePropertiesProxies(sp)
        for b in self.case["bodies"]:
            if b["R"] is None:
                continue
            t = b["type"]
            c = KM.Array3()
            c[0], c[1], c[2] = b["x"], 0.0, 0.0
            el = self.creator_destructor.CreateSphericParticle(sp, c, props[t], b["R"], "SphericParticle3D")
            sp.GetSubModelPart(f"s{t}").AddNodes([el.GetNode(0).Id])
            sp.GetSubModelPart(f"s{t}").AddElements([el.Id])
            el.GetNode(0).SetSolutionStepValue(KM.VELOCITY_X, b["v"])
        for b in self.case["bodies"]:
            if b["R"] is not None:
                continue
            rf = self.rigid_face_model_part
            pw = KM.Properties(b["type"])
            rf.AddProperties(pw)
            L = 1.0
            rf.CreateNewNode(1001, 0.0, -L, -L)
            rf.CreateNewNode(1002, 0.0, L, -L)
            rf.CreateNewNode(1003, 0.0, -L, L)
            rf.CreateNewNode(1004, 0.0, L, L)
            rf.CreateNewCondition("RigidFace3D3N", 1001, [1001, 1002, 1003], pw)
            rf.CreateNewCondition("RigidFace3D3N", 1002, [1003, 1002, 1004], pw)

    def FinalizeSolutionStep(self):
        super().FinalizeSolutionStep()
        xs = [(n.X, n.GetSolutionStepValue(KM.RADIUS)) for n in self.spheres_model_part.Nodes]
        if len(xs) == 2:
            (x1, r1), (x2, r2) = sorted(xs)
            self.peak = max(self.peak, r1 + r2 - (x2 - x1))
        else:
            self.peak = max(self.peak, xs[0][1] - xs[0][0])

    def Finalize(self):
        # the final velocities, in the order the spheres were made (node ids ascending)
        nodes = sorted(self.spheres_model_part.Nodes, key=lambda n: n.Id)
        self.v_final = [n.GetSolutionStepValue(KM.VELOCITY_X) for n in nodes]
        super().Finalize()


def run(case):
    with open("MaterialsDEM.json", "w") as fh:
        json.dump(_materials(case), fh)
    params = dict(_PARAMS, MaxTimeStep=case["dt"], FinalTime=case["dt"] * (case["steps"] + 0.5))
    stage = _Collide(KM.Model(), KM.Parameters(json.dumps(params)), case)
    stage.Run()
    v = list(stage.v_final)
    if case["bodies"][-1]["R"] is None:
        v.append(0.0)
    return {"v": v, "peak": stage.peak}


if __name__ == "__main__":
    with open(sys.argv[1]) as fh:
        cases = json.load(fh)
    out = [run(c) for c in cases]
    with open(sys.argv[2], "w") as fh:
        json.dump(out, fh)
