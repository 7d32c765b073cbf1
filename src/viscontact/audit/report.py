"""Audit tables (CSV, Markdown) and plots.  Reads results only; computes nothing new.

:func:`write_all` is what ``viscontact audit --all`` runs: for every formula and preset, every
target e on a grid and every end criterion, the prescribed alpha, the delivered e, the error
and the exact alpha, plus a compact summary at e = 0.3, 0.5, 0.9.
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Iterable, Sequence

from ..physics.pair import ContactPair
from ..physics.domain import range_text
from .engines import ENGINES, EngineAudit, audit_engine, get_preset, presets_of
from .formulas import FORMULAS, FormulaAudit, audit_formula

__all__ = [
    "DEFAULT_GRID", "SUMMARY_E", "DEFAULT_PHYSICAL", "formula_rows", "engine_rows",
    "engine_settings", "write_csv", "markdown_table", "summary_markdown", "plot_formulas",
    "plot_engines", "write_all",
]

#: target restitution grid of the full tables
DEFAULT_GRID: tuple[float, ...] = tuple(round(0.05 * i, 2) for i in range(1, 20)) + (0.99,)
#: the e values quoted in the summary
SUMMARY_E: tuple[float, ...] = (0.3, 0.5, 0.9)
#: collision used for the physical-unit presets: the indoor lacrosse ball of Jian et al. (2019)
#: dropped on a rigid plate (m* = m, R* = R), v_i = 1.716 m/s
DEFAULT_PHYSICAL = ContactPair(m_eff=0.1547, r_eff=0.03175, k_hertz=1.688e6, v=1.716)

ENDS = ("force", "overlap")

_FORMULA_FIELDS = ["formula", "model", "p", "derived_for", "end", "target_e", "alpha", "delivered_e",
                   "error", "exact_alpha", "note"]
_ENGINE_FIELDS = ["engine", "option", "versions", "clamp", "model", "end", "target_e", "input_name", "input_units",
                  "input_value", "alpha", "delivered_e", "error", "exact_alpha", "input_for_target",
                  "note"]


def formula_rows(grid: Iterable[float] = DEFAULT_GRID, ends: Sequence[str] = ENDS,
                 names: Iterable[str] | None = None) -> list[FormulaAudit]:
    """Every registered formula (or ``names``) at every e of ``grid`` under every end criterion."""
    out = []
    for name in (names or FORMULAS):
        for end in ends:
            for e in grid:
                out.append(audit_formula(name, e, end))
    return out


def engine_settings() -> list[tuple[str, str, bool | None, str | None]]:
    """(engine, option, clamp, version) for every preset: both clamp states where the engine
    has a switch; version None for the current preset, its last version for an older one."""
    out = []
    for eng, opts in ENGINES.items():
        for opt in opts:
            for pre in presets_of(eng, opt):
                for clamp in ((False, True) if pre.clamp_flag else (None,)):
                    out.append((eng, opt, clamp, pre.until))
    return out


def engine_rows(grid: Iterable[float] = DEFAULT_GRID,
                physical: ContactPair = DEFAULT_PHYSICAL) -> list[EngineAudit]:
    """Every preset and clamp state at every e of ``grid``."""
    out = []
    for eng, opt, clamp, ver in engine_settings():
        for e in grid:
            out.append(audit_engine(eng, opt, e, clamp=clamp, physical=physical, version=ver))
    return out


#: the numbers of a row that are None where they do not exist (shown as n/a, CSV: empty)
_VALUES = {"alpha", "delivered_e", "error", "exact_alpha", "input_value", "input_for_target"}


def _value(v: float | None, digits: int = 6) -> str:
    """A number of a row, ``n/a`` where it does not exist (the row's note says why)."""
    return "n/a" if v is None else _fmt(v, digits)


def _fmt(v, digits: int = 6) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        if not math.isfinite(v):
            return "n/a"
        return f"{v:.{digits}g}"
    return str(v)


def _row(obj, fields: Sequence[str]) -> dict:
    d = obj.to_dict()
    return {k: d.get(k) for k in fields}


def write_csv(rows: Sequence, path: str) -> str:
    """Write formula or engine rows as CSV (empty cell for a value that does not exist)."""
    fields = _FORMULA_FIELDS if rows and isinstance(rows[0], FormulaAudit) else _ENGINE_FIELDS
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields)
        w.writeheader()
        for r in rows:
            d = _row(r, fields)
            w.writerow({k: repr(v) if isinstance(v, float) else v for k, v in d.items()})
    return path


def markdown_table(rows: Sequence) -> str:
    """A Markdown table of formula or engine rows."""
    fields = _FORMULA_FIELDS if rows and isinstance(rows[0], FormulaAudit) else _ENGINE_FIELDS
    lines = ["| " + " | ".join(fields) + " |", "|" + "---|" * len(fields)]
    for r in rows:
        d = _row(r, fields)
        lines.append("| " + " | ".join(_value(d[k]) if k in _VALUES else _fmt(d[k])
                                       for k in fields) + " |")
    return "\n".join(lines) + "\n"


def _engine_label(eng: str, opt: str, clamp: bool | None, version: str | None = None) -> str:
    pre = get_preset(eng, opt, version)
    label = f"{eng} {opt}" + (f" (<= {pre.until})" if pre.until else "")
    if pre.clamp_flag:
        label += f" {'+' if clamp else 'no '}{pre.clamp_flag}"
    return label


def summary_markdown(e_values: Sequence[float] = SUMMARY_E,
                     physical: ContactPair = DEFAULT_PHYSICAL) -> str:
    """Delivered e of every formula (both end criteria) and preset at ``e_values``."""
    out = ["### Published formulas: delivered e\n",
           "Each cell: e delivered by the formula's alpha (exact solve) under the zero-force / "
           "zero-overlap end criterion. `n/a`: the formula has no alpha for that e, or its alpha "
           f"lies outside the domain {range_text('alpha')}.\n"]
    head = "| formula | law | derived for | " + " | ".join(f"e = {e:g} (force / overlap)" for e in e_values) + " |"
    out += [head, "|" + "---|" * (3 + len(e_values))]
    for name, f in FORMULAS.items():
        cells = []
        for e in e_values:
            a, b = (audit_formula(f, e, end).delivered_e for end in ENDS)
            cells.append(f"{_value(a, 4)} / {_value(b, 4)}")
        out.append(f"| {name} | {f.law_label} | {f.derived_for or '-'} | " + " | ".join(cells) + " |")
    out += ["\n### DEM-engine presets: delivered e and the input for the target\n",
            "Each cell: delivered e when the target e is typed (restitution inputs) or, for dashpots "
            "in physical units, when the value calibrated exactly for the zero-overlap criterion is "
            "typed; in brackets the value to type to get the target "
            f"(physical presets: m* = {physical.m_eff:g} kg, R* = {physical.r_eff:g} m, "
            f"k_Hertz = {physical.k_hertz:g} N/m^1.5, v = {physical.v:g} m/s, T = {physical.T:.6g} s).\n"]
    head = "| engine setting | law | end | input | " + " | ".join(f"e = {e:g}" for e in e_values) + " |"
    out += [head, "|" + "---|" * (4 + len(e_values))]
    for eng, opt, clamp, ver in engine_settings():
        rows = [audit_engine(eng, opt, e, clamp=clamp, physical=physical, version=ver) for e in e_values]
        r0 = rows[0]
        unit = "" if r0.input_units == "-" else f" [{r0.input_units}]"
        cells = [f"{_value(r.delivered_e, 4)} [{_value(r.input_for_target, 5)}]" for r in rows]
        out.append(f"| {_engine_label(eng, opt, clamp, ver)} | {r0.model} | zero {r0.end} | "
                   f"{r0.input_name}{unit} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def plot_formulas(rows: Sequence[FormulaAudit], path: str) -> str:
    """Delivered against target e, one line per formula, one panel per end criterion."""
    import matplotlib  # here, so that the audit command's --help does not load it
    from matplotlib.figure import Figure

    ends = [end for end in ENDS if any(r.end == end for r in rows)]
    fig = Figure(figsize=(7.5 * len(ends), 8.5))
    axes = fig.subplots(1, len(ends), squeeze=False)
    names = list(dict.fromkeys(r.formula for r in rows))
    cmap = matplotlib.colormaps["tab20"]
    styles = ["-", "--", "-.", ":"]
    for ax, end in zip(axes[0], ends):
        ax.plot([0, 1], [0, 1], color="k", lw=0.8, label="delivered = target")
        for i, name in enumerate(names):
            pts = [(r.target_e, r.delivered_e) for r in rows if r.formula == name and r.end == end
                   and r.delivered_e is not None]
            if pts:
                x, y = zip(*pts)
                ax.plot(x, y, styles[i % len(styles)], color=cmap(i % 20), marker=".", ms=3, label=name)
        ax.set_xlabel("target e")
        ax.set_ylabel("delivered e (exact solve)")
        ax.set_title(f"zero-{end} end of contact")
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1)
        ax.grid(alpha=0.3)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=5, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.14, 1, 1))
    fig.savefig(path, dpi=120)
    return path


def plot_engines(rows: Sequence[EngineAudit], path: str) -> str:
    """Delivered against target e, one line per engine setting."""
    import matplotlib  # here, so that the audit command's --help does not load it
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 10))
    ax = fig.subplots()
    ax.plot([0, 1], [0, 1], color="k", lw=0.8, label="delivered = target")
    keys = list(dict.fromkeys((r.engine, r.option, r.versions, r.clamp, r.end) for r in rows))
    cmap = matplotlib.colormaps["tab20"]
    for i, (eng, opt, versions, clamp, end) in enumerate(keys):
        pts = [(r.target_e, r.delivered_e) for r in rows if (r.engine, r.option, r.versions, r.clamp, r.end)
               == (eng, opt, versions, clamp, end) and r.delivered_e is not None]
        if pts:
            x, y = zip(*pts)
            pre = next(p for p in presets_of(eng, opt) if p.versions == versions)
            label = _engine_label(eng, opt, clamp if pre.clamp_flag else None, pre.until) + f" (zero {end})"
            ax.plot(x, y, "-" if end == "force" else "--", color=cmap(i % 20), marker=".", ms=3,
                    label=label)
    ax.set_xlabel("target e")
    ax.set_ylabel("delivered e (exact solve)")
    ax.set_title("DEM-engine presets: target e typed (physical dashpots: zero-overlap calibration)")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return path


def write_all(outdir: str, grid: Iterable[float] = DEFAULT_GRID,
              physical: ContactPair = DEFAULT_PHYSICAL, plots: bool = True) -> list[str]:
    """Write formulas.{csv,md,png}, engines.{csv,md,png} and summary.md into ``outdir``."""
    os.makedirs(outdir, exist_ok=True)
    grid = tuple(grid)
    frows = formula_rows(grid)
    erows = engine_rows(grid, physical)
    paths = [write_csv(frows, os.path.join(outdir, "formulas.csv")),
             write_csv(erows, os.path.join(outdir, "engines.csv"))]
    for name, rows in (("formulas.md", frows), ("engines.md", erows)):
        p = os.path.join(outdir, name)
        with open(p, "w") as fh:
            fh.write(markdown_table(rows))
        paths.append(p)
    p = os.path.join(outdir, "summary.md")
    with open(p, "w") as fh:
        fh.write(summary_markdown(physical=physical))
    paths.append(p)
    if plots:
        paths.append(plot_formulas(frows, os.path.join(outdir, "formulas.png")))
        paths.append(plot_engines(erows, os.path.join(outdir, "engines.png")))
    return paths
