"""Exact batch solve: collisions per second against a scipy solve_ivp loop (issue 4, item 1).

    python3 benchmarks/bench_speed.py [--n 100000] [--baseline 300] [--check 6] [--laws LH Ts ...]

For every law, n random (alpha, beta) in [0, 10] (beta only for Jian; power with p = 0.75),
zero-force end:

- throughput of ``viscontact.restitution(..., exact=True)`` (the solver, not the tables of
  ``benchmarks/bench_tables.py``) and of the batch solver itself
  (``solve_batch``: e, t_c, residual, dissipated work, separated: what
  ``collide(..., history=False)`` returns), after one warm-up call (compilation is cached);
- the same for the baseline a DEM user would write (scipy ``solve_ivp``, DOP853, rtol 1e-10,
  event location; ``benchmarks/bench_restitution.py``) on a few hundred of the same
  collisions, in the same run, and the ratio of per-collision throughputs;
- the largest |e - exact| on a sample that includes alpha and beta down to 1e-9, against an
  independent high-precision solve (mpmath Taylor series at 22 digits, ``scripts/references.py``),
  or the closed forms for Hunt-Crossley (exact relation) and Tsuji;
- cost against batch size (n/10 and n) and threads (1 and all).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numba
import numpy as np

import viscontact as vc
from viscontact.physics.laws import resolve
from viscontact.solvers.batch import BATCH_RTOL, solve_batch

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "scripts"))  # references.py
from bench_restitution import baseline_e  # noqa: E402
from references import hunt_e, taylor_reference, tsuji_force_e  # noqa: E402

P_POWER = 0.75
TARGET_RATE, TARGET_RATIO = 1e6, 3000.0


def law_inputs(law: str, n: int, rng: np.random.Generator):
    """(resolved law, alpha, beta or None, keyword arguments for restitution)."""
    alpha = rng.uniform(0.0, 10.0, n)
    if law == "Jian":
        beta = rng.uniform(0.0, 10.0, n)
        return resolve(law, beta=0.0), alpha, beta, {"beta": beta}
    kw = {"p": P_POWER} if law == "power" else {}
    return resolve(law, **kw), alpha, None, kw


def best_time(fn, repeat: int = 3) -> float:
    """Shortest wall time of ``repeat`` calls (the machine is shared; the minimum is the cost)."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def exact_e(law: str, p: float, alpha: float, beta: float) -> float:
    """Closed forms for Hunt and Tsuji, the 22-digit Taylor-series solve for the others."""
    if law == "Hunt":
        return hunt_e(alpha)
    if law == "Ts":
        return tsuji_force_e(alpha)
    ref = taylor_reference(p, alpha, beta, "force", t_stop=50.0)
    assert ref is not None, "the zero-force end always comes"
    return ref[0]


def accuracy_sample(law: str, k: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """k (alpha, beta) pairs: the extremes 1e-9 and 10 first, then log-uniform ones.

    For ``power`` (x = s^4) alpha starts at 1e-3: below, the zero force is so flat that the
    Taylor reference's root search takes minutes (Ts, also x = s^4, covers tiny alpha exactly).
    """
    low = -3 if law == "power" else -9
    fixed_a, fixed_b = [10.0**low, 10.0, 10.0**low, 10.0], [1e-9, 1e-9, 10.0, 10.0]
    alpha = np.array(fixed_a + list(10 ** rng.uniform(low, 1, max(k - 4, 0))))[:k]
    beta = np.array(fixed_b + list(10 ** rng.uniform(-9, 1, max(k - 4, 0))))[:k]
    return alpha, (beta if law == "Jian" else np.zeros(k))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100_000, help="collisions per law (default 1e5)")
    ap.add_argument("--baseline", type=int, default=300,
                    help="collisions per law for the scipy loop (default 300)")
    ap.add_argument("--check", type=int, default=6,
                    help="collisions per law checked against the high-precision solve (default 6)")
    ap.add_argument("--laws", nargs="+", default=list(vc.MODELS))
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    threads = numba.get_num_threads()

    t0 = time.perf_counter()
    for law in args.laws:  # compile (or load from the cache) every specialisation once
        lp, a, b, kw = law_inputs(law, 8, rng)
        vc.restitution(law, a, exact=True, **kw)
    print(f"numba threads: {threads}; first calls (compile or cache load): "
          f"{time.perf_counter() - t0:.1f} s; batch rtol {BATCH_RTOL:g}; n = {args.n}")

    head = (f"{'law':>6} {'restitution/s':>14} {'batch/s':>12} {'scipy loop/s':>13} "
            f"{'ratio':>8} {'1 thread/s':>11} {'t(n)/t(n/10)':>13} {'max|e-exact|':>13}")
    print(head)
    print("-" * len(head))
    worst_rate, worst_ratio, worst_err = np.inf, np.inf, 0.0
    for law in args.laws:
        lp, a, b, kw = law_inputs(law, args.n, rng)
        t_rest = best_time(lambda: vc.restitution(law, a, exact=True, **kw))
        t_batch = best_time(lambda: solve_batch(lp, a, beta=b))
        small = args.n // 10
        t_small = best_time(lambda: solve_batch(lp, a[:small], beta=None if b is None else b[:small]))
        numba.set_num_threads(1)
        t_one = best_time(lambda: solve_batch(lp, a, beta=b), repeat=1)
        numba.set_num_threads(threads)

        nb = args.baseline
        bb = np.zeros(nb) if b is None else b[:nb]
        t0 = time.perf_counter()
        e_base = np.array([baseline_e(lp.p, float(x), float(y)) for x, y in zip(a[:nb], bb)])
        t_base = time.perf_counter() - t0
        e_ours = solve_batch(lp, a[:nb], beta=None if b is None else b[:nb]).e
        assert np.max(np.abs(e_ours - e_base)) < 1e-6, "baseline and batch disagree"

        sa, sb = accuracy_sample(law, args.check, rng)
        e_s = solve_batch(lp, sa, beta=sb if law == "Jian" else None).e
        err = max(abs(e - exact_e(law, lp.p, x, y)) for e, x, y in zip(e_s, sa, sb))

        rate_rest, rate_batch, rate_base = args.n / t_rest, args.n / t_batch, nb / t_base
        ratio = rate_rest / rate_base
        worst_rate, worst_ratio = min(worst_rate, rate_rest), min(worst_ratio, ratio)
        worst_err = max(worst_err, err)
        print(f"{law:>6} {rate_rest:14.3g} {rate_batch:12.3g} {rate_base:13.3g} {ratio:8.0f} "
              f"{args.n / t_one:11.3g} {t_batch / t_small:13.2f} {err:13.2e}")
    print("-" * len(head))
    print(f"slowest law: {worst_rate:.3g} collisions/s (target {TARGET_RATE:.0e}), "
          f"smallest ratio {worst_ratio:.0f} (target {TARGET_RATIO:.0f}), "
          f"largest |e - exact| {worst_err:.1e} (contract 1e-8)")


if __name__ == "__main__":
    main()
