"""``viscontact dem-study``: the many-particle DEM study (bouncing ball, cooling gas, column
collapse) with its report page."""

from __future__ import annotations

import argparse
import sys

from ..physics.domain import NP_MAX
from .common import add_force_option, report_written


def _dem_study(args: argparse.Namespace) -> int:
    import time

    from ..demstudy.engine import LammpsError
    from ..demstudy.report import dem_study
    from . import UserError

    t0 = time.perf_counter()
    try:
        out = dem_study(args.out, quick=args.quick, np_=args.np, force=args.force,
                        progress=None if args.quiet else sys.stderr, jobs=args.jobs)
    except LammpsError as exc:  # no plugin, no LAMMPS, or LAMMPS stopped: one line
        raise UserError(str(exc).splitlines()[0] if str(exc) else "LAMMPS failed") from None
    if not args.quiet:
        report_written(out, time.perf_counter() - t0, digits=0)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "dem-study", help="DEM study with LAMMPS: bouncing ball, cooling gas, column collapse",
        description="Run three DEM studies with LAMMPS and the viscontact plugin, every law "
        "calibrated exactly to the same e: a lacrosse ball bouncing to rest (against the exact "
        "sequence of single collisions), a freely cooling granular gas (against Haff's law and "
        "the kinetic theory of each law's exact e(v)) and the collapse of a granular column "
        "(run-out and final height at several aspect ratios against the published scaling, "
        "each law's difference from KK with a 95 % interval over several seeds); write "
        "tables, figures, dumps and index.html into DIR.")
    p.add_argument("--out", default="viscontact-dem-study", metavar="DIR",
                   help="report directory (default: viscontact-dem-study)")
    p.add_argument("--np", type=int, default=1, metavar="N",
                   help=f"MPI ranks for the gas and the collapse (mpirun -np N on this machine), "
                   f"a whole number in [1, {NP_MAX}] (default 1)")
    p.add_argument("--jobs", type=int, default=None, metavar="J",
                   help=f"independent LAMMPS runs at a time (the laws, seeds, aspect ratios and "
                   f"parts of the study), a whole number in [1, {NP_MAX}] (default: the cores "
                   f"this process may use divided by --np; the report is the same for any J)")
    p.add_argument("--quick", action="store_true",
                   help="small systems and short runs (a few minutes on two cores)")
    add_force_option(p, "the report in DIR (only its own, unchanged files)")
    p.add_argument("--no-progress", "--quiet", dest="quiet", action="store_true",
                   help="no progress on stderr (--quiet: the same)")
    p.set_defaults(handler=_dem_study)
