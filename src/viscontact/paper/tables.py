"""The study's tables built from :class:`viscontact.paper.study.StudyResults` (reads results only).

Each is a :class:`viscontact._support.report.Table`: raw values plus how to print them.
"""

from __future__ import annotations

import math
from typing import Any

from .._support.report import Column, Table, fixed as _fixed, scaled as _scaled, sig as _sig
from .._support.report import text as _text
from .study import BETA_GRID, TABLE1_MODELS, StudyResults

__all__ = ["Table", "table1", "table2", "table4", "comparison", "all_tables", "beta_header"]

def beta_header(beta: float) -> str:
    """Column head of Table 2: ``beta=<value>``."""
    return f"beta={beta:g}"


def table1(res: StudyResults) -> Table:
    cols = [Column("alpha", _sig(6), "alpha", _fixed(2))]
    cols += [Column(m, _fixed(6), m, _fixed(4)) for m in TABLE1_MODELS]
    rows = [[float(a)] + [float(res.table1[m][i]) for m in TABLE1_MODELS]
            for i, a in enumerate(res.alpha_grid)]
    return Table("table1", "Table 1",
                 "Coefficient of restitution e against the damping constant alpha for the five "
                 "laws without relaxation (zero-force end of contact).", cols, rows)


def table2(res: StudyResults) -> Table:
    cols = [Column("alpha", _sig(6), "alpha", _fixed(2))]
    cols += [Column(beta_header(b), _fixed(6), beta_header(b) + (" (KK)" if b == 0 else ""),
                    _fixed(4)) for b in BETA_GRID]
    rows = [[float(a)] + [float(res.table2[b][i]) for b in BETA_GRID]
            for i, a in enumerate(res.alpha_grid)]
    return Table("table2", "Table 2",
                 "Coefficient of restitution e of the Jian law against alpha for each relaxation "
                 "constant beta = tau / T (beta = 0 is Kuwabara-Kono; zero-force end).", cols, rows)


def table4(res: StudyResults) -> Table:
    cols = [
        Column("ball", _text, "ball", _text),
        Column("model", _text, "law", _text),
        Column("m_eff [kg]", _sig(10), "m* [g]", _scaled(1e3, 1)),
        Column("R_eff [m]", _sig(10), "R* [mm]", _scaled(1e3, 2)),
        Column("k_hertz [N/m^1.5]", _sig(10), "k_Hertz [10^6 N/m^1.5]", _scaled(1e-6, 3)),
        Column("v_i [m/s]", _sig(10), "v_i [cm/s]", _scaled(1e2, 1)),
        Column("T [s]", _sig(10), "T [ms]", _scaled(1e3, 4)),
        Column("alpha", _sig(10), "alpha", _fixed(4)),
        Column("beta", _sig(10), "beta", _sig(3)),
        Column("tau [s]", _sig(10), "tau [ms]", _scaled(1e3, 4)),
        Column("c", _sig(10), "c", _sig(5)),
        Column("c unit", _text, "unit of c", _text),
    ]
    rows = []
    for key, bs in res.balls.items():
        for m, cal in bs.calibrations.items():
            rows.append([key, m, cal.m_eff, bs.ball.r_eff, cal.k_hertz, cal.v, cal.T, cal.alpha,
                         cal.beta, cal.tau, cal.c, cal.c_unit])
    return Table("table4", "Table 4",
                 "Each law calibrated to each lacrosse ball: alpha reproduces the measured e at "
                 "v_i = 171.6 cm/s (Jian with the study's beta), tau = beta T, and c is the "
                 "physical damping prefactor of delta^p delta' (Jian: of (1 - exp(-t/tau)) "
                 "delta^(1/2) delta'); rigid plate, so m* = m and R* = R.", cols, rows)


def _pct(x: Any) -> str:
    return "" if x is None or not math.isfinite(x) else f"{x:+.1f}"


def comparison(res: StudyResults) -> Table:
    cols = [
        Column("ball", _text, "ball", _text),
        Column("model", _text, "law", _text),
        Column("e measured", _sig(6), "e measured", _fixed(3)),
        Column("e predicted", _fixed(6), "e predicted", _fixed(4)),
        Column("tc measured [s]", _sig(6), "t_c measured [ms]", _scaled(1e3, 2)),
        Column("tc predicted [s]", _sig(8), "t_c predicted [ms]", _scaled(1e3, 3)),
        Column("tc error [%]", _sig(4), "t_c error [%]", _pct),
        Column("fmax predicted [N]", _sig(8), "F_max predicted [N]", _fixed(1)),
        Column("dmax predicted [m]", _sig(8), "delta_max predicted [mm]", _scaled(1e3, 3)),
        Column("residual predicted [m]", _sig(8), "residual overlap [mm]", _scaled(1e3, 3)),
    ]
    rows = []
    for key, bs in res.balls.items():
        b = bs.ball
        for m, d in bs.drops.items():
            rows.append([key, m, b.e, d.e, b.tc, d.tc, 100.0 * (d.tc - b.tc) / b.tc, d.fmax,
                         d.dmax, d.residual])
    return Table("comparison", "Comparison with the drop tests",
                 "Each calibrated law's predicted drop (v_i = 171.6 cm/s, zero-force end) next "
                 "to the measurement.  e is matched by construction; t_c and F_max are "
                 "predictions (no F_max was tabulated for the measurements).", cols, rows)


def all_tables(res: StudyResults) -> list[Table]:
    return [table1(res), table2(res), table4(res), comparison(res)]
