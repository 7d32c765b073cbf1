"""Dynamic angle of repose in a rotating drum whose mantle is an STL mesh against the same drum
as a rotating LAMMPS region, over several seeds each (docs/fix_viscontact_mesh.md).

    python3 scripts/mesh_drum_study.py [--seeds 1 2 3 4 5] [--law KK] [--out DIR] [--force]
                                       [--faces 128] [--from 1.0] [--var NAME VALUE ...]

Each seed runs ``viscontact/dem/examples/in.mesh.drum`` (320 spheres of 3.2-4.8 mm, a third of
a quasi-2D drum of radius 4 cm, periodic along its axis, turning at 15 rpm after a settle)
twice: ``-var wall mesh`` (the mantle a tube of ``--faces`` flat faces written by
``python3 -m viscontact.dem.stl drum``, turning with the mesh fix's ``rotate``) and ``-var wall
region`` (a ``region cylinder`` turning with ``rotate``), the same law, spheres (the seed places
and sizes them), fill and rotation.

The angle: in every dump frame from ``--from`` seconds of turning on (the flow is steady after
about 0.8 s: one avalanche cycle), the free surface is the top of the bed (largest y + radius)
in 7 bins of equal width across the central half of the drum (|x| <= R/2); the angle is the
arctangent of the least-squares slope of those tops against the bins' centres.  A run's angle
is the mean over its frames; the table gives each wall's mean over the seeds with its standard
error (sample standard deviation / sqrt(seeds)).  As a cross-check the bed's principal-axis
angle (the long axis of the second moment of the sphere centres) is averaged the same way.

The test: the means agree when |m_mesh - m_region| <= sqrt(se_mesh^2 + se_region^2); Welch's t
and its two-sided p are printed too.  Writes DIR/table.md, DIR/runs.csv and each run's dump.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from mesh_study_util import add_common, mean_se, open_out, run, welch, workdir, write_mesh  # noqa: E402

from viscontact.dem import read_dump  # noqa: E402

R = 0.04        # the drum's radius in in.mesh.drum [m]
BINS = 7


def surface_angle(x: np.ndarray, y: np.ndarray, r: np.ndarray) -> float:
    """Degrees: arctan of the least-squares slope of the bed's top (max y + r per bin) against x
    over BINS equal bins of |x| <= R/2."""
    edges = np.linspace(-R / 2, R / 2, BINS + 1)
    xc, top = [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        m = (x >= lo) & (x < hi)
        if m.any():
            xc.append(0.5 * (lo + hi))
            top.append(float(np.max(y[m] + r[m])))
    if len(xc) < 3:
        raise ValueError("fewer than 3 bins hold spheres: is the drum empty?")
    return math.degrees(math.atan(np.polyfit(xc, top, 1)[0]))


def principal_angle(x: np.ndarray, y: np.ndarray) -> float:
    """Degrees: the direction of the long principal axis of the centres' second moment."""
    c = np.c_[x - x.mean(), y - y.mean()]
    _, vec = np.linalg.eigh(c.T @ c)
    ax = vec[:, 1]
    return math.degrees(math.atan(ax[1] / ax[0]))


def run_angles(dump: Path, first_step: int) -> tuple[float, float, int]:
    """(surface angle, principal-axis angle, frames) averaged over the frames from first_step."""
    frames = [f for f in read_dump(dump) if f.step >= first_step]
    if not frames:
        raise SystemExit(f"error: {dump} has no frame from step {first_step}: run longer")
    s = [surface_angle(f["x"], f["y"], f["radius"]) for f in frames]
    p = [principal_angle(f["x"], f["y"]) for f in frames]
    return float(np.mean(s)), float(np.mean(p)), len(frames)


def _default(name: str, text: str) -> str:
    return re.search(rf"^variable\s+{name}\s+index\s+(\S+)", text, re.M).group(1)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[2:]))
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4, 5], metavar="SEED",
                    help="seeds (fix pour places and sizes the spheres; default 1 2 3 4 5)")
    ap.add_argument("--law", default="KK", help="law.LAW of the examples (default KK)")
    ap.add_argument("--faces", type=int, default=128, help="the mesh tube's faces (default 128)")
    ap.add_argument("--from", dest="t_from", type=float, default=1.0, metavar="S",
                    help="seconds of turning after which frames count (default 1.0)")
    add_common(ap, "mesh-drum-study")
    args = ap.parse_args(argv)
    if len(args.seeds) < 2 or len(set(args.seeds)) != len(args.seeds):
        ap.error("--seeds needs at least two different seeds (a standard error)")
    walls = ("mesh", "region")
    dumps = [f"{w}-{s}.dump" for s in args.seeds for w in walls]
    out = open_out(args, "mesh_drum_study", ["table.md", "runs.csv", *dumps])
    variables = dict(args.var)
    rows: dict[str, list[tuple[int, float, float]]] = {w: [] for w in walls}
    with tempfile.TemporaryDirectory(prefix="viscontact-drum-") as tmp, out:
        d = workdir(Path(tmp))
        write_mesh(d, "drum", "drum.stl", radius=R, zlo=-0.01, zhi=0.022, faces=args.faces)
        text = (d / "in.mesh.drum").read_text()
        settle = int(variables.get("settle", _default("settle", text)))
        dt = float(re.search(r"^timestep\s+(\S+)", text, re.M).group(1))
        first = settle + round(args.t_from / dt)
        for s in args.seeds:
            for w in walls:
                res = run(d, "mesh.drum", f"{w} seed {s}", args.np,
                          {**variables, "law": args.law, "wall": w, "seed": s})
                if res.thermo["Atoms"][-1] != res.thermo["Atoms"][0]:
                    raise SystemExit(f"error: {w} seed {s} lost spheres")
                surf, pa, nf = run_angles(d / "mesh.drum.dump", first)
                (d / "mesh.drum.dump").replace(out.staging / f"{w}-{s}.dump")
                rows[w].append((s, surf, pa))
                print(f"    surface {surf:.2f} deg, principal axis {pa:.2f} deg ({nf} frames)",
                      file=sys.stderr)
        lines = table(rows, args)
        (out.staging / "table.md").write_text("\n".join(lines) + "\n")
        (out.staging / "runs.csv").write_text(
            "wall,seed,surface_deg,principal_deg\n"
            + "".join(f"{w},{s},{a:.4f},{p:.4f}\n" for w in walls for s, a, p in rows[w]))
    print("\n".join(lines))
    return 0


def table(rows: dict[str, list[tuple[int, float, float]]], args: argparse.Namespace) -> list[str]:
    """The Markdown table: per-seed angles, means with standard errors, the test."""
    seeds = [s for s, _, _ in rows["mesh"]]
    lines = [f"dynamic angle of repose [degrees], in.mesh.drum, law {args.law}, mesh tube of "
             f"{args.faces} faces vs region cylinder, frames from {args.t_from} s of turning",
             "", "| wall | " + " | ".join(f"seed {s}" for s in seeds) + " | mean +- se | "
             "principal axis mean +- se |", "|---|" + "---|" * (len(seeds) + 2)]
    stats = {}
    for w, rs in rows.items():
        m, se = mean_se([a for _, a, _ in rs])
        pm, pse = mean_se([p for _, _, p in rs])
        stats[w] = (m, se, [a for _, a, _ in rs], pm, pse, [p for _, _, p in rs])
        lines.append(f"| {w} | " + " | ".join(f"{a:.2f}" for _, a, _ in rs)
                     + f" | {m:.2f} +- {se:.2f} | {pm:.2f} +- {pse:.2f} |")
    lines.append("")
    for what, i in (("surface", 0), ("principal axis", 3)):
        (m1, se1), (m2, se2) = stats["mesh"][i:i + 2], stats["region"][i:i + 2]
        t, dof, p = welch(stats["mesh"][i + 2], stats["region"][i + 2])
        comb = math.hypot(se1, se2)
        verdict = "agree" if abs(m1 - m2) <= comb else "differ"
        lines.append(f"{what}: |m_mesh - m_region| = {abs(m1 - m2):.2f} deg, sqrt(se_mesh^2 + "
                     f"se_region^2) = {comb:.2f} deg: {verdict}; Welch t = {t:.2f} "
                     f"({dof:.1f} dof), p = {p:.2f}")
    return lines


if __name__ == "__main__":
    raise SystemExit(main())
