"""The tables of docs/fit-restitution.md: coverage and ranking of the e(v) fit over synthetic
data sets per law, and the fits of the shipped real bounce timings.

    PYTHONPATH=src python3 scripts/fit_restitution_table.py [--seeds 100]

Synthetic data as in tests/fit/test_restitution.py: 10 speeds over a decade (0.3 to 3 m/s),
e of the generating law (alpha_ref 0.3 at 1 m/s; Jian alpha 0.6, beta 0.5; power p 0.8) plus
Gaussian noise of the drop tests' scatter (0.008) and a phone's timing (0.1 ms on each flight).
"""

from __future__ import annotations

import argparse
import math
from importlib import resources

import numpy as np

from viscontact.fit import (RES_LAWS, drag_constant, fit_restitution, fit_restitution_sets,
                            model_e, read_drops, reduce_bounces)
from viscontact.physics.laws import lookup

TRUTH = {"LH": (0.3, None), "Ts": (0.3, None), "KK": (0.3, None), "Li": (0.3, None),
         "Hunt": (0.3, None), "Jian": (0.6, 0.5), "power": (0.3, 0.8)}
V = np.geomspace(0.3, 3.0, 10)


def synthetic(seeds: int) -> None:
    print("| law | coverage alpha_ref | coverage beta_ref / p | first | within dAICc < 2 | "
          "median dAICc of the runner-up |")
    print("|---|---|---|---|---|---|")
    for law in RES_LAWS:
        a, second = TRUTH[law]
        spec = lookup(law)
        e0 = model_e(law, V, 1.0, a, beta=second if spec.needs_beta else None,
                     p=second if spec.p is None else None)
        sig = np.sqrt(0.008 ** 2 + (e0 * math.sqrt(2) * 1e-4 / (2 * V / 9.81)) ** 2)
        E = e0 + sig * np.random.default_rng(27).standard_normal((seeds, V.size))
        fits = {o: fit_restitution_sets(V, E, law=o, sigma=sig, vref=1.0) for o in RES_LAWS}
        mine = fits[law]
        aicc = np.array([fits[o].aicc for o in RES_LAWS])
        d = mine.aicc - aicc.min(axis=0)
        others = np.sort(np.delete(aicc, RES_LAWS.index(law), axis=0) - mine.aicc, axis=0)[0]
        c2 = "-" if second is None else f"{np.mean(np.abs(mine.second - second) <= mine.second_err):.2f}"
        print(f"| {law} | {np.mean(np.abs(mine.alpha - a) <= mine.alpha_err):.2f} | {c2} | "
              f"{np.mean(d == 0):.2f} | {np.mean(d < 2):.2f} | {np.median(others):+.1f} |")


def real() -> None:
    for name, mass, radius in (("bounces_pingpong.csv", 2.7e-3, 0.02),
                               ("bounces_golf.csv", 45.93e-3, 0.021335)):
        path = resources.files("viscontact") / "data" / name
        red = reduce_bounces(read_drops(path), k_drag=drag_constant(mass, radius))
        fit = fit_restitution(red.data, rejected=red.rejected)
        d = red.data
        print(f"\n{name}: {d.n} points ({len(red.rejected)} left out), v = {d.v.min():.3g} to "
              f"{d.v.max():.3g} m/s, mean e = {d.e.mean():.4f}, vref = {fit.vref} m/s")
        print("| rank | law | alpha_ref | beta_ref / p | rms | dAICc | LOO |")
        print("|---|---|---|---|---|---|---|")
        best = fit.laws[fit.ranking[0]].aicc
        for i, k in enumerate(fit.ranking, 1):
            f = fit.laws[k]
            s = (f"{f.beta:.3g} ± {f.beta_err:.2g}" if f.beta is not None else
                 f"p = {f.p:.3f} ± {f.p_err:.3f}" if f.p_err is not None else "-")
            print(f"| {i} | {k} | {f.alpha:.4g} ± {f.alpha_err:.2g} | {s} | {f.rms:.4f} | "
                  f"{f.aicc - best:.1f} | {f.loo:.4f} |")
        print(fit.verdict)
        for r in red.rejected:
            print("left out:", r["source"].rsplit("/", 1)[-1], r["impact"], r["reason"])


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--seeds", type=int, default=100)
    synthetic(ap.parse_args().seeds)
    real()
