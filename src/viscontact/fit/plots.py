"""Plots of fits: reads results only, never fits or solves anything itself.

:func:`plot_fit` draws one recording against every fitted law like the study's Figs. 8-9
(delta, delta', F against t, and the F-delta loop); :func:`plot_global` draws measured and
predicted e, t_c, F_max against the impact speed like Figs. 10-12.  Laws keep their colours
(:data:`viscontact.collision.plots.LAW_COLORS`); measurements are black.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from matplotlib.figure import Figure

from ..collision.plots import LAW_COLORS, LAW_MARKERS, SWEEP_PANELS
from ..paper.figures import MEASURED
from .fitting import GlobalFit, LawFit
from .recording import Measured

__all__ = ["plot_fit", "plot_global"]

_DATA = dict(color="black", marker=".", ms=3, ls="none", label="recording", zorder=1)


def plot_fit(meas: Measured, fits: Sequence[LawFit], path: str | Path) -> Path:
    """delta, delta', F against t [ms] and F against delta: the recording and each fitted law."""
    fig = Figure(figsize=(11, 8))
    axes = fig.subplots(2, 2)
    (ax_d, ax_v), (ax_f, ax_loop) = axes
    t_ms = (meas.t - meas.t_start) * 1e3
    ax_d.plot(t_ms, meas.overlap * 1e3, **_DATA)
    ax_v.plot(t_ms, meas.velocity, **_DATA)
    ax_f.plot(t_ms, meas.force, **_DATA)
    inside = (meas.t >= meas.t_start) & (meas.t <= meas.t_end)
    ax_loop.plot(meas.overlap[inside] * 1e3, meas.force[inside], **_DATA)
    for f in fits:
        r = f.trace.impact
        tt = (r.t + f.t0 - meas.t_start) * 1e3
        kw = dict(color=LAW_COLORS.get(f.law), lw=1.5,
                  label=f"{f.law}: rms {f.rms:.3g} N ({f.rms_rel:.1%})")
        ax_d.plot(tt, r.delta * 1e3, **kw)
        ax_v.plot(tt, r.ddelta, **kw)
        ax_f.plot(tt, r.force, **kw)
        ax_loop.plot(r.delta * 1e3, r.force, **kw)
    for ax in axes.ravel():
        ax.grid(alpha=0.3)
        ax.axhline(0, color="0.3", lw=0.6)
    for ax in (ax_d, ax_v, ax_f):
        ax.axvline(meas.tc * 1e3, color="black", ls=":", lw=1)
    ax_d.set(xlabel="t [ms] from the contact start", ylabel="overlap delta [mm]",
             title="(a) overlap")
    ax_v.set(xlabel="t [ms]", ylabel="overlap rate delta' [m/s]", title="(b) overlap rate")
    ax_v.axhline(-meas.e * meas.v, color="black", ls=":", lw=1)
    ax_f.set(xlabel="t [ms]", ylabel="contact force F [N]", title="(c) contact force")
    ax_loop.set(xlabel="overlap delta [mm]", ylabel="contact force F [N]",
                title="(d) force-overlap loop")
    ax_d.legend(fontsize=8)
    fig.suptitle(f"{Path(meas.path).name}: measured e = {meas.e:.3f}, t_c = {meas.tc * 1e3:.3f} ms "
                 f"(dotted), v_i = {meas.v:.4g} m/s", fontsize=11)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    return path


def plot_global(fits: Sequence[GlobalFit], path: str | Path) -> Path:
    """e, t_c [ms], F_max [N] against v_i [cm/s]: measured (stars), each law's global fit."""
    fig = Figure(figsize=(15, 4.8))
    axes = fig.subplots(1, 3)
    for ax, (key, scale, label) in zip(axes, SWEEP_PANELS):
        for g in fits:
            color = LAW_COLORS.get(g.law)
            if g.sweep is not None:
                ax.plot(g.sweep.v * 100, getattr(g.sweep, key) * scale, "-", color=color,
                        label=g.law)
            pts = g.points()
            ax.plot([p["v"] * 100 for p in pts], [p[f"{key}_fit"] * scale for p in pts],
                    LAW_MARKERS.get(g.law, "o"), color=color, ms=5, ls="none")
        if fits:
            pts = fits[0].points()
            ax.plot([p["v"] * 100 for p in pts], [p[key] * scale for p in pts],
                    **(MEASURED | {"label": "measured"}))
        ax.set(xlabel="impact speed v_i [cm/s]", ylabel=label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("One set of physical constants (c, tau, k_Hertz) per law fitted to all recordings")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    return path
