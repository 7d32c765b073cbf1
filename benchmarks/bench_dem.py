"""The LAMMPS plugin's cost per particle-step for every law against native ``pair_style granular``.

    python3 benchmarks/bench_dem.py [--quick] [--ranks 1 2] [--packings loose dense drum]
                                    [--steps N] [--repeat R] [--laws LH Ts ...] [--full | --only-full]

Two packings of about 10^4 equal spheres (d = 1 cm, rho = 2500 kg/m^3, E = 10 MPa, nu = 0.3,
Mindlin friction mu = 0.5), fully periodic, no gravity, no walls (the pair style is what is
measured), and a wall-dominated case:

* ``loose``: a granular gas, a simple cubic lattice of spacing 1.15 d (volume fraction 0.34)
  with Gaussian random velocities of 1 m/s rms; measured after a warm-up of 3 ms (the gaps
  close within about 1 ms, so collisions are under way);
* ``dense``: a pack, an fcc lattice whose neighbours overlap by 0.1 % of d (12 contacts per
  sphere, volume fraction 0.74), random velocities of 1 cm/s;
* ``drum``: a drum of radius 0.2 m turning about its (periodic) axis so fast that the spheres
  lie in one layer on its mantle (omega^2 R = 10 g, gravity across the axis: the centrifuging
  regime), rings 1.2 d apart: one contact with the turning region wall per sphere and almost
  none between spheres, so ``fix viscontact/wall region`` against native ``fix
  wall/gran/region`` is what is measured (our LH c0 against native ``damping velocity``, the
  rigid wall against native's wall of E = 2 E_p; :func:`drum_cases`).

Every law (calibrated to e = 0.8 at vref = 1 m/s, zero-force end; Jian beta = 0.5, power
p = 0.75) runs through ``pair_style viscontact``, and in the same LAMMPS process, on the same
packing, the nearest native damping of ``pair_style granular`` (``hertz/material``, ``tangential
mindlin NULL 0.0 0.5``, ``limit_damping``): ``velocity`` for LH, ``tsuji`` for Ts and
``viscoelastic`` for the others (KK exactly; Li, Hunt, Jian and power have no native
counterpart), each with the input the audit (:mod:`viscontact.audit.engines`) says gives
e = 0.8 at 1 m/s for a pair of these spheres.  Each case is run ``--repeat`` times (best kept:
on a shared machine the shortest is the least disturbed; the cases interleaved) after a
warm-up; the figure is LAMMPS's loop time / (steps x particles) in microseconds, and the
``Pair`` share of it.  The ratio plugin/native is also given by CPU time (loop time x LAMMPS's
"CPU use" x ranks), which other work on a shared machine disturbs less than wall time.

With ``--full`` (or ``--only-full``) a case with every sub-model on is added: JKR cohesion
(W = 0.5 J/m^2), tangential ``mindlin NULL 0.5 0.5`` (tangential damping), rolling ``sds``
and twisting ``sds``, no clamp, for the laws native also has, in their exactly equivalent
physical forms: our ``LH c0 C`` against native ``damping velocity C`` and our ``KK c0 C``
against native ``viscoelastic`` with eta0 = C/(m* sqrt(R*)) (one sphere size, so one m*, R*).

Targets: plugin / native <= 1 for every law; t(1 rank) / t(2 ranks) >= 1.7.

With ``--hopper`` only the wall cost is measured instead: spheres (d = 4 mm) in a conical
hopper (outlet radius 1 cm at z = 0, radius 5 cm at z = 7 cm, open outlet) flowing out under
gravity, the hopper once as ``fix viscontact/wall mesh`` (an STL cone of 64 facets, 128
triangles) and once as ``fix viscontact/wall region`` (LAMMPS's analytic ``region cone``),
the same spheres from the same lattice, the same law (LH with friction).  Figure: loop time
per particle-step of each (best of --repeat, after a warm-up), and their ratio.
Target: mesh / region <= 1.3 (measured 1.22-1.23: 0.118-0.119 against 0.097 us per particle-step,
--repeat 5, quiet machine; 1.37 before the mesh's cells listed only the triangles overlapping
them).
"""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
import tempfile
from pathlib import Path

E, NU, RHO, D, MU = 1.0e7, 0.3, 2500.0, 0.01, 0.5
E_TARGET, VREF, BETA, P_POWER = 0.8, 1.0, 0.5, 0.75
LAWS = ("LH", "Ts", "KK", "Li", "Hunt", "Jian", "power")
NATIVE_OF = {"LH": "velocity", "Ts": "tsuji"}  # the rest: viscoelastic
#: measured steps per run: the gas costs a tenth of the pack per particle-step, and a run of
#: under a second is timed mostly by noise
DEFAULT_STEPS = {"loose": 1500, "dense": 300, "drum": 1000}
KB = 1.380649e-23  # LAMMPS's Boltzmann constant in units si [J/K]

_LOOP = re.compile(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms")
_PAIR = re.compile(r"^Pair\s*\|\s*(\S+)\s*\|\s*(\S+)\s*\|")
_CPU = re.compile(r"^(\S+)% CPU use with (\d+) MPI tasks")


def packing_lines(kind: str, n_side: int) -> list[str]:
    """Deterministic packing of ``kind`` (the same on any number of ranks: loop geom)."""
    mass = RHO * math.pi * D**3 / 6.0
    if kind == "loose":
        lattice, v_rms = f"lattice sc {1.15 * D!r}", 1.0
    else:
        lattice, v_rms = f"lattice fcc {math.sqrt(2.0) * D * (1.0 - 1e-3)!r}", 0.01
    temp = mass * v_rms**2 / (3.0 * KB)  # velocity create takes a temperature
    return [
        "units si", "atom_style sphere", "atom_modify map array", "boundary p p p",
        "comm_modify vel yes", lattice, f"region box block 0 {n_side} 0 {n_side} 0 {n_side}",
        "create_box 1 box", "create_atoms 1 box", f"set type 1 diameter {D!r}",
        f"set type 1 density {RHO!r}",
        f"velocity all create {temp!r} 4928459 dist gaussian loop geom mom yes rot no",
        f"neighbor {0.1 * D!r} bin", "neigh_modify delay 0 every 1 check yes",
        "fix move all nve/sphere", "timestep 1e-5", "thermo 0",
    ]


def cases() -> list[tuple[str, str, str]]:
    """(label, law, pair lines) for every plugin law and every native damping used."""
    from viscontact import dem
    from viscontact.audit.engines import get_preset
    from viscontact.physics.pair import contact_pair

    mass = RHO * math.pi * D**3 / 6.0
    pair = contact_pair(mass, radius=D / 2, modulus=E, poisson=NU, mass2=mass, radius2=D / 2,
                        modulus2=E, poisson2=NU).at(VREF)
    out = []
    for law in LAWS:
        dl = dem.contact_law(law, e=E_TARGET, vref=VREF, beta=BETA if law == "Jian" else None,
                             p=P_POWER if law == "power" else None)
        lines = dem.coeff_lines(dl, E=E, nu=NU, friction=MU, plugin="-")
        out.append((f"plugin {law}", law, [lines.pair_style, lines.pair_coeff]))
    for option, law in (("velocity", "LH"), ("tsuji", "Ts"), ("viscoelastic", "KK")):
        alpha = float(dem.contact_law(law, e=E_TARGET, vref=VREF).alpha)
        value = get_preset("lammps", option).from_alpha(alpha, pair)
        out.append((f"native {option}", law, [
            "pair_style granular",
            f"pair_coeff * * hertz/material {E!r} {value!r} {NU!r} damping {option} "
            f"tangential mindlin NULL 0.0 {MU!r} limit_damping"]))
    return out


#: the full case's sub-models: (ours after the damping, native after the damping)
W_JKR, LH_C0, KK_ETA0 = 0.5, 0.3, 300.0
_FULL_TAIL = (f"tangential mindlin NULL 0.5 {MU!r} rolling sds 200.0 0.05 0.1 "
              "twisting sds 1e-05 1e-07 0.001")


def full_cases() -> list[tuple[str, str, list[str]]]:
    """(label, law, pair lines) of the case with every sub-model: plugin LH and KK in the
    physical forms that equal native velocity and viscoelastic, and those natives."""
    mass = RHO * math.pi * D**3 / 6.0
    kk_c0 = KK_ETA0 * (mass / 2) * math.sqrt(D / 4)  # c0 = eta0 m* sqrt(R*)
    out = []
    for law, c0, option, coeff in (("LH", LH_C0, "velocity", LH_C0),
                                   ("KK", kk_c0, "viscoelastic", KK_ETA0)):
        out.append((f"plugin {law} full", law, [
            "pair_style viscontact",
            f"pair_coeff * * jkr {E!r} {NU!r} {W_JKR!r} damping {law} c0 {c0!r} end overlap {_FULL_TAIL}"]))
        out.append((f"native {option} full", law, [
            "pair_style granular",
            f"pair_coeff * * jkr {E!r} {coeff!r} {NU!r} {W_JKR!r} damping {option} {_FULL_TAIL}"]))
    return out


#: the wall-dominated case: a drum of radius DRUM_R [m] turning about z so fast (omega^2 R =
#: DRUM_G g) that every sphere is pressed onto its mantle (the centrifuging regime of a rotating
#: drum); rings of spheres 1.2 d apart on the mantle, layers 1.2 d apart along the periodic axis:
#: one region-wall contact per sphere and almost no sphere-sphere contact, so the wall fix is
#: most of the cost
DRUM_R, DRUM_G, G = 0.2, 10.0, 9.81


def drum_lines(n_layers: int, data: Path) -> list[str]:
    """The turning drum: its spheres (written to ``data`` once, read by every case, the same on
    any number of ranks) and region ``drum``; the contact lines and the wall fix follow
    (:func:`drum_cases`)."""
    omega = math.sqrt(DRUM_G * G / DRUM_R)
    r_ring = DRUM_R - 0.5 * D * (1.0 - 1e-3)  # touching the mantle (an overlap of 5e-4 d)
    per_ring = int(2.0 * math.pi * r_ring / (1.2 * D))
    length = 1.2 * D * n_layers
    half = 1.05 * DRUM_R
    if not data.exists():
        rows = []
        for k in range(n_layers):
            z = 1.2 * D * (k + 0.5)
            for j in range(per_ring):
                phi = 2.0 * math.pi * (j + 0.5 * (k % 2)) / per_ring
                x, y = r_ring * math.cos(phi), r_ring * math.sin(phi)
                # atom_style sphere: id type diameter density x y z
                rows.append(f"{len(rows) + 1} 1 {D!r} {RHO!r} {x!r} {y!r} {z!r}")
        data.write_text(f"turning drum\n\n{len(rows)} atoms\n1 atom types\n\n"
                        f"{-half!r} {half!r} xlo xhi\n{-half!r} {half!r} ylo yhi\n"
                        f"0 {length!r} zlo zhi\n\nAtoms # sphere\n\n" + "\n".join(rows) + "\n")
    return ["units si", "atom_style sphere", "atom_modify map array", "boundary f f p",
            "comm_modify vel yes", f"read_data {data}",
            # the rigid rotation of the wall, then gravity across the axis
            f"variable vx atom {-omega!r}*y", f"variable vy atom {omega!r}*x",
            "velocity all set v_vx v_vy 0.0", f"variable theta equal {omega!r}*dt*elapsed",
            f"region drum cylinder z 0 0 {DRUM_R!r} -1 {length + 1!r} side in open 1 open 2 "
            "rotate v_theta 0 0 0 0 0 1",
            f"fix gravity all gravity {G!r} vector 0 -1 0",
            f"neighbor {0.1 * D!r} bin", "neigh_modify delay 0 every 1 check yes",
            "fix move all nve/sphere", "timestep 1e-5", "thermo 0"]


def drum_cases() -> list[tuple[str, str, list[str]]]:
    """(label, law, contact lines) of the drum: our LH c0 pair and region wall (a rigid wall)
    against native ``damping velocity`` and ``fix wall/gran/region`` (a wall of E = 2 E_p,
    the rigid wall's equal), Mindlin friction as in :func:`cases`."""
    tail = f"tangential mindlin NULL 0.0 {MU!r} damping velocity limit_damping"
    ours = f"damping LH c0 {LH_C0!r} end force tangential mindlin {MU!r}"
    return [
        ("plugin drum", "LH", [
            "pair_style viscontact", f"pair_coeff * * hertz/material {E!r} {NU!r} {ours}",
            f"fix wall all viscontact/wall region drum wall_material rigid {ours}"]),
        ("native drum", "LH", [
            "pair_style granular", f"pair_coeff * * hertz/material {E!r} {LH_C0!r} {NU!r} {tail}",
            f"fix wall all wall/gran/region granular hertz/material {2 * E!r} {LH_C0!r} {NU!r} "
            f"{tail} region drum"]),
    ]


def write_input(path: Path, kind: str, n_side: int, warm: int, steps: int, repeat: int,
                todo: list[tuple[str, str, list[str]]]) -> None:
    """Every case ``repeat`` times, interleaved (A B C ... A B C ...), so that a burst of other
    work on the machine does not fall on one case only; each time from the same packing."""
    body = []
    for rep in range(repeat):
        for label, _law, pair_lines in todo:
            head = (drum_lines(n_side, path.with_name(f"drum{n_side}.data")) if kind == "drum"
                    else packing_lines(kind, n_side))
            body += [f"# case: {label}, repeat {rep + 1}", "clear", *head,
                     *pair_lines, f"run {warm}", f"run {steps}"]
    path.write_text("\n".join(body) + "\n")


def parse(log: Path, todo, repeat: int) -> dict[str, tuple[float, float, float, int]]:
    """label -> (best wall us per particle-step, its Pair share, best CPU core-us per
    particle-step (wall x CPU use x ranks: what the case cost while other work shared the
    cores), atoms)."""
    loops, pairs, cpus = [], [], []
    for line in log.read_text().splitlines():
        m = _LOOP.match(line)
        if m:
            loops.append((float(m.group(1)), int(m.group(2)), int(m.group(3)), int(m.group(4))))
        m = _PAIR.match(line)
        if m:
            pairs.append(float(m.group(2)))  # the average over ranks
        m = _CPU.match(line)
        if m:
            cpus.append(float(m.group(1)) / 100.0)
    n = 2 * repeat * len(todo)  # a warm-up and a measured run per case and repeat
    if not (len(loops) == len(pairs) == len(cpus) == n):
        raise RuntimeError(f"{log}: expected {n} runs, found {len(loops)}")
    out = {}
    for k, (label, _law, _lines) in enumerate(todo):
        idx = [2 * (rep * len(todo) + k) + 1 for rep in range(repeat)]
        best = min(idx, key=lambda i: loops[i][0])
        t, procs, steps, atoms = loops[best]
        cpu = min(loops[i][0] * cpus[i] * loops[i][1] for i in idx)
        out[label] = (1e6 * t / (steps * atoms), pairs[best] / t if t > 0 else math.nan,
                      1e6 * cpu / (steps * atoms), atoms)
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="about 2000 particles and fewer steps (a smoke run, not the figures)")
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2], help="MPI rank counts (default 1 2)")
    ap.add_argument("--packings", nargs="+", choices=("loose", "dense", "drum"),
                    default=["loose", "dense", "drum"])
    ap.add_argument("--laws", nargs="+", default=list(LAWS), help="plugin laws (default all)")
    ap.add_argument("--steps", type=int, default=None,
                    help="measured steps per run (default: loose 1500, dense 300, so that a run "
                         "takes seconds; quick 100)")
    ap.add_argument("--repeat", type=int, default=3, help="measured runs per case, best kept (default 3)")
    ap.add_argument("--full", action="store_true",
                    help="also the case with JKR, tangential damping, rolling and twisting (LH, KK)")
    ap.add_argument("--only-full", action="store_true", help="only that case")
    ap.add_argument("--hopper", action="store_true",
                    help="only the mesh hopper against the region cone (the wall's cost)")
    args = ap.parse_args()
    if args.hopper:
        return hopper_main(args)
    from viscontact import dem

    warm = 150 if args.quick else 300
    plugin = dem.plugin_path(progress=lambda m: print(m, file=sys.stderr))
    todo = [] if args.only_full else [c for c in cases()
                                      if c[0].startswith("native") or c[1] in args.laws]
    if args.full or args.only_full:
        todo += full_cases()
    packings = [k for k in args.packings if k != "drum" or not args.only_full]
    print(f"plugin {plugin}\nload average {os.getloadavg()[0]:.2f} before (timings on a shared "
          "machine scale with the cores actually free)")
    results: dict[tuple[str, int], dict[str, tuple[float, float, int]]] = {}
    with tempfile.TemporaryDirectory(prefix="viscontact-bench-dem-") as tmp:
        for kind in packings:
            # cubic packings: spheres per side; the drum: rings along its axis (98: 9,996)
            n_side = {"loose": (8, 22), "dense": (5, 14), "drum": (20, 98)}[kind][not args.quick]
            here = drum_cases() if kind == "drum" else todo
            for ranks in args.ranks:
                inp = Path(tmp) / f"in.{kind}.{ranks}"
                steps = args.steps or (100 if args.quick else DEFAULT_STEPS[kind])
                write_input(inp, kind, n_side, warm, steps, args.repeat, here)
                res = dem.run_input(inp, np=ranks, progress=sys.stderr.isatty(), quiet=True)
                results[(kind, ranks)] = parse(res.log_path, here, args.repeat)
                print(f"  {kind} on {ranks} rank(s): {res.seconds:.1f} s", file=sys.stderr)
    report(results, args)
    print(f"load average {os.getloadavg()[0]:.2f} after")
    return 0


HOPPER_CASES = ("mesh", "region")


def hopper_lines(wall: str, stl: Path, warm: int, steps: int) -> list[str]:
    """One hopper case: a simple cubic lattice of 4 mm spheres filling the cone above 2 cm,
    gravity, the outlet open; a warm-up run, then the measured run."""
    law = (f"damping LH c0 0.5 tangential mindlin NULL 0.5 {MU!r}")
    wall_words = (f"wall_material rigid {law} particle {E!r} {NU!r}")
    geom = f"mesh {stl}" if wall == "mesh" else "region cone"
    return ["clear", "units si", "atom_style sphere", "atom_modify map array", "boundary f f f",
            "comm_modify vel yes", "newton off",
            "region box block -0.052 0.052 -0.052 0.052 -0.02 0.08", "create_box 1 box",
            "region cone cone z 0 0 0.01 0.05 0.0 0.07 side in open 1 open 2",
            "region fill cone z 0 0 0.024 0.044 0.02 0.07 side in",
            "lattice sc 0.0045", "create_atoms 1 region fill",
            "set group all diameter 0.004", f"set group all density {RHO!r}",
            f"pair_style viscontact", f"pair_coeff * * hertz/material {E!r} {NU!r} {law}",
            f"fix hopper all viscontact/wall {geom} {wall_words}",
            "fix gravity all gravity 9.81 vector 0 0 -1", "fix move all nve/sphere",
            "neighbor 0.001 bin", "neigh_modify delay 0", "timestep 1e-5",
            "thermo_modify lost ignore", f"run {warm}", f"run {steps}"]


def hopper_main(args) -> int:
    """Mesh hopper against region cone: loop time per particle-step of each, and the ratio."""
    from viscontact import dem
    from viscontact.dem.stl import hopper, write_stl

    warm, steps = (300, 300) if args.quick else (1000, args.steps or 2000)
    print(f"load average {os.getloadavg()[0]:.2f} before")
    with tempfile.TemporaryDirectory(prefix="viscontact-bench-hopper-") as tmp:
        stl = write_stl(Path(tmp) / "hopper.stl", hopper(0.01, 0.05, 0.07, 64), binary=False)
        body = []
        for _ in range(args.repeat):
            for wall in HOPPER_CASES:
                body += [f"# case: {wall}", *hopper_lines(wall, stl, warm, steps)]
        inp = Path(tmp) / "in.hopper"
        inp.write_text("\n".join(body) + "\n")
        res = dem.run_input(inp, progress=sys.stderr.isatty(), quiet=True)
        loops = [(float(m.group(1)), int(m.group(3)), int(m.group(4)))
                 for m in map(_LOOP.match, res.log_path.read_text().splitlines()) if m]
    best = {}
    for k, (t, nstep, atoms) in enumerate(loops):
        if k % 2 == 1:    # the measured runs
            wall = HOPPER_CASES[(k // 2) % len(HOPPER_CASES)]
            cost = 1e6 * t / (nstep * atoms)
            best[wall] = min(best.get(wall, (math.inf, 0)), (cost, atoms))
    print("| hopper wall | us / particle-step | atoms at the end |\n|---|---|---|")
    for wall in HOPPER_CASES:
        print(f"| {wall} | {best[wall][0]:.3f} | {best[wall][1]} |")
    print(f"mesh / region = {best['mesh'][0] / best['region'][0]:.2f} (target <= 1.3)")
    print(f"load average {os.getloadavg()[0]:.2f} after")
    return 0


def report(results, args) -> None:
    native_of = {law: NATIVE_OF.get(law, "viscoelastic") for law in LAWS}
    if args.full or args.only_full:
        report_full(results, args)
    if any(kind == "drum" for kind, _r in results):
        report_drum(results, args)
    if args.only_full:
        return
    for kind in [k for k in args.packings if k != "drum"]:
        atoms = next(iter(results[(kind, args.ranks[0])].values()))[3]
        print(f"\n{kind}: {atoms} particles; wall us per particle-step (Pair share), plugin/native "
              "by wall time and by CPU time")
        head = f"{'law':<6} {'native damping':<14}"
        for r in args.ranks:
            head += f" | {r} rank: {'plugin':>13} {'native':>13} {'wall':>5} {'cpu':>5}"
        if len(args.ranks) > 1:
            head += f" | speed-up {args.ranks[0]}->{args.ranks[-1]}: plugin native"
        print(head)
        for law in args.laws:
            nat = f"native {native_of[law]}"
            row = f"{law:<6} {native_of[law]:<14}"
            for r in args.ranks:
                pu, ps, pc, _ = results[(kind, r)][f"plugin {law}"]
                nu, ns, nc, _ = results[(kind, r)][nat]
                row += (f" | {'':>7} {pu:7.3f} ({ps:4.0%}) {nu:7.3f} ({ns:4.0%}) {pu / nu:5.2f} "
                        f"{pc / nc:5.2f}")
            if len(args.ranks) > 1:
                lo, hi = results[(kind, args.ranks[0])], results[(kind, args.ranks[-1])]
                row += (f" | {'':>20} {lo[f'plugin {law}'][0] / hi[f'plugin {law}'][0]:5.2f}  "
                        f"{lo[nat][0] / hi[nat][0]:5.2f}")
            print(row)
    print("\ntargets: plugin/native <= 1 for every law; speed-up 1 -> 2 ranks >= 1.7 "
          "(needs two free cores)")


def report_drum(results, args) -> None:
    """The wall-dominated drum: plugin/native by wall and CPU time per rank count."""
    atoms = results[("drum", args.ranks[0])]["plugin drum"][3]
    row = "drum   LH vs native velocity, region walls"
    for r in args.ranks:
        pu, _, pc, _ = results[("drum", r)]["plugin drum"]
        nu, _, nc, _ = results[("drum", r)]["native drum"]
        row += f" | {r} rank: {pu:7.3f} {nu:7.3f} ratio {pu / nu:5.2f} (cpu {pc / nc:5.2f})"
    print(f"\nturning drum, {atoms} particles on its mantle (fix viscontact/wall region against "
          "fix wall/gran/region): wall us per particle-step, plugin/native by wall and CPU time")
    print(row)


def report_full(results, args) -> None:
    """The full case: plugin/native by wall and CPU time per law, packing and rank count."""
    print("\nevery sub-model on (jkr, mindlin with tangential damping, rolling sds, twisting sds): "
          "wall us per particle-step, plugin/native by wall and CPU time")
    for kind in [k for k in args.packings if k != "drum"]:
        for law, option in (("LH", "velocity"), ("KK", "viscoelastic")):
            row = f"{kind:<6} {law:<3} vs native {option:<13}"
            for r in args.ranks:
                pu, _, pc, _ = results[(kind, r)][f"plugin {law} full"]
                nu, _, nc, _ = results[(kind, r)][f"native {option} full"]
                row += f" | {r} rank: {pu:7.3f} {nu:7.3f} ratio {pu / nu:5.2f} (cpu {pc / nc:5.2f})"
            print(row)


if __name__ == "__main__":
    raise SystemExit(main())
