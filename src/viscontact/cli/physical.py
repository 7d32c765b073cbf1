"""Commands in physical units: ``sweep`` and ``reproduce``; the physical form of ``calibrate``.

All options are SI (kg, m, m/s, Pa, N/m^1.5, s) unless a ball from the drop tests is named
with ``--ball``, which fills in its measured mass, radius, k_Hertz, impact speed, e and beta
(any option given explicitly overrides the ball's value).
"""

from __future__ import annotations

import argparse
import csv
import io
import os
import sys
from typing import Any

import numpy as np

from ..physics.pair import check_positive, contact_pair, drop_speed
from ..paper.experiment import PhysicalCalibration, ball, calibrate_physical, load_balls
from ..physics.laws import STUDY_MODELS, lookup
from ..collision.sweep import SWEEP_FIELDS, velocity_sweep
from .._support import outputs
from .common import (add_force_option, add_model_options, finite_json, note, print_json,
                     report_written)
from ..physics.domain import range_text as _R
from ..physics.laws import Jian, Power

_PHYSICAL = ("ball", "mass", "radius", "k_hertz", "modulus", "poisson", "mass2", "radius2",
             "modulus2", "poisson2", "v", "drop_height")


def add_physical_options(p: argparse.ArgumentParser) -> None:
    """Particle properties, impact speed and the ball shortcut."""
    g = p.add_argument_group("physical properties (SI units)")
    g.add_argument("--ball", metavar="NAME",
                   help=f"use a ball of the drop tests: {', '.join(load_balls())} "
                   "(mass, radius, k_Hertz, v, e, beta; explicit options override)")
    g.add_argument("--mass", type=float, metavar="KG", help=f"mass of the particle, in {_R('mass')}")
    g.add_argument("--radius", type=float, metavar="M", help=f"radius of the particle, in {_R('radius')}")
    g.add_argument("--k-hertz", dest="k_hertz", type=float, metavar="N/M^1.5",
                   help=f"Hertz stiffness k_Hertz, in {_R('k_hertz')} (or give --E and --nu with --radius)")
    g.add_argument("--E", "--modulus", dest="modulus", type=float, metavar="PA",
                   help=f"Young's modulus, in {_R('modulus')}")
    g.add_argument("--nu", "--poisson", dest="poisson", type=float, metavar="NU",
                   help=f"Poisson ratio, in {_R('poisson')}")
    g.add_argument("--mass2", type=float, metavar="KG",
                   help=f"mass of the second sphere, in {_R('mass')} (default: a fixed wall)")
    g.add_argument("--radius2", type=float, metavar="M",
                   help=f"radius of the second sphere, in {_R('radius')} (default: a flat wall)")
    g.add_argument("--E2", "--modulus2", dest="modulus2", type=float, metavar="PA",
                   help=f"Young's modulus of the second body, in {_R('modulus')} (default: rigid)")
    g.add_argument("--nu2", "--poisson2", dest="poisson2", type=float, metavar="NU",
                   help="Poisson ratio of the second body (with --E2)")
    g.add_argument("--v", type=float, metavar="M/S", help=f"impact speed, in {_R('v')}")
    g.add_argument("--drop-height", dest="drop_height", type=float, metavar="M",
                   help=f"drop height, in {_R('drop_height')}, instead of --v (v = sqrt(2 g h), g = 9.81 m/s^2)")


def has_physical(args: argparse.Namespace) -> bool:
    return any(getattr(args, k, None) is not None for k in _PHYSICAL)


def check_beta_applies(model: str | None, beta: float | None) -> None:
    """Refuse an explicit --beta for a law without a relaxation time (it would be ignored)."""
    if model is not None and beta is not None and not lookup(model).needs_beta:
        raise ValueError(f"--beta only applies to a law with a relaxation time (Jian); "
                         f"{lookup(model).name} has none")


def _contact(args: argparse.Namespace) -> tuple[float, float, float | None, Any]:
    """(m*, k_Hertz, v or None, ball or None) from the options."""
    if args.k_hertz is not None:
        unused = [f for f, v in (("--radius", args.radius), ("--radius2", args.radius2),
                                 ("--nu2", args.poisson2)) if v is not None]
        if unused:
            raise ValueError(f"{', '.join(unused)} only serve to compute k_Hertz from --E and "
                             "--nu; with --k-hertz they would be ignored")
    if args.poisson2 is not None and args.modulus2 is None:
        raise ValueError("--nu2 goes with --E2 (the second body's elastic constants)")
    b = ball(args.ball) if args.ball is not None else None
    mass = args.mass if args.mass is not None else (b.mass if b else None)
    radius = args.radius if args.radius is not None else (b.radius if b else None)
    k = args.k_hertz
    if k is None and args.modulus is None and b is not None:
        k = b.k_hertz
    if mass is None:
        raise ValueError("give --mass (kg) or --ball")
    if k is None and args.modulus is None and args.poisson is None:
        raise ValueError("give --k-hertz, or --E and --nu with --radius (or --ball)")
    pair = contact_pair(mass, radius=radius, k_hertz=k, modulus=args.modulus,
                        poisson=args.poisson, mass2=args.mass2, radius2=args.radius2,
                        modulus2=args.modulus2, poisson2=args.poisson2)
    if args.v is not None and args.drop_height is not None:
        raise ValueError("give --v or --drop-height, not both")
    if args.v is not None:
        v = check_positive("impact speed --v", args.v)
    elif args.drop_height is not None:
        v = drop_speed(args.drop_height)
    else:
        v = b.v_in if b else None
    return pair.m_eff, pair.k_hertz, v, b


def _models(args: argparse.Namespace, beta: float | None) -> list[str]:
    """--law, or every study law (Jian only when beta is known)."""
    if args.model is not None:
        return [lookup(args.model).name]
    models = list(STUDY_MODELS)
    if beta is None:
        models.remove(Jian.name)
        note("note: Jian skipped (give --beta, or --law Jian --beta B)")
    return models


def _calibrations(args: argparse.Namespace) -> tuple[list[PhysicalCalibration], Any]:
    m_eff, k, v, b = _contact(args)
    if v is None:
        raise ValueError("give the impact speed: --v (m/s) or --drop-height (m)")
    e = args.e if args.e is not None else (b.e if b else None)
    if e is None:
        raise ValueError("give the measured restitution coefficient --e")
    check_beta_applies(args.model, args.beta)
    beta = args.beta if args.beta is not None else (b.beta if b else None)
    cals = []
    for m in _models(args, beta):
        needs = lookup(m).needs_beta
        if needs and beta is None:
            raise ValueError("model Jian needs --beta (relaxation time / T)")
        cals.append(calibrate_physical(m, e, m_eff=m_eff, k_hertz=k, v=v,
                                       beta=beta if needs else None, p=args.p, end=args.end))
    return cals, b


def _fmt(x: float | None, spec: str) -> str:
    width = int("".join(ch for ch in spec.split(".")[0] if ch.isdigit()) or 0)
    return f"{'-':>{width}}" if x is None else format(x, spec)


def calibrate_physical_cmd(args: argparse.Namespace) -> int:
    """``viscontact calibrate`` with physical options: alpha, T, c and tau per law."""
    cals, b = _calibrations(args)
    c0 = cals[0]
    if args.json:
        print_json({"ball": b.key if b else None, "m_eff": c0.m_eff, "k_hertz": c0.k_hertz,
                    "v": c0.v, "T": c0.T, "e": c0.e, "end": c0.end,
                    "laws": [c.to_dict() for c in cals]})
        return 0
    src = f"{b.key} ({b.name}), " if b else ""
    print(f"{src}m* = {c0.m_eff:.6g} kg, k_Hertz = {c0.k_hertz:.6g} N/m^1.5, "
          f"v_i = {c0.v:.6g} m/s, e = {c0.e:g}, zero-{c0.end} end")
    print(f"time scale T = {c0.T * 1e3:.6g} ms")
    print(f"{'law':<6} {'alpha':>12} {'beta':>7} {'tau [ms]':>10} {'c':>13}  unit of c")
    for c in cals:
        name = c.model + (f" p={c.p:g}" if c.model == Power.name else "")
        print(f"{name:<6} {c.alpha:>12.8g} {_fmt(c.beta, '>7.4g')} "
              f"{_fmt(None if c.tau is None else c.tau * 1e3, '>10.6g')} {c.c:>13.7g}  {c.c_unit}")
    return 0


def _speeds(args: argparse.Namespace) -> np.ndarray:
    if args.speeds is not None:
        if args.v_min is not None or args.v_max is not None or args.num is not None:
            raise ValueError("give --speeds or --v-min/--v-max/--num, not both")
        v = np.array(args.speeds, dtype=float)
    else:
        lo = 0.30 if args.v_min is None else args.v_min
        hi = 2.60 if args.v_max is None else args.v_max
        num = 24 if args.num is None else args.num
        check_positive("--v-min", lo)
        check_positive("--v-max", hi)
        if hi < lo:
            raise ValueError(f"--v-max ({hi:g}) is below --v-min ({lo:g})")
        if not 1 <= num <= 10000:
            raise ValueError(f"--num must be between 1 and 10000, got {num}")
        if num == 1 and hi != lo:
            raise ValueError("--num 1 gives one speed: give --speeds V (or --num 2 or more)")
        v = np.linspace(lo, hi, num)
    for x in v:
        check_positive("impact speed", x)
    return v


def _sweep_outputs(args: argparse.Namespace) -> list[tuple[str, str]]:
    """(path, kind) of each output, checked before any work ('-': stdout)."""
    if args.json not in (None, "-"):
        note("note: --json FILE is deprecated; use --json-out FILE (--json alone prints on stdout)")
    outs = [(path, kind) for path, kind in ((args.csv, "csv"), (args.json, "json"),
                                            (args.json_out, "json"), (args.plot, "plot"))
            if path is not None]
    if [p for p, _ in outs].count("-") > 1:
        raise ValueError("only one of --csv -, --json and --json-out - can go to stdout")
    files = [os.path.abspath(p) for p, k in outs if p != "-"]
    if len(set(files)) < len(files):
        raise ValueError("--csv, --json-out and --plot must name different files")
    for path, kind in outs:
        if kind == "plot" or path != "-":
            outputs.check_file(path, "sweep", args.force, _flag(kind),
                               ".png" if kind == "plot" else None)
    if args.force and not files:
        raise ValueError("--force only goes with --csv FILE, --json-out FILE or --plot FILE")
    return outs or [("-", "csv")]


def _flag(kind: str) -> str:
    """The option that names a file of this kind (for messages)."""
    return "--json-out" if kind == "json" else f"--{kind}"


def _sweep(args: argparse.Namespace) -> int:
    outs = _sweep_outputs(args)
    speeds = _speeds(args)
    if args.c is not None:
        if args.model is None:
            raise ValueError("--c needs --law (c's unit depends on the law)")
        if args.e is not None:
            raise ValueError("give --c (and --tau) or --e to calibrate, not both")
        if args.beta is not None:
            raise ValueError("--beta goes with --e (calibration); with --c give --tau [s]")
        if args.v is not None or args.drop_height is not None:
            raise ValueError("--v/--drop-height give the speed of a calibration (with --e); with "
                             "--c the speeds are --speeds or --v-min/--v-max/--num")
        m_eff, k, _v, b = _contact(args)
        setups = [(lookup(args.model).name, args.c, args.tau)]
        measured = None
    else:
        if args.tau is not None:
            raise ValueError("--tau goes with --c; with --e give --beta instead")
        cals, b = _calibrations(args)
        m_eff, k = cals[0].m_eff, cals[0].k_hertz
        setups = [(c.model, c.c, c.tau) for c in cals]
        measured = (b.v_in, b.e, b.tc) if b is not None else None
    results = [velocity_sweep(m, speeds, m_eff=m_eff, k_hertz=k, c=c, tau=tau, p=args.p,
                              end=args.end) for m, c, tau in setups]
    for path, kind in outs:
        if kind == "plot":
            from ..collision.plots import plot_sweeps

            title = ("Velocity sweep" + (f", {b.key}" if b else "")
                     + ": m*, k_Hertz, c and tau held fixed")
            outputs.write_png(path, "sweep", args.force, "--plot",
                              lambda tmp: plot_sweeps(results, tmp, title, measured))
            note(f"plot written to {path}")
            continue
        doc = finite_json({"sweeps": [r.to_dict() for r in results]})
        if path == "-":
            if kind == "csv":
                sys.stdout.write(_sweep_csv(results))
            else:
                print_json(doc)
        elif kind == "csv":
            outputs.write_text(path, "sweep", args.force, "--csv", _sweep_csv(results))
            note(f"CSV written to {path}")
        else:
            outputs.write_json(path, "sweep", args.force, "--json-out", doc)
            note(f"JSON written to {path}")
    return 0


def _sweep_csv(results) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["model"] + [f"{n} [{u}]" if u != "1" else n for n, u in SWEEP_FIELDS])
    for r in results:
        for row in r.rows():
            w.writerow([row["model"]] + ["" if row[n] is None else repr(row[n])
                                         for n, _ in SWEEP_FIELDS])
    return buf.getvalue()


def _reproduce(args: argparse.Namespace) -> int:
    import time

    from ..paper.report import reproduce

    t0 = time.perf_counter()
    out = reproduce(args.out, force=args.force, progress=None if args.quiet else sys.stderr)
    if not args.quiet:
        report_written(out, time.perf_counter() - t0)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "sweep", help="e, t_c, F_max against impact speed with physical constants held fixed",
        description="Velocity sweep: hold m*, k_Hertz, c (and tau) fixed and vary the impact "
        "speed. Either give --law with --c (and --tau for Jian), or calibrate at --v from a "
        "measured --e (every law unless --law), or name a --ball.")
    add_model_options(p, required=False, model_help=" (default: every law of the study)")
    add_physical_options(p)
    d = p.add_argument_group("damping")
    d.add_argument("--c", type=float, help="physical damping prefactor c [N s/m^(1+p)] (with --law; it must give "
                   f"alpha in {_R('alpha')} at every speed)")
    d.add_argument("--tau", type=float, help=f"relaxation time tau [s] (Jian, with --c; beta = tau / T in {_R('beta')})")
    d.add_argument("--e", type=float, help=f"calibrate: restitution coefficient measured at --v, in {_R('e')}")
    d.add_argument("--beta", type=float, help=f"calibrate: Jian's beta = tau / T at --v, in {_R('beta')}")
    s = p.add_argument_group("speeds (default: 0.30 to 2.60 m/s, 24 values)")
    s.add_argument("--speeds", type=float, nargs="+", metavar="M/S", help=f"impact speeds, in {_R('v')}")
    s.add_argument("--v-min", type=float, metavar="M/S", help=f"lowest impact speed, in {_R('v')}")
    s.add_argument("--v-max", type=float, metavar="M/S", help=f"highest impact speed, in {_R('v')}")
    s.add_argument("--num", type=int, default=None, help="number of speeds (default 24)")
    o = p.add_argument_group("output (default: CSV on stdout)")
    o.add_argument("--csv", metavar="FILE", help="write CSV ('-': stdout)")
    o.add_argument("--json", nargs="?", const="-", metavar="FILE",
                   help="print one JSON object on stdout (the old form --json FILE still writes "
                   "FILE, with a deprecation note: use --json-out FILE)")
    o.add_argument("--json-out", metavar="FILE", help="write the JSON object to FILE ('-': stdout)")
    o.add_argument("--plot", metavar="FILE.png",
                   help="plot e, t_c, F_max against v as PNG (the name must end in .png)")
    add_force_option(p, "the --csv, --json-out and --plot files")
    p.set_defaults(handler=_sweep)

    p = sub.add_parser(
        "reproduce", help="write the study's tables, figures and report page",
        description="Compute Tables 1, 2, 4 and Figures 2-12 of Jian et al. (2019), compare every "
        "law with the lacrosse-ball drop tests, and write them with index.html into DIR.")
    p.add_argument("--out", default="viscontact-report", metavar="DIR",
                   help="report directory (default: viscontact-report)")
    p.add_argument("--force", action="store_true",
                   help="replace an earlier report in DIR (only its own, unchanged files; a "
                   "directory that is not empty and holds no report is always refused)")
    p.add_argument("--no-progress", "--quiet", dest="quiet", action="store_true",
                   help="no progress on stderr (--quiet: the same)")
    p.set_defaults(handler=_reproduce)
