"""Every number behind the study's tables and figures (Jian et al., Powder Technol. 356 (2019) 735), computed once.

:func:`run_study` solves all collisions and returns a :class:`StudyResults`; the report
package (:mod:`viscontact.report`) only reads it.  Grids are module constants so that the
tables, figures and tests agree on them.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..calibration.inverse import restitution
from ..collision.single import CollisionResult, collide
from ..collision.impact import ImpactResult, impact
from ..physics.pair import hertz_limit
from .experiment import Ball, PhysicalCalibration, calibrate_ball, load_balls
from ..physics.laws import STUDY_MODELS
from .._support.parallel import forked_map
from ..collision.sweep import SweepResult, study_speeds, velocity_sweep
from ..physics.laws import Hunt, Jian, KK, LH, Li, Ts

__all__ = [
    "ALPHA_GRID", "PUBLISHED_E", "BETA_GRID", "TABLE1_MODELS", "ALPHA_REF", "BETA_REF", "SERIES_ALPHAS",
    "FIG6_BETAS", "BallStudy", "StudyResults", "run_study", "STEPS",
]

#: Table 1 / Table 2 alpha grid: 0, 0.02, ..., 0.20, 0.3, ..., 1.2, 1.4, ..., 3.0 (30 values)
ALPHA_GRID: tuple[float, ...] = tuple(
    [round(0.02 * i, 2) for i in range(11)]
    + [round(0.1 * i, 1) for i in range(3, 13)]
    + [round(0.2 * i, 1) for i in range(7, 16)]
)
#: Table 2: Jian's beta values (beta = 0 is KK)
BETA_GRID: tuple[float, ...] = (0.0, 0.1, 0.3, 0.5, 1.0, 1.5, 2.0, 2.5, 3.2)
#: Table 1's laws (Jian has its own table)
TABLE1_MODELS: tuple[str, ...] = (LH.name, Ts.name, KK.name, Li.name, Hunt.name)
#: Fig. 2 and Fig. 6: alpha; Fig. 2: Jian's beta
ALPHA_REF = 0.3
BETA_REF = 0.5
#: e at alpha = 0.3 as published (zero-force end; Jian with beta = 0.5), Jian et al. 2019
PUBLISHED_E: dict[str, float] = {
    LH.name: 0.6207, Ts.name: 0.6778, KK.name: 0.7221, Li.name: 0.7890, Hunt.name: 0.8329,
    Jian.name: 0.7622,
}
#: Figs. 3-5: the alpha values drawn for each law
SERIES_ALPHAS: tuple[float, ...] = (0.0, 0.2, 0.4, 0.6, 0.8, 1.0)
#: Fig. 6: Jian's beta values at alpha = 0.3 (beta -> 0 drawn as beta = 0, i.e. KK)
FIG6_BETAS: tuple[float, ...] = (0.0, 0.1, 0.5, 1.0)

#: the steps of :func:`run_study`, in order, with their relative cost (for progress bars)
STEPS: tuple[tuple[str, int], ...] = (
    ("table 1: e(alpha), five laws", 3),
    ("table 2: e(alpha), Jian for nine beta", 5),
    ("figures 2-6: collision histories", 2),
    ("calibrating the laws to both balls", 2),
    ("ball drops and velocity sweeps", 8),
)


def _beta_kw(model: str, beta: float) -> dict[str, float]:
    return {"beta": beta} if model == Jian.name else {}


@dataclass
class BallStudy:
    """One ball: its calibration per law, the simulated drop, and the velocity sweep.

    ``hertz_tc`` [s] and ``hertz_fmax`` [N]: the undamped impact at each sweep speed.
    """

    ball: Ball
    calibrations: dict[str, PhysicalCalibration]
    drops: dict[str, ImpactResult]
    sweeps: dict[str, SweepResult]
    hertz_tc: np.ndarray = field(default_factory=lambda: np.empty(0))
    hertz_fmax: np.ndarray = field(default_factory=lambda: np.empty(0))


@dataclass
class StudyResults:
    """Everything the report shows (non-dimensional unless stated; ball parts in SI).

    Attributes:
        alpha_grid; table1[model] e on the grid; table2[beta] Jian's e on the grid.
        reference: the six laws at alpha = 0.3 (Jian beta = 0.5), with histories (Fig. 2).
        series[model]: the law at each of SERIES_ALPHAS (Figs. 3-5; Jian at beta = 0.5).
        jian_betas: Jian at alpha = 0.3 for each of FIG6_BETAS (Fig. 6).
        balls[key]: :class:`BallStudy` for each ball (Table 4, Figs. 8-12).
    """

    alpha_grid: np.ndarray
    table1: dict[str, np.ndarray]
    table2: dict[float, np.ndarray]
    reference: list[CollisionResult]
    series: dict[str, list[CollisionResult]]
    jian_betas: list[CollisionResult]
    balls: dict[str, BallStudy] = field(default_factory=dict)
    speeds: np.ndarray = field(default_factory=lambda: study_speeds())


def _drop_and_sweep(speeds: np.ndarray, job: tuple) -> tuple:
    """(the drop at the measured speed, the velocity sweep) of one calibrated law."""
    m, v_in, cal = job
    drop = impact(m, m_eff=cal.m_eff, k_hertz=cal.k_hertz, v=v_in, c=cal.c, tau=cal.tau)
    sweep = velocity_sweep(m, speeds, m_eff=cal.m_eff, k_hertz=cal.k_hertz, c=cal.c, tau=cal.tau)
    return drop, sweep


def run_study(step: Callable[[str], None] | None = None, *, n_speeds: int = 24) -> StudyResults:
    """Solve everything the report needs (about 800 collisions).

    ``step(name)`` is called before each of :data:`STEPS` (for progress display).
    """
    step = step or (lambda _name: None)
    names = iter(name for name, _ in STEPS)
    grid = np.array(ALPHA_GRID)

    step(next(names))
    # A few hundred values: solved directly, so a first run builds no interpolation tables.
    table1 = {m: np.asarray(restitution(m, grid, exact=True)) for m in TABLE1_MODELS}

    step(next(names))
    table2 = {b: np.asarray(restitution(Jian.name, grid, beta=b, exact=True)) for b in BETA_GRID}

    step(next(names))
    reference = [collide(m, ALPHA_REF, **_beta_kw(m, BETA_REF)) for m in STUDY_MODELS]
    series = {m: [collide(m, a, **_beta_kw(m, BETA_REF)) for a in SERIES_ALPHAS]
              for m in STUDY_MODELS}
    jian_betas = [collide(Jian.name, ALPHA_REF, beta=b) for b in FIG6_BETAS]

    step(next(names))
    balls = load_balls()
    cals = {k: calibrate_ball(b) for k, b in balls.items()}

    step(next(names))
    speeds = study_speeds(n_speeds)
    # each calibrated law's drop and sweep (a few hundred solves with histories) on every core
    keys = [(key, m) for key in balls for m in cals[key]]
    jobs = [(m, balls[key].v_in, cals[key][m]) for key, m in keys]
    results = dict(zip(keys, forked_map(functools.partial(_drop_and_sweep, speeds), jobs)))
    studies = {}
    for key, b in balls.items():
        drops = {m: results[key, m][0] for m in cals[key]}
        sweeps = {m: results[key, m][1] for m in cals[key]}
        hertz = np.array([hertz_limit(b.m_eff, b.k_hertz, v) for v in speeds])
        studies[key] = BallStudy(ball=b, calibrations=cals[key], drops=drops, sweeps=sweeps,
                                 hertz_tc=hertz[:, 0], hertz_fmax=hertz[:, 2])
    return StudyResults(alpha_grid=grid, table1=table1, table2=table2, reference=reference,
                        series=series, jian_betas=jian_betas, balls=studies, speeds=speeds)
