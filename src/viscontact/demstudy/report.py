"""``viscontact dem-study``: run the three DEM studies and write their report.

The report is built in a temporary sibling of DIR and moved into place whole, with the same
rules as ``viscontact reproduce`` (:mod:`viscontact.report.build`): DIR is marked by a file
listing what the report wrote; ``force`` replaces exactly those files; nothing else in DIR
is ever touched.  LAMMPS works in a scratch directory that is removed at the end; the report
keeps the dumps (LAMMPS text dumps, which OVITO and ParaView open), the inputs and the
contact lines of every law, so that any run can be repeated with ``lmp`` alone.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TextIO

import numpy as np

from ..laws import STUDY_MODELS
from .. import domain
from ..dem.run import stop_on_signals
from ..outputs import OutputDir
from ..report.html import PAGE_CSS
from ..report.tables import Column, Table
from ..report.tables import _fixed as _f, _sig as _g, _text as _t
from . import bounce as bounce_mod
from . import flow as flow_mod
from . import gas as gas_mod
from . import jobs as jobs_mod
from . import theory

__all__ = ["dem_study", "StudyConfig", "QUICK", "FULL", "DEFAULT_OUT"]

DEFAULT_OUT = "viscontact-dem-study"
INPUTS = ("bounce.in", "gas_prepare.in", "gas_cool.in", "collapse_prepare.in", "collapse.in")
FIGURES = ("bounce.png", "bounce_series.png", "gas_cooling.png", "gas_snapshot.png",
           "collapse.png", "collapse_snapshot.png")
TABLES = ("bounce", "bounce_sequence", "gas", "flow", "flow_laws", "flow_runs")


@dataclass(frozen=True)
class StudyConfig:
    balls: tuple[str, ...]
    gas: gas_mod.GasSetup
    flow: flow_mod.FlowSetup
    haff: gas_mod.HaffCheck = gas_mod.QUICK_HAFF
    models: tuple[str, ...] = STUDY_MODELS
    quick: bool = False


QUICK = StudyConfig(balls=("ILB",), gas=gas_mod.QUICK_GAS, flow=flow_mod.QUICK_FLOW,
                    haff=gas_mod.QUICK_HAFF, quick=True)
FULL = StudyConfig(balls=("ILB", "OLB"), gas=gas_mod.FULL_GAS, flow=flow_mod.FULL_FLOW,
                   haff=gas_mod.FULL_HAFF)


def report_files(cfg: StudyConfig) -> list[str]:
    """Names of the files a report consists of (the marker excluded)."""
    files = [f"{t}.{ext}" for t in TABLES for ext in ("csv", "md")] + list(FIGURES)
    files += ["index.html", "results.json"] + list(INPUTS)
    files += [f"gas-{m}.dump" for m in cfg.models]
    files += [f"collapse-{m}-seed{cfg.flow.seeds[0]}.dump" for m in cfg.models]
    files += [f"coeffs-gas-{m}.lmp" for m in cfg.models]
    files += [f"coeffs-collapse-{m}.lmp" for m in cfg.models]
    files += [f"coeffs-bounce-{b}-{m}.lmp" for b in cfg.balls for m in cfg.models]
    return files


class _Progress:
    """One line per step on stderr: elapsed time and what is being done."""

    def __init__(self, stream: TextIO | None):
        self.stream = stream
        self.t0 = time.perf_counter()
        self.lock = threading.Lock()  # runs start in threads of their own (jobs.concurrent)

    def __call__(self, name: str) -> None:
        if self.stream is not None:
            with self.lock:
                print(f"viscontact dem-study: [{time.perf_counter() - self.t0:6.1f} s] {name}",
                      file=self.stream, flush=True)


@dataclass
class Results:
    cfg: StudyConfig
    bounces: list[bounce_mod.BounceCase] = field(default_factory=list)
    gas: gas_mod.GasStudy | None = None
    flow: flow_mod.FlowStudy | None = None
    seconds: dict[str, float] = field(default_factory=dict)
    np_: int = 1


def run_all(cfg: StudyConfig, work: Path, np_: int, step, jobs: int = 1) -> Results:
    """The bounces, the gas and the collapse; up to ``jobs`` LAMMPS runs at a time (each of
    ``np_`` ranks).  ``seconds`` holds each part's wall time (they overlap when jobs > 1)."""
    res = Results(cfg, np_=np_)

    def timed(name: str, fn):
        def run():
            t = time.perf_counter()
            out = fn()
            res.seconds[name] = time.perf_counter() - t
            return out
        return run

    # the gas (the longest chains: thermalise, then cool) gets free slots first, the short
    # bounce runs last, where they fill the end
    with jobs_mod.concurrent(jobs), stop_on_signals():
        res.bounces, res.gas, res.flow = jobs_mod.run_each(
            jobs_mod.first(2, timed("bounce", lambda: bounce_mod.run_bounces(
                work / "bounce", balls=cfg.balls, models=cfg.models, step=step))),
            jobs_mod.first(0, timed("gas", lambda: gas_mod.run_gas(
                work / "gas", cfg.gas, models=cfg.models, np_=np_, step=step, haff=cfg.haff))),
            jobs_mod.first(1, timed("flow", lambda: flow_mod.run_flow(
                work / "flow", cfg.flow, models=cfg.models, np_=np_, step=step))))
    res.seconds = {k: res.seconds[k] for k in ("bounce", "gas", "flow")}
    return res


# ------------------------------------------------------------------------------ tables
def _pm(n: int):
    def fmt(x) -> str:
        m, s = x
        return "" if not math.isfinite(m) else f"{m:.{n}f} ± {s:.{n}f}"
    return fmt


def _pm_csv(x) -> str:
    m, s = x
    return f"{m:.6g};{s:.6g}"


def _parting_speed(c: bounce_mod.BounceCase, tol: float = 0.1) -> float:
    """Impact speed of the first bounce whose e (gravity in contact) differs from the exact
    single collision at that speed by more than tol (relative)."""
    for v, e, ex in zip(c.dem.v_in, c.dem.e, c.exact_at_dem):
        if math.isfinite(e) and math.isfinite(ex) and abs(e / ex - 1.0) > tol:
            return float(v)
    return math.nan


def _isolated_error(c: bounce_mod.BounceCase) -> tuple[float, float, float, int]:
    """The gravity-in-flight DEM run against the exact solution, over the bounces both count:
    largest relative difference of e from the exact collision at the same impact speed, of
    the impact speeds from the exact sequence, of the time from first to last overlap; and
    that number of bounces."""
    if c.isolated is None:
        return math.nan, math.nan, math.nan, 0
    n = min(c.isolated.n, c.exact.n)
    if n == 0:
        return math.nan, math.nan, math.nan, 0
    de = np.max(np.abs(c.isolated.e[:n] / np.array(c.exact_at_isolated[:n]) - 1.0))
    dv = np.max(np.abs(c.isolated.v_in[:n] / c.exact.column("v_in")[:n] - 1.0))
    tc = np.array([b.tc_overlap for b in c.exact.bounces[:n]])
    dt = np.max(np.abs(c.isolated.tc[:n] / tc - 1.0))
    return float(de), float(dv), float(dt), n


def _first_drop(c: bounce_mod.BounceCase) -> tuple[float, float]:
    """(e_exact - e_DEM, (1 - e_exact) g t_c / v) at the first bounce (gravity in contact)."""
    drop, bound, _ = c.gravity_drop()
    return (float(drop[0]), float(bound[0])) if len(drop) else (math.nan, math.nan)


def bounce_table(res: Results) -> Table:
    ms = (lambda x: "" if not math.isfinite(x) else f"{x * 1e3:.3f}")
    cols = [
        Column("ball", _t, "ball", _t), Column("law", _t, "law", _t),
        Column("bounces exact", _g(6), "bounces, exact", _g(6)),
        Column("t_rest exact [s]", _g(8), "t_rest exact [s]", _f(3)),
        Column("bounces DEM", _g(6), "bounces, DEM", _g(6)),
        Column("t_rest DEM [s]", _g(8), "t_rest DEM [s]", _f(3)),
        Column("first apex DEM [m]", _g(8), "1st apex DEM [mm]", lambda x: f"{x * 1e3:.2f}"),
        Column("first force contact DEM [s]", _g(8), "1st force contact DEM [ms]", ms),
        Column("first force contact exact [s]", _g(8), "1st force contact exact [ms]", ms),
        Column("first overlap time DEM [s]", _g(8), "1st overlap time DEM [ms]", ms),
        Column("first bounce de/e", _g(4), "1st bounce: e_DEM/e_exact - 1", _g(2)),
        Column("first drop of e", _g(4), "1st bounce: e_exact - e_DEM", _g(2)),
        Column("first (1-e) g tc/v", _g(4), "(1 - e) g t_c / v", _g(2)),
        Column("parting speed [m/s]", _g(6), "10 % apart at v [cm/s]",
               lambda x: "" if not math.isfinite(x) else f"{x * 1e2:.1f}"),
        Column("check bounces", _g(6), "check: bounces", _g(6)),
        Column("check max de/e", _g(4), "check: max abs(de/e)", _g(2)),
        Column("check max dv/v", _g(4), "check: max abs(dv_k/v_k)", _g(2)),
        Column("check max dtc/tc", _g(4), "check: max abs(dt_c/t_c) (overlap)", _g(2)),
    ]
    rows = []
    for c in res.bounces:
        de, dv, dtc, n = _isolated_error(c)
        drop, bound = _first_drop(c)
        tcf = float(c.dem.tc_force[0]) if len(c.dem.tc_force) else math.nan
        rows.append([c.ball, c.model, c.exact.n, c.exact.t_rest, c.dem.n, c.dem.t_rest,
                     float(c.dem.apex[0]), tcf, float(c.tc_at_dem[0]), float(c.dem.tc[0]),
                     float(c.dem.e[0] / c.exact_at_dem[0] - 1.0), drop, bound,
                     _parting_speed(c), n, de, dv, dtc])
    return Table("bounce", "A ball bouncing to rest",
                 f"Each ball dropped from {bounce_mod.DROP_HEIGHT * 100:g} cm onto a rigid plate, "
                 "every law calibrated to the ball's measured e at 171.6 cm/s (zero-force end). "
                 f"A bounce counts when its flight rises at least {bounce_mod.H_MIN * 1e6:g} um; "
                 "t_rest is when the last counted flight lands. Exact: single collisions solved "
                 "exactly, flights in closed form, gravity during contact neglected. DEM: LAMMPS "
                 "with the viscontact plugin, gravity acting throughout. Force contact: first "
                 "touch to the zero-force end (the contact time a force plate measures; DEM to "
                 "one time step, exact: the single collision at the DEM's impact speed); overlap "
                 "time: first to last overlap, which adds the force-free recovery of the overlap "
                 "left at the zero-force end. e_exact - e_DEM: the drop of e that gravity during "
                 "contact causes at the first bounce, next to (1 - e) g t_c / v (t_c: the exact "
                 "force contact time), which bounds it. '10 % apart at v': the impact speed at "
                 "which the DEM e first differs by more than 10 % from the exact e at that speed. "
                 "Check: the DEM run with gravity acting only in flight against the exact "
                 "solution over the bounces both count: largest relative difference of e from "
                 "the exact collision at the same impact speed, of the impact speeds from the "
                 "exact sequence, and of the overlap time.", cols, rows)


def bounce_sequence_table(res: Results) -> Table:
    cols = [Column("ball", _t, "ball", _t), Column("law", _t, "law", _t),
            Column("bounce", _g(6), "k", _g(6)),
            Column("v_in DEM [m/s]", _g(10), "v_in DEM [cm/s]", lambda x: f"{x * 1e2:.2f}"),
            Column("e DEM", _g(10), "e DEM", _f(4)),
            Column("e exact at v_in", _g(10), "e exact at v_in", _f(4)),
            Column("drop of e", _g(6), "e_exact - e_DEM", _g(3)),
            Column("(1-e) g tc / v", _g(6), "(1 - e) g t_c / v", _g(3)),
            Column("v_in exact sequence [m/s]", _g(10), "v_in exact seq. [cm/s]",
                   lambda x: "" if not math.isfinite(x) else f"{x * 1e2:.2f}")]
    rows = []
    for c in res.bounces:
        drop, bound, _ = c.gravity_drop()
        for k in range(min(len(c.dem.v_in), 12)):
            if not math.isfinite(c.dem.e[k]):
                break
            vex = c.exact.bounces[k].v_in if k < c.exact.n else math.nan
            rows.append([c.ball, c.model, k + 1, float(c.dem.v_in[k]), float(c.dem.e[k]),
                         float(c.exact_at_dem[k]), float(drop[k]), float(bound[k]), vex])
    return Table("bounce_sequence", "Bounce by bounce",
                 "The first bounces of the DEM drop (gravity throughout) next to the exact single "
                 "collision at the same impact speed, and the impact speeds of the exact sequence. "
                 "The drop of e grows as the ball slows (g t_c / v grows like v^(-6/5)); (1 - e) "
                 "g t_c / v, t_c the exact force contact time at v, bounds it.", cols, rows)


def _late_mean(t: np.ndarray, x: np.ndarray, t_from: float) -> float:
    sel = t >= t_from
    return float(np.mean(x[sel])) if sel.any() else math.nan


def gas_table(res: Results) -> Table:
    g = res.gas
    assert g is not None
    s = g.setup
    tau0 = s.tau0()
    band = g.band
    cols = [Column("law", _t, "law", _t), Column("p", _g(6), "p", _g(3)),
            Column("q", _g(6), "q = (4p-1)/5", _g(3)),
            Column("exponent asymptote", _g(6), "small-dissipation asymptote -2/(1+q)",
                   lambda x: "" if not math.isfinite(x) else f"{x:.3f}"),
            Column("exponent measured;err", _pm_csv, "local exponent DEM", _pm(3)),
            Column("exponent kinetic theory", _g(6), "local exponent theory", _f(3)),
            Column("fit from [tau0]", _g(4), "fit from t/tau0", _g(3)),
            Column("max |T/T_theory - 1|", _g(4), "max abs(T/T_theory - 1)", _f(3)),
            Column("T/T_theory at end", _g(6), "T/T_theory at end", _f(3)),
            Column("T/T_Haff at end", _g(6), "T/T_Haff at end", _f(3)),
            Column("a2 DEM", _g(4), "a2 DEM (t >= 1 tau0)", _f(3)),
            Column("a2 theory", _g(4), "a2 theory (same dumps)", _f(4)),
            Column("e_eff at end", _g(4), "e_eff at end", _f(3)),
            Column("max density index", _g(4), "max density var/mean (t > 0)", _f(2)),
            Column("ideal gas max density index", _g(4), "ideal gas: max of the dumps (97.5 %)",
                   _f(2)),
            Column("max flow ratio", _g(4), "max flow ratio (t > 0)", _f(2)),
            Column("ideal gas max flow ratio", _g(4), "ideal gas: max of the dumps (97.5 %) ",
                   _f(2)),
            Column("box / L_c at end", _g(4), "box / L_c at end", _f(2)),
            Column("us per particle-step", _g(4), "us per particle-step", _g(3))]
    rows = []
    for m, r in g.runs.items():
        p = theory.damping_exponent(m)
        q = theory.q_exponent(m)
        haff_end = float(r.T[-1] / theory.haff_temperature(r.t[-1], s.T0, tau0))
        cost = r.wall_s / max(1, r.steps * s.n) * 1e6
        late = r.dump_t > 0
        rows.append([m, p, q, theory.late_exponent(m) if q >= 0 else math.nan,
                     (r.slope, r.slope_err), r.slope_theory, r.fit_from / tau0, r.theory_dev,
                     float(r.T[-1] / r.T_theory[-1]), haff_end,
                     _late_mean(r.dump_t, r.a2, tau0), _late_mean(r.dump_t, r.a2_theory, tau0),
                     float(r.e_eff[-1]), float(np.max(r.density_index[late])),
                     band.get("density_max", (math.nan,))[0], float(np.max(r.flow_ratio[late])),
                     band.get("flow_max", (math.nan,))[0], r.L_over_Lc_end, cost])
    bd = band.get("density", (math.nan,) * 3)
    bf = band.get("flow", (math.nan,) * 3)
    ba = band.get("a2", (math.nan,) * 3)
    return Table("gas", "Freely cooling gas",
                 f"{s.n} smooth spheres, volume fraction {s.phi:g}, periodic box of "
                 f"{s.box / s.sigma:.1f} diameters, thermalised elastically, then every law "
                 f"calibrated to e = {s.e:g} at the rms normal impact speed of the initial gas "
                 f"(Jian: beta = {s.beta:g}), contacts lasting {s.tc_ratio:g} mean free times at "
                 f"that speed; simulated for {s.t_end_tau0:g} tau0 (Haff time of the constant-e "
                 "gas). Local exponent: slope of ln T against ln t over the last half decade "
                 "(from the time shown; +- one sigma of the fit, which leaves out that two "
                 "realisations of the full study's gas differed by 0.002 to 0.02, Ts by 0.06 as "
                 "its gas clustered), the same fit to the kinetic theory of the law's exact e(v) "
                 "(T_theory), and the asymptote -2/(1+q) that the theory approaches as 1 - e -> 0 "
                 "(none for LH: its e falls towards 0 as the gas cools and its theory turns back "
                 "towards -2). max |T/T_theory - 1|: T averaged over 20 blocks evenly spaced in "
                 "ln t. a2 = (3/5) <v^4>/<v^2>^2 - 1 averaged over the dumps from 1 tau0, next to "
                 "the homogeneous-cooling value of a constant e (van Noije & Ernst 1998) at the "
                 "law's effective e = sqrt(1 - <1 - e^2>) at each dump's temperature; one "
                 f"Maxwellian sample of {s.n} spheres gives a2 within [{ba[0]:.3f}, {ba[2]:.3f}] "
                 "(95 %). Density var/mean: variance over mean of the sphere count in cells; flow "
                 "ratio: kinetic energy of the cell-averaged velocity over its value for "
                 "independent velocities; largest value over the dumps after t = 0; an ideal gas "
                 f"of the same size and cells gives [{bd[0]:.2f}, {bd[2]:.2f}] and "
                 f"[{bf[0]:.2f}, {bf[2]:.2f}] (95 %), the thermalised elastic gas "
                 f"{g.elastic_density_var:.2f} (excluded volume). box / L_c: the box over the "
                 "shortest box in which shear modes of the homogeneous cooling state grow, at "
                 "the law's effective e at the end (below 1: linearly stable). Cost: wall time "
                 f"per particle and step on {res.np_} rank(s).", cols, rows)


def _mean_sd(x) -> tuple[float, float]:
    x = np.asarray(x, dtype=float)
    return float(np.nanmean(x)), (float(np.nanstd(x, ddof=1)) if len(x) > 1 else math.nan)


def flow_tables(res: Results) -> tuple[Table, Table, Table]:
    f = res.flow
    assert f is not None
    s = f.setup
    cols = [Column("aspect nominal", _g(4), "a nominal", _g(3)),
            Column("law", _t, "law", _t), Column("seeds", _g(4), "seeds", _g(4)),
            Column("aspect ratio", _g(6), "a = H0/L0", _f(2)),
            Column("v_ref [m/s]", _g(4), "v_ref = sqrt(g H0) [m/s]", _f(3)),
            Column("peak rms speed [m/s];spread", _pm_csv, "peak rms speed [m/s]", _pm(3)),
            Column("runout;spread", _pm_csv, "(L_f - L0)/L0", _pm(2)),
            Column("runout Lube 2005", _g(4), "Lube et al. 2005", _f(2)),
            Column("height/L0;spread", _pm_csv, "H_f/L0", _pm(2)),
            Column("height/L0 Lube 2005", _g(4), "Lube et al. 2005 ", _f(2)),
            Column("angle [deg];spread", _pm_csv, "deposit angle [deg]", _pm(1)),
            Column("t_rest [s];spread", _pm_csv, "time to rest [s]", _pm(4))]
    rows = []
    for aspect in s.aspects:
        for m, runs in f.by_law(aspect).items():
            a = float(np.mean([r.a for r in runs]))
            rows.append([aspect, m, len(runs), a, runs[0].vref, _mean_sd([r.v_peak for r in runs]),
                         _mean_sd([r.runout for r in runs]), float(theory.collapse_runout(a)),
                         _mean_sd([r.height / r.L0 for r in runs]),
                         float(theory.collapse_height(a)), _mean_sd([r.angle for r in runs]),
                         _mean_sd([r.t_rest for r in runs])])
    t1 = Table("flow", "Collapse of a granular column",
               f"About {f.n_particles} frictional spheres (diameters uniform in [0.8, 1.2] d0, "
               f"d0 = {s.d0 * 1e3:g} mm, mu = {s.mu:g}) in a slab {s.W_d:g} d0 deep (periodic), "
               f"columns of {s.area_d:g} d0^2 (L0 H0) released from a gate onto a rough floor; "
               f"every law calibrated to e = {s.e:g} at v_ref = sqrt(g H0) of its column (Jian: "
               f"beta = {s.beta:g}); at a = {s.compare:g} every law runs, at the other aspect "
               f"ratios {', '.join(s.sweep_models) if s.sweep_models else 'every law'}. H0 and H_f "
               "are measured above the rough floor's top (z = d0), a from the settled column. "
               "Mean ± standard deviation over the random seeds (the same columns for every "
               "law). Published: the quasi-2D scaling of Lube et al., Phys. Rev. E 72 (2005) "
               "041301, at the measured a (run-out 1.2 a below a = 2.3, 1.9 a^(2/3) above; "
               "H_f/L0 = a below 1.15, a^0.4 above); Lajeunesse et al., Phys. Fluids 17 (2005) "
               "103302, give the same linear run-out below a = 3. Time to rest: kinetic energy "
               "per sphere below 1e-4 m g d0, interpolated between samples 0.5 ms apart.",
               cols, rows)
    cols3 = [Column("law", _t, "law", _t),
             Column("e at v_ref", _g(4), f"e at v_ref = {s.vref(s.compare):.2f} m/s", _f(3)),
             Column("e at peak rms speed", _g(4), f"e at {f.v_peak:.2f} m/s (peak rms)", _f(3)),
             Column("e at sqrt(g d0)", _g(4), f"e at sqrt(g d0) = {s.v_grain:.3f} m/s", _f(3))]
    stats = {}
    for attr, name, unit, n in (("runout", "run-out", "", 3), ("angle", "angle", " [deg]", 2),
                                ("t_rest", "t_rest", " [ms]", 1), ("height", "H_f", " [d0]", 2)):
        scale = 1e3 if attr == "t_rest" else (1.0 / s.d0 if attr == "height" else 1.0)
        diffs, mdd = f.law_differences(attr)
        stats[attr] = ({d.model: (d.diff * scale, d.half95 * scale) for d in diffs}, mdd * scale)
        cols3.append(Column(f"{name} - KK{unit};half95", _pm_csv, f"{name} - KK{unit} (95 %)",
                            _pm(n)))
    rows3 = []
    for m in f.by_law(s.compare):
        row = [m, s.e, f.e_peak.get(m, math.nan), f.e_grain.get(m, math.nan)]
        for attr in stats:
            row.append(stats[attr][0].get(m, (0.0, 0.0)) if m != "KK" else (0.0, 0.0))
        rows3.append(row)
    mdds = "; ".join(f"{a} {stats[a][1]:.3g}" for a in stats)
    t3 = Table("flow_laws", "Column collapse: each law against KK",
               f"At a = {s.compare:g}: each law's mean difference from KK over the same "
               f"{len(s.seeds)} columns, ± the half-width of its 95 % interval (the error "
               "variance from the residual of the additive law + seed model, "
               f"(laws - 1)(seeds - 1) degrees of freedom). Smallest difference this design "
               f"detects (two-sided 5 % test, 80 % power): {mdds} (same units). An interval "
               "that contains 0 does not show that the laws agree, only that they differ by "
               "less than about its half-width. e at v_ref is the calibration; the other two "
               "columns are what each law gives at the grains' peak rms speed (measured, mean "
               "over the seeds) and at the grain-scale speed.", cols3, rows3)
    cols2 = [Column("law", _t, "law", _t), Column("seed", _g(6), "seed", _g(6)),
             Column("aspect nominal", _g(4), "a nominal", _g(3)),
             Column("H0/L0", _g(6), "H0/L0", _f(2)), Column("runout", _g(6), "(L_f-L0)/L0", _f(3)),
             Column("height/L0", _g(6), "H_f/L0", _f(3)),
             Column("angle [deg]", _g(6), "angle [deg]", _f(2)),
             Column("t_rest [s]", _g(6), "t_rest [s]", _f(4)),
             Column("peak rms speed [m/s]", _g(4), "peak rms speed [m/s]", _f(3)),
             Column("wall [s]", _g(4), "wall time [s]", _f(1))]
    rows2 = [[r.model, r.seed, r.aspect, r.a, r.runout, r.height / r.L0, r.angle, r.t_rest,
              r.v_peak, r.wall_s] for r in f.runs]
    t2 = Table("flow_runs", "Column collapse, every run", "One row per law, aspect ratio and seed.",
               cols2, rows2)
    return t1, t3, t2


def all_tables(res: Results) -> list[Table]:
    return [bounce_table(res), bounce_sequence_table(res), gas_table(res), *flow_tables(res)]


# -------------------------------------------------------------------------------- page
_CSS = PAGE_CSS + "code { background: #f3f3f3; padding: 0 0.2em; }\n"


def _fig(name: str) -> str:
    import html

    from .figures import CAPTIONS

    e = html.escape
    return (f'<figure id="{e(name[:-4])}"><img src="{e(name)}" alt="{e(CAPTIONS[name])}">'
            f"<figcaption>{e(CAPTIONS[name])}</figcaption></figure>")


def _command(cfg: StudyConfig, np_: int) -> str:
    return "viscontact dem-study" + (" --quick" if cfg.quick else "") + (
        f" --np {np_}" if np_ > 1 else "")


def render_index(res: Results, tables: list[Table], version: str, backend: str) -> str:
    import html
    from datetime import datetime, timezone

    e = html.escape
    t = {x.stem: x for x in tables}
    g, f = res.gas, res.flow
    assert g is not None and f is not None
    files = ", ".join(f'<a href="{s}.csv">{s}.csv</a> / <a href="{s}.md">{s}.md</a>' for s in t)
    dumps = ", ".join(f'<a href="gas-{m}.dump">gas-{m}.dump</a>' for m in g.runs)
    dumps += ", " + ", ".join(f'<a href="collapse-{m}-seed{f.setup.seeds[0]}.dump">'
                              f"collapse-{m}-seed{f.setup.seeds[0]}.dump</a>" for m in f.by_law())
    inputs = ", ".join(f'<a href="{n}">{n}</a>' for n in INPUTS)
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    tau0 = g.setup.tau0()
    ts = g.runs.get("Ts")
    haff = ""
    if g.haff is not None and g.haff_dev.size:
        each = ", ".join(f"{100 * d:.1f}" for d in g.haff_max_dev_each)
        haff = (f"Haff's law (Ts, constant e): {len(g.haff_dev)} independent realisations of "
                f"the gas with {g.haff.n} spheres and stiffer contacts ({g.haff.tc_ratio:g} mean "
                f"free times) follow it within {100 * g.haff_max_dev:.1f} % on average over the "
                f"first {g.haff_window:g} tau0 (largest deviation of the realisations' mean T "
                f"/ T_Haff - 1, blocks of tau0/4; each realisation: {each} %). Softer contacts "
                "cool slower than Enskog's hard spheres (T above Haff's law by about 5 % by 4 "
                "tau0 at 0.02 mean free times, 8 % at 0.04), which the law comparison below "
                "shares with its kinetic theory.")
    secs = ", ".join(f"{k} {v:.0f} s" for k, v in res.seconds.items())
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>viscontact DEM study: what the damping law changes in many-particle flows</title>
<style>{_CSS}</style></head>
<body>
<h1>What the damping law changes in many-particle flows</h1>
<p>Three DEM studies with LAMMPS and the viscontact plugin (<code>pair_style viscontact</code>,
<code>fix viscontact/wall</code>{'' if backend == 'plugin' else "; here LAMMPS's own pair_style granular stands in"}), every law calibrated
exactly to the same restitution coefficient, each checked against theory where theory exists.
Generated {e(stamp)} by <code>{e(_command(res.cfg, res.np_))}</code> with viscontact
{e(version)}{' (quick: small systems, short runs)' if res.cfg.quick else ''}; run time: {e(secs)}.</p>
<p>Tables as files: {files}. Dumps (LAMMPS text, open in OVITO or ParaView): {dumps}.
LAMMPS inputs (plain, run them with <code>lmp -in</code>): {inputs}; the contact lines of every
law are in <code>coeffs-*.lmp</code>.</p>

<h2>1. A ball bouncing to rest</h2>
<p class="note">{e(_bounce_note(res))}</p>
{t["bounce"].to_html()}
{_fig("bounce.png")}
{_fig("bounce_series.png")}
{t["bounce_sequence"].to_html()}

<h2>2. Freely cooling granular gas</h2>
<p class="note">Haff time tau0 = {tau0:.4g} s. {e(haff)} {e(_gas_note(res))}</p>
{t["gas"].to_html()}
{_fig("gas_cooling.png")}
{_fig("gas_snapshot.png")}

<h2>3. Collapse of a granular column</h2>
<p class="note">{e(_flow_note(f))}</p>
{t["flow"].to_html()}
{t["flow_laws"].to_html()}
{_fig("collapse.png")}
{_fig("collapse_snapshot.png")}
{t["flow_runs"].to_html()}
</body></html>
"""


def _span(xs, fmt: str = "{:.3g}", unit: str = "") -> str:
    """'a to b unit' (or 'a unit' when they print alike) over the finite values of xs."""
    x = [float(v) for v in xs if math.isfinite(float(v))]
    if not x:
        return "n/a"
    lo, hi = fmt.format(min(x)), fmt.format(max(x))
    return (lo if lo == hi else f"{lo} to {hi}") + unit


def _bounce_note(res: Results) -> str:
    """What the bounce data show (every number from this run)."""
    from ..experiment import load_balls

    parts = ["Each lacrosse ball falls from 15 cm onto a rigid plate. The exact sequence is one "
             "exact collision per bounce with flights in closed form and no gravity during "
             "contact; the DEM drop keeps gravity on during contact."]
    for b in dict.fromkeys(c.ball for c in res.bounces):
        cs = [c for c in res.bounces if c.ball == b]
        ball = load_balls()[b]
        drops = [_first_drop(c) for c in cs]
        rel = [float(1.0 - c.dem.e[0] / c.exact_at_dem[0]) for c in cs]
        ok = n_small = 0
        first_over = []
        small = bounce_mod.GRAVITY_SMALL
        for c in cs:
            d, bnd, gtv = c.gravity_drop()
            fin = np.isfinite(d) & np.isfinite(bnd) & (gtv < small)
            n_small += int(fin.sum())
            ok += int(np.sum((d[fin] >= 0) & (d[fin] <= bnd[fin])))
            over = np.isfinite(d) & np.isfinite(bnd) & (d > bnd)
            if over.any():
                first_over.append(float(gtv[np.argmax(over)]))
        parts.append(
            f"{b}: the force contact of the first bounce (first touch to the zero-force end) "
            f"lasts {_span([c.dem.tc_force[0] * 1e3 for c in cs], '{:.2f}', ' ms')} in the DEM "
            f"({_span([c.tc_at_dem[0] * 1e3 for c in cs], '{:.2f}', ' ms')} for the exact "
            f"collision at the same speed; the ball's measured contact time is "
            f"{ball.tc * 1e3:.2f} ms); the overlap lasts "
            f"{_span([c.dem.tc[0] * 1e3 for c in cs], '{:.2f}', ' ms')}, longer wherever the "
            "ball recovers an overlap left at the zero-force end without force. Gravity during "
            f"contact lowers the first bounce's e by {_span([d for d, _ in drops], '{:.4f}')} "
            f"({_span([100 * r for r in rel], '{:.2f}', ' %')} of e), "
            f"{_span([d / bd for d, bd in drops], '{:.2f}')} of (1 - e) g t_c / v "
            f"(= {_span([bd for _, bd in drops], '{:.4f}')}, t_c the exact force contact "
            f"time). While g t_c / v < {small:g} that expression bounds the drop ({ok} of the "
            f"{n_small} DEM bounces there)"
            + (f"; slower bounces exceed it (from g t_c / v = {_span(first_over, '{:.2f}')}), "
               "where gravity during contact is no small correction" if first_over else "")
            + ". It is an observed bound, not a derived correction (an elastic bounce is "
            "symmetric in time and keeps e = 1 under gravity, so the drop vanishes with 1 - e).")
        check = [(c.model, c.isolated.n, c.exact.n) for c in cs if c.isolated is not None]
        differ = [f"{m} {n_d} vs {n_e}" for m, n_d, n_e in check if n_d != n_e]
        errs = [_isolated_error(c)[0] for c in cs]
        if check:
            parts.append(
                f"With gravity only in flight the DEM check run reproduces the exact sequence "
                f"to the time step's error, not exactly: e within "
                f"{_span(errs, '{:.1e}')} of the exact collision at each impact speed (largest "
                "relative difference over the bounces, largest at the slowest); bounces counted "
                + ("as in the exact series for every law" if not differ else
                   "differ from the exact series for " + ", ".join(differ) +
                   " (a flight near h_min)") + ".")
    parts.append("The ball comes to rest on the plate after finitely many bounces for every law, "
                 "whereas the exact series never ends for laws whose e does not fall at low speed "
                 "(it is cut where a flight falls below 10 um). The series figure shows where the "
                 "power law v_k ~ k^(-1/q) of small dissipation applies: "
                 + _series_note(res) + ".")
    return " ".join(parts)


def _series_note(res: Results) -> str:
    from .figures import asymptote_reached, series_local_exponent

    out = []
    for c in res.bounces:
        q = theory.q_exponent(c.model)
        if q <= 0 or c.exact.n < 3:
            continue
        v = c.exact.column("v_in")
        _, sl = series_local_exponent(v)
        out.append(f"{c.ball} {c.model} {'reaches' if asymptote_reached(c.model, v) else 'not'}"
                   f" (local exponent {sl[-1]:.2f} at bounce {c.exact.n - 1}, -1/q = "
                   f"{-1 / q:.2f})")
    return "; ".join(out) if out else "no law with q > 0 here"


def _gas_note(res: Results) -> str:
    g = res.gas
    assert g is not None
    s = g.setup
    tau0 = s.tau0()
    runs = g.runs
    bd, bf, ba = (g.band.get(k, (math.nan,) * 3) for k in ("density", "flow", "a2"))
    parts = [
        f"Every law follows the kinetic theory of its own exact e(v) within "
        f"{_span([100 * r.theory_dev for r in runs.values()], '{:.1f}', ' %')} (largest "
        "|T/T_theory - 1| over the run, per law) and its local exponent over the last half "
        f"decade within {max(abs(r.slope - r.slope_theory) for r in runs.values()):.3f} of the "
        "theory's. The asymptote -2/(1+q) holds only as 1 - e -> 0; by the end of this run the "
        "laws' effective e = sqrt(1 - <1 - e^2>) are "
        + ", ".join(f"{m} {r.e_eff[-1]:.3f}" for m, r in runs.items())
        + ", so the local exponents are transients of the theory, not its asymptote; LH's "
        "losses grow as the gas cools and its theory turns back towards Haff's -2 rather than "
        "reaching -5/2."]
    late = {m: r.dump_t >= tau0 for m, r in runs.items()}
    a2m = {m: float(np.mean(r.a2[late[m]])) if late[m].any() else math.nan
           for m, r in runs.items()}
    a2t = {m: float(np.mean(r.a2_theory[late[m]])) if late[m].any() else math.nan
           for m, r in runs.items()}
    parts.append(
        f"The velocity distribution: a2 from 1 tau0 is "
        + ", ".join(f"{m} {a2m[m]:+.3f} (theory {a2t[m]:+.4f})" for m in runs)
        + f"; one Maxwellian sample of {s.n} spheres scatters within [{ba[0]:+.3f}, "
        f"{ba[2]:+.3f}], so this gas resolves a2 only where it exceeds that band; the theory "
        "neglects a2, which changes the cooling rate by a factor of about 1 + 3 a2 / 16.")
    dmax = g.band.get("density_max", (math.nan,) * 3)[0]
    fmax = g.band.get("flow_max", (math.nan,) * 3)[0]
    over_d = [m for m, r in runs.items() if np.max(r.density_index[r.dump_t > 0]) > dmax]
    over_f = [m for m, r in runs.items() if np.max(r.flow_ratio[r.dump_t > 0]) > fmax]
    n_d = max(len(r.dump_t) for r in runs.values())
    parts.append(
        f"Homogeneity on {n_d} dumps per law (t = 0 the thermalised elastic gas): the variance "
        f"over the mean of the cell counts (one ideal-gas sample of the same size: "
        f"[{bd[0]:.2f}, {bd[2]:.2f}], 95 %; the largest of {n_d - 1} such samples stays below "
        f"{dmax:.2f}; the elastic gas {g.elastic_density_var:.2f}, lower by excluded volume) "
        + ("never exceeds that for any law" if not over_d else
           "exceeds it for " + ", ".join(over_d))
        + f"; the flow energy ratio (one sample [{bf[0]:.2f}, {bf[2]:.2f}], the largest of "
        f"{n_d - 1} below {fmax:.2f}) "
        + ("never exceeds it for any law" if not over_f else
           "exceeds it for " + ", ".join(over_f)) + ". "
        + ("Within this noise the dumps show no clustering or large-scale flow." if not (
            over_d or over_f) else "A flow ratio somewhat above an ideal gas's is what a cooling "
           "granular gas does before any instability: collisions that conserve momentum but "
           "lose energy correlate the velocities of neighbours (van Noije et al., Phys. Rev. "
           "Lett. 79 (1997) 411); the density shows no clusters unless named."))
    lc0 = theory.shear_instability_length(s.e, n=s.n_density, sigma=s.sigma, phi=s.phi)
    parts.append(
        f"Box and clustering: the box is {s.box / s.sigma:.1f} diameters; the shortest box in "
        f"which shear modes of the homogeneous cooling state grow (the first step towards "
        f"clusters; a linear estimate, Goldhirsch & Zanetti 1993) is {lc0 / s.sigma:.0f} "
        f"diameters at e = {s.e:g}, so box / L_c = {s.box / lc0:.2f}: linear theory expects no "
        "instability for Ts here. L_c grows (box / L_c falls) for laws whose e rises as the gas "
        "cools and shrinks for LH (box / L_c at the end: "
        + ", ".join(f"{m} {r.L_over_Lc_end:.2f}" for m, r in runs.items()) + ").")
    return " ".join(parts)


def _flow_note(f: flow_mod.FlowStudy) -> str:
    s = f.setup
    parts = [
        "Every law is calibrated to the same e at v_ref = sqrt(g H0) of its column ("
        + _span([s.vref(a) for a in s.aspects], "{:.2f}", " m/s") + "), the free-fall speed "
        "scale of the column. The grains move slower: their rms speed peaks at "
        + _span([r.v_peak for r in f.runs], "{:.2f}", " m/s") + f", and at a = {s.compare:g} "
        f"the laws' e at that speed ({f.v_peak:.2f} m/s) are "
        + ", ".join(f"{m} {e:.3f}" for m, e in f.e_peak.items())
        + f", at sqrt(g d0) = {s.v_grain:.3f} m/s "
        + ", ".join(f"{m} {e:.3f}" for m, e in f.e_grain.items())
        + ": the laws agree in e only near v_ref, and the collisions of the collapse span "
        "these speeds."]
    sweep = s.sweep_models or tuple(dict.fromkeys(r.model for r in f.runs))
    for m in sweep:
        items = []
        for aspect in s.aspects:
            rs = [r for r in f.at(aspect) if r.model == m]
            if not rs:
                continue
            a = float(np.mean([r.a for r in rs]))
            ro = float(np.mean([r.runout for r in rs]))
            hf = float(np.mean([r.height / r.L0 for r in rs]))
            items.append(f"a = {a:.2f}: run-out {ro:.2f} (published "
                         f"{float(theory.collapse_runout(a)):.2f}), H_f/L0 {hf:.2f} (published "
                         f"{float(theory.collapse_height(a)):.2f})")
        parts.append(f"{m} against the quasi-2D scaling of Lube et al. 2005 (mean over "
                     f"{len(s.seeds)} seeds): " + "; ".join(items) + ".")
    parts.append("The published laws come from columns of hundreds to thousands of grains; these "
                 f"columns are {math.sqrt(s.area_d / max(s.aspects)):.0f} to "
                 f"{math.sqrt(s.area_d / min(s.aspects)):.0f} grains long, where size effects "
                 "of order tens of percent are reported, so agreement within that is what can "
                 "be expected.")
    for attr, name, scale, unit in (("runout", "run-out", 1.0, ""),
                                    ("angle", "deposit angle", 1.0, " deg"),
                                    ("t_rest", "time to rest", 1e3, " ms")):
        diffs, mdd = f.law_differences(attr)
        if not diffs or not math.isfinite(mdd):
            parts.append(f"{name}: too few seeds or laws to compare.")
            continue
        sig = [d.model for d in diffs if abs(d.diff) > d.half95]
        parts.append(
            f"{name} against KK (a = {s.compare:g}, {len(s.seeds)} seeds): differences "
            + ", ".join(f"{d.model} {d.diff * scale:+.3g} ± {d.half95 * scale:.3g}{unit}"
                        for d in diffs)
            + " (95 %); "
            + ("no interval excludes 0" if not sig else
               "the interval excludes 0 for " + ", ".join(sig))
            + f"; this design detects differences of about {mdd * scale:.3g}{unit} or more "
            "(5 % level, 80 % power), smaller ones it cannot rule out.")
    return " ".join(parts)


def _results_json(res: Results) -> dict:
    g, f = res.gas, res.flow
    out: dict = {"quick": res.cfg.quick, "np": res.np_, "seconds": res.seconds, "bounce": [],
                 "gas": {}, "flow": {}}
    for c in res.bounces:
        de, dv, _, _ = _isolated_error(c)
        drop, bound, gtv = c.gravity_drop()
        out["bounce"].append({"ball": c.ball, "law": c.model, "bounces_dem": c.dem.n,
                              "t_rest_dem": c.dem.t_rest, "bounces_exact": c.exact.n,
                              "t_rest_exact": c.exact.t_rest, "check_max_de": de,
                              "check_max_dv": dv, "check_bounces": c.isolated.n
                              if c.isolated is not None else None,
                              "tc_force_dem": c.dem.tc_force.tolist(),
                              "tc_overlap_dem": c.dem.tc.tolist(),
                              "tc_force_exact": list(c.tc_at_dem),
                              "drop": drop.tolist(), "bound": bound.tolist(),
                              "g_tc_over_v": gtv.tolist()})
    if g is not None:
        out["gas"] = {"n": g.setup.n, "phi": g.setup.phi, "e": g.setup.e, "tau0": g.setup.tau0(),
                      "tc_ratio": g.setup.tc_ratio,
                      "haff_max_dev": g.haff_max_dev, "haff_window_tau0": g.haff_window,
                      "haff_max_dev_each": g.haff_max_dev_each,
                      "haff_mean_dev": g.haff_mean_dev.tolist(), "haff_t": g.haff_t.tolist(),
                      "haff_n": g.haff.n if g.haff else None,
                      "haff_tc_ratio": g.haff.tc_ratio if g.haff else None,
                      "particle_steps": g.particle_steps,
                      "laws": {m: {"exponent": r.slope, "err": r.slope_err,
                                   "exponent_theory": r.slope_theory,
                                   "fit_from_tau0": r.fit_from / g.setup.tau0(),
                                   "asymptote": theory.late_exponent(m),
                                   "theory_max_dev": r.theory_dev,
                                   "T_over_theory_end": float(r.T[-1] / r.T_theory[-1]),
                                   "dump_t_tau0": (r.dump_t / g.setup.tau0()).tolist(),
                                   "density_index": r.density_index.tolist(),
                                   "flow_ratio": r.flow_ratio.tolist(),
                                   "a2": r.a2.tolist(), "a2_theory": r.a2_theory.tolist(),
                                   "e_eff": r.e_eff.tolist(), "box_over_Lc_end": r.L_over_Lc_end,
                                   "wall_s": r.wall_s, "steps": r.steps}
                               for m, r in g.runs.items()},
                      "ideal_gas_band": g.band, "elastic_density_index": g.elastic_density_var,
                      "box_sigma": g.setup.box / g.setup.sigma}
    if f is not None:
        out["flow"] = {"compare_aspect": f.setup.compare, "e_grain": f.e_grain,
                       "runs": [{"law": r.model, "seed": r.seed, "aspect": r.aspect, "a": r.a,
                                 "runout": r.runout, "height_L0": r.height / r.L0,
                                 "angle": r.angle, "t_rest": r.t_rest, "v_peak": r.v_peak,
                                 "vref": r.vref} for r in f.runs]}
        for attr in ("runout", "angle", "t_rest"):
            diffs, mdd = f.law_differences(attr)
            out["flow"][f"{attr}_minus_KK"] = {d.model: [d.diff, d.half95] for d in diffs}
            out["flow"][f"{attr}_detectable"] = mdd
    from ..cli.common import finite_json

    return finite_json(out)


def _write_all(res: Results, tmp: Path, work: Path, step) -> list[str]:
    from .. import __version__
    from .engine import backend, input_path
    from .figures import write_figures

    step("tables (CSV and Markdown)")
    tables = all_tables(res)
    for t in tables:
        (tmp / f"{t.stem}.csv").write_text(t.to_csv(), encoding="utf-8")
        (tmp / f"{t.stem}.md").write_text(t.to_markdown(), encoding="utf-8")
    write_figures(res, tmp, tick=step)
    for name in INPUTS:
        shutil.copyfile(input_path(name), tmp / name)
    g, f = res.gas, res.flow
    for m, r in g.runs.items():
        shutil.copyfile(r.dump, tmp / f"gas-{m}.dump")
        shutil.copyfile(r.dump.parent / "coeffs.lmp", tmp / f"coeffs-gas-{m}.lmp")
    for r in f.runs:
        if r.seed == f.setup.seeds[0]:
            shutil.copyfile(r.dump, tmp / f"collapse-{r.model}-seed{r.seed}.dump")
            shutil.copyfile(r.dump.parent / "coeffs.lmp", tmp / f"coeffs-collapse-{r.model}.lmp")
    for c in res.bounces:
        shutil.copyfile(work / "bounce" / f"bounce-{c.ball}-{c.model}" / "coeffs.lmp",
                        tmp / f"coeffs-bounce-{c.ball}-{c.model}.lmp")
    (tmp / "results.json").write_text(json.dumps(_results_json(res), indent=1) + "\n",
                                      encoding="utf-8")
    step("index.html")
    (tmp / "index.html").write_text(render_index(res, tables, __version__, backend()),
                                    encoding="utf-8")
    files = report_files(res.cfg)
    missing = [x for x in files if not (tmp / x).is_file()]
    if missing:  # pragma: no cover - a bug, never user input
        raise RuntimeError(f"report incomplete: {missing}")
    return files


def dem_study(out: str | os.PathLike = DEFAULT_OUT, *, quick: bool = False, np_: int = 1,
              force: bool = False, progress: TextIO | None = sys.stderr,
              config: StudyConfig | None = None, jobs: int | None = None) -> Path:
    """Run the bouncing ball, the cooling gas and the column collapse; write the report.

    ``quick``: small systems and short runs (minutes); ``np_``: MPI ranks for the gas and the
    collapse (``mpirun -np``); ``jobs``: independent LAMMPS runs at a time (None: as many as
    fill the cores, :func:`viscontact.demstudy.jobs.default_jobs`); the report is the same
    for any ``jobs``.  Raises :class:`viscontact.outputs.OutputError` (a ValueError) when ``out`` holds
    an earlier report and ``force`` is False, when it holds other files with the report's
    names, or when it cannot be written; nothing is left behind in that case.
    """
    domain.check_int("--np (number of MPI ranks)", np_, 1, domain.NP_MAX)
    if jobs is None:
        jobs = jobs_mod.default_jobs(np_)
    domain.check_int("--jobs (LAMMPS runs at a time)", jobs, 1, domain.NP_MAX)
    cfg = config or (QUICK if quick else FULL)
    out_dir = OutputDir(out, "dem-study", force, expected=report_files(cfg))
    from .engine import backend

    backend()  # the plugin builds (or LammpsError says what to install) before any work
    work = Path(tempfile.mkdtemp(prefix="viscontact-dem-study-"))
    try:
        with out_dir:
            step = _Progress(progress)
            res = run_all(cfg, work, np_, step, jobs)
            _write_all(res, out_dir.staging, work, step)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return Path(out)
