"""``viscontact fit``: fit the contact laws to force-plate recordings of impacts, and to
restitution measured at several speeds (a table, bounce timings, recordings: see
:mod:`.fit_restitution`)."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path
from typing import Any

import numpy as np

from .._support import outputs
from .._support.progress import Progress
from ..physics.pair import HERTZ_TC, check_positive, drop_speed, time_scale
from ..fit.fitting import FIT_LAWS, GlobalFit, LawFit, Weights, fit_global, fit_laws
from ..fit.recording import (FORCE_UNITS, TIME_UNITS, Measured, RecordingError,
                             measure, read_recording)
from ..fit.synthetic import EXAMPLE, example_recording
from ..physics.laws import lookup
from . import fit_restitution as _res
from .common import add_force_option, finite_json, note, print_json
from ..physics.domain import range_text as _R
from ..physics.laws import Power


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "fit", help="fit every law to force-plate recordings of impacts",
        description="Read force-plate recordings (CSV or text: time and force), integrate them "
        "for the overlap and its rate, report what they say (e, t_c, F_max, delta_max, k_Hertz, "
        "residual overlap), fit every law by least squares with uncertainties, and rank the "
        "laws. Several recordings (e.g. one per drop height) also get one global fit of the "
        "physical constants c, tau, k_Hertz per law. --restitution, --bounces and --audio fit "
        "every law to e measured at several impact speeds instead (or as well), rank them "
        "and write the DEM lines of the best.")
    p.add_argument("recordings", nargs="*", metavar="RECORDING",
                   help="CSV or whitespace-separated file: time and force columns, '#' comments, "
                   "optional header with units such as 'time [ms],force [N]'")
    p.add_argument("--example", action="store_true",
                   help="fit the example recording that ships with viscontact (a synthetic "
                   f"{EXAMPLE['model']} drop of the {EXAMPLE['ball']} ball)")
    b = p.add_argument_group("the impact (SI units)")
    b.add_argument("--mass", "--m-eff", dest="mass", type=float, metavar="KG",
                   help=f"mass of the ball m*, in {_R('mass')} (a ball on a rigid plate: m* = m); "
                   "needed by force recordings, by the air drag of --bounces/--audio and by "
                   "the physical constants")
    b.add_argument("--radius", "--r-eff", dest="radius", type=float, metavar="M",
                   help=f"radius R*, in {_R('radius')} (optional: for the effective modulus E*)")
    b.add_argument("--velocity", "--v", dest="velocity", type=float, nargs="+", metavar="M/S",
                   help=f"impact speed, in {_R('v')}: one for all recordings, or one per recording")
    b.add_argument("--drop-height", dest="drop_height", type=float, nargs="+", metavar="M",
                   help=f"drop height, in {_R('drop_height')}, instead of --velocity (v = sqrt(2 g h), g = 9.81 m/s^2)")
    b.add_argument("--time-unit", choices=list(TIME_UNITS), default=None,
                   help="time unit of the files when their header gives none (default s)")
    b.add_argument("--force-unit", choices=list(FORCE_UNITS), default=None,
                   help="force unit of the files when their header gives none (default N)")
    f = p.add_argument_group("fit")
    f.add_argument("--laws", nargs="+", default=["all"], metavar="LAW",
                   help=f"laws to fit: 'all' (default: {', '.join(FIT_LAWS)}) or some of them")
    f.add_argument("--hold-k-hertz", action="store_true",
                   help="hold k_Hertz at the value measured from the force at maximum overlap "
                   "(the study's way; default: fit it too); the global fit always fits it")
    f.add_argument("--weights", type=float, nargs=3, default=[1.0, 0.0, 0.0],
                   metavar=("W_F", "W_DELTA", "W_RATE"),
                   help=f"weights of the force, overlap and overlap-rate residuals, each in {_R('weight')}, scaled "
                   "by F_max, delta_max, v_i (default 1 0 0: force only)")
    _res.add_options(p)
    o = p.add_argument_group("output")
    o.add_argument("--out", metavar="DIR",
                   help="write fit.json and the plots (fit_<recording>.png, global.png) into DIR "
                   "(a new or empty directory, or one holding an earlier fit with --force)")
    add_force_option(o, "the files of an earlier fit in --out")
    o.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    o.add_argument("--no-progress", "--quiet", dest="quiet", action="store_true",
                   help="no progress bar on stderr (--quiet: the same)")
    p.set_defaults(handler=_fit)


def _paths(args: argparse.Namespace) -> list[str]:
    paths = list(args.recordings) + ([str(example_recording())] if args.example else [])
    if not paths and not _res.wanted(args):
        raise ValueError("give one or more recordings (or --example), or restitution data: "
                         "--restitution, --bounces or --audio")
    return paths


def _speeds(args: argparse.Namespace, n: int) -> list[float]:
    if args.velocity is not None and args.drop_height is not None:
        raise ValueError("give --velocity or --drop-height, not both")
    if args.velocity is not None:
        speeds = [check_positive("impact speed --velocity", v) for v in args.velocity]
    elif args.drop_height is not None:
        speeds = [drop_speed(h) for h in args.drop_height]
    else:
        raise ValueError("give the impact speed: --velocity (m/s) or --drop-height (m)")
    if len(speeds) == 1:
        return speeds * n
    if len(speeds) != n:
        raise ValueError(f"give one impact speed for all recordings or one per recording "
                         f"({n} recordings, {len(speeds)} speeds)")
    return speeds


def _laws(names: list[str]) -> list[str]:
    if [n.lower() for n in names] == ["all"]:
        return list(FIT_LAWS)
    return list(dict.fromkeys(lookup(n).name for n in names))


def _pm(x: float | None, err: float | None, scale: float = 1.0, fmt: str = ".4g") -> str:
    if x is None:
        return "-"
    s = format(x * scale, fmt)
    return s if err is None else f"{s} ± {format(err * scale, '.2g')}"


def _print_recording(m: Measured, fits: list[LawFit]) -> None:
    print(f"{m.path}: {m.rate / 1e3:.4g} kHz, {m.n_contact} samples in contact, baseline "
          f"{m.baseline:.4g} N removed, noise {m.noise:.3g} N, v_i = {m.v:.4g} m/s")
    emod = "" if m.e_modulus is None else f", E* = {m.e_modulus:.4g} Pa"
    print(f"  measured: e = {m.e:.4f}, t_c = {m.tc * 1e3:.4f} ms, F_max = {m.fmax:.4g} N, "
          f"delta_max = {m.dmax * 1e3:.4f} mm, k_Hertz = {m.k_hertz:.4g} N/m^1.5, "
          f"residual overlap = {m.residual * 1e3:.4f} mm{emod}")
    print(f"  {'rank':<4} {'law':<6} {'alpha':<17} {'beta':<16} {'p':<15} "
          f"{'k_Hertz [N/m^1.5]':<20} {'c':<33} {'tau [ms]':<16} {'rms [N]':>8} {'/F_max':>6}")
    for i, f in enumerate(fits, 1):
        c = f"{_pm(f.c, f.c_err)} {f.c_unit}"
        k = _pm(f.k_hertz, f.k_hertz_err) if f.k_fitted else f"{f.k_hertz:.4g} (held)"
        print(f"  {i:<4} {f.law:<6} {_pm(f.alpha, f.alpha_err):<17} {_pm(f.beta, f.beta_err):<16} "
              f"{_pm(f.p if f.law == Power.name else None, f.p_err):<15} {k:<20} {c:<33} "
              f"{_pm(f.tau, f.tau_err, 1e3):<16} {f.rms:>8.3g} {f.rms_rel:>6.2%}")


def _print_global(fits: list[GlobalFit]) -> None:
    print(f"global fit over {len(fits[0].measured)} recordings (one c, tau, k_Hertz per law), "
          "best first:")
    print(f"  {'law':<6} {'c':<30} {'tau [ms]':<18} {'k_Hertz [N/m^1.5]':<22} {'rms [N]':>8}  "
          "e / t_c [ms] / F_max [N] predicted (measured) at each v_i")
    for g in fits:
        c = f"{_pm(g.c, g.c_err)} {g.c_unit}"
        pts = "; ".join(f"{p['v']:.3g} m/s: {p['e_fit']:.3f} ({p['e']:.3f}) / "
                        f"{p['tc_fit'] * 1e3:.3f} ({p['tc'] * 1e3:.3f}) / "
                        f"{p['fmax_fit']:.4g} ({p['fmax']:.4g})" for p in g.points())
        p_txt = f" p = {_pm(g.p, g.p_err)}" if g.law == Power.name else ""
        print(f"  {g.law:<6} {c:<30} {_pm(g.tau, g.tau_err, 1e3):<18} "
              f"{_pm(g.k_hertz, g.k_hertz_err):<22} {g.rms:>8.3g}  {pts}{p_txt}")


def _fit(args: argparse.Namespace) -> int:
    paths = _paths(args)
    laws = _laws(args.laws)
    if args.force and args.out is None:
        raise ValueError("--force only goes with --out")
    res = _res.wanted(args)
    names = (_output_names(paths) if paths else ["fit.json"]) + (_res.output_names(args) if res else [])
    out = None if args.out is None else outputs.OutputDir(args.out, "fit", args.force,
                                                          expected=names)
    measured: list[Measured] = []
    results: list[list[LawFit]] = []
    globals_: list[GlobalFit] = []
    if paths:
        speeds = _speeds(args, len(paths))
        weights = Weights(*args.weights)
        if args.mass is None:
            raise ValueError("force recordings need the ball's --mass (kg)")
        mass = check_positive("--mass", args.mass)
        measured = [_measure(p, v, mass, args) for p, v in zip(paths, speeds)]
        results, globals_ = _fit_recordings(measured, laws, weights, args)
    restitution = _res.run(args, laws) if res else None
    doc = _document(measured, results, globals_) if paths else {}
    if restitution is not None:
        doc["restitution"] = _res.document(restitution[0], restitution[2])
    if out is not None:
        _write_outputs(out, measured, results, globals_, doc, args, restitution)
    if args.json:
        print_json(doc)
        return 0
    for m, fits in zip(measured, results):
        _print_recording(m, fits)
    if globals_:
        _print_global(globals_)
    if restitution is not None:
        _res.print_result(*restitution)
    return 0


def _fit_recordings(measured: list[Measured], laws: list[str], weights: Weights,
                    args: argparse.Namespace) -> tuple[list[list[LawFit]], list[GlobalFit]]:
    glob = len(measured) > 1
    bar = Progress(len(measured) * len(laws) + (len(laws) if glob else 0), unit="fit",
                   leave=False, stream=None if args.quiet else sys.stderr)
    results: list[list[LawFit]] = []
    for m in measured:
        bar.describe(Path(m.path).name)
        results.append(fit_laws(m, laws, fit_k=not args.hold_k_hertz, weights=weights,
                                progress=lambda _law: bar.update()))
    globals_: list[GlobalFit] = []
    if glob:
        for law in laws:
            bar.describe(f"global {law}")
            start = [next(f for f in fits if f.law == law) for fits in results]
            globals_.append(fit_global(measured, law, start=start, weights=weights))
            bar.update()
        globals_.sort(key=lambda g: g.bic)
    bar.close()
    return results, globals_


def _document(measured: list[Measured], results: list[list[LawFit]],
              globals_: list[GlobalFit]) -> dict[str, Any]:
    """The JSON object: one recording -> {file, measured, laws}; several -> recordings, global."""
    per = [{"file": m.path, "measured": m.to_dict(), "laws": [f.to_dict() for f in fits]}
           for m, fits in zip(measured, results)]
    if len(per) == 1:
        return per[0]
    return {"recordings": per, "global": [g.to_dict() for g in globals_]}


def _plot_names(paths: list[str]) -> list[str]:
    """fit_<stem>.png per recording (fit_<stem>_2.png ... for repeated stems)."""
    stems: dict[str, int] = {}
    names = []
    for path in paths:
        stem = Path(path).stem
        stems[stem] = stems.get(stem, 0) + 1
        names.append(f"fit_{stem}" + (f"_{stems[stem]}" if stems[stem] > 1 else "") + ".png")
    return names


def _output_names(paths: list[str]) -> list[str]:
    return _plot_names(paths) + (["global.png"] if len(paths) > 1 else []) + ["fit.json"]


#: t_c / T of a recording outside this band is no impact of a ball of the mass and speed given
#: (the undamped Hertz contact: 3.218; damped laws at either end stay well inside)
_TC_BAND = (0.3, 30.0)
#: how far e may exceed 1, and the residual overlap fall below 0 (relative to delta_max),
#: from noise alone
_SLACK = 0.05


def _implausible(m: Measured) -> list[str]:
    """What in a measurement is physically impossible (empty when it is plausible)."""
    bad = []
    if m.e > 1.0 + _SLACK:
        bad.append(f"e = {m.e:.4g} > 1")
    if m.residual < -_SLACK * m.dmax:
        bad.append(f"a negative residual overlap ({m.residual * 1e3:.4g} mm)")
    try:
        ratio = m.tc / time_scale(m.mass, m.k_hertz, m.v)
    except ValueError:  # k_Hertz <= 0 or outside any physical range: implausible in any case
        ratio = math.inf
    if not _TC_BAND[0] <= ratio <= _TC_BAND[1]:
        bad.append(f"t_c = {m.tc * 1e3:.4g} ms, {ratio / HERTZ_TC:.3g} times the Hertz contact "
                   "time of the k_Hertz measured")
    return bad


def _measure(path: str, v: float, mass: float, args: argparse.Namespace) -> Measured:
    """measure(), refusing a physically impossible result; when the file reads right with
    another --time-unit (its header gives none), the one line names it."""
    rec = read_recording(path, time_unit=args.time_unit, force_unit=args.force_unit)
    try:
        m = measure(rec, mass=mass, v=v, radius=args.radius)
    except RecordingError as exc:
        problem, error = str(exc), exc
    else:
        bad = _implausible(m)
        if not bad:
            return m
        problem = f"{path}: {' and '.join(bad)}: impossible for an impact"
        error = None
    for unit in ("s", "ms", "us"):
        if unit == (args.time_unit or "s"):
            continue
        other = read_recording(path, time_unit=unit, force_unit=args.force_unit)
        if np.array_equal(other.t, rec.t):
            break  # the header gives the unit: --time-unit changes nothing
        try:
            right = not _implausible(measure(other, mass=mass, v=v))
        except ValueError:
            right = False
        if right:
            raise RecordingError(f"{problem}; the file reads right with --time-unit {unit} "
                                 f"(or a header such as 'time [{unit}],force [N]')")
    if error is not None:
        raise error
    raise RecordingError(f"{problem}; check --time-unit, --force-unit, --mass and the impact "
                         "speed")


def _write_outputs(out: outputs.OutputDir, measured: list[Measured],
                   results: list[list[LawFit]], globals_: list[GlobalFit],
                   doc: dict[str, Any], args: argparse.Namespace, restitution: Any) -> None:
    from ..fit.plots import plot_fit, plot_global

    with out:
        for name, m, fits in zip(_plot_names([m.path for m in measured]), measured, results):
            plot_fit(m, fits, out.staging / name)
        if globals_:
            plot_global(globals_, out.staging / "global.png")
        if restitution is not None:
            _res.write_outputs(out.staging, args, restitution[0], restitution[1])
        text = json.dumps(finite_json(doc), indent=2) + "\n"
        (out.staging / "fit.json").write_text(text, encoding="utf-8")
    note(f"fit.json and plots written to {out.out}{os.sep}")
