"""Command ``audit``: what a published formula or a DEM-engine setting really delivers."""

from __future__ import annotations

import argparse
import os

from ..audit.engines import ENGINES, audit_engine, get_preset
from ..physics.pair import ContactPair
from ..audit.formulas import FORMULAS, audit_formula, get_formula
from ..solvers import END_CRITERIA
from .._support import outputs
from .common import add_force_option, add_law_option, print_json


DEFAULT_OUT = "viscontact-report/audit"
from ..physics.domain import range_text as _R


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "audit", help="what published alpha(e) formulas and DEM-engine settings really deliver",
        description="Audit a published closed-form alpha(e) (--formula) or a DEM-engine damping "
        "setting (--engine): the alpha it gives, the restitution that alpha really delivers (exact "
        "solve), the exact alpha, and for engines the value to type to get the target e. "
        "--all writes the full tables (CSV, Markdown) and plots into a directory.")
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--formula", metavar="NAME",
                      help=f"one of: first-order (with --law), {', '.join(FORMULAS)}")
    what.add_argument("--engine", metavar="NAME", help=f"one of: {', '.join(ENGINES)}")
    what.add_argument("--all", action="store_true", help="write every table and plot into --out")
    p.add_argument("--e", type=float, help=f"target restitution coefficient in {_R('e')}")
    p.add_argument("--end", choices=END_CRITERIA, default=None,
                   help="formulas: end criterion of the exact solve (default force)")
    add_law_option(p, "formula first-order: the law (LH, Ts, KK, Li, Hunt, power)")
    p.add_argument("--p", type=float, default=None, help=f"formula first-order with --law power: exponent in {_R('p')}")
    p.add_argument("--damping", metavar="OPTION", default=None,
                   help="engine damping option; lammps: " + ", ".join(ENGINES["lammps"]))
    p.add_argument("--engine-version", metavar="VERSION", default=None,
                   help="engine release, e.g. yade 2022.01a (Antypov-Elliott) or 2023.02a (Thornton "
                   "2013 fit); default: the current release")
    p.add_argument("--limit-damping", action="store_true",
                   help="LAMMPS: limit_damping (clamp attraction: contact ends at zero force)")
    p.add_argument("--limit-force", action="store_true",
                   help="LIGGGHTS: limitForce on (clamp attraction: contact ends at zero force)")
    p.add_argument("--value", type=float, default=None,
                   help="engine: the value you type (default: the target e for restitution inputs; for "
                   "physical dashpots the value calibrated for the zero-overlap criterion)")
    phys = p.add_argument_group("physical quantities (LAMMPS velocity, mass_velocity, viscoelastic)")
    phys.add_argument("--m-eff", type=float, help=f"effective mass m*, in {_R('mass')}")
    phys.add_argument("--r-eff", type=float, help=f"effective radius R*, in {_R('radius')}")
    phys.add_argument("--e-eff", type=float, help=f"effective modulus E*, in {_R('modulus')} (or give --k-hertz)")
    phys.add_argument("--k-hertz", type=float, help=f"Hertz stiffness (4/3) E* sqrt(R*), in {_R('k_hertz')}")
    phys.add_argument("--v", type=float, help=f"impact speed v_i, in {_R('v')}")
    p.add_argument("--out", default=None, metavar="DIR",
                   help=f"--all: output directory (default {DEFAULT_OUT}; a new or empty "
                   "directory, or one holding an earlier audit with --force)")
    add_force_option(p, "--all: the files of an earlier audit in --out")
    p.add_argument("--no-plots", action="store_true", help="--all: tables only")
    p.add_argument("--grid", type=float, nargs="+", metavar="E",
                   help=f"--all: target e values in {_R('e')} (default 0.05, 0.10, ..., 0.95, 0.99)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=_audit)


def _physical(args: argparse.Namespace) -> ContactPair | None:
    given = [args.m_eff, args.r_eff, args.e_eff, args.k_hertz, args.v]
    if all(v is None for v in given):
        return None
    missing = [n for n, v in (("--m-eff", args.m_eff), ("--r-eff", args.r_eff), ("--v", args.v)) if v is None]
    if missing:
        raise ValueError(f"physical quantities incomplete: missing {', '.join(missing)}")
    return ContactPair.from_effective(m_eff=args.m_eff, r_eff=args.r_eff, v=args.v, e_eff=args.e_eff,
                                      k_hertz=args.k_hertz)


def _audit(args: argparse.Namespace) -> int:
    if args.all:
        return _all(args)
    if args.e is None:
        raise ValueError("--e (the target restitution coefficient) is required")
    only_all = [f for f, v in (("--grid", args.grid), ("--out", args.out),
                               ("--no-plots", args.no_plots), ("--force", args.force))
                if v not in (None, False)]
    if only_all:
        raise ValueError(f"{', '.join(only_all)} only apply to --all")
    if args.formula is not None:
        return _formula(args)
    return _engine(args)


def _no_engine_options(args: argparse.Namespace) -> None:
    used = [flag for flag, v in (("--damping", args.damping), ("--value", args.value),
                                 ("--engine-version", args.engine_version),
                                 ("--m-eff", args.m_eff), ("--r-eff", args.r_eff), ("--e-eff", args.e_eff),
                                 ("--k-hertz", args.k_hertz), ("--v", args.v)) if v is not None]
    used += [f for f, v in (("--limit-damping", args.limit_damping), ("--limit-force", args.limit_force)) if v]
    if used:
        raise ValueError(f"{', '.join(used)} only apply to --engine")


def _formula(args: argparse.Namespace) -> int:
    _no_engine_options(args)
    if args.p is not None and args.formula.strip().lower() != "first-order":
        raise ValueError("--p only applies to --formula first-order (with --law power)")
    f = get_formula(args.formula, model=args.model, p=args.p)
    end = args.end or "force"
    r = audit_formula(f, args.e, end)
    if args.json:
        d = r.to_dict()
        d["reference"] = f.reference
        print_json(d)
        return 0
    print(f"{f.name} ({f.title}; {f.law_label} law; {f.reference})")
    print(f"  target e            {r.target_e:.10g}")
    print(f"  alpha (formula)     {_num(r.alpha)}")
    print(f"  delivered e         {_num(r.delivered_e)}   (zero-{end} end, exact solve)")
    print(f"  error               {_num(r.error, '+.3e')}")
    print(f"  exact alpha         {_num(r.exact_alpha)}")
    if r.note:
        print(f"  note: {r.note}")
    return 0


def _num(v: float | None, spec: str = ".10g", unit: str = "") -> str:
    """A result's number, or ``none`` where it does not exist (the note line says why)."""
    return "none" if v is None else f"{v:{spec}}{unit}"


def _engine(args: argparse.Namespace) -> int:
    if args.end is not None:
        raise ValueError("--end is set by the engine; use --limit-damping / --limit-force where the engine has it")
    if args.model is not None or args.p is not None:
        raise ValueError("--law/--p only apply to --formula first-order")
    pre = get_preset(args.engine, args.damping, args.engine_version)
    clamp: bool | None = None
    for flag, on in (("limit_damping", args.limit_damping), ("limitForce", args.limit_force)):
        if on:
            if pre.clamp_flag != flag:
                raise ValueError(f"--{'limit-damping' if flag == 'limit_damping' else 'limit-force'} "
                                 f"does not apply to {pre.engine}")
            clamp = True
    phys = _physical(args)
    if phys is not None and not pre.needs_physical:
        raise ValueError(f"{pre.engine} {pre.option} takes a restitution coefficient; physical "
                         "quantities are not needed")
    r = audit_engine(pre.engine, pre.option, args.e, clamp=clamp, physical=phys, value=args.value,
                     version=args.engine_version)
    if args.json:
        print_json(r.to_dict())
        return 0
    unit = "" if r.input_units == "-" else f" [{r.input_units}]"
    flag = f", {pre.clamp_flag} {'on' if r.clamp else 'off'}" if pre.clamp_flag else ""
    print(f"{r.engine} {r.option}{flag}: {r.model} law, contact ends at zero {r.end}")
    print(f"  versions: {r.versions}")
    print(f"  mapping: {r.mapping}")
    print(f"  source:  {r.source}")
    print(f"  spring:  {r.spring}")
    print(f"  wall:    {r.wall}")
    print(f"  checked: {r.checked}")
    if r.T is not None:
        print(f"  T = {r.T:.6g} s")
    print(f"  target e            {r.target_e:.10g}")
    print(f"  you type {r.input_name:<10} {_num(r.input_value, unit=unit)}")
    print(f"  alpha               {_num(r.alpha)}")
    print(f"  delivered e         {_num(r.delivered_e)}   (error {_num(r.error, '+.3e')})")
    print(f"  exact alpha         {_num(r.exact_alpha)}")
    print(f"  type instead        {_num(r.input_for_target, unit=unit)}   (gives e = {r.target_e:g})")
    if r.note:
        print(f"  note: {r.note}")
    return 0


def _all(args: argparse.Namespace) -> int:
    extra = [f for f, v in (("--formula", args.formula), ("--engine", args.engine), ("--e", args.e),
                            ("--value", args.value), ("--damping", args.damping),
                            ("--engine-version", args.engine_version),
                            ("--law", args.model), ("--p", args.p), ("--end", args.end))
             if v is not None]
    extra += [f for f, v in (("--limit-damping", args.limit_damping),
                             ("--limit-force", args.limit_force)) if v]
    if extra:
        raise ValueError(f"--all takes no {', '.join(extra)} (it audits everything)")
    from ..audit.report import DEFAULT_GRID, DEFAULT_PHYSICAL, write_all

    phys = _physical(args) or DEFAULT_PHYSICAL
    grid = tuple(args.grid) if args.grid else DEFAULT_GRID
    for e in grid:
        if not 0.0 < e <= 1.0:
            raise ValueError(f"--grid values must be in (0, 1]; got {e!r}")
    names = ["formulas.csv", "engines.csv", "formulas.md", "engines.md", "summary.md"]
    names += [] if args.no_plots else ["formulas.png", "engines.png"]
    out = outputs.OutputDir(DEFAULT_OUT if args.out is None else args.out, "audit", args.force, expected=names)
    with out:
        staged = write_all(str(out.staging), grid=grid, physical=phys, plots=not args.no_plots)
    paths = [str(out.out / os.path.basename(p)) for p in staged]
    if args.json:
        print_json({"out": str(out.out), "files": paths})
    else:
        for path in paths:
            print(path)
    return 0
