"""Commands ``collide``, ``restitution`` and ``calibrate`` (non-dimensional; ``calibrate``
also takes physical options, handled in :mod:`.physical`)."""

from __future__ import annotations

import argparse
import csv
import sys

import numpy as np

from ..calibration.inverse import alpha_from_e, restitution
from ..collision.single import collide
from .._support import outputs
from . import physical
from .common import add_force_option, add_model_options, conflict, note, print_json
from ..physics.domain import range_text as _R
from ..physics.laws import Power


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("collide", help="solve one collision (non-dimensional)",
                       description="Solve one normal collision x'' + x^(3/2) + alpha g x^p x' = 0 "
                       "and print e, t_c, F_max, x_max, residual overlap and dissipated energy.")
    add_model_options(p)
    p.add_argument("--alpha", type=float, required=True, help=f"damping constant alpha in {_R('alpha')}")
    p.add_argument("--beta", type=float, default=None,
                   help=f"relaxation time / T (Jian only), in {_R('beta')}")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--histories", action="store_true", help="with --json: include t, x, v, f")
    p.add_argument("--plot", metavar="FILE.png", help="save x, x', F^ against t^ and the F^-x loop "
                   "as PNG (the name must end in .png; an existing file only with --force, and "
                   "only one written by collide)")
    add_force_option(p, "the --plot file")
    p.set_defaults(handler=_collide)

    p = sub.add_parser("restitution", help="e for one or more alpha values",
                       description="Coefficient of restitution for each alpha (and beta for Jian).")
    add_model_options(p)
    p.add_argument("--alpha", type=float, nargs="+", required=True, help=f"one or more alpha in {_R('alpha')}")
    p.add_argument("--beta", type=float, nargs="+", default=None,
                   help=f"Jian only: one beta, or one per alpha, in {_R('beta')}")
    p.add_argument("--csv", action="store_true", help="print CSV (alpha,beta,e)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=_restitution)

    p = sub.add_parser(
        "calibrate", help="alpha (and T, c, tau in physical units) from a measured e",
        description="Find alpha so that the law gives restitution e exactly. With physical "
        "options (--mass, --k-hertz or --E/--nu with --radius, --v or --drop-height; or --ball) "
        "also print the time scale T, the physical damping coefficient c and tau = beta T, for "
        "--law or for every law of the study.")
    add_model_options(p, required=False,
                      model_help=" (required without physical options; with them, default: "
                      "every law of the study)")
    p.add_argument("--e", type=float, default=None,
                   help=f"target restitution coefficient in {_R('e')}")
    p.add_argument("--beta", type=float, default=None,
                   help=f"relaxation time / T (Jian only), in {_R('beta')}")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    physical.add_physical_options(p)
    p.set_defaults(handler=_calibrate)


def _collide(args: argparse.Namespace) -> int:
    if args.histories and not args.json:
        raise ValueError("--histories only goes with --json (it adds t, x, v, f to the object)")
    if args.force and args.plot is None:
        raise ValueError("--force only goes with --plot")
    if args.plot is not None:
        outputs.check_file(args.plot, "collide", args.force, "--plot", ".png")
    r = collide(args.model, args.alpha, beta=args.beta, p=args.p, end=args.end)
    if args.plot is not None:
        from ..collision.plots import plot_collision

        outputs.write_png(args.plot, "collide", args.force, "--plot",
                          lambda tmp: plot_collision([r], tmp))
    if args.json:
        print_json(r.to_dict(histories=args.histories))
        return 0
    name = r.model + (f" (beta = {r.beta:g})" if r.beta is not None else "")
    name += f" (p = {r.p:g})" if r.model == Power.name else ""
    print(f"{name}, alpha = {r.alpha:g}, zero-{r.end} end")
    rows = [
        ("restitution e", r.e), ("contact time t_c", r.tc), ("peak force F_max", r.fmax),
        ("  at t", r.t_fmax), ("maximum overlap x_max", r.xmax), ("  at t", r.t_xmax),
        ("residual overlap", r.residual), ("dissipated energy", r.dissipated),
    ]
    for label, value in rows:
        print(f"  {label:<24} {value:.10g}")
    if not r.separated:
        print(f"  note: {r.status}")
    if args.plot:
        note(f"plot written to {args.plot}")  # a status line (stderr), not a result
    return 0


def _restitution(args: argparse.Namespace) -> int:
    conflict(("--csv", args.csv), ("--json", args.json))
    alpha = np.array(args.alpha)
    beta = None
    if args.beta is not None:
        if len(args.beta) not in (1, len(alpha)):
            raise ValueError(f"give one --beta or one per --alpha ({len(alpha)}); got {len(args.beta)}")
        beta = np.broadcast_to(np.array(args.beta), alpha.shape)
    e = np.atleast_1d(restitution(args.model, alpha, beta=beta, p=args.p, end=args.end))
    if args.json:
        out = {"model": args.model, "end": args.end, "alpha": alpha.tolist(), "e": e.tolist()}
        if beta is not None:
            out["beta"] = beta.tolist()
        print_json(out)
        return 0
    writer = csv.writer(sys.stdout) if args.csv else None
    header = ["alpha"] + (["beta"] if beta is not None else []) + ["e"]
    if writer:
        writer.writerow(header)
    else:
        print("  ".join(f"{h:>14}" for h in header))
    for i in range(alpha.size):
        row = [alpha[i]] + ([beta[i]] if beta is not None else []) + [e[i]]
        if writer:
            writer.writerow([repr(float(v)) for v in row])
        else:
            print("  ".join(f"{v:>14.10g}" for v in row))
    return 0


def _calibrate(args: argparse.Namespace) -> int:
    if physical.has_physical(args):
        return physical.calibrate_physical_cmd(args)
    if args.model is None:
        raise ValueError("give --law (or physical options such as --mass, --k-hertz, --v, "
                         "or --ball)")
    if args.e is None:
        raise ValueError("give the target restitution coefficient --e")
    physical.check_beta_applies(args.model, args.beta)
    a = alpha_from_e(args.model, args.e, beta=args.beta, p=args.p, end=args.end)
    if args.json:
        print_json({"model": args.model, "end": args.end, "e": args.e, "beta": args.beta,
                    "p": args.p, "alpha": a})
    else:
        print(f"{args.model}: alpha = {a:.12g} gives e = {args.e:g} (zero-{args.end} end)")
    return 0
