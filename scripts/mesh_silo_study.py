"""Discharge of the STL-mesh silo (and the conical hopper) against Beverloo's correlation for
two laws (docs/fix_viscontact_mesh.md).

    python3 scripts/mesh_silo_study.py [--orifices 0.018 0.021 0.024] [--laws KK LH]
                                       [--hopper] [--out DIR] [--force] [--var NAME VALUE ...]

Each (orifice D, law) runs ``viscontact/dem/examples/in.mesh.silo`` as shipped (2500 spheres of
d = 3 mm, rho_p = 2500 kg/m^3, fix pour at -var vol 0.08, filled for 40000 steps, then
discharged for 30000 steps of 1e-5 s) with the mesh ``python3 -m viscontact.dem.stl silo
siloD.stl --radius 0.03 --height 0.12 --orifice D``.

* W, the discharge rate: the least-squares slope of the lost mass (spheres gone below the box
  times their mass, from the thermo column Atoms every 500 steps) against time over the steady
  part, from 0.1 s after the plug is pulled (a sphere takes 0.078 s to fall from the orifice to
  the box's floor, 3 cm below, where it is lost) until 20 % of the bed is gone or the run ends
  (the bed is only 2 cm deep: it flows slower as it drains); the slopes of the first and the second
  half of that window are printed too (equal for a steady rate).  DIR/NAME.csv keeps each run's
  lost mass against time.
* rho_b, the bulk density: measured in the filled bed at the moment the plug is pulled (the
  dump frame of that step): the mass of the spheres whose centres lie between 2 d and 5 d above
  the floor, over the silo's cross-section times that height.
* Beverloo: W_B = C rho_b sqrt(g) (D - k d)^(5/2), k = 1.5, C = 0.58 (Beverloo, Leniger & van
  de Velde 1961; published C 0.55-0.65, k 1-3); C fitted = W / (rho_b sqrt(g) (D - k d)^(5/2));
  the exponent fitted per law: the least-squares slope of log W against log(D - k d).

``--hopper``: also runs ``in.mesh.hopper`` as shipped (1200 spheres of 4 mm in a cone of outlet
diameter 20 mm, half-angle 29.7 degrees from the vertical) for each law and compares its W with
Beverloo for hoppers, W_B F(theta), with Rose & Tanaka's factor F = (tan theta tan phi_d)^-0.35
(theta the half-angle from the vertical, phi_d the angle of the flat-bottomed silo's stagnant
zone boundary to the horizontal, taken as 45 degrees; F = 1 for theta >= 90 - phi_d; as given
by Nedderman, Statics and Kinematics of Granular Materials, 1992, ch. 10), with C the silo
runs' mean fitted C of the law.  rho_b there: the spheres with centres 2 d to 5 d above the
outlet, over the cone's frustum volume.

Writes DIR/table.md, DIR/runs.csv and the lost mass of each run, DIR/silo-DDmm-LAW.csv and
DIR/hopper-LAW.csv.
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
from mesh_study_util import add_common, open_out, run, workdir, write_mesh  # noqa: E402

from viscontact.dem import read_dump  # noqa: E402

G, K, C_BEV = 9.81, 1.5, 0.58
DT, THERMO = 1e-5, 500              # the inputs' timestep and thermo interval
SILO_R = 0.03
HOPPER = dict(outlet=0.01, radius=0.05, height=0.07)   # in.mesh.hopper's cone
PHI_D = 45.0
# the steady part: from 0.1 s after the plug (a sphere takes sqrt(2 * 0.03 m / g) = 0.078 s to
# fall from the orifice to the box's floor, where it is lost), until 20 % of the bed is lost
START, LOST_MAX = 0.1, 0.2


def lost_mass(thermo: dict, t_plug: float, mass: float) -> tuple[np.ndarray, np.ndarray, float]:
    """(t, lost mass, spheres at the plug) from the thermo columns Step and Atoms:
    lost = (N at the plug - N) * mass."""
    step, atoms = np.asarray(thermo["Step"], float), np.asarray(thermo["Atoms"], float)
    t = step * DT
    n0 = float(atoms[np.argmin(np.abs(t - t_plug))])
    return t, (n0 - atoms) * mass, n0


def rate(t: np.ndarray, lost: np.ndarray, t_plug: float, total: float
         ) -> tuple[float, float, float, float, float]:
    """(W, W of the window's first half, of its second half, window start, window end): the
    least-squares slope of the lost mass from t_plug + START s while at most LOST_MAX of the
    bed's mass ``total`` is gone (the bed, 2 cm deep, flows slower as it drains)."""
    w = (t >= t_plug + START - 1e-9) & (lost <= LOST_MAX * total)
    if w.sum() < 6:
        raise SystemExit("error: fewer than 6 thermo rows in the steady part: run longer (--var steps)")
    tw, lw = t[w], lost[w]
    half = len(tw) // 2
    slope = lambda a, b: float(np.polyfit(a, b, 1)[0])  # noqa: E731
    return (slope(tw, lw), slope(tw[:half + 1], lw[:half + 1]), slope(tw[half:], lw[half:]),
            float(tw[0] - t_plug), float(tw[-1] - t_plug))


def bulk_density(frame, d: float, radius_at) -> float:
    """Mass of the spheres with centres 2 d to 5 d above z = 0 over the volume there
    (``radius_at(z)``: the container's radius; integrated by the trapezoid rule)."""
    z = frame["z"]
    m = frame["mass"] if "mass" in frame.columns else None
    lo, hi = 2 * d, 5 * d
    inside = (z >= lo) & (z < hi)
    zs = np.linspace(lo, hi, 101)
    vol = float(np.trapezoid(np.pi * np.asarray([radius_at(v) for v in zs]) ** 2, zs))
    mass = float(m[inside].sum()) if m is not None else \
        float(inside.sum()) * 2500.0 * math.pi / 6 * d ** 3
    return mass / vol


def beverloo(rho_b: float, D: float, d: float, c: float = C_BEV) -> float:
    """W = C rho_b sqrt(g) (D - k d)^(5/2) [kg/s]."""
    return c * rho_b * math.sqrt(G) * (D - K * d) ** 2.5


def rose_tanaka(theta_deg: float, phi_d_deg: float = PHI_D) -> float:
    """F = (tan theta tan phi_d)^-0.35 for theta < 90 - phi_d, else 1."""
    if theta_deg >= 90 - phi_d_deg:
        return 1.0
    return (math.tan(math.radians(theta_deg)) * math.tan(math.radians(phi_d_deg))) ** -0.35


def _fill(text: str, name: str) -> int:
    """The default of ``variable NAME index VALUE`` in an input."""
    return int(re.search(rf"^variable\s+{name}\s+index\s+(\S+)", text, re.M).group(1))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[2:]))
    ap.add_argument("--orifices", type=float, nargs="+", default=[0.018, 0.021, 0.024],
                    metavar="D", help="orifice diameters [m] (default 0.018 0.021 0.024)")
    ap.add_argument("--laws", nargs="+", default=["KK", "LH"], help="laws (default KK LH)")
    ap.add_argument("--hopper", action="store_true", help="also the conical hopper, each law")
    add_common(ap, "mesh-silo-study")
    args = ap.parse_args(argv)
    if len(args.orifices) < 2 and not args.hopper:
        ap.error("--orifices needs at least two diameters (the fitted exponent)")
    names = [f"silo-{D * 1000:g}mm-{law}.csv" for D in args.orifices for law in args.laws]
    names += [f"hopper-{law}.csv" for law in args.laws] if args.hopper else []
    out = open_out(args, "mesh_silo_study", ["table.md", "runs.csv", *names])
    variables = dict(args.var)
    silo_rows, hopper_rows = [], []
    with tempfile.TemporaryDirectory(prefix="viscontact-silo-") as tmp, out:
        d = workdir(Path(tmp))
        text = (d / "in.mesh.silo").read_text()
        fill = int(variables.get("fill", _fill(text, "fill")))
        every = int(variables.get("every", _fill(text, "every")))
        if fill % every:
            ap.error("--var fill must be a multiple of --var every (the dump at the plug)")
        dp = 0.003
        mass = 2500.0 * math.pi / 6 * dp ** 3
        for D in args.orifices:
            mesh = write_mesh(d, "silo", f"silo{D}.stl", radius=SILO_R, height=0.12, orifice=D)
            for law in args.laws:
                res = run(d, "mesh.silo", f"silo D = {D * 1000:g} mm, {law}", args.np,
                          {**variables, "law": law, "mesh": mesh.name})
                frame = next(f for f in read_dump(d / "mesh.silo.dump") if f.step == fill)
                rho_b = bulk_density(frame, dp, lambda z: SILO_R)
                silo_rows.append(_measure(res, fill * DT, mass, law, D, rho_b, out.staging,
                                          f"silo-{D * 1000:g}mm-{law}"))
        if args.hopper:
            htext = (d / "in.mesh.hopper").read_text()
            hfill = int(variables.get("fill", _fill(htext, "fill")))
            hp = 0.004
            hmass = 2500.0 * math.pi / 6 * hp ** 3
            write_mesh(d, "hopper", "hopper.stl", **HOPPER)
            cone = lambda z: HOPPER["outlet"] + z * (HOPPER["radius"] - HOPPER["outlet"]) / HOPPER["height"]  # noqa: E731
            for law in args.laws:
                res = run(d, "mesh.hopper", f"hopper, {law}", args.np, {**variables, "law": law})
                frame = next(f for f in read_dump(d / "mesh.hopper.dump") if f.step == hfill)
                rho_b = bulk_density(frame, hp, cone)
                hopper_rows.append(_measure(res, hfill * DT, hmass, law, 2 * HOPPER["outlet"],
                                            rho_b, out.staging, f"hopper-{law}"))
        lines = table(silo_rows, hopper_rows, dp, 0.004)
        (out.staging / "table.md").write_text("\n".join(lines) + "\n")
        (out.staging / "runs.csv").write_text(
            runs_csv([("silo", silo_rows, dp), ("hopper", hopper_rows, 0.004)]))
    print("\n".join(lines))
    return 0


def _measure(res, t_plug: float, mass: float, law: str, D: float, rho_b: float, staging: Path,
             name: str) -> tuple:
    """One run's row (law, D, W, W halves, window, rho_b); its lost mass against time goes to
    staging/NAME.csv (for another choice of the steady part)."""
    t, lost, n0 = lost_mass(res.thermo, t_plug, mass)
    w, w1, w2, t0, t1 = rate(t, lost, t_plug, n0 * mass)
    (staging / f"{name}.csv").write_text("t_after_plug_s,lost_mass_kg\n" + "".join(
        f"{a - t_plug:.5f},{b:.8g}\n" for a, b in zip(t, lost) if a >= t_plug - 1e-9))
    print(f"    W = {w:.4f} kg/s over {t0:.2f}-{t1:.2f} s after the plug (halves {w1:.4f}, "
          f"{w2:.4f}), rho_b = {rho_b:.0f} kg/m^3, lost at the end {lost[-1] / (n0 * mass):.0%}",
          file=sys.stderr)
    return (law, D, w, w1, w2, (t0, t1), rho_b, n0 * mass)


def runs_csv(groups: list[tuple[str, list, float]]) -> str:
    """CSV of the runs (rows of :func:`_measure`): groups of (container's name, its rows, its
    sphere diameter [m])."""
    return ("container,law,D_m,D_over_d,W_kg_s,W_first_half,W_second_half,window_from_s,"
            "window_to_s,rho_b,bed_kg\n"
            + "".join(f"{c},{r[0]},{r[1]},{r[1] / dp:.4g},{r[2]:.6g},{r[3]:.6g},{r[4]:.6g},"
                      f"{r[5][0]:.3f},{r[5][1]:.3f},{r[6]:.1f},{r[7]:.6g}\n"
                      for c, rows, dp in groups for r in rows))


def joint_fit(rows: list, dp: float) -> tuple[float, float]:
    """(C, k) of Beverloo's correlation fitted together: W^(2/5) = (C rho_b sqrt(g))^(2/5)
    (D - k d) is a straight line against D (least squares over the rows of :func:`_measure`,
    rho_b their mean): its slope a = (C rho_b sqrt(g))^(2/5), its intercept -a k d."""
    x = np.array([r[1] for r in rows])
    a, b = np.polyfit(x, np.array([r[2] for r in rows]) ** 0.4, 1)
    rho = float(np.mean([r[6] for r in rows]))
    return float(a ** 2.5 / (rho * math.sqrt(G))), float(-b / (a * dp))


def exponent(rows: list, dp: float) -> float:
    """The least-squares slope of log W against log(D - k d), k = 1.5."""
    return float(np.polyfit(np.log([r[1] - K * dp for r in rows]), np.log([r[2] for r in rows]),
                            1)[0])


def silo_table(rows: list, dp: float, title: str) -> tuple[list[str], dict[str, float]]:
    """Markdown lines of the silo runs (rows of :func:`_measure`): per law and D, W against
    Beverloo with C = 0.58 and the fitted C; per law the exponent, the mean C and the joint fit
    of C and k.  Also the law's mean fitted C."""
    lines = [f"{title} (d = {dp * 1000:g} mm): W against Beverloo W_B = C rho_b sqrt(g) "
             f"(D - {K} d)^(5/2), C = {C_BEV}, rho_b measured", "",
             "| law | D [mm] | D/d | rho_b [kg/m^3] | W [kg/s] | fit over [s] | W halves [kg/s] | "
             "W_B [kg/s] | C fitted |",
             "|---|---|---|---|---|---|---|---|---|"]
    c_mean = {}
    for law in dict.fromkeys(r[0] for r in rows):
        cs = []
        for _, D, w, w1, w2, win, rho, _ in (r for r in rows if r[0] == law):
            wb = beverloo(rho, D, dp)
            cs.append(C_BEV * w / wb)
            lines.append(f"| {law} | {D * 1000:g} | {D / dp:.3g} | {rho:.0f} | {w:.4f} | "
                         f"{win[0]:.2f}-{win[1]:.2f} | {w1:.4f} / {w2:.4f} | {wb:.4f} | "
                         f"{cs[-1]:.3f} |")
        c_mean[law] = float(np.mean(cs))
    lines.append("")
    for law in c_mean:
        lr = [r for r in rows if r[0] == law]
        if len(lr) >= 2:
            c, k = joint_fit(lr, dp)
            lines.append(f"{law}: W ~ (D - {K} d)^{exponent(lr, dp):.2f} (Beverloo 2.5), mean C "
                         f"fitted {c_mean[law]:.3f}; C and k fitted together: C = {c:.3f}, "
                         f"k = {k:.2f}")
    return lines, c_mean


def table(silo_rows: list, hopper_rows: list, dp: float, hp: float) -> list[str]:
    """Markdown: the silo table, the fitted exponents, the hopper comparison."""
    lines, c_mean = silo_table(silo_rows, dp, "silo (in.mesh.silo)")
    if hopper_rows:
        theta = math.degrees(math.atan((HOPPER["radius"] - HOPPER["outlet"]) / HOPPER["height"]))
        f = rose_tanaka(theta)
        lines += ["", f"hopper (in.mesh.hopper, d = {hp * 1000:g} mm, D = "
                  f"{2 * HOPPER['outlet'] * 1000:g} mm, half-angle {theta:.1f} deg): Rose & "
                  f"Tanaka F = (tan theta tan {PHI_D:g})^-0.35 = {f:.3f}; C = the law's silo mean", "",
                  "| law | rho_b [kg/m^3] | W [kg/s] | fit over [s] | W halves [kg/s] | W_B flat "
                  "[kg/s] | W_B F [kg/s] | W / W_B flat |", "|---|---|---|---|---|---|---|---|"]
        for law, D, w, w1, w2, win, rho, _ in hopper_rows:
            wb = beverloo(rho, D, hp, c_mean.get(law, C_BEV))
            lines.append(f"| {law} | {rho:.0f} | {w:.4f} | {win[0]:.2f}-{win[1]:.2f} | "
                         f"{w1:.4f} / {w2:.4f} | {wb:.4f} | {wb * f:.4f} | {w / wb:.3f} |")
    return lines


if __name__ == "__main__":
    raise SystemExit(main())
