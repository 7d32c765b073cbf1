"""The relaxation factor g = 1 - exp(-t/beta) (table and series, no library calls) against
40-digit mpmath."""

import math

import mpmath
import numpy as np

from viscontact.physics.kernels import relaxation


def test_relaxation_within_a_few_ulp_of_high_precision():
    rng = np.random.default_rng(7)
    ratios = np.concatenate([
        rng.uniform(0.0, 45.0, 1500), 10.0 ** rng.uniform(-14.0, 0.5, 1000),
        np.arange(0, 641) / 16.0,  # every table node
        np.arange(0, 640) / 16.0 + 1.0 / 16.0 * (1.0 - 1e-15),  # just below the next node
    ])
    mpmath.mp.dps = 40
    worst = 0.0
    for y in ratios:
        t, beta = float(y) * 0.37, 0.37
        exact = 1 - mpmath.exp(-mpmath.mpf(t) / mpmath.mpf(beta))
        g = relaxation(t, beta)
        worst = max(worst, abs(g - float(exact)) / float(exact) if exact else abs(g))
    assert worst <= 4 * 2.0 ** -52, worst


def test_relaxation_edges():
    assert relaxation(1.0, 0.0) == 1.0  # KK: no relaxation
    assert relaxation(0.0, 0.5) == 0.0
    assert relaxation(1e3, 1e-9) == 1.0  # capped where exp(-t/beta) < 5e-18
    assert relaxation(math.nan, 0.5) == 1.0  # NaN time treated as long relaxed
