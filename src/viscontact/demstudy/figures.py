"""Figures of the DEM study (read results only).  Every law keeps its colour of
:data:`viscontact.plotting.LAW_COLORS`; theory is drawn in black."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..plotting import LAW_COLORS, LAW_MARKERS, plt
from . import theory

__all__ = ["CAPTIONS", "write_figures"]

DPI = 110

CAPTIONS = {
    "bounce.png": "A ball bouncing to rest. Top: apex height of every flight against the bounce "
                  "number, DEM with gravity throughout (markers) and the exact sequence of single "
                  "collisions (lines), one panel per ball. Bottom: how far the DEM e lies from the "
                  "exact single collision at the same impact speed, against g t_c / v, the speed "
                  "gravity adds during a contact relative to the impact speed; the difference is about "
                  "(1 - e) g t_c / v, below the dashed line (filled: gravity "
                  "throughout; open: gravity only in flight, the check, at the level of the time "
                  "step).",
    "bounce_series.png": "The exact bounce series of every law: impact speed against bounce "
                         "number. Ts keeps e constant (geometric); LH loses more as it slows and "
                         "stops sooner; KK, Jian, Li and Hunt lose less and less (e -> 1), so their "
                         "speeds fall as the power law v_k ~ k^(-1/q) that 1 - e ~ v^q predicts "
                         "(dashed: the continuum solution v_k = (v_0^-q + q A k)^(-1/q) with A "
                         "from the last bounce).",
    "gas_cooling.png": "Freely cooling gas. Top left: T/T0 against t/tau0 for every law "
                       "(solid) and the kinetic theory of the same law's exact e(v) (dashed). "
                       "Top right: the local exponent d ln T / d ln t (DEM: slopes over a third "
                       "of a decade; theory dashed) and each law's asymptote -2/(1+q) (dotted): "
                       "KK and Jian approach -5/3, Li -1.25, Hunt -1; Ts is Haff's -2. Bottom "
                       "left: Haff's law for Ts, T/T_Haff - 1 of each realisation (thin) and "
                       "their mean (the check; grey band: 5 %). Bottom right: homogeneity "
                       "(density variance ratio, solid; flow energy ratio, dashed): 1 for a "
                       "homogeneous gas.",
    "gas_snapshot.png": "The gas at the end of the run with Ts (left) and KK (right): spheres "
                        "coloured by speed over the rms speed (open the dumps gas-*.dump in OVITO "
                        "or ParaView for every law and time).",
    "collapse.png": "Column collapse. Left: the deposit's free surface for every law (first "
                    "seed) and the initial column (grey). Middle and right: run-out and deposit "
                    "angle per law, every seed (dots) with mean and standard deviation (bars).",
    "collapse_snapshot.png": "The deposit of the column with Ts (first seed) seen from the side, "
                             "spheres to scale and coloured by diameter (collapse-*.dump hold "
                             "the whole collapse in 3D).",
}


def _save(fig, path: Path) -> None:
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    plt.close(fig)


def _bounce(res, path: Path) -> None:
    balls = list(dict.fromkeys(c.ball for c in res.bounces))
    fig, axes = plt.subplots(2, len(balls), figsize=(6.5 * len(balls), 9), squeeze=False)
    for j, b in enumerate(balls):
        ax = axes[0, j]
        for c in res.bounces:
            if c.ball != b:
                continue
            col = LAW_COLORS[c.model]
            ex = c.exact
            k = np.arange(1, ex.n + 1)
            ax.plot(k, ex.column("apex") * 1e3, "-", color=col, lw=1.2)
            ok = np.isfinite(c.dem.apex)
            kd = np.arange(1, len(c.dem.apex) + 1)[ok]
            ax.plot(kd, c.dem.apex[ok] * 1e3, LAW_MARKERS[c.model], color=col, ms=5,
                    label=f"{c.model}: {c.dem.n} bounces, rests at {c.dem.t_rest:.2f} s")
        ax.axhline(res.bounces[0].dem.h_min * 1e3, color="0.4", lw=0.8, ls=":")
        ax.set(yscale="log", xscale="log", xlabel="bounce k", ylabel="apex of flight k [mm]",
               title=f"{b}: DEM (markers) and exact sequence (lines)")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
        ax = axes[1, j]
        for c in res.bounces:
            if c.ball != b:
                continue
            col = LAW_COLORS[c.model]
            gr = c.gravity_ratio()
            err = np.abs(c.dem.e / np.array(c.exact_at_dem) - 1.0)
            ok = np.isfinite(err) & (err > 0)
            ax.plot(gr[ok], err[ok], LAW_MARKERS[c.model], color=col, ms=5, label=c.model)
            if c.isolated is not None:
                n = min(c.isolated.n, c.exact.n)
                if n:
                    gi = theory.gravity_ratio(c.isolated.v_in[:n], m=_mass(c), k_hertz=_k(c))
                    ei = np.abs(c.isolated.e[:n] / np.array(c.exact_at_isolated[:n]) - 1.0)
                    ax.plot(gi, np.maximum(ei, 1e-7), LAW_MARKERS[c.model], mfc="none", color=col,
                            ms=5)
        x = np.logspace(-2.5, 1, 50)
        ax.plot(x, x, "k--", lw=0.8, label="|de/e| = g t_c / v")
        ax.set(xscale="log", yscale="log", xlabel="g t_c / v", ylabel="|e_DEM / e_exact(v) - 1|",
               title=f"{b}: where the DEM and the exact sequence part")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    _save(fig, path)


def _mass(c) -> float:
    from ..experiment import load_balls

    return load_balls()[c.ball].mass


def _k(c) -> float:
    from ..experiment import load_balls

    return load_balls()[c.ball].k_hertz


def _bounce_series(res, path: Path) -> None:
    balls = list(dict.fromkeys(c.ball for c in res.bounces))
    fig, axes = plt.subplots(1, len(balls), figsize=(6.5 * len(balls), 4.8), squeeze=False)
    for j, b in enumerate(balls):
        ax = axes[0, j]
        for c in res.bounces:
            if c.ball != b or c.exact.n == 0:
                continue
            col = LAW_COLORS[c.model]
            v = c.exact.column("v_in")
            k = np.arange(1, len(v) + 1)
            ax.plot(k, v, "-", color=col, lw=1.5, label=f"{c.model} (q = {theory.q_exponent(c.model):.2g})")
            q = theory.q_exponent(c.model)
            if q > 0 and len(v) > 3:
                e_last = c.exact.bounces[-1].e
                A = (1.0 - e_last) / v[-1] ** q
                kk = np.logspace(0, math.log10(len(v) * 3), 60)
                ax.plot(kk, theory.series_scaling(q, A, v[0], kk - 1), "--", color=col, lw=0.9)
        ax.set(xscale="log", yscale="log", xlabel="bounce k", ylabel="impact speed v_k [m/s]",
               title=f"{b}: exact bounce series")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    _save(fig, path)


def _gas(res, path: Path) -> None:
    from .gas import local_exponents

    g = res.gas
    s = g.setup
    tau0 = s.tau0()
    fig, axes = plt.subplots(2, 2, figsize=(14, 10))
    ax = axes[0, 0]
    for m, r in g.runs.items():
        col = LAW_COLORS[m]
        ax.plot(r.t / tau0, r.T / s.T0, "-", color=col, lw=1.5, label=m)
        ax.plot(r.t / tau0, r.T_theory / s.T0, "--", color=col, lw=1)
    ax.set(xscale="log", yscale="log", xlabel="t / tau0", ylabel="T / T0",
           title=f"{s.n} spheres, phi = {s.phi:g}, e = {s.e:g} at v_ref (dashed: kinetic theory)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    ax = axes[0, 1]
    for m, r in g.runs.items():
        col = LAW_COLORS[m]
        tc, k = local_exponents(r.t, r.T)
        ax.plot(tc / tau0, k, "o-", color=col, ms=3, lw=1,
                label=f"{m}: {r.slope:.2f} (theory {r.slope_theory:.2f}, "
                      f"asymptote {theory.late_exponent(m):.2f})")
        tc, k = local_exponents(r.t, r.T_theory)
        ax.plot(tc / tau0, k, "--", color=col, lw=1)
        ax.axhline(theory.late_exponent(m), color=col, lw=0.8, ls=":")
    ax.set(xscale="log", xlabel="t / tau0", ylabel="d ln T / d ln t",
           title="local cooling exponent")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, title="last half decade")
    ax = axes[1, 0]
    ax.axhspan(-5, 5, color="0.9")
    if g.haff_dev.size:
        for d in g.haff_dev:
            ax.plot(g.haff_t, d * 100, "-", color=LAW_COLORS["Ts"], lw=0.8, alpha=0.6)
        ax.plot(g.haff_t, g.haff_mean_dev * 100, "s-", color=LAW_COLORS["Ts"], ms=4,
                label=f"mean of {len(g.haff_dev)} realisations ({g.haff.n} spheres, contact "
                      f"{g.haff.tc_ratio:g} mean free times)")
        ax.legend(fontsize=8)
    ax.axhline(0, color="k", lw=0.8)
    ax.set(xlabel="t / tau0", ylabel="T / T_Haff - 1 [%]", title="Ts against Haff's law")
    ax.grid(alpha=0.3)
    ax = axes[1, 1]
    for m, r in g.runs.items():
        col = LAW_COLORS[m]
        ax.plot(np.maximum(r.dump_t / tau0, 1e-2), r.density_ratio, "-o", color=col, ms=3, label=m)
        ax.plot(np.maximum(r.dump_t / tau0, 1e-2), r.flow_ratio, "--", color=col, lw=1)
    ax.axhline(1, color="k", lw=0.8)
    ax.set(xscale="log", xlabel="t / tau0", ylabel="ratio to a homogeneous gas",
           title="homogeneity (solid: density, dashed: flow)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    _save(fig, path)


def _scatter3d(ax, x, y, z, c, size, cmap, title, label):
    sc = ax.scatter(x, y, z, c=c, s=size, cmap=cmap, depthshade=True, linewidths=0)
    ax.set_title(title)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    plt.colorbar(sc, ax=ax, shrink=0.6, label=label)


def _gas_snapshot(res, path: Path) -> None:
    g = res.gas
    laws = [m for m in ("Ts", "KK") if m in g.runs] or list(g.runs)[:1]
    fig = plt.figure(figsize=(7 * len(laws), 6))
    for i, m in enumerate(laws):
        fr = g.runs[m].final
        v = np.sqrt(fr["vx"] ** 2 + fr["vy"] ** 2 + fr["vz"] ** 2)
        ax = fig.add_subplot(1, len(laws), i + 1, projection="3d")
        size = 3e4 / max(len(v), 1)
        _scatter3d(ax, fr["x"] * 1e3, fr["y"] * 1e3, fr["z"] * 1e3, v / np.sqrt(np.mean(v ** 2)),
                   size, "viridis", f"{m}, t = {g.runs[m].t[-1] / g.setup.tau0():.3g} tau0",
                   "speed / rms speed")
    _save(fig, path)


def _collapse(res, path: Path) -> None:
    from .flow import deposit_profile

    f = res.flow
    s = f.setup
    d0 = s.d0
    fig, axes = plt.subplots(1, 3, figsize=(17, 4.8), gridspec_kw={"width_ratios": [2, 1, 1]})
    ax = axes[0]
    seed0 = s.seeds[0]
    runs0 = [r for r in f.runs if r.seed == seed0]
    if runs0:
        r0 = runs0[0]
        ax.fill([0, r0.L0 / d0, r0.L0 / d0, 0], [0, 0, r0.H0 / d0, r0.H0 / d0], color="0.88",
                label="initial column")
    for r in runs0:
        g = r.final["type"] == 1
        xs, hs = deposit_profile(r.final["x"][g], (r.final["z"] + r.final["radius"])[g], 2 * d0)
        ax.plot(xs / d0, hs / d0, "-", color=LAW_COLORS[r.model], lw=1.5, label=r.model)
    ax.set(xlabel="x / d0", ylabel="surface height / d0", title=f"deposits (seed {seed0})")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    by = f.by_law()
    for ax, attr, lab in ((axes[1], "runout", "(L_f - L0) / L0"), (axes[2], "angle", "deposit angle [deg]")):
        for i, (m, runs) in enumerate(by.items()):
            vals = np.array([getattr(r, attr) for r in runs])
            col = LAW_COLORS[m]
            ax.plot(np.full(len(vals), i) + np.linspace(-0.15, 0.15, len(vals)), vals, "o",
                    color=col, ms=4, alpha=0.7)
            sd = vals.std(ddof=1) if len(vals) > 1 else 0.0
            ax.errorbar(i, np.nanmean(vals), yerr=sd, fmt="s", color=col, capsize=5, ms=7)
        ax.set_xticks(range(len(by)), list(by))
        ax.set(ylabel=lab)
        ax.grid(alpha=0.3)
    axes[1].set_title("run-out")
    axes[2].set_title("deposit angle")
    _save(fig, path)


def _collapse_snapshot(res, path: Path) -> None:
    """Side view (x-z) of the deposit, every sphere drawn to scale, the nearest in front."""
    from matplotlib.collections import EllipseCollection

    f = res.flow
    r = next((r for r in f.runs if r.model == "Ts"), f.runs[0])
    fr = r.final
    d0 = f.setup.d0
    g = fr["type"] == 1
    front = float(np.percentile((fr["x"] + fr["radius"])[g], 99.0))
    xmax = front + 4 * d0
    fig, ax = plt.subplots(figsize=(13, 13 * (r.H0 + 2 * d0) / xmax + 1.2))
    order = np.argsort(fr["y"])[::-1]  # far spheres first, near ones drawn over them
    order = order[fr["x"][order] < xmax + d0]
    diam = 2 * fr["radius"][order] / d0
    offsets = np.column_stack([fr["x"][order], fr["z"][order]]) / d0
    colors = np.where(fr["type"][order] == 1, 0.0, 1.0)
    cmap = plt.get_cmap("plasma")
    norm = plt.Normalize(0.8, 1.2)
    facec = [cmap(norm(dd)) if c == 0.0 else (0.75, 0.75, 0.75, 1.0)
             for dd, c in zip(diam, colors)]
    coll = EllipseCollection(diam, diam, np.zeros_like(diam), units="xy", offsets=offsets,
                             offset_transform=ax.transData, facecolors=facec,
                             edgecolors="0.2", linewidths=0.3)
    ax.add_collection(coll)
    ax.set_xlim(-1, xmax / d0)
    ax.set_ylim(-0.5, r.H0 / d0 + 1.5)
    ax.set_aspect("equal")
    ax.set(xlabel="x / d0", ylabel="z / d0",
           title=f"{r.model}, seed {r.seed}: the deposit at rest, side view (grey: the rough floor)")
    sm = plt.cm.ScalarMappable(norm=norm, cmap=cmap)
    plt.colorbar(sm, ax=ax, shrink=0.8, label="diameter / d0")
    _save(fig, path)


_DRAW = {"bounce.png": _bounce, "bounce_series.png": _bounce_series, "gas_cooling.png": _gas,
         "gas_snapshot.png": _gas_snapshot, "collapse.png": _collapse,
         "collapse_snapshot.png": _collapse_snapshot}


def write_figures(res, out: Path, tick=None) -> list[str]:
    for name, draw in _DRAW.items():
        draw(res, out / name)
        if tick:
            tick(f"figure {name}")
    return list(_DRAW)
