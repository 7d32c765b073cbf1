"""Run head-on collisions in real DEM engines (LIGGGHTS, Yade, Kratos DEM) and measure e.

Used by tests/audit/test_engines.py and scripts/engine_runs.py (which refreshes the recorded
results of tests/data/engine_runs.json).  One engine process runs a whole batch of cases.

Geometries (SI units), all frictionless, no gravity, relative impact speed ``v``:

* ``equal``: two spheres of material A, velocities +v/2 and -v/2;
* ``unlike``: a sphere of A and a sphere of B (other radius, density, E and nu);
* ``wall``: a sphere of A moving at -v onto a flat wall of material B at x = 0.

The delivered e is the relative normal speed after / before.  The time step is T/STEPS_PER_T
with T = (m*^2 / (k_Hertz^2 v))^(1/5) the Hertz time scale (Jian et al. 2019, docs/laws.md): the contact lasts
about 3.2 T, so T/STEPS_PER_T = t_c/(3.2 STEPS_PER_T); the run ends RUN_T time scales after
first touch.  The undamped cases (typed e = 1) also return the peak overlap, from which the
engine's Hertz stiffness follows: delta_max = (5 m* v^2 / (4 k))^(2/5).
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
from dataclasses import asdict, dataclass

#: tests/, where the recorded results and the engines' scripts live
HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests")
RECORDED = os.path.join(HERE, "data", "engine_runs.json")

#: sphere materials: radius [m], density [kg/m^3], Young's modulus [Pa], Poisson ratio
#: and the engine's material/type number (1 = A, 2 = B)
MAT_A = {"R": 0.01, "rho": 2500.0, "E": 1.0e9, "nu": 0.3, "type": 1}
MAT_B = {"R": 0.006, "rho": 7800.0, "E": 3.0e9, "nu": 0.25, "type": 2}
GEOMETRIES = ("equal", "unlike", "wall")
STEPS_PER_T = 400   # dt = T/400, about t_c/1300: the error in e stays below 1e-4 (tested)
RUN_T = 4.0         # the damped contacts end before 3.3 T; the undamped one at 3.22 T
GAP = 1e-7          # initial surface gap [m]; the spheres touch within a few steps


@dataclass(frozen=True)
class Case:
    """One collision: geometry, the e typed into the engine, the impact speed [m/s], the
    LIGGGHTS ``limitForce`` switch (ignored by the other engines), and for a typed e that the
    audit advised, the target e it should deliver (None for a plain typed e)."""

    geometry: str
    e: float
    v: float
    clamp: bool = False
    target: float | None = None


def _mass(m: dict) -> float:
    return m["rho"] * 4.0 / 3.0 * math.pi * m["R"] ** 3


def effective(geometry: str, wall_r_factor: float = 1.0) -> tuple[float, float, float]:
    """(m*, R*, E*) of a geometry; ``wall_r_factor``: R*/R the engine takes at a flat wall."""
    a = MAT_A
    b = a if geometry == "equal" else MAT_B
    estar = 1.0 / ((1 - a["nu"] ** 2) / a["E"] + (1 - b["nu"] ** 2) / b["E"])
    if geometry == "wall":
        return _mass(a), wall_r_factor * a["R"], estar
    ma, mb = _mass(a), _mass(b)
    return ma * mb / (ma + mb), a["R"] * b["R"] / (a["R"] + b["R"]), estar


def k_hertz(geometry: str, wall_r_factor: float = 1.0) -> float:
    """(4/3) E* sqrt(R*) [N/m^1.5]."""
    _, r, estar = effective(geometry, wall_r_factor)
    return 4.0 / 3.0 * estar * math.sqrt(r)


def time_scale(geometry: str, v: float) -> float:
    """T = (m*^2 / (k^2 v))^(1/5) with the true flat-wall R* (the shortest over the engines'
    wall conventions, R*/R = 1 or 1/2, so the time step is fine for both)."""
    m, _, _ = effective(geometry)
    return (m * m / (k_hertz(geometry) ** 2 * v)) ** 0.2


def peak_overlap(geometry: str, v: float, wall_r_factor: float = 1.0) -> float:
    """Undamped Hertz peak overlap (5 m* v^2 / (4 k))^(2/5) [m]."""
    m, _, _ = effective(geometry, wall_r_factor)
    return (5.0 * m * v * v / (4.0 * k_hertz(geometry, wall_r_factor))) ** 0.4


def bodies(case: Case) -> list[dict]:
    """The bodies of a case: material, position [m] and velocity [m/s]; the wall has R None."""
    a = MAT_A
    if case.geometry == "wall":
        return [dict(a, x=a["R"] + GAP, v=-case.v), dict(MAT_B, R=None, x=0.0, v=0.0)]
    if case.geometry not in GEOMETRIES:
        raise ValueError(f"geometry must be one of {GEOMETRIES}, got {case.geometry!r}")
    b = a if case.geometry == "equal" else MAT_B
    return [dict(a, x=-(a["R"] + GAP / 2), v=case.v / 2), dict(b, x=b["R"] + GAP / 2, v=-case.v / 2)]


def schedule(case: Case) -> tuple[float, int]:
    """(dt, steps) of a case."""
    T = time_scale(case.geometry, case.v)
    dt = T / STEPS_PER_T
    return dt, int(math.ceil((GAP / case.v + RUN_T * T) / dt))


def delivered(case: Case, v_after: list[float]) -> float:
    """Relative normal speed after / before (the wall does not move)."""
    if case.geometry == "wall":
        return v_after[0] / case.v
    return (v_after[1] - v_after[0]) / case.v


@dataclass
class Result:
    case: Case
    e: float                 # delivered
    peak: float | None       # largest overlap seen [m] (undamped cases only where measured)


# ------------------------------------------------------------------------------ engines
def liggghts_exe() -> str | None:
    return shutil.which("liggghts") or shutil.which("lmp_liggghts")


def yade_exe() -> str | None:
    return shutil.which("yade")


def kratos_available() -> bool:
    import importlib.metadata

    try:  # the distribution, not an import (importing Kratos prints its banner)
        importlib.metadata.version("KratosDEMApplication")
        return True
    except importlib.metadata.PackageNotFoundError:
        return False


def engine_version(engine: str) -> str:
    """The installed engine's release string (e.g. 3.8.0, 2023.02a, 10.4.4)."""
    import re

    if engine == "kratos":
        import importlib.metadata

        return importlib.metadata.version("KratosDEMApplication")
    cmd = [yade_exe(), "--version"] if engine == "yade" else [liggghts_exe(), "-log", "none"]
    p = subprocess.run(cmd, input="", capture_output=True, text=True, errors="replace", timeout=120)
    pat = r"Yade version:\s*(\S+)" if engine == "yade" else r"LIGGGHTS-PUBLIC\s+([\d.]+)"
    m = re.search(pat, p.stdout + p.stderr)
    if not m:
        raise RuntimeError(f"cannot read the {engine} version from: {(p.stdout + p.stderr)[-500:]}")
    return m.group(1)


def missing_reason(engine: str) -> str | None:
    """Why ``engine`` cannot run here (None when it can)."""
    if engine == "liggghts" and liggghts_exe() is None:
        return "LIGGGHTS not installed (Debian: apt-get install liggghts)"
    if engine == "yade" and yade_exe() is None:
        return "Yade not installed (Debian: apt-get install yade)"
    if engine == "kratos" and not kratos_available():
        return "Kratos DEM not installed (pip install -e '.[kratos]', i.e. KratosDEMApplication==10.4.4)"
    return None


def _liggghts_case(i: int, case: Case) -> str:
    """One case of the LIGGGHTS batch input (types: 1 = material A, 2 = material B/wall)."""
    dt, steps = schedule(case)
    e = case.e
    lines = [
        "clear", "units si", "atom_style granular", "atom_modify map array", "boundary f f f",
        "newton off", "communicate single vel yes", "hard_particles yes",
        "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05 units box", "create_box 2 box",
        "neighbor 0.001 bin", "neigh_modify delay 0",
        f"fix m1 all property/global youngsModulus peratomtype {MAT_A['E']!r} {MAT_B['E']!r}",
        f"fix m2 all property/global poissonsRatio peratomtype {MAT_A['nu']!r} {MAT_B['nu']!r}",
        f"fix m3 all property/global coefficientRestitution peratomtypepair 2 {e!r} {e!r} {e!r} {e!r}",
        "fix m4 all property/global coefficientFriction peratomtypepair 2 0.0 0.0 0.0 0.0",
        f"pair_style gran model hertz tangential no_history limitForce {'on' if case.clamp else 'off'}",
        "pair_coeff * *",
    ]
    bs = bodies(case)
    spheres = [b for b in bs if b["R"] is not None]
    for b in bs:
        if b["R"] is None:
            # the model options go after the wall's geometry for fix wall/gran
            lines.append(f"fix wall all wall/gran model hertz tangential no_history primitive type "
                         f"{b['type']} xplane 0.0 limitForce {'on' if case.clamp else 'off'}")
    for b in spheres:
        lines.append(f"create_atoms {b['type']} single {b['x']!r} 0 0 units box")
    for j, b in enumerate(spheres):
        lines.append(f"set atom {j + 1} diameter {2 * b['R']!r} density {b['rho']!r} vx {b['v']!r}")
    lines += ["fix integr all nve/sphere", f"timestep {dt!r}", "thermo 100000000"]
    if e >= 1.0:  # undamped: record the gap every step for the peak overlap
        if case.geometry == "wall":
            lines.append(f"variable ov{i} equal {MAT_A['R']!r}-x[1]")
        else:
            lines.append(f"variable ov{i} equal {spheres[0]['R'] + spheres[1]['R']!r}-(x[2]-x[1])")
        lines.append(f'fix pk all print 1 "${{ov{i}}}" file peak{i}.txt screen no title none')
    lines += [f"run {steps}"]
    vs = " ".join(f"${{v{i}_{j}}}" for j in range(len(spheres)))
    for j in range(len(spheres)):
        lines.insert(-1, f"variable v{i}_{j} equal vx[{j + 1}]")
    lines.append(f'print "RESULT {i} {vs}"')
    return "\n".join(lines)


def run_liggghts(cases: list[Case]) -> list[Result]:
    """All ``cases`` in one LIGGGHTS process."""
    with tempfile.TemporaryDirectory(prefix="vc-liggghts-") as d:
        script = "\n".join(_liggghts_case(i, c) for i, c in enumerate(cases)) + "\n"
        with open(os.path.join(d, "in.batch"), "w") as fh:
            fh.write(script)
        p = subprocess.run([liggghts_exe(), "-in", "in.batch", "-echo", "none", "-log", "none"],
                           cwd=d, capture_output=True, text=True, errors="replace", timeout=600)
        if p.returncode != 0 or "ERROR" in p.stdout:
            raise RuntimeError("LIGGGHTS failed: " + (p.stdout + p.stderr)[-2000:])
        vel = {}
        for line in p.stdout.splitlines():
            if line.startswith("RESULT "):
                parts = line.split()
                vel[int(parts[1])] = [float(x) for x in parts[2:]]
        out = []
        for i, c in enumerate(cases):
            peak = None
            if c.e >= 1.0:
                with open(os.path.join(d, f"peak{i}.txt")) as fh:
                    peak = max(float(x) for x in fh.read().split())
            out.append(Result(c, delivered(c, vel[i]), peak))
        return out


def _batch_json(cases: list[Case]) -> list[dict]:
    out = []
    for c in cases:
        dt, steps = schedule(c)
        out.append({"bodies": bodies(c), "e": c.e, "dt": dt, "steps": steps,
                    "geometry": c.geometry})
    return out


def _run_script(cmd: list[str], cases: list[Case], name: str) -> list[Result]:
    with tempfile.TemporaryDirectory(prefix=f"vc-{name}-") as d:
        cin, cout = os.path.join(d, "cases.json"), os.path.join(d, "out.json")
        with open(cin, "w") as fh:
            json.dump(_batch_json(cases), fh)
        env = dict(os.environ, OMP_NUM_THREADS="1")
        p = subprocess.run(cmd + [cin, cout], cwd=d, capture_output=True, text=True, timeout=600,
                           env=env)
        if p.returncode != 0 or not os.path.exists(cout):
            raise RuntimeError(f"{name} failed: " + (p.stdout + p.stderr)[-2000:])
        with open(cout) as fh:
            res = json.load(fh)
    return [Result(c, delivered(c, r["v"]), r["peak"] if c.e >= 1.0 else None)
            for c, r in zip(cases, res)]


def run_yade(cases: list[Case]) -> list[Result]:
    """All ``cases`` in one Yade process (``yade -n -x``)."""
    return _run_script([yade_exe(), "-n", "-x", os.path.join(HERE, "engines", "yade_collide.py")],
                       cases, "yade")


def run_kratos(cases: list[Case]) -> list[Result]:
    """All ``cases`` in one Python process with Kratos DEM."""
    return _run_script([sys.executable, os.path.join(HERE, "engines", "kratos_collide.py")],
                       cases, "kratos")


RUNNERS = {"liggghts": run_liggghts, "yade": run_yade, "kratos": run_kratos}


# ----------------------------------------------------------------------- recorded results
def record(engine: str, version: str, results: list[Result], path: str = RECORDED) -> None:
    """Store ``results`` of ``engine`` (replacing its earlier ones) in the JSON file."""
    data = {}
    if os.path.exists(path):
        with open(path) as fh:
            data = json.load(fh)
    data[engine] = {"version": version, "steps_per_T": STEPS_PER_T,
                    "runs": [dict(asdict(r.case), delivered=r.e, peak=r.peak) for r in results]}
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as fh:
        json.dump(data, fh, indent=1)
        fh.write("\n")


def recorded(engine: str, path: str = RECORDED) -> tuple[str, list[Result]] | None:
    """(version, results) recorded for ``engine``, or None."""
    if not os.path.exists(path):
        return None
    with open(path) as fh:
        data = json.load(fh).get(engine)
    if not data:
        return None
    out = [Result(Case(r["geometry"], r["e"], r["v"], r["clamp"], r.get("target")), r["delivered"],
                  r["peak"]) for r in data["runs"]]
    return data["version"], out


# --------------------------------------------------------------------------------- plans
E_TYPED = (0.3, 0.6, 0.9)
SPEEDS = (0.1, 1.0, 10.0)


def _clamps(engine: str) -> tuple[bool, ...]:
    return (False, True) if engine == "liggghts" else (False,)


def _audit(engine: str, e: float, clamp: bool, version: str | None):
    from viscontact.audit.engines import audit_engine

    return audit_engine(engine, None, e, clamp=clamp if engine == "liggghts" else None,
                        version=version)


def plan(engine: str, version: str | None = None, *, quick: bool = False) -> list[Case]:
    """The cases run for ``engine``: every typed e of E_TYPED on every geometry at every speed
    (LIGGGHTS: limitForce off and on), the input the audit advises for each target e on every
    geometry at 1 m/s, and one undamped collision per geometry (peak overlap).  ``quick``: a
    subset for a slow engine: e = 0.3 on every geometry at 1 m/s, the advice for 0.3 on unlike
    spheres, the undamped wall)."""
    es, speeds = ((0.3,), (1.0,)) if quick else (E_TYPED, SPEEDS)
    out = [Case(g, e, v, c) for g in GEOMETRIES for e in es for v in speeds for c in _clamps(engine)]
    for g in (("unlike",) if quick else GEOMETRIES):
        for e in es:
            for c in _clamps(engine):
                inp = _audit(engine, e, c, version).input_for_target
                if inp is not None and abs(inp - e) > 1e-12:
                    out.append(Case(g, inp, 1.0, c, target=e))
    out += [Case(g, 1.0, 1.0) for g in (("wall",) if quick else GEOMETRIES)]
    return out


def run_plan(engine: str, *, quick: bool = False) -> tuple[str, list[Result]]:
    """(version, results) of the engine's plan, run in one process."""
    version = engine_version(engine)
    return version, RUNNERS[engine](plan(engine, version, quick=quick))


def wall_factor(engine: str, version: str | None) -> float:
    """R*/R the audit says the engine takes for a sphere on a flat wall."""
    from viscontact.audit.engines import get_preset

    return get_preset(engine, None, version).wall_r_factor


def check(engine: str, version: str, results: list[Result], tol: float = 1e-3) -> list[str]:
    """What differs between the engine's results and the audit (empty when all agree):
    a typed e must deliver the audit's prediction, an advised input its target, each to
    ``tol``; an undamped peak overlap must be the Hertz one for the audit's spring and wall
    R* to 1e-3 relative (the other wall convention is 15 % off)."""
    bad = []
    for r in results:
        c = r.case
        if c.e >= 1.0:
            want = peak_overlap(c.geometry, c.v, wall_factor(engine, version))
            if not abs(r.peak / want - 1.0) <= 1e-3:
                bad.append(f"{c}: peak overlap {r.peak:.6g} m, audit's spring and R* give {want:.6g} m")
            if abs(r.e - 1.0) > tol:
                bad.append(f"{c}: undamped collision delivered e = {r.e:.6f}")
            continue
        want = c.target if c.target is not None else _audit(engine, c.e, c.clamp, version).delivered_e
        what = "advised input, target" if c.target is not None else "audit predicts"
        if want is None or not abs(r.e - want) <= tol:
            bad.append(f"{c}: delivered {r.e:.6f}, {what} {want}")
    return bad
