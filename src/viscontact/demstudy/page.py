"""The DEM study's report page (``index.html``: the figures, the tables and the notes that read
the numbers) and its ``results.json``."""

from __future__ import annotations

import math

import numpy as np

from .._support.report import PAGE_CSS, Table
from . import bounce as bounce_mod
from . import flow as flow_mod
from . import theory
from .results import INPUTS, Results, StudyConfig
from .tables import _first_drop, _isolated_error
from ..physics.laws import Ts

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
    ts = g.runs.get(Ts.name)
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
    from ..paper.experiment import load_balls

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
    from .._support.outputs import finite_json

    return finite_json(out)
