"""``viscontact reproduce``: compute the study, write the report atomically.

The report is written into a temporary sibling of DIR and moved into place only when it is
complete, so a failure or an interrupt leaves nothing half-written.  DIR is marked by the
file :data:`MARKER`, which lists the files the report made: ``force=True`` replaces exactly
those, and nothing else in DIR is ever deleted or overwritten.
"""

from __future__ import annotations

import json
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import TextIO

from ..study import STEPS, StudyResults, run_study
from .figures import FIGURES, write_figures
from .html import render_index
from .tables import all_tables

__all__ = ["reproduce", "ReportError", "MARKER", "report_files", "DEFAULT_OUT"]

MARKER = ".viscontact-report"
DEFAULT_OUT = "viscontact-report"
_TABLE_STEMS = ("table1", "table2", "table4", "comparison")


class ReportError(ValueError):
    """The report cannot be written where asked (message says why and what to do)."""


def report_files() -> list[str]:
    """Names of the files a report consists of (the marker excluded)."""
    return ([f"{s}.{ext}" for s in _TABLE_STEMS for ext in ("csv", "md")] + list(FIGURES)
            + ["index.html"])


class _Progress:
    """Step names on stderr: a tqdm bar on a terminal, one line per step otherwise."""

    def __init__(self, total: int, stream: TextIO | None):
        self.stream = stream
        self.bar = None
        self.i = 0
        self.total = total
        self.t0 = time.perf_counter()
        if stream is not None and stream.isatty():
            from tqdm import tqdm

            width = min(shutil.get_terminal_size((100, 20)).columns, 110)
            self.bar = tqdm(total=total, file=stream, unit="step", leave=True, ncols=width,
                            bar_format="{desc:<44} {bar} {n_fmt}/{total_fmt} [{elapsed}]")

    def __call__(self, name: str, weight: int = 1) -> None:
        if self.bar is not None:
            if self.i:
                self.bar.update(self._last)
            self.bar.set_description_str(name)
        elif self.stream is not None:
            print(f"viscontact reproduce: [{time.perf_counter() - self.t0:5.1f} s] {name}",
                  file=self.stream, flush=True)
        self.i += 1
        self._last = weight

    def close(self) -> None:
        if self.bar is not None:
            self.bar.set_description_str("done")
            self.bar.update(self.total - self.bar.n)
            self.bar.close()


def _read_manifest(out: Path) -> list[str] | None:
    """Files listed in DIR's marker, or None if DIR holds no report."""
    marker = out / MARKER
    if not marker.exists():
        return None
    try:
        files = json.loads(marker.read_text(encoding="utf-8")).get("files", [])
        return [f for f in files if isinstance(f, str) and "/" not in f and f not in ("", ".", "..")]
    except (OSError, ValueError, AttributeError):
        return []


def _check_target(out: Path, force: bool) -> list[str]:
    """Refuse what must not be overwritten; return the old report's files (to replace)."""
    if out.exists() and not out.is_dir():
        raise ReportError(f"{out} exists and is not a directory; choose another --out")
    if not out.exists():
        return []
    old = _read_manifest(out)
    if old is not None and not force:
        raise ReportError(f"{out} already holds a report; use --force to replace it "
                          "(only the report's own files are replaced)")
    ours = set(old or [])
    foreign = sorted(f for f in report_files() if (out / f).exists() and f not in ours)
    if foreign:
        raise ReportError(
            f"{out} already has {', '.join(foreign[:4])}{' ...' if len(foreign) > 4 else ''} "
            "not written by viscontact reproduce; they are never overwritten: choose another --out")
    return old or []


def _make_dirs(path: Path) -> list[Path]:
    """mkdir -p, returning the directories created (deepest last)."""
    missing = []
    p = path
    while not p.exists():
        missing.append(p)
        if p.parent == p:
            break
        p = p.parent
    for d in reversed(missing):
        d.mkdir()
    return list(reversed(missing))


def _probe_writable(d: Path) -> None:
    fd, name = tempfile.mkstemp(prefix=".viscontact-probe-", dir=d)
    os.close(fd)
    os.unlink(name)


def _write_all(res: StudyResults, tmp: Path, step: Callable[[str, int], None]) -> list[str]:
    from .. import __version__

    step("tables (CSV and Markdown)", 1)
    tables = all_tables(res)
    for t in tables:
        (tmp / f"{t.stem}.csv").write_text(t.to_csv(), encoding="utf-8")
        (tmp / f"{t.stem}.md").write_text(t.to_markdown(), encoding="utf-8")
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
    from .. import __version__

    if not str(out).strip():
        raise ReportError("--out must name a directory")
    out = Path(out)
    old_files = _check_target(out, force)
    created: list[Path] = []
    tmp: Path | None = None
    try:
        try:
            created = _make_dirs(out.parent)
            if out.exists():
                _probe_writable(out)
            tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-", dir=out.parent))
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o777 & ~umask)  # mkdtemp makes it private; a report is not
        except OSError as exc:
            raise ReportError(f"cannot write the report to {out}: "
                              f"{exc.strerror or exc}") from None
        total = sum(w for _, w in STEPS) + len(FIGURES) + 2
        step = _Progress(total, progress)
        weights = dict(STEPS)
        res = run_study(lambda name: step(name, weights[name]))
        files = _write_all(res, tmp, step)
        (tmp / MARKER).write_text(json.dumps(
            {"tool": "viscontact reproduce", "version": __version__, "files": files}, indent=1)
            + "\n", encoding="utf-8")
        step.close()
        _install(tmp, out, files, old_files)
        tmp = None
        created = []
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        for d in reversed(created):
            try:
                d.rmdir()
            except OSError:
                pass
    return out


def _install(tmp: Path, out: Path, files: list[str], old_files: list[str]) -> None:
    """Move the finished report into ``out`` (a rename when ``out`` does not exist yet)."""
    if not out.exists():
        os.rename(tmp, out)
        return
    for f in old_files:
        if f not in files and (out / f).is_file():
            (out / f).unlink()
    for f in files + [MARKER]:
        os.replace(tmp / f, out / f)
    tmp.rmdir()
