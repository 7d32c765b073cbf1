"""What the mesh-wall studies (scripts/mesh_drum_study.py, scripts/mesh_silo_study.py) share:
a working copy of the shipped examples with a mesh written by ``viscontact.dem.stl``, one run
of an example input with a progress line, Welch's test and the protected ``--out`` directory
(docs/fix_viscontact_mesh.md shows the tables)."""

from __future__ import annotations

import argparse
import contextlib
import io
import math
import shutil
import sys
import time
from pathlib import Path

from viscontact import dem
from viscontact._support.outputs import OutputDir, OutputError
from viscontact.dem import stl

EXAMPLES = Path(dem.__file__).parent / "examples"


def add_common(ap: argparse.ArgumentParser, default_out: str) -> None:
    """--out DIR, --force, --var NAME VALUE, --np."""
    ap.add_argument("--out", default=default_out, metavar="DIR",
                    help=f"directory for the table, the per-run figures and the dumps (default "
                    f"{default_out}; an existing one only with --force, and only if this script "
                    "wrote it)")
    ap.add_argument("--force", action="store_true", help="replace this script's earlier --out")
    ap.add_argument("--var", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"),
                    help="a LAMMPS index variable for every run (repeatable), e.g. --var steps 100000")
    ap.add_argument("--np", type=int, default=1, help="MPI ranks per run (default 1)")


def open_out(args: argparse.Namespace, command: str, names: list[str]) -> OutputDir:
    """The --out directory, checked before any run (exit 2 with one line if refused)."""
    try:
        return OutputDir(args.out, command, args.force, expected=names)
    except OutputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        raise SystemExit(2) from None


def workdir(tmp: Path) -> Path:
    """A copy of the shipped examples under ``tmp``."""
    d = tmp / "examples"
    shutil.copytree(EXAMPLES, d)
    return d


def write_mesh(d: Path, shape: str, name: str, **opts: float) -> Path:
    """The STL file ``d/name`` of ``stl.SHAPE(**opts)`` (as ``python3 -m viscontact.dem.stl``)."""
    words = [shape, str(d / name), "--force"]
    for k, v in opts.items():
        words += [f"--{k}", repr(v)]
    with contextlib.redirect_stdout(io.StringIO()):   # its "N triangles" line
        ok = stl.main(words) == 0
    if not ok:
        raise SystemExit(f"error: could not write {name}")
    return d / name


def run(d: Path, name: str, label: str, np_: int, variables: dict) -> dem.RunResult:
    """One run of ``d/in.NAME``, with a progress line (label, seconds) on stderr."""
    t0 = time.perf_counter()
    print(f"  {label} ...", end="", file=sys.stderr, flush=True)
    res = dem.run_input(d / f"in.{name}", np=np_, progress=False, quiet=True, force=True,
                        variables=variables)
    print(f" {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
    return res


def welch(a: list[float], b: list[float]) -> tuple[float, float, float]:
    """Welch's t, its degrees of freedom (Welch-Satterthwaite) and the two-sided p for the
    difference of the means of two samples of unequal variance."""
    from scipy import stats

    res = stats.ttest_ind(a, b, equal_var=False)
    va, vb = _var_mean(a), _var_mean(b)
    dof = (va + vb) ** 2 / (va ** 2 / (len(a) - 1) + vb ** 2 / (len(b) - 1))
    return float(res.statistic), dof, float(res.pvalue)


def _var_mean(x: list[float]) -> float:
    """The squared standard error of the mean of ``x``."""
    m = sum(x) / len(x)
    return sum((v - m) ** 2 for v in x) / (len(x) - 1) / len(x)


def mean_se(x: list[float]) -> tuple[float, float]:
    """Mean and standard error of the mean (sample standard deviation / sqrt(n))."""
    return sum(x) / len(x), math.sqrt(_var_mean(x))
