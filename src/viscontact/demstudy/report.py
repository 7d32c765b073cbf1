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
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TextIO

import numpy as np

from ..laws import STUDY_MODELS
from .. import domain
from ..outputs import OutputDir
from ..report.html import PAGE_CSS
from ..report.tables import Column, Table
from ..report.tables import _fixed as _f, _sig as _g, _text as _t
from . import bounce as bounce_mod
from . import flow as flow_mod
from . import gas as gas_mod
from . import theory

__all__ = ["dem_study", "StudyConfig", "QUICK", "FULL", "DEFAULT_OUT"]

DEFAULT_OUT = "viscontact-dem-study"
INPUTS = ("bounce.in", "gas_prepare.in", "gas_cool.in", "collapse_prepare.in", "collapse.in")
FIGURES = ("bounce.png", "bounce_series.png", "gas_cooling.png", "gas_snapshot.png",
           "collapse.png", "collapse_snapshot.png")
TABLES = ("bounce", "bounce_sequence", "gas", "flow", "flow_runs")


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

    def __call__(self, name: str) -> None:
        if self.stream is not None:
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


def run_all(cfg: StudyConfig, work: Path, np_: int, step) -> Results:
    res = Results(cfg, np_=np_)
    t = time.perf_counter()
    res.bounces = bounce_mod.run_bounces(work / "bounce", balls=cfg.balls, models=cfg.models,
                                         step=step)
    res.seconds["bounce"] = time.perf_counter() - t
    t = time.perf_counter()
    res.gas = gas_mod.run_gas(work / "gas", cfg.gas, models=cfg.models, np_=np_, step=step,
                              haff=cfg.haff)
    res.seconds["gas"] = time.perf_counter() - t
    t = time.perf_counter()
    res.flow = flow_mod.run_flow(work / "flow", cfg.flow, models=cfg.models, np_=np_, step=step)
    res.seconds["flow"] = time.perf_counter() - t
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


def bounce_table(res: Results) -> Table:
    cols = [
        Column("ball", _t, "ball", _t), Column("law", _t, "law", _t),
        Column("bounces exact", _g(6), "bounces, exact", _g(6)),
        Column("t_rest exact [s]", _g(8), "t_rest exact [s]", _f(3)),
        Column("bounces DEM", _g(6), "bounces, DEM", _g(6)),
        Column("t_rest DEM [s]", _g(8), "t_rest DEM [s]", _f(3)),
        Column("first apex DEM [m]", _g(8), "1st apex DEM [mm]", lambda x: f"{x * 1e3:.2f}"),
        Column("first tc DEM [s]", _g(8), "1st t_c DEM [ms]", lambda x: f"{x * 1e3:.3f}"),
        Column("first bounce de/e", _g(4), "1st bounce: e_DEM/e_exact - 1", _g(2)),
        Column("parting speed [m/s]", _g(6), "10 % apart at v [cm/s]",
               lambda x: "" if not math.isfinite(x) else f"{x * 1e2:.1f}"),
        Column("check bounces", _g(6), "check: bounces", _g(6)),
        Column("check max de/e", _g(4), "check: max |de/e|", _g(2)),
        Column("check max dv/v", _g(4), "check: max |dv_k/v_k|", _g(2)),
        Column("check max dtc/tc", _g(4), "check: max |dt_c/t_c|", _g(2)),
    ]
    rows = []
    for c in res.bounces:
        de, dv, dtc, n = _isolated_error(c)
        rows.append([c.ball, c.model, c.exact.n, c.exact.t_rest, c.dem.n, c.dem.t_rest,
                     float(c.dem.apex[0]), float(c.dem.tc[0]),
                     float(c.dem.e[0] / c.exact_at_dem[0] - 1.0), _parting_speed(c), n, de, dv,
                     dtc])
    return Table("bounce", "A ball bouncing to rest",
                 f"Each ball dropped from {bounce_mod.DROP_HEIGHT * 100:g} cm onto a rigid plate, "
                 "every law calibrated to the ball's measured e at 171.6 cm/s (zero-force end). "
                 f"A bounce counts when its flight rises at least {bounce_mod.H_MIN * 1e6:g} um; "
                 "t_rest is when the last counted flight lands. Exact: single collisions solved "
                 "exactly, flights in closed form, gravity during contact neglected. DEM: LAMMPS "
                 "with the viscontact plugin, gravity acting throughout. '10 % apart at v': the "
                 "impact speed at which the DEM e first differs by more than 10 % from the exact e "
                 "at that speed (gravity during contact). Check: the DEM run with gravity acting "
                 "only in flight against the exact solution over the bounces both count: largest "
                 "relative difference of e from the exact collision at the same impact speed, of "
                 "the impact speeds from the exact sequence, and of the time from first to last "
                 "overlap.", cols, rows)


def bounce_sequence_table(res: Results) -> Table:
    cols = [Column("ball", _t, "ball", _t), Column("law", _t, "law", _t),
            Column("bounce", _g(6), "k", _g(6)),
            Column("v_in DEM [m/s]", _g(10), "v_in DEM [cm/s]", lambda x: f"{x * 1e2:.2f}"),
            Column("e DEM", _g(10), "e DEM", _f(4)),
            Column("e exact at v_in", _g(10), "e exact at v_in", _f(4)),
            Column("g tc / v", _g(6), "g t_c / v", _g(3)),
            Column("v_in exact sequence [m/s]", _g(10), "v_in exact seq. [cm/s]",
                   lambda x: "" if not math.isfinite(x) else f"{x * 1e2:.2f}")]
    rows = []
    for c in res.bounces:
        gr = c.gravity_ratio()
        for k in range(min(len(c.dem.v_in), 12)):
            if not math.isfinite(c.dem.e[k]):
                break
            vex = c.exact.bounces[k].v_in if k < c.exact.n else math.nan
            rows.append([c.ball, c.model, k + 1, float(c.dem.v_in[k]), float(c.dem.e[k]),
                         float(c.exact_at_dem[k]), float(gr[k]), vex])
    return Table("bounce_sequence", "Bounce by bounce",
                 "The first bounces of the DEM drop (gravity throughout) next to the exact single "
                 "collision at the same impact speed, and the impact speeds of the exact sequence. "
                 "They part as g t_c / v, the speed gravity adds during a contact relative to the "
                 "impact speed, grows like v^(-6/5).", cols, rows)


def gas_table(res: Results) -> Table:
    g = res.gas
    assert g is not None
    s = g.setup
    tau0 = s.tau0()
    cols = [Column("law", _t, "law", _t), Column("p", _g(6), "p", _g(3)),
            Column("q", _g(6), "q = (4p-1)/5", _g(3)),
            Column("exponent asymptote", _g(6), "asymptote -2/(1+q)", _f(3)),
            Column("exponent measured;err", _pm_csv, "local exponent DEM", _pm(3)),
            Column("exponent kinetic theory", _g(6), "local exponent theory", _f(3)),
            Column("fit from [tau0]", _g(4), "fit from t/tau0", _g(3)),
            Column("max |T/T_theory - 1|", _g(4), "max abs(T/T_theory - 1)", _f(3)),
            Column("T/T_theory at end", _g(6), "T/T_theory at end", _f(3)),
            Column("T/T_Haff at end", _g(6), "T/T_Haff at end", _f(3)),
            Column("max density ratio", _g(4), "max density var. ratio", _f(2)),
            Column("max flow ratio", _g(4), "max flow ratio", _f(2)),
            Column("us per particle-step", _g(4), "us per particle-step", _g(3))]
    rows = []
    for m, r in g.runs.items():
        p = theory.damping_exponent(m)
        haff_end = float(r.T[-1] / theory.haff_temperature(r.t[-1], s.T0, tau0))
        cost = r.wall_s / max(1, r.steps * s.n) * 1e6
        rows.append([m, p, theory.q_exponent(m), theory.late_exponent(m),
                     (r.slope, r.slope_err), r.slope_theory, r.fit_from / tau0, r.theory_dev,
                     float(r.T[-1] / r.T_theory[-1]), haff_end, float(np.max(r.density_ratio)),
                     float(np.max(r.flow_ratio)), cost])
    return Table("gas", "Freely cooling gas",
                 f"{s.n} smooth spheres, volume fraction {s.phi:g}, periodic box, thermalised "
                 f"elastically, then every law calibrated to e = {s.e:g} at the rms normal impact "
                 f"speed of the initial gas (Jian: beta = {s.beta:g}), contacts lasting "
                 f"{s.tc_ratio:g} mean free times at that speed; simulated for {s.t_end_tau0:g} "
                 "tau0 (Haff time of the constant-e gas). Local exponent: slope of ln T against "
                 "ln t over the last half decade (from the time shown; +- one sigma of the fit, "
                 "which leaves out that two realisations of the full study's gas differed by 0.002 "
                 "to 0.02, Ts by 0.06 as its gas clustered), "
                 "the same fit to the kinetic theory of the law's exact e(v) (T_theory), and the "
                 "asymptote -2/(1+q) that the theory approaches as 1 - e -> 0. max |T/T_theory - "
                 "1|: T averaged over 20 blocks evenly spaced in ln t. Density ratio: variance "
                 "over mean of the sphere count in cells, over its value in the elastic gas "
                 "(clusters raise it); flow ratio: kinetic energy of the cell-averaged velocity "
                 "over its value for independent velocities (vortices raise it); both 1 for a "
                 "homogeneous gas, largest value over the dumps. Cost: wall time per particle and "
                 f"step on {res.np_} rank(s).", cols, rows)


def flow_tables(res: Results) -> tuple[Table, Table]:
    f = res.flow
    assert f is not None
    by = f.by_law()
    cols = [Column("law", _t, "law", _t), Column("seeds", _g(4), "seeds", _g(4)),
            Column("aspect ratio", _g(6), "a = H0/L0", _f(2)),
            Column("runout;spread", _pm_csv, "(L_f - L0)/L0", _pm(2)),
            Column("angle [deg];spread", _pm_csv, "deposit angle [deg]", _pm(1)),
            Column("t_rest [s];spread", _pm_csv, "time to rest [s]", _pm(3))]
    rows = []
    for m, runs in by.items():
        ro = np.array([r.runout for r in runs])
        an = np.array([r.angle for r in runs])
        tr = np.array([r.t_rest for r in runs])
        a = np.mean([r.H0 / r.L0 for r in runs])
        sd = (lambda x: float(np.std(x, ddof=1)) if len(x) > 1 else math.nan)
        rows.append([m, len(runs), a, (float(ro.mean()), sd(ro)), (float(np.nanmean(an)), sd(an)),
                     (float(tr.mean()), sd(tr))])
    s = f.setup
    t1 = Table("flow", "Collapse of a granular column",
               f"About {f.n_particles} frictional spheres (diameters uniform in [0.8, 1.2] d0, "
               f"mu = {s.mu:g}) in a slab {s.W_d:g} d0 deep (periodic), column {s.L0_d:g} d0 long, "
               "released from a gate onto a rough floor; every law calibrated to "
               f"e = {s.e:g} at v_ref = sqrt(g d0) = {s.vref:.3g} m/s (Jian: beta = {s.beta:g}). "
               "Mean ± standard deviation over the random seeds (the same columns for every law).",
               cols, rows)
    cols2 = [Column("law", _t, "law", _t), Column("seed", _g(6), "seed", _g(6)),
             Column("H0/L0", _g(6), "H0/L0", _f(2)), Column("runout", _g(6), "(L_f-L0)/L0", _f(3)),
             Column("angle [deg]", _g(6), "angle [deg]", _f(2)),
             Column("t_rest [s]", _g(6), "t_rest [s]", _f(3)),
             Column("wall [s]", _g(4), "wall time [s]", _f(1))]
    rows2 = [[r.model, r.seed, r.H0 / r.L0, r.runout, r.angle, r.t_rest, r.wall_s] for r in f.runs]
    t2 = Table("flow_runs", "Column collapse, every run", "One row per law and seed.", cols2, rows2)
    return t1, t2


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
<p class="note">Each lacrosse ball falls from 15 cm onto a rigid plate. The DEM drop keeps
gravity on during contact; the exact sequence is one exact collision per bounce with flights in
closed form. They agree while g t_c / v is small and part as it grows (like v^(-6/5)): the
DEM e falls below the exact one by about (1 - e) g t_c / v (an elastic bounce is symmetric in
time and keeps e = 1 under gravity); at low speed gravity adds a speed during the contact
comparable to the impact speed, and the ball ends resting
on the plate after finitely many bounces for every law, whereas the exact series never ends for
laws whose e does not fall at low speed. With gravity only in flight, the DEM reproduces the
exact sequence to the level of the time step (check columns).</p>
{t["bounce"].to_html()}
{_fig("bounce.png")}
{_fig("bounce_series.png")}
{t["bounce_sequence"].to_html()}

<h2>2. Freely cooling granular gas</h2>
<p class="note">Haff time tau0 = {tau0:.4g} s. {e(haff)} Homogeneity was checked on
{len(ts.dump_t) if ts is not None else 0} dumps per law: the variance of the sphere count in
cells (relative to the thermalised elastic gas) and the energy of the cell-averaged flow
(relative to independent velocities) both stay near 1 while the gas is homogeneous; clusters
and vortices raise them. Every law is set next to the kinetic theory of its own exact e(v)
(the Enskog cooling rate with the loss 1 - e^2 averaged over the Maxwellian impact speeds); its
local exponent over the last half decade next to the same slope of that theory and the
asymptote -2/(1 + q) the theory reaches only as 1 - e -> 0.</p>
{t["gas"].to_html()}
{_fig("gas_cooling.png")}
{_fig("gas_snapshot.png")}

<h2>3. Collapse of a granular column</h2>
<p class="note">{e(_flow_verdict(f))}</p>
{t["flow"].to_html()}
{_fig("collapse.png")}
{_fig("collapse_snapshot.png")}
{t["flow_runs"].to_html()}
</body></html>
"""


def _flow_verdict(f: flow_mod.FlowStudy) -> str:
    """Whether the laws differ beyond the spread across seeds (two-way ANOVA, law and seed)."""
    parts = []
    for attr, name in (("runout", "run-out"), ("angle", "deposit angle")):
        F, p = f.law_effect(attr)
        if not math.isfinite(p):
            parts.append(f"{name}: too few seeds to tell")
            continue
        verdict = "differ beyond" if p < 0.05 else "do not differ beyond"
        parts.append(f"{name}: the laws {verdict} the spread across seeds "
                     f"(two-way analysis of variance, law and seed: F = {F:.2f}, p = {p:.2g})")
    return "; ".join(parts) + "."


def _results_json(res: Results) -> dict:
    g, f = res.gas, res.flow
    out: dict = {"quick": res.cfg.quick, "np": res.np_, "seconds": res.seconds, "bounce": [],
                 "gas": {}, "flow": {}}
    for c in res.bounces:
        de, dv, _, _ = _isolated_error(c)
        out["bounce"].append({"ball": c.ball, "law": c.model, "bounces_dem": c.dem.n,
                              "t_rest_dem": c.dem.t_rest, "bounces_exact": c.exact.n,
                              "t_rest_exact": c.exact.t_rest, "check_max_de": de,
                              "check_max_dv": dv})
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
                                   "wall_s": r.wall_s, "steps": r.steps}
                               for m, r in g.runs.items()}}
    if f is not None:
        out["flow"] = {m: {"runout": [r.runout for r in rs], "angle": [r.angle for r in rs]}
                       for m, rs in f.by_law().items()}
        out["flow_law_effect_p"] = {a: f.law_effect(a)[1] for a in ("runout", "angle")}
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
              config: StudyConfig | None = None) -> Path:
    """Run the bouncing ball, the cooling gas and the column collapse; write the report.

    ``quick``: small systems and short runs (minutes); ``np_``: MPI ranks for the gas and the
    collapse (``mpirun -np``).  Raises :class:`viscontact.outputs.OutputError` (a ValueError) when ``out`` holds
    an earlier report and ``force`` is False, when it holds other files with the report's
    names, or when it cannot be written; nothing is left behind in that case.
    """
    domain.check_int("--np (number of MPI ranks)", np_, 1, domain.NP_MAX)
    cfg = config or (QUICK if quick else FULL)
    out_dir = OutputDir(out, "dem-study", force, expected=report_files(cfg))
    from .engine import backend

    backend()  # the plugin builds (or LammpsError says what to install) before any work
    work = Path(tempfile.mkdtemp(prefix="viscontact-dem-study-"))
    try:
        with out_dir:
            step = _Progress(progress)
            res = run_all(cfg, work, np_, step)
            _write_all(res, out_dir.staging, work, step)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return Path(out)
