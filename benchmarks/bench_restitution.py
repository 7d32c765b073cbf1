"""Collisions per second of viscontact.restitution against a plain scipy solve_ivp loop.

    python3 benchmarks/bench_restitution.py [--n 1000] [--laws LH Ts ...]

For each law: e over n alpha values in [0, 10] (zero-force end; Jian with beta = 0.5,
power with p = 0.75) by viscontact, then by the baseline a DEM user would write (DOP853,
rtol 1e-10, event location, original variables x, x'), in the same run; prints throughput,
the ratio, and the largest difference between the two answers.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.integrate import solve_ivp

import viscontact as vc

EXTRA = {"Jian": {"beta": 0.5}, "power": {"p": 0.75}}


def baseline_e(p: float, alpha: float, beta: float) -> float:
    """The plain approach: integrate x'' = -F in t until F (or x) returns to zero."""

    def force(y, t):
        x = max(y[0], 0.0)
        g = 1.0 if beta == 0 else 1.0 - math.exp(-t / beta)
        return x**1.5 + alpha * g * x**p * y[1]

    def rhs(t, y):
        return [y[1], -force(y, t)]

    def zero_force(t, y):
        return force(y, t) if t > 1e-9 else 1.0

    def zero_overlap(t, y):
        return y[0] if t > 1e-9 else 1.0

    for ev in (zero_force, zero_overlap):
        ev.terminal, ev.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 1000.0), [0.0, 1.0], method="DOP853", rtol=1e-10, atol=1e-12,
                    events=[zero_force, zero_overlap])
    return -sol.y[1, -1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000, help="alpha values per law (default 1000)")
    ap.add_argument("--laws", nargs="+", default=list(vc.MODELS))
    args = ap.parse_args()
    alphas = np.linspace(0.0, 10.0, args.n)
    vc.restitution("KK", [0.1, 0.2], exact=True)  # compile / warm caches outside the timing
    print(f"{'law':>6} {'viscontact [1/s]':>17} {'scipy loop [1/s]':>17} {'ratio':>8} {'max |de|':>10}")
    for law in args.laws:
        kw = EXTRA.get(law, {})
        t0 = time.perf_counter()
        e = vc.restitution(law, alphas, exact=True, **kw)  # the solver, not the tables
        t_vc = time.perf_counter() - t0
        p = kw.get("p", vc.LAWS[law].p)
        t0 = time.perf_counter()
        e_base = np.array([baseline_e(p, a, kw.get("beta", 0.0)) for a in alphas])
        t_base = time.perf_counter() - t0
        rate_vc, rate_base = args.n / t_vc, args.n / t_base
        print(f"{law:>6} {rate_vc:17.1f} {rate_base:17.1f} {rate_vc / rate_base:8.2f} "
              f"{np.max(np.abs(e - e_base)):10.2e}")


if __name__ == "__main__":
    main()
