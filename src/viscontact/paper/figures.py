"""The study's figures 2 to 12 (Jian et al., Powder Technol. 356 (2019) 735), drawn from a :class:`StudyResults`.

Reads results only.  Every law keeps its colour from :data:`viscontact.collision.plots.LAW_COLORS`
in every figure; several curves of one law (several alpha or beta) are shades of that colour.
Measured values are drawn in black.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from matplotlib import colors as mcolors
from matplotlib.figure import Figure

from ..physics.laws import LAWS, STUDY_MODELS
from .._support.parallel import forked_map
from ..collision.plots import LAW_COLORS, LAW_MARKERS
from .study import (
    ALPHA_REF, BETA_GRID, BETA_REF, PUBLISHED_E, TABLE1_MODELS, BallStudy, StudyResults,
)
from ..physics.laws import Jian

__all__ = ["FIGURES", "write_figures", "law_name", "shades"]

DPI = 110
MEASURED = dict(color="black", marker="*", markersize=13, linestyle="none", zorder=5)
_T_HAT, _X_HAT = "t^ = t / T", "x = delta / (T v_i)"
_V_HAT, _F_HAT = "x' = delta' / v_i", "F^ = F T / (m* v_i)"


_FULL_NAMES = {Jian.name: "Jian et al., relaxation time"}


def law_name(model: str) -> str:
    """'LH (Lee-Herrmann)'."""
    return f"{model} ({_FULL_NAMES.get(model, LAWS[model].title)})"


def shades(model: str, n: int) -> list[tuple[float, float, float]]:
    """``n`` shades of a law's colour, light to dark (several alpha or beta of one law)."""
    base = np.array(mcolors.to_rgb(LAW_COLORS[model]))
    out = []
    for f in np.linspace(0.0, 1.0, n):
        if f < 0.5:  # mix with white: 55 % white at the light end
            w = 0.55 * (1 - 2 * f)
            out.append(tuple(base * (1 - w) + w))
        else:  # mix with black: 45 % black at the dark end
            k = 0.45 * (2 * f - 1)
            out.append(tuple(base * (1 - k)))
    return out


def _grid(ax) -> None:
    ax.grid(alpha=0.3)
    ax.axhline(0, color="0.3", lw=0.6)


def _four_panels(title: str):
    fig = Figure(figsize=(11, 8))
    axes = fig.subplots(2, 2)
    for ax in axes.ravel():
        _grid(ax)
    fig.suptitle(title, fontsize=12)
    return fig, axes


def _nondim_panels(ax4, results, colors, labels, styles=None) -> None:
    """x, x', F^ against t^ and the F^-x loop; a dot marks the end of each contact."""
    (ax_x, ax_v), (ax_f, ax_loop) = ax4
    for i, (r, c, lab) in enumerate(zip(results, colors, labels)):
        kw = dict(color=c, lw=1.6, ls=(styles[i] if styles else "-"))
        ax_x.plot(r.t, r.x, label=lab, **kw)
        ax_x.plot(r.t[-1], r.x[-1], "o", color=c, ms=4)
        ax_v.plot(r.t, r.v, **kw)
        ax_f.plot(r.t, r.f, **kw)
        ax_loop.plot(r.x, r.f, **kw)
        ax_v.plot(r.t[-1], r.v[-1], "o", color=c, ms=4)
        ax_f.plot(r.t[-1], r.f[-1], "o", color=c, ms=4)
        ax_loop.plot(r.x[-1], r.f[-1], "o", color=c, ms=4)
    ax_x.set(xlabel=_T_HAT, ylabel=_X_HAT, title="(a) overlap")
    ax_v.set(xlabel=_T_HAT, ylabel=_V_HAT, title="(b) overlap rate")
    ax_f.set(xlabel=_T_HAT, ylabel=_F_HAT, title="(c) contact force")
    ax_loop.set(xlabel=_X_HAT, ylabel=_F_HAT, title="(d) force against overlap")
    for ax in (ax_x, ax_v, ax_f):
        ax.set_xlim(left=0)
    ax_loop.set_xlim(left=0)


def _finish(fig, path: Path, legend_handles=None, ncol=3, rect_bottom=0.0) -> None:
    if legend_handles is not None:
        handles, labels = legend_handles
        fig.legend(handles, labels, loc="lower center", ncol=ncol, fontsize=9, frameon=False)
    fig.tight_layout(rect=(0, rect_bottom, 1, 0.97))
    fig.savefig(path, dpi=DPI)


def fig02(res: StudyResults, path: Path) -> None:
    rs = res.reference
    fig, axes = _four_panels(
        f"Fig. 2. All six laws at alpha = {ALPHA_REF:g} (Jian: beta = {BETA_REF:g}), "
        "non-dimensional; dots mark the end of contact (zero force)")
    labels = [f"{law_name(r.model)}: e = {r.e:.4f}, t_c = {r.tc:.3f}" for r in rs]
    _nondim_panels(axes, rs, [LAW_COLORS[r.model] for r in rs], labels)
    _finish(fig, path, axes[0, 0].get_legend_handles_labels(), ncol=2, rect_bottom=0.1)


def _series_figure(res: StudyResults, path: Path, what: str) -> None:
    number, quantity, ylabel = {
        "x": (3, "overlap", _X_HAT), "v": (4, "overlap rate", _V_HAT),
        "f": (5, "contact force", _F_HAT),
    }[what]
    fig = Figure(figsize=(13, 7.5))
    axes = fig.subplots(2, 3, sharex=True, sharey=True)
    for ax, m in zip(axes.ravel(), STUDY_MODELS):
        series = res.series[m]
        cols = shades(m, len(series) - 1)
        for r in series:
            if r.alpha == 0:
                ax.plot(r.t, getattr(r, what), color="0.35", ls="--", lw=1.2,
                        label="alpha = 0 (no damping)")
            else:
                ax.plot(r.t, getattr(r, what), color=cols.pop(0), lw=1.6,
                        label=f"alpha = {r.alpha:g}, e = {r.e:.3f}")
        title = law_name(m) + (f", beta = {BETA_REF:g}" if m == Jian.name else "")
        ax.set_title(title, color=LAW_COLORS[m], fontsize=11, fontweight="bold")
        _grid(ax)
        ax.legend(fontsize=7.5, loc={"x": "lower center", "v": "lower left", "f": "upper right"}[what])
    for ax in axes[1]:
        ax.set_xlabel(_T_HAT)
    for ax in axes[:, 0]:
        ax.set_ylabel(ylabel)
    axes[0, 0].set_xlim(0, max(r.t[-1] for s in res.series.values() for r in s) * 1.02)
    fig.suptitle(f"Fig. {number}. {quantity.capitalize()} against time for each law at several "
                 "alpha (zero-force end of contact)", fontsize=12)
    _finish(fig, path)


def fig03(res, path):
    _series_figure(res, path, "x")


def fig04(res, path):
    _series_figure(res, path, "v")


def fig05(res, path):
    _series_figure(res, path, "f")


def fig06(res: StudyResults, path: Path) -> None:
    rs = res.jian_betas
    fig, axes = _four_panels(f"Fig. 6. Jian law at alpha = {ALPHA_REF:g} for several relaxation "
                             "constants beta = tau / T (beta = 0 is Kuwabara-Kono)")
    labels = [("beta -> 0 (= KK)" if r.beta == 0 else f"beta = {r.beta:g}") +
              f": e = {r.e:.4f}, t_c = {r.tc:.3f}" for r in rs]
    styles = ["-", "--", "-.", ":"][: len(rs)]
    _nondim_panels(axes, rs, shades(Jian.name, len(rs)), labels, styles)
    _finish(fig, path, axes[0, 0].get_legend_handles_labels(), ncol=2, rect_bottom=0.08)


def _measured_e_lines(ax, res: StudyResults) -> None:
    for key, bs in res.balls.items():
        ax.axhline(bs.ball.e, color="black", ls=":", lw=1.0)
        ax.annotate(f"{key} measured e = {bs.ball.e:g}", (ax.get_xlim()[1], bs.ball.e),
                    xytext=(-4, 3), textcoords="offset points", ha="right", fontsize=8)


def fig07(res: StudyResults, path: Path) -> None:
    fig = Figure(figsize=(14.5, 5.5))
    (ax_a, ax_b) = fig.subplots(1, 2, sharey=True)
    a = res.alpha_grid
    for m in TABLE1_MODELS:
        ax_a.plot(a, res.table1[m], "-", marker=LAW_MARKERS[m], ms=3.5, color=LAW_COLORS[m],
                  label=law_name(m))
    cols = shades(Jian.name, len(BETA_GRID))
    for b, c in zip(BETA_GRID, cols):
        ax_b.plot(a, res.table2[b], "-o", ms=3, color=c,
                  label=f"beta = {b:g}" + (" (= KK)" if b == 0 else ""))
    for ax, t in ((ax_a, "(a) five laws (Table 1)"), (ax_b, "(b) Jian law for each beta (Table 2)")):
        ax.set(xlabel="damping constant alpha", title=t, xlim=(0, a[-1]), ylim=(0, 1.02))
        ax.grid(alpha=0.3)
        _measured_e_lines(ax, res)
    ax_a.plot([ALPHA_REF] * len(TABLE1_MODELS), [PUBLISHED_E[m] for m in TABLE1_MODELS],
              "kx", ms=8, mew=1.5, zorder=6, label=f"published value at alpha = {ALPHA_REF:g}")
    ax_b.plot([ALPHA_REF], [PUBLISHED_E[Jian.name]], "kx", ms=8, mew=1.5, zorder=6,
              label=f"published value\n(alpha = {ALPHA_REF:g}, beta = {BETA_REF:g})")
    ax_a.set_ylabel("coefficient of restitution e")
    ax_a.legend(fontsize=8.5, loc="upper right", bbox_to_anchor=(1.0, 0.84))
    ax_b.legend(fontsize=8.5, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle("Fig. 7. Coefficient of restitution against alpha (zero-force end); dotted: "
                 "the balls' measured e", fontsize=12)
    _finish(fig, path)


def _ball_figure(bs: BallStudy, number: int, path: Path) -> None:
    b = bs.ball
    fig, axes = _four_panels(
        f"Fig. {number}. {b.key}, {b.name}: drop at v_i = {b.v_in * 100:.1f} cm/s\n"
        f"each law calibrated to the measured e = {b.e:g} (Jian: beta = {b.beta:g}); "
        "dots: end of contact (zero force); black: measured")
    (ax_x, ax_v), (ax_f, ax_loop) = axes
    for m, d in bs.drops.items():
        c = LAW_COLORS[m]
        t = d.t * 1e3
        ax_x.plot(t, d.delta * 1e3, color=c, lw=1.6,
                  label=f"{law_name(m)}: t_c = {d.tc * 1e3:.2f} ms, F_max = {d.fmax:.0f} N")
        ax_v.plot(t, d.ddelta, color=c, lw=1.6)
        ax_f.plot(t, d.force, color=c, lw=1.6)
        ax_loop.plot(d.delta * 1e3, d.force, color=c, lw=1.6)
        for ax, x, y in ((ax_x, t, d.delta * 1e3), (ax_v, t, d.ddelta), (ax_f, t, d.force),
                         (ax_loop, d.delta * 1e3, d.force)):
            ax.plot(x[-1], y[-1], "o", color=c, ms=4)
    tc_ms = b.tc * 1e3
    for ax in (ax_x, ax_v, ax_f):
        ax.axvline(tc_ms, color="black", ls="--", lw=1.0)
    ax_x.plot([], [], color="black", ls="--", lw=1.0, label=f"measured t_c = {tc_ms:.2f} ms")
    ax_v.plot([0, tc_ms], [b.v_in, -b.v_out], **MEASURED, clip_on=False)
    ax_x.plot([], [], **MEASURED, label=f"measured v_i = {b.v_in * 100:.1f} cm/s and "
              f"v_o = {b.v_out * 100:.1f} cm/s (e = {b.e:g})")
    ax_x.set(xlabel="time t [ms]", ylabel="overlap delta [mm]", title="(a) overlap")
    ax_v.set(xlabel="time t [ms]", ylabel="overlap rate delta' [m/s]",
             title="(b) overlap rate (stars: measured)")
    ax_f.set(xlabel="time t [ms]", ylabel="contact force F [N]", title="(c) contact force")
    ax_loop.set(xlabel="overlap delta [mm]", ylabel="contact force F [N]",
                title="(d) force against overlap")
    for ax in (ax_x, ax_v, ax_f, ax_loop):
        ax.set_xlim(left=0)
    _finish(fig, path, ax_x.get_legend_handles_labels(), ncol=2, rect_bottom=0.12)


def fig08(res, path):
    _ball_figure(res.balls["ILB"], 8, path)


def fig09(res, path):
    _ball_figure(res.balls["OLB"], 9, path)


def _sweep_figure(res: StudyResults, path: Path, number: int, what: str) -> None:
    label, scale, measured = {
        "e": ("coefficient of restitution e", 1.0, lambda b: b.e),
        "tc": ("contact time t_c [ms]", 1e3, lambda b: b.tc * 1e3),
        "fmax": ("peak force F_max [N]", 1.0, None),
    }[what]
    fig = Figure(figsize=(13, 5.5))
    axes = fig.subplots(1, 2)
    for ax, (key, bs) in zip(axes, res.balls.items()):
        b = bs.ball
        ax.axvspan(b.v_min * 100, b.v_max * 100, color="0.92", zorder=0,
                   label=f"range of v_i in the tests ({b.v_min * 100:.1f}-{b.v_max * 100:.1f} cm/s)")
        ax.axvline(b.v_in * 100, color="0.5", lw=0.8, ls=":",
                   label=f"calibration speed {b.v_in * 100:.1f} cm/s")
        for m, s in bs.sweeps.items():
            ax.plot(s.v * 100, getattr(s, what) * scale, color=LAW_COLORS[m], lw=1.8,
                    marker=LAW_MARKERS[m], ms=5, markevery=(STUDY_MODELS.index(m) % 3, 3),
                    label=law_name(m))
        if what in ("tc", "fmax"):
            ref = bs.hertz_tc * 1e3 if what == "tc" else bs.hertz_fmax
            ax.plot(res.speeds * 100, ref, color="0.45", ls="--", lw=1.2,
                    label="no damping (Hertz, closed form)")
        if measured is not None:
            ax.plot([b.v_in * 100], [measured(b)], **MEASURED, label="measured at 171.6 cm/s")
        ax.set(xlabel="impact speed v_i [cm/s]", ylabel=label,
               title=f"({'ab'[list(res.balls).index(key)]}) {key}, {b.name}")
        ax.set_xlim(res.speeds[0] * 100, res.speeds[-1] * 100)
        ax.grid(alpha=0.3)
    quantity = {"e": "Coefficient of restitution", "tc": "Contact time", "fmax": "Peak force"}[what]
    note = "" if measured else " (not measured)"
    fig.suptitle(f"Fig. {number}. {quantity}{note} against impact speed, with m*, k_Hertz, c and "
                 "tau held at their 171.6 cm/s calibration", fontsize=12)
    handles, labels = axes[0].get_legend_handles_labels()
    order = list(range(2, len(labels))) + [0, 1]  # laws first, then the reference marks
    _finish(fig, path, ([handles[i] for i in order], [labels[i] for i in order]), ncol=4,
            rect_bottom=0.13)


def fig10(res, path):
    _sweep_figure(res, path, 10, "e")


def fig11(res, path):
    _sweep_figure(res, path, 11, "tc")


def fig12(res, path):
    _sweep_figure(res, path, 12, "fmax")


#: file name -> (drawing function, caption for the report page)
FIGURES: dict[str, tuple[Callable[[StudyResults, Path], None], str]] = {
    "fig02.png": (fig02, "Fig. 2. Overlap, overlap rate and force against time, and the "
                  "force-overlap loop, for all six laws at alpha = 0.3 (Jian with beta = 0.5)."),
    "fig03.png": (fig03, "Fig. 3. Overlap x against time for each law at alpha = 0 to 1.0 "
                  "(Jian with beta = 0.5)."),
    "fig04.png": (fig04, "Fig. 4. Overlap rate x' against time for each law at alpha = 0 to 1.0."),
    "fig05.png": (fig05, "Fig. 5. Contact force F^ against time for each law at alpha = 0 to 1.0; "
                  "only Hunt-Crossley ends with zero overlap."),
    "fig06.png": (fig06, "Fig. 6. The Jian law at alpha = 0.3 for beta -> 0 (Kuwabara-Kono), 0.1, "
                  "0.5 and 1.0: a longer relaxation time delays the damping and raises e."),
    "fig07.png": (fig07, "Fig. 7. Coefficient of restitution against alpha: (a) the five laws "
                  "of Table 1, (b) the Jian law for each beta of Table 2."),
    "fig08.png": (fig08, "Fig. 8. Indoor lacrosse ball (ILB): the drop simulated with every "
                  "calibrated law, with the measured speeds and contact time."),
    "fig09.png": (fig09, "Fig. 9. Outdoor lacrosse ball (OLB): the drop simulated with every "
                  "calibrated law, with the measured speeds and contact time."),
    "fig10.png": (fig10, "Fig. 10. Coefficient of restitution against impact speed for both "
                  "balls, physical constants held at their calibration."),
    "fig11.png": (fig11, "Fig. 11. Contact time against impact speed for both balls."),
    "fig12.png": (fig12, "Fig. 12. Peak contact force against impact speed for both balls."),
}


def _draw(res: StudyResults, out: Path, name: str) -> Path:
    FIGURES[name][0](res, out / name)
    return out / name


def write_figures(res: StudyResults, out: Path, names: Sequence[str] | None = None,
                  tick: Callable[[str], None] | None = None, workers: int | None = None) -> list[Path]:
    """Draw the figures (all, or ``names``) into directory ``out``; returns the paths.

    Rendering dominates a report's run time, so the figures are drawn in ``workers`` forked
    processes (default: one per core; :func:`viscontact._support.parallel.forked_map`); ``tick(name)``
    is called as each one is finished.
    """
    return forked_map(functools.partial(_draw, res, out), list(names or FIGURES),
                      workers=workers, done=tick)
