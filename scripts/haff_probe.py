"""How close one realisation of the cooling gas comes to Haff's law over its first 4 tau0.

    python3 scripts/haff_probe.py [--np 1] [--n 4000] [--tc-ratio 0.02] [--seed 2024]

Runs the full DEM study's gas (``viscontact.demstudy.gas.FULL_GAS``, Ts law, e = 0.8) with the
given number of spheres, contact time over mean free time and seed for 4 Haff times tau0, and
prints T(0)/T0 - 1, T/T_Haff - 1 in blocks of tau0/4, and the largest deviation (the quantity the
issue bounds by 5 %).  Needs LAMMPS and the plugin (built on first use).
"""

from __future__ import annotations

import argparse
import dataclasses
import tempfile
from pathlib import Path

import numpy as np

from viscontact.demstudy import gas


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--np", type=int, default=1, help="MPI ranks (default 1)")
    ap.add_argument("--n", type=int, default=gas.FULL_GAS.n, help="spheres (default 4000)")
    ap.add_argument("--tc-ratio", type=float, default=gas.FULL_GAS.tc_ratio,
                    help="contact time / mean free time at v_ref (default 0.02)")
    ap.add_argument("--seed", type=int, default=gas.FULL_GAS.seed, help="random seed")
    a = ap.parse_args()
    s = dataclasses.replace(gas.FULL_GAS, n=a.n, t_end_tau0=4.0, tc_ratio=a.tc_ratio, dumps=2,
                            seed=a.seed)
    with tempfile.TemporaryDirectory() as work:
        run = gas.run_gas(Path(work), s, models=("Ts",), np_=a.np).runs["Ts"]
    _, dev = gas.haff_deviation(run.t, run.T, s.T0, s.tau0(), 4.0)
    print(f"np={a.np} n={a.n} tc_ratio={a.tc_ratio} seed={a.seed}: T(0)/T0 - 1 = "
          f"{run.T[0] / s.T0 - 1:+.4f}; max |T/T_Haff - 1| over 4 tau0 = {np.max(np.abs(dev)):.4f}")
    print("T/T_Haff - 1 per tau0/4:", " ".join(f"{d:+.3f}" for d in dev))


if __name__ == "__main__":
    main()
