"""Plots of e(v) fits, bounce reductions and detected impacts: read results only.

:func:`plot_restitution`: the data with error bars, every law's fitted e(v), and a residual
panel; :func:`plot_reduction`: e against v per drop, the points left out marked;
:func:`plot_onsets`: a recording's waveform with the impact times found.  Laws keep their
colours (:data:`viscontact.collision.plots.LAW_COLORS`); data are black.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import ScalarFormatter

from ..collision.plots import LAW_COLORS
from .restitution import RestitutionFit

__all__ = ["plot_restitution", "plot_reduction", "plot_onsets"]


def plot_restitution(fit: RestitutionFit, path: str | Path) -> Path:
    """e against v: data (error bars: the sigma the fit used), each law's curve; residuals."""
    fig = Figure(figsize=(8, 7))
    ax, res = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 1.3]})
    d = fit.data
    err = d.sigma if d.sigma is not None else None
    if err is None and fit.sigma_source == "residuals":
        err = np.full(d.n, fit.best.rms)
    ax.errorbar(d.v, d.e, yerr=err, fmt="o", color="black", ms=4, capsize=2,
                label=f"data ({d.n} points)", zorder=3)
    vv = np.geomspace(d.v.min() / 1.1, d.v.max() * 1.1, 120)
    order = fit.ranking or list(fit.laws)
    n_law = len(order)
    for i, name in enumerate(order):
        f = fit.laws[name]
        color = LAW_COLORS.get(name, None)
        label = f"{name} (rms {f.rms:.3g}" + ("" if f.aicc is None else
                                              f", AICc {f.aicc - fit.laws[order[0]].aicc:+.1f}") + ")"
        ax.plot(vv, f.e_at(vv), color=color, lw=2.0 if i == 0 else 1.0, label=label)
        shift = (i - (n_law - 1) / 2) * 0.006
        res.plot(d.v * (1 + shift), d.e - f.e_fit, "o", ms=3, color=color)
    res.axhline(0.0, color="black", lw=0.8)
    ax.set_xscale("log")
    for axis in (ax.xaxis, res.xaxis):
        axis.set_major_formatter(ScalarFormatter())
        axis.set_minor_formatter(ScalarFormatter())
    ax.set_ylabel("restitution e")
    ax.set_title(fit.verdict, fontsize=8, wrap=True)
    ax.legend(fontsize=7)
    res.set_xlabel("impact speed v [m/s]")
    res.set_ylabel("e - e_fit")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return Path(path)


def plot_reduction(points: Sequence[dict[str, Any]], path: str | Path) -> Path:
    """e against v of every bounce point, one colour per drop; points left out as crosses."""
    fig = Figure(figsize=(7, 4.5))
    ax = fig.subplots()
    drops = sorted({p["drop"] for p in points})
    named = len(drops) <= 8  # a legend entry per drop only while it stays readable
    marked = False
    for d in drops:
        mine = [p for p in points if p["drop"] == d]
        kept = [p for p in mine if p["kept"]]
        left = [p for p in mine if not p["kept"]]
        src = str(mine[0].get("source", f"drop {d}"))
        line = ax.plot([p["v"] for p in kept], [p["e"] for p in kept], "o-", ms=4, lw=0.8,
                       label=Path(src.split(", drop")[0]).name + src[len(src.split(", drop")[0]):]
                       if named else None)
        if left:
            ax.plot([p["v"] for p in left], [p["e"] for p in left], "x", ms=8, mew=2,
                    color=line[0].get_color(), label=None if marked else "left out")
            marked = True
    if not named:
        ax.plot([], [], "o-", color="0.5", label=f"{len(drops)} drops, one colour each")
    ax.set_xlabel("impact speed v [m/s]")
    ax.set_ylabel("restitution e")
    ax.set_title("bounce timings reduced to (v, e)", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return Path(path)


def plot_onsets(x: np.ndarray, rate: float, times: np.ndarray, path: str | Path,
                title: str = "") -> Path:
    """The waveform (every sample's envelope, decimated for drawing) and the impacts found."""
    fig = Figure(figsize=(10, 3.5))
    ax = fig.subplots()
    step = max(1, x.size // 20000)
    n = x.size // step
    blocks = np.abs(x[: n * step]).reshape(n, step).max(axis=1)
    t = (np.arange(n) * step + step / 2) / rate
    ax.fill_between(t, -blocks, blocks, color="0.35", lw=0.6, edgecolor="0.35")
    for k, tk in enumerate(times):
        ax.axvline(tk, color="tab:red", lw=0.8, ls="--", alpha=0.7)
        ax.text(tk, 1.02, str(k + 1), transform=ax.get_xaxis_transform(), fontsize=6,
                ha="center", color="tab:red")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("signal")
    ax.set_title(title or f"{len(times)} impacts found", fontsize=9, pad=12)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return Path(path)
