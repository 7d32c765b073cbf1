"""Figures of collisions and sweeps, and each law's colour and marker in every figure.

Reads results only; never solves anything itself.  Figures are bare
:class:`~matplotlib.figure.Figure` objects (``savefig`` renders with Agg by itself), so the
matplotlib backend of whoever imports viscontact is never changed."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from matplotlib.figure import Figure

from ..physics.laws import MODELS, lookup
from .single import CollisionResult


#: One colour per law, the same in every figure (matplotlib's tab10 cycle, in registry order).
LAW_COLORS: dict[str, str] = dict(zip(MODELS, (
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#7f7f7f")))

#: One marker per law, for curves that lie close together (sweeps, e against alpha).
LAW_MARKERS: dict[str, str] = dict(zip(MODELS, ("o", "s", "^", "v", "D", "P", "x")))

#: The three panels of a velocity sweep, e, t_c [ms], F_max [N] against v: (attribute of the
#: sweep, scale to the axis unit, axis label).
SWEEP_PANELS: tuple[tuple[str, float, str], ...] = (
    ("e", 1.0, "coefficient of restitution e"), ("tc", 1e3, "contact time t_c [ms]"),
    ("fmax", 1.0, "peak force F_max [N]"))


def law_label(r: CollisionResult) -> str:
    label = r.model
    if r.beta is not None:
        label += f", beta={r.beta:g}"
    if lookup(r.model).p is None:  # the exponent is the user's
        label += f", p={r.p:g}"
    return f"{label}, alpha={r.alpha:g}"


def collision_axes(fig=None):
    """A 2x2 grid: x, x', F^ against t^, and the F^-x loop, labelled."""
    fig = fig or Figure(figsize=(10, 7.5))
    axes = fig.subplots(2, 2)
    (ax_x, ax_v), (ax_f, ax_loop) = axes
    ax_x.set(xlabel="t^ = t / T", ylabel="x = delta / (T v_i)", title="overlap")
    ax_v.set(xlabel="t^ = t / T", ylabel="x' = delta' / v_i", title="overlap rate")
    ax_f.set(xlabel="t^ = t / T", ylabel="F^ = F T / (m* v_i)", title="contact force")
    ax_loop.set(xlabel="x = delta / (T v_i)", ylabel="F^ = F T / (m* v_i)", title="force-overlap loop")
    for ax in axes.ravel():
        ax.grid(alpha=0.3)
        ax.axhline(0, color="k", lw=0.6)
    return fig, axes


def plot_collision(results: Sequence[CollisionResult], path: str | Path, title: str | None = None,
                   colors: Sequence[str] | None = None) -> Path:
    """x, x', F^ against t^ and the F^-x loop for one or more collisions, saved as PNG."""
    fig, axes = collision_axes()
    (ax_x, ax_v), (ax_f, ax_loop) = axes
    for i, r in enumerate(results):
        color = colors[i] if colors else LAW_COLORS.get(r.model) if len(results) < 2 or len(
            {q.model for q in results}) == len(results) else None
        kw = {"color": color, "label": law_label(r)}
        ax_x.plot(r.t, r.x, **kw)
        ax_v.plot(r.t, r.v, **kw)
        ax_f.plot(r.t, r.f, **kw)
        ax_loop.plot(r.x, r.f, **kw)
    ax_x.legend(fontsize=8)
    if title is None and len(results) == 1:
        r = results[0]
        title = f"{law_label(r)}, zero-{r.end} end: e = {r.e:.4f}, t_c = {r.tc:.4f}"
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    return path


def plot_sweeps(sweeps: Sequence, path: str | Path, title: str | None = None,
                measured: tuple[float, float, float] | None = None) -> Path:
    """e, t_c [ms] and F_max [N] against impact speed [cm/s] for one or more velocity sweeps.

    ``sweeps``: :class:`viscontact.collision.sweep.SweepResult` objects; ``measured``: optional
    (v [m/s], e, t_c [s]) drawn as black stars.
    """
    fig = Figure(figsize=(14, 4.8))
    axes = fig.subplots(1, 3)
    for ax, (attr, scale, label) in zip(axes, SWEEP_PANELS):
        for s in sweeps:
            lab = s.model + (f", p={s.p:g}" if lookup(s.model).p is None else "")
            ax.plot(s.v * 100, getattr(s, attr) * scale, "-o", ms=3, color=LAW_COLORS.get(s.model),
                    label=lab)
        ax.set(xlabel="impact speed v_i [cm/s]", ylabel=label)
        ax.grid(alpha=0.3)
    if measured is not None:
        v, e, tc = measured
        axes[0].plot([v * 100], [e], "k*", ms=12, label="measured")
        axes[1].plot([v * 100], [tc * 1e3], "k*", ms=12)
    axes[0].legend(fontsize=8)
    fig.suptitle(title or "Velocity sweep: m*, k_Hertz, c and tau held fixed")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    return path
