"""Figures of the DEM study (read results only).  Every law keeps its colour of
:data:`viscontact.collision.plots.LAW_COLORS`; theory and published laws are drawn in black or grey.
Every mark a figure draws has a legend entry; every axis says its unit (or that it has none)."""

from __future__ import annotations

import math
from functools import partial
from pathlib import Path

import numpy as np
import matplotlib
import matplotlib.cm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.ticker import FormatStrFormatter, LogLocator, NullFormatter, NullLocator

from .._support.parallel import forked_map
from ..collision.plots import LAW_COLORS, LAW_MARKERS
from . import theory
from .bounce import GRAVITY_SMALL
from ..physics.laws import KK, LH, Ts

__all__ = ["CAPTIONS", "write_figures", "series_local_exponent", "asymptote_reached"]

DPI = 110

CAPTIONS = {
    "bounce.png": "A ball bouncing to rest. Top: apex height of every flight against the bounce "
                  "number, DEM with gravity acting throughout (markers) and the exact sequence of "
                  "single collisions without gravity in contact (lines); the dotted line is h_min "
                  "= 10 um, the lowest flight that counts as a bounce. Bottom: what gravity during "
                  "contact does to e. Filled markers: the drop of e, e_exact(v) - e_DEM, over "
                  "(1 - e_exact(v)) g t_c / v, t_c the exact force contact time at the same impact "
                  "speed v, against g t_c / v; below the dashed line (ratio 1) that expression "
                  "bounds the drop, which it does while g t_c / v < 0.25 (dotted), not for "
                  "slower bounces. Open markers: the check run with gravity only in flight, "
                  "|e_exact(v) - e_DEM| over the same expression (the time step's error).",
    "bounce_series.png": "The exact bounce series of every law (single collisions, gravity in "
                         "flight only). Left: impact speed against bounce number. Right: its local "
                         "exponent d ln v_k / d ln k. When 1 - e = A v^q at small dissipation "
                         "(q = (4p - 1)/5), v_k approaches A' k^(-1/q) (dotted lines on the "
                         "right); the power law is drawn on the left (dashed, through the last "
                         "bounce) only for a law whose local exponent has come within 10 % of "
                         "-1/q. Ts (q = 0) is geometric, LH (q < 0) stops after finitely many "
                         "bounces: neither has a power law.",
    "gas_cooling.png": "Freely cooling gas (time in Haff times tau0 of the constant-e gas). "
                       "Top left: T / T_theory, each law's temperature over the kinetic theory "
                       "of its own exact e(v); grey band: +- one sample's noise sqrt(2 / (3 N)). "
                       "Top right: local exponent d ln T / d ln t of the DEM (markers; slopes over "
                       "a third of a decade) and of the theory (dashed); dotted: the "
                       "small-dissipation asymptote -2/(1+q), drawn only for laws whose e tends "
                       "to a constant or to 1 (not LH, whose e falls as the gas cools). Middle "
                       "left: Haff's law for Ts, T/T_Haff - 1 of each realisation (thin) and their "
                       "mean (the check; grey band: 5 %). Middle right: a2 = (3/5) <v^4>/<v^2>^2 "
                       "- 1 per dump (markers) and the homogeneous-cooling value of a constant e "
                       "at each law's effective e at that temperature (dashed); grey: 95 % band of "
                       "one Maxwellian sample of N spheres. Bottom: homogeneity per dump, the "
                       "variance over the mean of the sphere count in cells (left) and the "
                       "energy of the cell-averaged flow over its value for independent "
                       "velocities (right); grey: 95 % band of one ideal-gas sample with the "
                       "same number of spheres and cells, dashed: the value the largest of the "
                       "run's dumps would stay below in an ideal gas (97.5 %); the x axis is linear up to 1 tau0 and "
                       "logarithmic beyond, so t = 0 (the thermalised elastic gas) lies at 0.",
    "gas_snapshot.png": "The gas at the end of the run, a slab a third of the box deep: the "
                        "number of sphere centres per bin over its mean (colour; an ideal gas "
                        "varies by +- 1/sqrt(mean count) per bin, printed in each title) and the "
                        "centres themselves (dots). Clusters show as bins far above 1 next to "
                        "empty ones; the dumps gas-*.dump hold every law and time (OVITO, "
                        "ParaView).",
    "collapse.png": "Column collapse. Top left: the deposit's free surface of every law (first "
                    "seed) at the aspect ratio where all laws run, the initial column (grey) on "
                    "the rough floor (hatched; its top, z = d0, is the level heights are measured "
                    "from) and each deposit's front L_f (ticks). Top middle and right: run-out "
                    "(L_f - L0)/L0 and final height H_f/L0 against the measured aspect ratio a, "
                    "every run (markers), with the published quasi-2D scaling (Lube et al. 2005: "
                    "lines; the dashed part is beyond the range where that branch was fitted). "
                    "Bottom: each law's mean difference from KK over the same columns with its "
                    "95 % interval from the seeds; grey band: the smallest difference the "
                    "design detects (5 % level, 80 % power).",
    "collapse_snapshot.png": "The deposit of the column with Ts (first seed) seen from the side, "
                             "spheres to scale and coloured by diameter; grey: the rough floor, "
                             "dashed: its top (z = d0), dotted: the front L_f (collapse-*.dump "
                             "hold the whole collapse in 3D).",
}


def _save(fig, path: Path) -> None:
    fig.savefig(path, dpi=DPI, bbox_inches="tight")


def _balls(res) -> list[str]:
    return list(dict.fromkeys(c.ball for c in res.bounces))


def _bounce(res, path: Path) -> None:
    balls = _balls(res)
    fig = Figure(figsize=(9.5 * len(balls), 10), layout='constrained')
    axes = fig.subplots(2, len(balls), squeeze=False)
    for j, b in enumerate(balls):
        cases = [c for c in res.bounces if c.ball == b]
        ax = axes[0, j]
        for c in cases:
            col = LAW_COLORS[c.model]
            k = np.arange(1, c.exact.n + 1)
            ax.plot(k, c.exact.column("apex") * 1e3, "-", color=col, lw=1.2)
            ok = np.isfinite(c.dem.apex)
            kd = np.arange(1, len(c.dem.apex) + 1)[ok]
            ax.plot(kd, c.dem.apex[ok] * 1e3, LAW_MARKERS[c.model], color=col, ms=5, ls="none")
        h_min = cases[0].dem.h_min * 1e3
        ax.axhline(h_min, color="0.4", lw=0.8, ls=":")
        handles = [Line2D([], [], color=LAW_COLORS[c.model], marker=LAW_MARKERS[c.model], ls="-",
                          label=f"{c.model}: DEM {c.dem.n} bounces, rests at "
                                f"{c.dem.t_rest:.2f} s (exact {c.exact.n})") for c in cases]
        handles += [Line2D([], [], color="k", marker="o", ls="none", label="markers: DEM, "
                           "gravity throughout"),
                    Line2D([], [], color="k", ls="-", label="lines: exact sequence"),
                    Line2D([], [], color="0.4", ls=":", label=f"h_min = {h_min * 1e3:g} um")]
        ax.set(yscale="log", xscale="log", xlabel="bounce k", ylabel="apex of flight k [mm]",
               title=f"{b}: DEM and exact sequence")
        ax.grid(alpha=0.3, which="both")
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        ax = axes[1, j]
        for c in cases:
            col = LAW_COLORS[c.model]
            drop, bound, gtv = c.gravity_drop()
            ok = np.isfinite(drop) & np.isfinite(bound) & (drop > 0) & (bound > 0)
            ax.plot(gtv[ok], drop[ok] / bound[ok], LAW_MARKERS[c.model], color=col, ms=5,
                    ls="none")
            if c.isolated is not None:
                n = min(c.isolated.n, len(c.exact_at_isolated), c.exact.n)
                e_ex = np.array(c.exact_at_isolated[:n])
                err = np.abs(e_ex - c.isolated.e[:n])
                tci = np.array([b_.tc for b_ in c.exact.bounces[:n]])  # speeds agree to 1 %
                gi = c.isolated.g * tci / c.isolated.v_in[:n]
                bi = (1.0 - e_ex) * gi
                ok = np.isfinite(err) & (err > 0) & np.isfinite(bi) & (bi > 0)
                ax.plot(gi[ok], err[ok] / bi[ok], LAW_MARKERS[c.model], mfc="none", color=col,
                        ms=5, ls="none")
        ax.axhline(1.0, color="k", ls="--", lw=0.8)
        ax.axvline(GRAVITY_SMALL, color="0.4", ls=":", lw=0.8)
        handles = [Line2D([], [], color=LAW_COLORS[c.model], marker=LAW_MARKERS[c.model],
                          ls="none", label=c.model) for c in cases]
        handles += [Line2D([], [], color="k", marker="o", ls="none",
                           label="filled: gravity in contact, e_exact - e_DEM"),
                    Line2D([], [], color="k", marker="o", mfc="none", ls="none",
                           label="open: gravity only in flight, |e_exact - e_DEM|"),
                    Line2D([], [], color="k", ls="--", label="the bound: ratio 1"),
                    Line2D([], [], color="0.4", ls=":",
                           label=f"g t_c / v = {GRAVITY_SMALL:g}: bound stated below it")]
        ax.set(xscale="log", yscale="log", xlabel="g t_c / v  [-]  (t_c: exact force contact)",
               ylabel="drop of e / ((1 - e_exact) g t_c / v)  [-]",
               title=f"{b}: gravity during contact lowers e")
        ax.grid(alpha=0.3, which="both")
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    _save(fig, path)


def series_local_exponent(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Local exponent d ln v_k / d ln k of a bounce series v_1, v_2, ... (central differences,
    k = 2 .. n-1): (k, exponent)."""
    v = np.asarray(v, dtype=float)
    if len(v) < 3:
        return np.empty(0), np.empty(0)
    k = np.arange(1, len(v) + 1, dtype=float)
    s = np.log(v[2:] / v[:-2]) / np.log(k[2:] / k[:-2])
    return k[1:-1], s


def asymptote_reached(model: str, v: np.ndarray, tol: float = 0.1) -> bool:
    """Whether the series' last local exponent lies within ``tol`` (relative) of -1/q, the
    power law of 1 - e = A v^q (q > 0 only)."""
    q = theory.q_exponent(model)
    _, s = series_local_exponent(v)
    return q > 0 and len(s) > 0 and abs(s[-1] * q + 1.0) <= tol


def _bounce_series(res, path: Path) -> None:
    balls = _balls(res)
    fig = Figure(figsize=(13, 4.8 * len(balls)))
    axes = fig.subplots(len(balls), 2, squeeze=False)
    for j, b in enumerate(balls):
        ax, ax2 = axes[j]
        for c in res.bounces:
            if c.ball != b or c.exact.n == 0:
                continue
            col = LAW_COLORS[c.model]
            q = theory.q_exponent(c.model)
            v = c.exact.column("v_in")
            k = np.arange(1, len(v) + 1)
            ax.plot(k, v, "-", color=col, lw=1.5, label=f"{c.model} (q = {q:.2g})")
            kk, s = series_local_exponent(v)
            ax2.plot(kk, s, "-", color=col, lw=1.2, label=c.model)
            if q > 0:
                ax2.axhline(-1.0 / q, color=col, lw=0.8, ls=":")
                if asymptote_reached(c.model, v):
                    ka = np.geomspace(len(v) / 3, len(v) * 3, 20)
                    ax.plot(ka, v[-1] * (ka / len(v)) ** (-1.0 / q), "--", color=col, lw=0.9)
        ax.set(xscale="log", yscale="log", xlabel="bounce k", ylabel="impact speed v_k [m/s]",
               title=f"{b}: exact bounce series")
        ax.grid(alpha=0.3, which="both")
        h, _ = ax.get_legend_handles_labels()
        h.append(Line2D([], [], color="k", ls="--", label="k^(-1/q) through the last bounce "
                        "(only where reached)"))
        ax.legend(handles=h, fontsize=7)
        qs = [theory.q_exponent(c.model) for c in res.bounces if c.ball == b]
        low = min([-1.0 / q for q in qs if q > 0] + [-4.0]) - 1.0
        ax2.set(xscale="log", xlabel="bounce k", ylabel="d ln v_k / d ln k  [-]",
                ylim=(low, 0.3), title=f"{b}: local exponent of the series")
        ax2.grid(alpha=0.3, which="both")
        h, _ = ax2.get_legend_handles_labels()
        h.append(Line2D([], [], color="k", ls=":", label="-1/q (laws with q > 0)"))
        ax2.legend(handles=h, fontsize=7, ncol=2)
    _save(fig, path)


def _symlog_time(ax, tau0_label: str = "t / tau0") -> None:
    """x axis linear on [0, 1] and logarithmic beyond: t = 0 where it belongs."""
    ax.set_xscale("symlog", linthresh=1.0, linscale=0.6)
    ax.set_xlim(left=0.0)
    right = ax.get_xlim()[1]
    ticks = [t for t in (0, 0.25, 0.5, 0.75, 1, 2, 5, 10, 20, 50, 100, 200, 500) if t <= right]
    ax.set_xticks(ticks, [f"{t:g}" for t in ticks])
    ax.xaxis.set_minor_locator(NullLocator())
    ax.set_xlabel(f"{tau0_label}  (linear to 1, logarithmic beyond)")


def _gas(res, path: Path) -> None:
    from .gas import local_exponents

    g = res.gas
    s = g.setup
    tau0 = s.tau0()
    fig = Figure(figsize=(14, 15))
    axes = fig.subplots(3, 2)
    ax = axes[0, 0]
    noise = math.sqrt(2.0 / (3.0 * s.n))
    ax.axhspan(1 - noise, 1 + noise, color="0.88", label=f"+- sqrt(2/(3N)) = {noise:.3f}")
    for m, r in g.runs.items():
        ax.plot(r.t[1:] / tau0, r.T[1:] / r.T_theory[1:], "-", color=LAW_COLORS[m], lw=1.2,
                label=f"{m}: max dev. {100 * r.theory_dev:.1f} %")
    ax.axhline(1, color="k", lw=0.8)
    ax.set(xscale="log", xlabel="t / tau0", ylabel="T / T_theory  [-]",
           title=f"{s.n} spheres, phi = {s.phi:g}, e = {s.e:g} at v_ref: DEM over kinetic theory")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax = axes[0, 1]
    for m, r in g.runs.items():
        col = LAW_COLORS[m]
        tc, k = local_exponents(r.t, r.T)
        ax.plot(tc / tau0, k, LAW_MARKERS[m], color=col, ms=3, ls="none",
                label=f"{m}: last half decade {r.slope:.2f} (theory {r.slope_theory:.2f})")
        tc, k = local_exponents(r.t, r.T_theory)
        ax.plot(tc / tau0, k, "--", color=col, lw=1)
        if theory.q_exponent(m) >= 0:
            ax.axhline(theory.late_exponent(m), color=col, lw=0.8, ls=":")
    h, _ = ax.get_legend_handles_labels()
    h += [Line2D([], [], color="k", ls="--", label="kinetic theory of the law's e(v)"),
          Line2D([], [], color="k", ls=":", label="asymptote -2/(1+q) (not LH)")]
    ax.set(xscale="log", xlabel="t / tau0", ylabel="d ln T / d ln t  [-]",
           title="local cooling exponent: DEM (markers) and theory (dashed)")
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.grid(alpha=0.3, which="both")
    ax.legend(handles=h, fontsize=7)
    ax = axes[1, 0]
    ax.axhspan(-5, 5, color="0.9", label="+- 5 %")
    if g.haff_dev.size:
        for d in g.haff_dev:
            ax.plot(g.haff_t, d * 100, "-", color=LAW_COLORS[Ts.name], lw=0.8, alpha=0.6)
        ax.plot([], [], "-", color=LAW_COLORS[Ts.name], lw=0.8, alpha=0.6, label="each realisation")
        ax.plot(g.haff_t, g.haff_mean_dev * 100, "s-", color=LAW_COLORS[Ts.name], ms=4,
                label=f"mean of {len(g.haff_dev)} realisations ({g.haff.n} spheres, contact "
                      f"{g.haff.tc_ratio:g} mean free times)")
    ax.axhline(0, color="k", lw=0.8)
    ax.set(xlabel="t / tau0", ylabel="T / T_Haff - 1 [%]", title="Ts against Haff's law")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    band = g.band
    ax = axes[1, 1]
    if "a2" in band:
        ax.axhspan(band["a2"][0], band["a2"][2], color="0.88",
                   label=f"Maxwellian sample of {s.n}: 95 %")
    for m, r in g.runs.items():
        col = LAW_COLORS[m]
        ax.plot(r.dump_t / tau0, r.a2, LAW_MARKERS[m], color=col, ms=4, ls="none", label=m)
        ax.plot(r.dump_t / tau0, r.a2_theory, "--", color=col, lw=1)
    ax.axhline(0, color="k", lw=0.8)
    h, _ = ax.get_legend_handles_labels()
    h.append(Line2D([], [], color="k", ls="--", label="homogeneous cooling, e_eff(T)"))
    _symlog_time(ax)
    ax.set(ylabel="a2  [-]", title="velocity distribution: a2 per dump")
    ax.grid(alpha=0.3, which="both")
    ax.legend(handles=h, fontsize=7, ncol=2)
    for ax, key, attr, ylab, title in (
            (axes[2, 0], "density", "density_index", "var / mean of cell counts  [-]",
             "density homogeneity"),
            (axes[2, 1], "flow", "flow_ratio", "flow energy / independent velocities  [-]",
             "large-scale flow")):
        if key in band:
            ax.axhspan(band[key][0], band[key][2], color="0.88",
                       label=f"ideal gas, {s.n} spheres, same cells: one sample, 95 %")
        if f"{key}_max" in band:
            k = max(len(r.dump_t) for r in g.runs.values()) - 1
            ax.axhline(band[f"{key}_max"][0], color="0.4", ls="--", lw=0.9,
                       label=f"ideal gas: the largest of {k} samples stays below (97.5 %)")
        for m, r in g.runs.items():
            ax.plot(r.dump_t / tau0, getattr(r, attr), "-" + LAW_MARKERS[m], color=LAW_COLORS[m],
                    ms=4, lw=1, label=m)
        _symlog_time(ax)
        ax.set(ylabel=ylab, title=title)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7, ncol=2)
    _save(fig, path)


def _gas_snapshot(res, path: Path) -> None:
    g = res.gas
    s = g.setup
    laws = [m for m in (Ts.name, KK.name, LH.name) if m in g.runs] or list(g.runs)[:1]
    fig = Figure(figsize=(6.0 * len(laws), 5.2), layout='constrained')
    axes = fig.subplots(1, len(laws), squeeze=False)
    L = s.box
    bins = max(4, round((s.n / 3.0 / 10.0) ** 0.5))  # about 10 centres per bin in the slab
    for ax, m in zip(axes[0], laws):
        fr = g.runs[m].final
        x, y, z = (np.mod(fr[c], L) / s.sigma for c in ("x", "y", "z"))
        sel = z < L / s.sigma / 3.0
        h, xe, ye = np.histogram2d(x[sel], y[sel], bins=bins, range=[[0, L / s.sigma]] * 2)
        mean = sel.sum() / bins ** 2
        im = ax.imshow(h.T / mean, origin="lower", extent=[xe[0], xe[-1], ye[0], ye[-1]],
                       cmap="RdBu_r", vmin=0.0, vmax=2.0)
        ax.plot(x[sel], y[sel], ".", color="k", ms=1.5)
        ax.set(xlabel="x / sigma", ylabel="y / sigma", aspect="equal",
               title=f"{m}, t = {g.runs[m].t[-1] / s.tau0():.3g} tau0 (ideal gas: +- "
                     f"{1 / math.sqrt(mean):.2f})")
        ax.figure.colorbar(im, ax=ax, shrink=0.8, label="centres per bin / mean  [-]")
    _save(fig, path)


def _collapse(res, path: Path) -> None:
    from .flow import FLOOR_TOP_D, deposit_profile

    f = res.flow
    s = f.setup
    d0 = s.d0
    fig = Figure(figsize=(18, 10))
    gs = fig.add_gridspec(2, 3)
    ax = fig.add_subplot(gs[0, 0])
    seed0 = s.seeds[0]
    runs0 = [r for r in f.at(s.compare) if r.seed == seed0]
    xmax = 1.0
    if runs0:
        r0 = runs0[0]
        ax.fill([0, r0.L0 / d0, r0.L0 / d0, 0],
                [FLOOR_TOP_D, FLOOR_TOP_D, FLOOR_TOP_D + r0.H0 / d0, FLOOR_TOP_D + r0.H0 / d0],
                color="0.85", label=f"initial column, a = {r0.a:.2f}")
        xmax = max(r.front for r in runs0) / d0 + 3
        ax.fill_between([0, xmax], 0, FLOOR_TOP_D, facecolor="none", edgecolor="0.5",
                        hatch="///", lw=0, label="rough floor (top at z = d0)")
    for i, r in enumerate(runs0):
        g = r.final["type"] == 1
        xs, hs = deposit_profile(r.final["x"][g], (r.final["z"] + r.final["radius"])[g], 2 * d0)
        col = LAW_COLORS[r.model]
        ax.plot(xs / d0, hs / d0, "-", color=col, lw=1.5, label=f"{r.model}: L_f = "
                f"{r.front / d0:.1f} d0")
        ax.plot([r.front / d0] * 2, [FLOOR_TOP_D - 0.6 - 0.15 * i, FLOOR_TOP_D + 0.6],
                "-", color=col, lw=2)
    ax.axhline(FLOOR_TOP_D, color="0.3", lw=0.8, ls="--")
    ax.set(xlabel="x / d0  (d0 = 1 mm)", ylabel="z / d0", xlim=(0, xmax),
           title=f"deposits at a = {s.compare:g} (seed {seed0}); ticks: fronts L_f")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    h, _ = ax.get_legend_handles_labels()
    h += [Line2D([], [], color="0.3", ls="--", lw=0.8, label="floor top, z = d0"),
          Line2D([], [], color="k", marker="|", ms=12, ls="none", label="front L_f (tick)")]
    ax.legend(handles=h, fontsize=7)
    a_line = np.geomspace(0.3, 6.0, 80)
    for k, (attr, lab, pub, branches) in enumerate((
            ("runout", "(L_f - L0) / L0  [-]", theory.collapse_runout, theory.LUBE_RUNOUT),
            ("height", "H_f / L0  [-]", theory.collapse_height, theory.LUBE_HEIGHT))):
        ax = fig.add_subplot(gs[0, 1 + k])
        for m in dict.fromkeys(r.model for r in f.runs):
            rs = [r for r in f.runs if r.model == m]
            val = [getattr(r, attr) / (1.0 if attr == "runout" else r.L0) for r in rs]
            ax.plot([r.a for r in rs], val, LAW_MARKERS[m], color=LAW_COLORS[m], ms=5, ls="none",
                    alpha=0.8, label=m)
        lo = 0.0
        for hi, c, p in branches:
            inside = (a_line > lo) & (a_line <= hi)
            ax.plot(a_line[inside], c * a_line[inside] ** p, "k-", lw=1)
            ax.plot(a_line, c * a_line ** p, "k--", lw=0.6, alpha=0.5)
            lo = hi
        h, _ = ax.get_legend_handles_labels()
        text = ("1.2 a (a < 2.3), 1.9 a^(2/3)" if attr == "runout" else "a (a < 1.15), a^0.4")
        h += [Line2D([], [], color="k", ls="-", label=f"Lube et al. 2005: {text}"),
              Line2D([], [], color="k", ls="--", lw=0.6, label="the same branch extended")]
        amin = min(r.a for r in f.runs)
        amax = max(r.a for r in f.runs)
        ax.set(xscale="log", yscale="log", xlabel="a = H0 / L0  [-]", ylabel=lab,
               xlim=(amin / 1.5, amax * 1.5),
               title="run-out" if attr == "runout" else "final height above the floor")
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
            axis.set_major_formatter(FormatStrFormatter("%g"))
            axis.set_minor_formatter(NullFormatter())
        ax.grid(alpha=0.3, which="both")
        ax.legend(handles=h, fontsize=7)
    for k, (attr, lab) in enumerate((("runout", "(L_f - L0)/L0 - KK's  [-]"),
                                     ("angle", "deposit angle - KK's  [deg]"),
                                     ("t_rest", "time to rest - KK's  [ms]"))):
        ax = fig.add_subplot(gs[1, k])
        diffs, mdd = f.law_differences(attr)
        scale = 1e3 if attr == "t_rest" else 1.0
        if math.isfinite(mdd):
            ax.axhspan(-mdd * scale, mdd * scale, color="0.88", label="smallest detectable")
        for i, d in enumerate(diffs):
            ax.errorbar(i, d.diff * scale, yerr=d.half95 * scale, fmt=LAW_MARKERS[d.model],
                        color=LAW_COLORS[d.model], capsize=5, ms=7)
        ax.axhline(0, color="k", lw=0.8)
        ax.set_xticks(range(len(diffs)), [d.model for d in diffs])
        h, _ = ax.get_legend_handles_labels()
        h.append(Line2D([], [], color="k", marker="o", ls="-", label="mean difference, 95 %"))
        ax.set(ylabel=lab, xlabel="law",
               title=f"a = {s.compare:g}: difference from KK ({len(s.seeds)} seeds)")
        ax.grid(alpha=0.3)
        ax.legend(handles=h, fontsize=7)
    fig.tight_layout()
    _save(fig, path)


def _collapse_snapshot(res, path: Path) -> None:
    """Side view (x-z) of the deposit, every sphere drawn to scale, the nearest in front."""
    from matplotlib.collections import EllipseCollection

    from .flow import FLOOR_TOP_D

    f = res.flow
    runs = f.at(f.setup.compare)
    r = next((r for r in runs if r.model == Ts.name), runs[0])
    fr = r.final
    d0 = f.setup.d0
    xmax = r.front + 4 * d0
    top = r.H0 + (FLOOR_TOP_D + 1.5) * d0
    fig = Figure(figsize=(13, 13 * top / xmax + 1.2))
    ax = fig.subplots()
    order = np.argsort(fr["y"])[::-1]  # far spheres first, near ones drawn over them
    order = order[fr["x"][order] < xmax + d0]
    diam = 2 * fr["radius"][order] / d0
    offsets = np.column_stack([fr["x"][order], fr["z"][order]]) / d0
    cmap = matplotlib.colormaps["plasma"]
    norm = matplotlib.colors.Normalize(0.8, 1.2)
    facec = [cmap(norm(dd)) if t == 1 else (0.75, 0.75, 0.75, 1.0)
             for dd, t in zip(diam, fr["type"][order])]
    coll = EllipseCollection(diam, diam, np.zeros_like(diam), units="xy", offsets=offsets,
                             offset_transform=ax.transData, facecolors=facec,
                             edgecolors="0.2", linewidths=0.3)
    ax.add_collection(coll)
    ax.axhline(FLOOR_TOP_D, color="k", ls="--", lw=1)
    ax.axvline(r.front / d0, color="k", ls=":", lw=1.2)
    ax.set_xlim(-1, xmax / d0)
    ax.set_ylim(-0.5, top / d0)
    ax.set_aspect("equal")
    ax.legend(handles=[Patch(color=(0.75, 0.75, 0.75), label="rough floor (immobile)"),
                       Line2D([], [], color="k", ls="--", label="floor top, z = d0"),
                       Line2D([], [], color="k", ls=":", label=f"front L_f = {r.front / d0:.1f} d0")],
              fontsize=8, loc="upper right")
    ax.set(xlabel="x / d0  (d0 = 1 mm)", ylabel="z / d0",
           title=f"{r.model}, seed {r.seed}, a = {r.a:.2f}: the deposit at rest "
                 f"(t = {r.t_rest * 1e3:.1f} ms), side view")
    sm = matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap)
    ax.figure.colorbar(sm, ax=ax, shrink=0.8, label="diameter / d0  [-]")
    _save(fig, path)


_DRAW = {"bounce.png": _bounce, "bounce_series.png": _bounce_series, "gas_cooling.png": _gas,
         "gas_snapshot.png": _gas_snapshot, "collapse.png": _collapse,
         "collapse_snapshot.png": _collapse_snapshot}


#: the results the figures of :func:`write_figures` draw, for its worker processes (forked:
#: they inherit it instead of receiving a pickled copy)
_RES = None


def _draw_one(name: str, out: Path) -> None:
    _DRAW[name](_RES, out / name)


def write_figures(res, out: Path, tick=None, jobs: int = 1) -> list[str]:
    """Draw every figure into ``out``, ``jobs`` at a time in forked processes
    (:func:`viscontact._support.parallel.forked_map`; the files are the same for any
    ``jobs``); ``tick(message)`` as each one is done."""
    global _RES
    names = list(_DRAW)
    _RES = res
    try:
        forked_map(partial(_draw_one, out=out), names, workers=max(1, min(jobs, len(names))),
                   done=lambda name: tick and tick(f"figure {name}"))
    finally:
        _RES = None
    return names
