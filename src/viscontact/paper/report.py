"""``viscontact reproduce``: compute the study, write the report atomically.

The report directory follows the rule of every command that writes
(:class:`viscontact._support.outputs.OutputDir`): it is built in a temporary directory and moved into
place only when complete, so a failure or an interrupt leaves nothing half-written; DIR's
manifest :data:`MARKER` lists the files the report made with their hashes, ``force=True``
replaces exactly those (while unchanged), and nothing else in DIR is ever deleted or
overwritten.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TextIO

from .._support.outputs import MANIFEST, OutputError
from .._support.report import build_report, write_tables
from .study import STEPS, StudyResults, run_study
from .figures import FIGURES, write_figures
from .html import render_index
from .tables import all_tables

__all__ = ["reproduce", "ReportError", "MARKER", "report_files", "DEFAULT_OUT"]

MARKER = MANIFEST
DEFAULT_OUT = "viscontact-report"
_TABLE_STEMS = ("table1", "table2", "table4", "comparison")


ReportError = OutputError  # the report cannot be written where asked (the message says why)


def report_files() -> list[str]:
    """Names of the files a report consists of (the marker excluded)."""
    return ([f"{s}.{ext}" for s in _TABLE_STEMS for ext in ("csv", "md")] + list(FIGURES)
            + ["index.html"])


def _write_all(res: StudyResults, tmp: Path, step: Callable[[str, int], None]) -> list[str]:
    from .._version import __version__

    step("tables (CSV and Markdown)", 1)
    tables = all_tables(res)
    write_tables(tables, tmp)
    write_figures(res, tmp, tick=lambda name: step(f"figure {name} done", 1))
    step("index.html", 1)
    (tmp / "index.html").write_text(render_index(res, tables, __version__), encoding="utf-8")
    files = report_files()
    missing = [f for f in files if not (tmp / f).is_file()]
    if missing:  # pragma: no cover - a bug, never user input
        raise RuntimeError(f"report incomplete: {missing}")
    return files


def reproduce(out: str | os.PathLike = DEFAULT_OUT, *, force: bool = False,
              progress: TextIO | None = sys.stderr) -> Path:
    """Compute every table and figure of the study and write the report into ``out``.

    ``progress``: stream for step names (None: silent).  Raises :class:`ReportError`
    (a ValueError) when ``out`` holds an earlier report and ``force`` is False, when it holds
    other files with the report's names, or when it cannot be written; nothing is left
    behind in that case.  Returns the report directory.
    """
    weights = dict(STEPS)
    return build_report(
        out, "reproduce", force=force, expected=report_files(),
        compute=lambda step: run_study(lambda name: step(name, weights[name])),
        write=_write_all, progress=progress, total=sum(weights.values()) + len(FIGURES) + 2,
        bar_format="{desc:<44} {bar} {n_fmt}/{total_fmt} [{elapsed}]")
