"""The DEM study's tables (bounces, the bounce sequence, the cooling gas, the column collapse),
built from the study's results (reads them only)."""

from __future__ import annotations

import math

import numpy as np

from .._support.report import Column, Table
from .._support.report import fixed as _f, sig as _g, text as _t
from . import bounce as bounce_mod
from . import theory
from .results import Results
from ..physics.laws import KK

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
            row.append(stats[attr][0].get(m, (0.0, 0.0)) if m != KK.name else (0.0, 0.0))
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
