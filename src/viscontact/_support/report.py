"""The one report builder of ``reproduce`` and ``dem-study``.

A report is a directory of tables (CSV at full precision in SI, and Markdown), figures and one
``index.html``, written into a staging directory and moved into place only when complete
(:class:`viscontact._support.outputs.OutputDir`).  :func:`build_report` runs the steps of one
report with the progress reporter; :class:`Table` holds raw values plus how to print them, so
the CSV, the Markdown and the HTML come from one place; ``PAGE_CSS`` styles every page.
"""

from __future__ import annotations

import csv
import html
import io
import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO, TypeVar

from .outputs import OutputDir
from .progress import Progress

__all__ = ["Column", "Table", "PAGE_CSS", "build_report", "write_tables", "fixed", "sig", "text",
           "scaled"]

R = TypeVar("R")

Fmt = Callable[[Any], str]


def missing(x: Any) -> bool:
    """No value to print: None, or a float that is not finite."""
    return x is None or (isinstance(x, float) and not math.isfinite(x))


def fixed(n: int) -> Fmt:
    return lambda x: "" if missing(x) else f"{x:.{n}f}"


def sig(n: int) -> Fmt:
    return lambda x: "" if missing(x) else f"{x:.{n}g}"


def text(x: Any) -> str:
    return "" if x is None else str(x)


def scaled(factor: float, n: int) -> Fmt:
    return lambda x: "" if x is None else f"{x * factor:.{n}f}"


@dataclass
class Column:
    """One column: CSV header and printer (machine, SI), Markdown/HTML header and printer."""

    csv_head: str
    csv_fmt: Fmt
    head: str
    fmt: Fmt

    @property
    def is_text(self) -> bool:
        return self.fmt is text


@dataclass
class Table:
    """A table: file stem, title, caption, columns and rows of raw values."""

    stem: str
    title: str
    caption: str
    columns: Sequence[Column]
    rows: list[list[Any]]

    def to_csv(self) -> str:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow([c.csv_head for c in self.columns])
        for row in self.rows:
            w.writerow([c.csv_fmt(x) for c, x in zip(self.columns, row)])
        return buf.getvalue()

    def to_markdown(self) -> str:
        lines = [f"**{self.title}.** {self.caption}", "",
                 "| " + " | ".join(c.head for c in self.columns) + " |",
                 "|" + "|".join("---" if c.is_text else "---:" for c in self.columns) + "|"]
        for row in self.rows:
            lines.append("| " + " | ".join(c.fmt(x) for c, x in zip(self.columns, row)) + " |")
        return "\n".join(lines) + "\n"

    def to_html(self) -> str:
        e = html.escape
        out = [f'<table id="{e(self.stem)}">',
               f"<caption><b>{e(self.title)}.</b> {e(self.caption)}</caption>", "<thead><tr>"]
        out += [f"<th>{e(c.head)}</th>" for c in self.columns]
        out.append("</tr></thead><tbody>")
        for row in self.rows:
            out.append("<tr>" + "".join(
                f'<td class="{"t" if c.is_text else "n"}">{e(c.fmt(x))}</td>'
                for c, x in zip(self.columns, row)) + "</tr>")
        out.append("</tbody></table>")
        return "\n".join(out)


#: the style of every report page (reproduce, dem-study)
PAGE_CSS = """
body { font-family: system-ui, sans-serif; max-width: 1250px; margin: 2em auto; padding: 0 1em;
       color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; } h2 { margin-top: 2em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }
caption { caption-side: top; text-align: left; padding-bottom: 0.4em; max-width: 60em; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.6em; }
th { background: #f2f2f2; } td.n { text-align: right; font-variant-numeric: tabular-nums; }
tbody tr:nth-child(even) { background: #fafafa; }
figure { margin: 1.5em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.95em; margin-top: 0.3em; }
.note { background: #f6f8fa; border-left: 4px solid #888; padding: 0.6em 1em; }
"""




def write_tables(tables: Sequence[Table], directory: Path) -> None:
    """Each table as ``<stem>.csv`` and ``<stem>.md`` in ``directory``."""
    for t in tables:
        (directory / f"{t.stem}.csv").write_text(t.to_csv(), encoding="utf-8")
        (directory / f"{t.stem}.md").write_text(t.to_markdown(), encoding="utf-8")


def build_report(out: str | os.PathLike, command: str, *, force: bool, expected: list[str],
                 compute: Callable[[Callable[..., None]], R],
                 write: Callable[[R, Path, Callable[..., None]], list[str]],
                 progress: TextIO | None, total: int | None = None,
                 bar_format: str | None = None) -> Path:
    """Compute a report's results and write its files into ``out``.

    ``compute(step)`` returns the results; ``write(results, staging, step)`` writes every file
    into the staging directory and returns their names; both call ``step(name[, weight])`` as
    each step begins (the bar on a terminal, one log line per step otherwise, nothing with
    ``progress=None``).  ``out`` is refused (:class:`~viscontact._support.outputs.OutputError`)
    when it holds an earlier report and ``force`` is False or files that are not the report's;
    nothing is left behind on failure.  Returns ``out``.
    """
    out_dir = OutputDir(out, command, force, expected=expected)
    with out_dir:
        bar = Progress(total, stream=progress, log=f"viscontact {command}",
                       bar_format=bar_format)
        results = compute(bar.step)
        write(results, out_dir.staging, bar.step)
        bar.close("done")
    return Path(out)
