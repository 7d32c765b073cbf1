"""Discharge of a large STL-mesh silo against Beverloo's correlation at D/d = 8-12, from one
filled bed (docs/fix_viscontact_mesh.md, "Silo against Beverloo").

    python3 scripts/mesh_silo_large.py [--orifices 0.024 0.030 0.036] [--laws KK]
                                       [--out DIR] [--force] [--np N] [--var NAME VALUE ...]

The shipped silo (scripts/mesh_silo_study.py: radius 3 cm, a bed 2 cm deep, D/d = 6-8) flows at
C of about 0.5; Beverloo's correlation holds for D > 6 d, and at small D/d intermittent arching
lowers the rate (Mankoc et al. 2007, Granular Matter 9:407).  This study tests the larger
orifices in a silo wide and deep enough for them:

* the fill, once, with the first of --laws (scripts/in.silo_large_fill): 15000 spheres of
  d = 3 mm, rho_p = 2500 kg/m^3, poured into a silo of radius 5 cm (``python3 -m
  viscontact.dem.stl silo silo.stl --radius 0.05 --height 0.15 --orifice D_min``, D_min the
  smallest orifice) closed by a plane wall 1 mm below the floor as in.mesh.silo is, for 60000
  steps of 1e-5 s: a bed about 4.6 cm deep (its kinetic energy 2e-7 J at the end), written to
  a restart file;
* one discharge per law and orifice D (scripts/in.silo_large_discharge) from that restart,
  with the pair and wall lines of the law (the spheres' contact history carries over: every
  shipped law has Mindlin's tangential model, mu = 0.5); the floor is the mesh with orifice D
  under a new fix ID (the fill's sphere-wall tangential springs are dropped at that step, a
  negligible change beside the floor opening under the bed), no plug, for 38000 steps.  An
  orifice wider than the fill's drops the spheres resting on the floor's ring between the two
  as the plug drops those in the orifice.

W, its halves, the window and rho_b are measured exactly as scripts/mesh_silo_study.py does
(rho_b in the filled bed, the same for every run), with C fitted at k = 1.5, the exponent
of W against (D - 1.5 d) and the joint fit of C and k.  Writes DIR/table.md, DIR/runs.csv and
each run's lost mass against time, DIR/large-DDmm-LAW.csv.
"""

from __future__ import annotations

import argparse
import math
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from mesh_silo_study import DT, _fill, _measure, bulk_density, runs_csv, silo_table  # noqa: E402
from mesh_study_util import add_common, open_out, run, workdir, write_mesh  # noqa: E402

from viscontact.dem import read_dump  # noqa: E402

HERE = Path(__file__).resolve().parent
INPUTS = ("in.silo_large_fill", "in.silo_large_discharge")
RADIUS, HEIGHT, DP = 0.05, 0.15, 0.003
DEPTH_MIN = 0.04          # the bed's depth asked of the study [m]


def parse(argv: list[str] | None) -> argparse.Namespace:
    """The options, checked: at least two orifices, each in (6 d, 2 R)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[2:]))
    ap.add_argument("--orifices", type=float, nargs="+", default=[0.024, 0.030, 0.036],
                    metavar="D", help="orifice diameters [m] (default 0.024 0.030 0.036)")
    ap.add_argument("--laws", nargs="+", default=["KK"], help="laws (default KK)")
    add_common(ap, "mesh-silo-large")
    args = ap.parse_args(argv)
    if len(args.orifices) < 2:
        ap.error("--orifices needs at least two diameters (the fitted exponent)")
    bad = [D for D in args.orifices if not 6 * DP - 1e-12 <= D < 2 * RADIUS]
    if bad:
        ap.error(f"--orifices must lie in [{6 * DP:g}, {2 * RADIUS:g}) m (6 d to the silo's "
                 f"diameter), got {bad[0]:g}")
    return args


def bed_depth(frame) -> float:
    """The bed's depth [m]: the mean height of the top of its highest 1 % of spheres, from
    the sphere centres in the silo (z >= 0) of a frame (a dump with columns z and radius)."""
    z = frame["z"][frame["z"] >= 0] + frame["radius"][frame["z"] >= 0]
    top = np.sort(z)[-max(1, len(z) // 100):]
    return float(top.mean())


def main(argv: list[str] | None = None) -> int:
    args = parse(argv)
    orifices = sorted(args.orifices)
    names = [f"large-{D * 1000:g}mm-{law}.csv" for D in orifices for law in args.laws]
    out = open_out(args, "mesh_silo_large", ["table.md", "runs.csv", *names])
    variables = dict(args.var)
    mass = 2500.0 * math.pi / 6 * DP ** 3
    rows = []
    with tempfile.TemporaryDirectory(prefix="viscontact-silo-large-") as tmp, out:
        d = workdir(Path(tmp))
        for name in INPUTS:
            shutil.copy(HERE / name, d / name)
        fill = int(variables.get("fill", _fill((d / INPUTS[0]).read_text(), "fill")))
        fill_mesh = write_mesh(d, "silo", "fill.stl", radius=RADIUS, height=HEIGHT,
                               orifice=orifices[0])
        law0, restart, frame_file = args.laws[0], "fill.restart", "fill.frame"
        run(d, INPUTS[0][3:], f"fill, {law0}", args.np,
            {**variables, "law": law0, "mesh": fill_mesh.name, "restart": restart,
             "frame": frame_file})
        frame = read_dump(d / frame_file)[-1]
        rho_b = bulk_density(frame, DP, lambda z: RADIUS)
        depth = bed_depth(frame)
        print(f"    bed {len(frame['z'])} spheres, {depth * 100:.2f} cm deep, rho_b = "
              f"{rho_b:.0f} kg/m^3", file=sys.stderr)
        if depth < DEPTH_MIN:
            print(f"warning: the bed is only {depth * 100:.2f} cm deep (asked: "
                  f"{DEPTH_MIN * 100:g} cm): raise --var n", file=sys.stderr)
        for law in args.laws:
            for D in orifices:
                mesh = write_mesh(d, "silo", f"silo{D}.stl", radius=RADIUS, height=HEIGHT,
                                  orifice=D)
                res = run(d, INPUTS[1][3:], f"discharge D = {D * 1000:g} mm, {law}", args.np,
                          {**{k: v for k, v in variables.items() if k != "fill"}, "law": law,
                           "mesh": mesh.name, "restart": restart})
                rows.append(_measure(res, fill * DT, mass, law, D, rho_b, out.staging,
                                     f"large-{D * 1000:g}mm-{law}"))
        lines, _ = silo_table(rows, DP, f"large silo (R = {RADIUS * 100:g} cm, one fill, {law0})")
        (out.staging / "table.md").write_text("\n".join(lines) + "\n")
        (out.staging / "runs.csv").write_text(runs_csv([("silo-large", rows, DP)]))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
