"""``viscontact dem-study``: run the three DEM studies and write their report.

The report is built in a temporary sibling of DIR and moved into place whole, with the same
rules as ``viscontact reproduce`` (:mod:`viscontact._support.report`): DIR is marked by a file
listing what the report wrote; ``force`` replaces exactly those files; nothing else in DIR
is ever touched.  LAMMPS works in a scratch directory that is removed at the end; the report
keeps the dumps (LAMMPS text dumps, which OVITO and ParaView open), the inputs and the
contact lines of every law, so that any run can be repeated with ``lmp`` alone.
"""

from __future__ import annotations

import json
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path
from typing import TextIO

from ..physics import domain
from ..dem.run import stop_on_signals
from .._support.report import build_report, write_tables
from . import bounce as bounce_mod
from . import flow as flow_mod
from . import gas as gas_mod
from . import jobs as jobs_mod
from .page import _results_json, render_index
from .results import (
    DEFAULT_OUT, FIGURES, FULL, INPUTS, QUICK, TABLES, Results, StudyConfig, report_files,
)
from .tables import all_tables

__all__ = ["dem_study", "run_all", "StudyConfig", "Results", "QUICK", "FULL", "DEFAULT_OUT",
           "INPUTS", "FIGURES", "TABLES", "report_files"]

def run_all(cfg: StudyConfig, work: Path, np_: int, step, jobs: int = 1) -> Results:
    """The bounces, the gas and the collapse; up to ``jobs`` LAMMPS runs at a time (each of
    ``np_`` ranks).  ``seconds`` holds each part's wall time (they overlap when jobs > 1)."""
    res = Results(cfg, np_=np_)

    def timed(name: str, fn):
        def run():
            t = time.perf_counter()
            out = fn()
            res.seconds[name] = time.perf_counter() - t
            return out
        return run

    # the gas (the longest chains: thermalise, then cool) gets free slots first, the short
    # bounce runs last, where they fill the end
    with jobs_mod.concurrent(jobs), stop_on_signals():
        res.bounces, res.gas, res.flow = jobs_mod.run_each(
            jobs_mod.first(2, timed("bounce", lambda: bounce_mod.run_bounces(
                work / "bounce", balls=cfg.balls, models=cfg.models, step=step))),
            jobs_mod.first(0, timed("gas", lambda: gas_mod.run_gas(
                work / "gas", cfg.gas, models=cfg.models, np_=np_, step=step, haff=cfg.haff))),
            jobs_mod.first(1, timed("flow", lambda: flow_mod.run_flow(
                work / "flow", cfg.flow, models=cfg.models, np_=np_, step=step))))
    res.seconds = {k: res.seconds[k] for k in ("bounce", "gas", "flow")}
    return res


def _write_all(res: Results, tmp: Path, work: Path, step, jobs: int = 1) -> list[str]:
    from .._version import __version__
    from .engine import backend, input_path
    from .figures import write_figures

    step("tables (CSV and Markdown)")
    tables = all_tables(res)
    write_tables(tables, tmp)
    write_figures(res, tmp, tick=step, jobs=jobs)
    for name in INPUTS:
        shutil.copyfile(input_path(name), tmp / name)
    g, f = res.gas, res.flow
    for m, r in g.runs.items():
        shutil.copyfile(r.dump, tmp / f"gas-{m}.dump")
        shutil.copyfile(r.dump.parent / "coeffs.lmp", tmp / f"coeffs-gas-{m}.lmp")
    for r in f.runs:
        if r.seed == f.setup.seeds[0]:
            shutil.copyfile(r.dump, tmp / f"collapse-{r.model}-seed{r.seed}.dump")
            shutil.copyfile(r.dump.parent / "coeffs.lmp", tmp / f"coeffs-collapse-{r.model}.lmp")
    for c in res.bounces:
        shutil.copyfile(work / "bounce" / f"bounce-{c.ball}-{c.model}" / "coeffs.lmp",
                        tmp / f"coeffs-bounce-{c.ball}-{c.model}.lmp")
    (tmp / "results.json").write_text(json.dumps(_results_json(res), indent=1) + "\n",
                                      encoding="utf-8")
    step("index.html")
    (tmp / "index.html").write_text(render_index(res, tables, __version__, backend()),
                                    encoding="utf-8")
    files = report_files(res.cfg)
    missing = [x for x in files if not (tmp / x).is_file()]
    if missing:  # pragma: no cover - a bug, never user input
        raise RuntimeError(f"report incomplete: {missing}")
    return files


def dem_study(out: str | os.PathLike = DEFAULT_OUT, *, quick: bool = False, np_: int = 1,
              force: bool = False, progress: TextIO | None = sys.stderr,
              config: StudyConfig | None = None, jobs: int | None = None) -> Path:
    """Run the bouncing ball, the cooling gas and the column collapse; write the report.

    ``quick``: small systems and short runs (minutes); ``np_``: MPI ranks for the gas and the
    collapse (``mpirun -np``); ``jobs``: independent LAMMPS runs at a time (None: as many as
    fill the cores, :func:`viscontact.demstudy.jobs.default_jobs`); the report is the same
    for any ``jobs``.  Raises :class:`viscontact._support.outputs.OutputError` (a ValueError) when ``out`` holds
    an earlier report and ``force`` is False, when it holds other files with the report's
    names, or when it cannot be written; nothing is left behind in that case.
    """
    domain.check_int("--np (number of MPI ranks)", np_, 1, domain.NP_MAX)
    if jobs is None:
        jobs = jobs_mod.default_jobs(np_)
    domain.check_int("--jobs (LAMMPS runs at a time)", jobs, 1, domain.NP_MAX)
    cfg = config or (QUICK if quick else FULL)
    from .engine import backend

    def compute(step):
        backend()  # the plugin builds (or LammpsError says what to install) before any work
        return run_all(cfg, work, np_, step, jobs)

    work = Path(tempfile.mkdtemp(prefix="viscontact-dem-study-"))
    try:
        return build_report(out, "dem-study", force=force, expected=report_files(cfg),
                            compute=compute,
                            write=lambda res, staging, step: _write_all(res, staging, work, step,
                                                                        jobs),
                            progress=progress)
    finally:
        shutil.rmtree(work, ignore_errors=True)
