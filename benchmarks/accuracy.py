"""Accuracy of viscontact against every independent reference of the core issue, in one table.

    python3 benchmarks/accuracy.py [--taylor 12]

Prints the largest error found against each reference (closed forms, the undamped Hertz
contact, the energy balance, a 22-digit mpmath Taylor-series solve, the published e values,
Jian with beta = 0 against KK, the calibration round trip) and the error against tolerance.
The references live in scripts/references.py and never call viscontact.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

import viscontact as vc

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))  # references.py
from references import (  # noqa: E402
    TC_HERTZ, XMAX_HERTZ, hunt_e, taylor_reference, tsuji_force_e, tsuji_overlap_alpha,
)

ENDS = ("force", "overlap")
ALPHAS = np.concatenate([[1e-9, 1e-6, 1e-3], np.linspace(0.01, 10.0, 40)])
EXTRA = {"Jian": {"beta": 0.5}, "power": {"p": 0.75}}
PUBLISHED = {"LH": 0.6207, "Ts": 0.6778, "KK": 0.7221, "Li": 0.7890, "Hunt": 0.8329, "Jian": 0.7622}


def _row(name: str, err: float, bound: float, cases: int) -> None:
    verdict = "ok" if err <= bound else "OVER"
    print(f"{name:<52} {cases:>6} {err:>11.2e} {bound:>9.0e}  {verdict}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--taylor", type=int, default=12, help="mpmath cases per end (slow: ~1 s each)")
    args = ap.parse_args()
    print(f"{'reference':<52} {'cases':>6} {'max error':>11} {'bound':>9}")

    err = max(abs(vc.collide("Hunt", a, end=end, history=False).e - hunt_e(a))
              for a in ALPHAS for end in ENDS)
    _row("Hunt-Crossley exact relation, e (both ends)", err, 1e-8, 2 * ALPHAS.size)

    targets = np.geomspace(1e-5, 0.999, 30)
    err = max(abs(vc.collide("Ts", tsuji_overlap_alpha(e), end="overlap", history=False).e - e)
              for e in targets)
    _row("Tsuji zero-overlap closed form, e", err, 1e-8, targets.size)

    err = max(abs(vc.collide("Ts", a, history=False).e - tsuji_force_e(a)) for a in ALPHAS)
    _row("Tsuji zero-force closed form, e", err, 1e-8, ALPHAS.size)

    undamped = [vc.collide(m, 0.0, end=end, **EXTRA.get(m, {})) for m in vc.MODELS for end in ENDS]
    _row("undamped Hertz contact, e", max(abs(r.e - 1) for r in undamped), 1e-8, len(undamped))
    _row("undamped Hertz contact, t_c", max(abs(r.tc - TC_HERTZ) for r in undamped), 1e-7,
         len(undamped))
    _row("undamped Hertz contact, x_max", max(abs(r.xmax - XMAX_HERTZ) for r in undamped), 1e-9,
         len(undamped))

    balance = [abs(vc.collide(m, a, end=end, history=False, **EXTRA.get(m, {})).energy_error)
               for m in vc.MODELS for a in ALPHAS[::4] for end in ENDS]
    _row("energy balance (docs/laws.md)", max(balance), 1e-8, len(balance))

    rng = np.random.default_rng(7)
    e_err = tc_err = 0.0
    cases = 0
    for end in ENDS:
        for _ in range(args.taylor):
            model = str(rng.choice(["LH", "Ts", "KK", "Li", "Jian"]))
            alpha = float(10 ** rng.uniform(-3, 1))  # the series root finder needs a transversal end
            beta = float(10 ** rng.uniform(-9, 1)) if model == "Jian" else 0.0
            ref = taylor_reference(vc.LAWS[model].p, alpha, beta, end, t_stop=20.0)
            if ref is None:
                continue
            r = vc.collide(model, alpha, end=end, history=False,
                           **({"beta": beta} if model == "Jian" else {}))
            e_err, tc_err = max(e_err, abs(r.e - ref[0])), max(tc_err, abs(r.tc - ref[1]))
            cases += 1
    _row("mpmath Taylor series (22 digits), e", e_err, 1e-8, cases)
    _row("mpmath Taylor series (22 digits), t_c", tc_err, 1e-7, cases)

    err = max(abs(round(vc.collide(m, 0.3, history=False, **EXTRA.get(m, {})).e, 4) - v)
              for m, v in PUBLISHED.items())
    _row("published e at alpha = 0.3 (Jian et al. 2019), 4 decimals", err, 0.0, len(PUBLISHED))

    err = max(abs(vc.restitution("Jian", a, beta=0.0, end=end) - vc.restitution("KK", a, end=end))
              for a in ALPHAS[::3] for end in ENDS)
    _row("Jian with beta = 0 against KK, e", err, 1e-12, ALPHAS[::3].size * 2)

    e_grid = np.linspace(0.05, 1.0, 20)
    err = max(float(np.max(np.abs(vc.restitution(m, vc.alpha_from_e(m, e_grid, **kw), **kw) - e_grid)))
              for m, kw in (("LH", {}), ("KK", {}), ("Hunt", {}), ("Jian", {"beta": 1.0})))
    _row("calibration round trip |e(alpha(e)) - e|", err, 1e-9, 4 * e_grid.size)

    print("\nconvergence (Li, alpha = 0.7, zero force; reference: rtol 1e-13):")
    exact = vc.collide("Li", 0.7, rtol=1e-13, history=False).e
    for rtol in (1e-6, 1e-8, 1e-10, 1e-12):
        e = vc.collide("Li", 0.7, rtol=rtol, history=False).e
        print(f"  rtol {rtol:.0e}: |e - e_ref| = {abs(e - exact):.2e}")
    if not math.isfinite(exact):  # pragma: no cover
        raise SystemExit("reference solve failed")


if __name__ == "__main__":
    main()
