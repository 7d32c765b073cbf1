"""The e(v) part of ``viscontact fit``: ``--restitution``, ``--bounces``, ``--audio``.

Reads the inputs, reduces timings and recordings to (v, e), fits every law
(:func:`viscontact.fit.fit_restitution`), prints the table and the verdict, and joins the
fit with the DEM lines (:func:`viscontact.dem.fromfit.fit_lines`).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

import numpy as np

from ..physics.domain import range_text as _R

__all__ = ["add_options", "wanted", "run", "output_names", "write_outputs", "print_result"]


def add_options(p: argparse.ArgumentParser) -> None:
    r = p.add_argument_group(
        "restitution at several speeds (instead of, or beside, force recordings)")
    r.add_argument("--restitution", metavar="FILE",
                   help="table of v [m/s] and e, optional sigma_e and tc [s] (CSV or text, "
                   "header with units such as 'v [cm/s],e,sigma_e'); rows at one speed are "
                   "replicates")
    r.add_argument("--bounces", nargs="+", metavar="FILE",
                   help="impact times of a bouncing ball, one file per drop: a column of times "
                   "[s] or phyphox's '(In)elastic collision' export")
    r.add_argument("--audio", nargs="+", metavar="FILE",
                   help="a recording of the bouncing per drop: WAV (any rate, 8-32 bit PCM or "
                   "float); m4a/AAC and others where ffmpeg is installed")
    r.add_argument("--E", dest="modulus", type=float, metavar="PA",
                   help=f"the ball's Young's modulus, in {_R('modulus')} (with --nu, --radius "
                   "and --mass: k_Hertz for c and tau, the Hertz contact time, the DEM lines)")
    r.add_argument("--nu", dest="poisson", type=float, metavar="NU",
                   help="the ball's Poisson ratio (with --E)")
    r.add_argument("--contact-time", type=float, metavar="S",
                   help="contact time [s] taken off each bounce interval")
    r.add_argument("--drag-coefficient", type=float, default=0.47, metavar="CD",
                   help="drag coefficient of the ball (default 0.47, a smooth sphere)")
    r.add_argument("--air-density", type=float, default=1.2, metavar="KG/M3",
                   help="density of air (default 1.2 kg/m^3)")
    r.add_argument("--no-drag", action="store_true",
                   help="reduce bounce timings without air drag (no --mass, --radius needed)")
    r.add_argument("--end", choices=("force", "overlap"), default="force",
                   help="when a contact ends: zero force (the study's, default) or zero overlap")
    r.add_argument("--vref", type=float, metavar="M/S",
                   help="reference speed of alpha_ref, beta_ref (default: the geometric mean "
                   "of the data's speeds)")
    r.add_argument("--dem-law", metavar="NAME",
                   help="write the DEM lines for this law (default: the best)")


def wanted(args: argparse.Namespace) -> bool:
    return bool(args.restitution or args.bounces or args.audio)


def _positive(name: str, value: float | None) -> float | None:
    if value is None:
        return None
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return float(value)


class Inputs:
    """What the e(v) part read: data, rejections, impacts, recordings (for the plots)."""

    def __init__(self) -> None:
        self.points: list[dict[str, Any]] = []
        self.audio: list[tuple[str, np.ndarray, float, np.ndarray]] = []
        self.notes: list[str] = []


def run(args: argparse.Namespace, laws: list[str]) -> tuple[Any, Inputs, Any]:
    """(RestitutionFit, Inputs, FitLines) from the command line."""
    from ..dem.fromfit import fit_lines
    from ..fit.audio import detect_impacts, read_audio
    from ..fit.bounces import drag_constant, read_drops, reduce_bounces
    from ..fit.recording import RecordingError
    from ..fit.restitution import fit_restitution, read_restitution, restitution_data
    from ..physics.pair import HERTZ_TC, contact_pair, time_scale

    mass = _positive("--mass", args.mass)
    radius = _positive("--radius", args.radius)
    modulus = _positive("--E", args.modulus)
    if args.poisson is not None and not (math.isfinite(args.poisson) and -1 < args.poisson < 0.5):
        raise ValueError(f"--nu must be in (-1, 0.5), got {args.poisson!r}")
    tc_given = _positive("--contact-time", args.contact_time)
    vref = _positive("--vref", args.vref)
    cd = _positive("--drag-coefficient", args.drag_coefficient)
    rho = _positive("--air-density", args.air_density)
    if (modulus is None) != (args.poisson is None):
        raise ValueError("give --E and --nu together")
    k_hertz = None
    if modulus is not None:
        if mass is None or radius is None:
            raise ValueError("--E and --nu need the ball's --mass and --radius (k_Hertz and "
                             "the physical constants c, tau)")
        k_hertz = contact_pair(mass, radius=radius, modulus=modulus,
                               poisson=args.poisson).k_hertz
    inp = Inputs()
    sets = []
    if args.restitution:
        sets.append(read_restitution(args.restitution))
    drops, sources = [], []
    if args.bounces:
        for f in args.bounces:
            mine = read_drops(f)
            drops.extend(mine)
            sources.extend([str(f)] if len(mine) == 1 else
                           [f"{f}, drop {i}" for i in range(1, len(mine) + 1)])
    for f in args.audio or []:
        x, rate = read_audio(f)
        t = detect_impacts(x, rate)
        if t.size < 3:
            raise RecordingError(f"{f}: {t.size} impact{'s' if t.size != 1 else ''} found; a "
                                 "(v, e) point needs three (is the ball audible above the "
                                 "noise? is this the recording of the bouncing?)")
        inp.audio.append((str(f), x, rate, t))
        drops.append(t)
        sources.append(str(f))
    rejected, impacts = [], []
    if drops:
        if args.no_drag:
            k = 0.0
        elif mass is None or radius is None:
            raise ValueError("the air drag of the bounce reduction needs the ball's --mass and "
                             "--radius (or --no-drag for the drag-free reduction)")
        else:
            k = drag_constant(mass, radius, drag_coefficient=cd, air_density=rho)
        if tc_given is not None:
            contact: Any = tc_given
        elif k_hertz is not None:
            def contact(v: float) -> float:  # the undamped Hertz t_c (each law's differs)
                return HERTZ_TC * time_scale(mass, k_hertz, max(v, 1e-6))
        else:
            contact = None
        red = reduce_bounces(drops, k_drag=k, contact_time=contact, sources=sources)
        if callable(contact) and not sets:
            # the law's own t_c: the best law of a first fit (with the Hertz t_c) gives it,
            # and the timings are reduced again with it
            first = fit_restitution(red.data, laws, end=args.end, vref=vref).best
            own = reduce_bounces(drops, k_drag=k, sources=sources,
                                 contact_time=lambda v: float(first.contact_time(v, mass, k_hertz)[0]))
            red = type(red)(own.data, own.rejected, own.impacts,
                            own.notes[:-1] + [f"the contact time of {first.law} (its own t_c(v), "
                                              "from a first fit with the Hertz t_c; E and nu "
                                              "give k_Hertz) taken off each interval"],
                            own.points)
        sets.append(red.data)
        rejected, impacts = red.rejected, red.impacts
        inp.points = red.points
        inp.notes += red.notes
    data = sets[0] if len(sets) == 1 else _join(sets, restitution_data)
    fit = fit_restitution(data, laws, end=args.end, vref=vref, mass=mass, k_hertz=k_hertz,
                          rejected=rejected, impacts=impacts)
    fit.notes.extend(inp.notes)
    if mass is None:
        fit.notes.append("no --mass: the dimensionless constants only (c and tau need the "
                         "mass and k_Hertz: --E, --nu, --radius, or contact times tc)")
    elif k_hertz is None and data.tc is None:
        fit.notes.append("c and tau need k_Hertz: give --E, --nu and --radius, or a tc column")
    lines = fit_lines(fit, law=args.dem_law, E=modulus, nu=args.poisson)
    if not fit.ranking and args.dem_law is None:
        lines.notes.insert(0, f"no ranking: the lines are for {lines.law.law}, the one-constant "
                           "law of smallest rms; choose another with --dem-law NAME")
    return fit, inp, lines


def _join(sets: list[Any], make: Any) -> Any:
    v = np.concatenate([s.v for s in sets])
    e = np.concatenate([s.e for s in sets])
    sig = None if any(s.sigma is None for s in sets) else np.concatenate([s.sigma for s in sets])
    tc = None if any(s.tc is None for s in sets) else np.concatenate([s.tc for s in sets])
    return make(v, e, sigma=sig, tc=tc, source=", ".join(s.source for s in sets))


def _pm(x: float | None, err: float | None, fmt: str = ".4g") -> str:
    if x is None:
        return "-"
    return format(x, fmt) + ("" if err is None or not math.isfinite(err) else
                             f" ± {format(err, '.2g')}")


def print_result(fit: Any, inp: Inputs, lines: Any) -> None:
    d = fit.data
    for src, _, rate, t in inp.audio:
        print(f"{src}: {t.size} impacts found at {rate / 1e3:.4g} kHz: "
              + ", ".join(f"{x:.4f}" for x in t) + " s")
    print(f"e(v): {d.n} points, v = {d.v.min():.4g} to {d.v.max():.4g} m/s, end = {fit.end}, "
          f"constants at vref = {fit.vref:.4g} m/s")
    for r in fit.rejected:
        print(f"  left out: {r['source']} impact {r['impact']} (v = {r['v']:.4g} m/s, "
              f"e = {r['e']:.4g}): {r['reason']}")
    order = fit.ranking or list(fit.laws)
    best = fit.laws[order[0]].aicc if fit.ranking else None
    print(f"  {'rank':<4} {'law':<6} {'alpha_ref':<20} {'beta_ref / p':<20} {'c':<30} "
          f"{'tau [ms]':<16} {'rms':>8} {'dAICc':>7} {'LOO':>8}")
    for i, name in enumerate(order, 1):
        f = fit.laws[name]
        second = _pm(f.beta, f.beta_err) if f.beta is not None else (
            f"p = {_pm(f.p, f.p_err)}" if f.p_err is not None else "-")
        c = "-" if f.c is None else f"{_pm(f.c, f.c_err)} {f.c_unit}"
        tau = "-" if f.tau is None else _pm(f.tau * 1e3, None if f.tau_err is None else f.tau_err * 1e3)
        da = "-" if best is None else f"{f.aicc - best:.2f}"
        loo = "-" if f.loo is None else f"{f.loo:.3g}"
        print(f"  {i if fit.ranking else '-':<4} {name:<6} {_pm(f.alpha, f.alpha_err):<20} "
              f"{second:<20} {c:<30} {tau:<16} {f.rms:>8.3g} {da:>7} {loo:>8}")
    print(f"  {fit.verdict}")
    for n in fit.notes:
        print(f"  note: {n}")
    print(f"DEM input for {lines.law.law} (alpha form at vref = {lines.law.vref:g} m/s):")
    for ln in lines.lines() or [lines.keywords]:
        print(f"  {ln}")
    for n in lines.notes:
        print(f"  note: {n}")


def document(fit: Any, lines: Any) -> dict[str, Any]:
    doc = fit.to_dict()
    doc["dem"] = lines.to_dict()
    return doc


def output_names(args: argparse.Namespace) -> list[str]:
    names = ["restitution.png"]
    if args.bounces or args.audio:
        names.append("bounces.png")
    for i, f in enumerate(args.audio or [], 1):
        names.append(f"audio_{i}_{Path(f).stem}.png")
    return names


def write_outputs(staging: Path, args: argparse.Namespace, fit: Any, inp: Inputs) -> None:
    from ..fit.restitution_plots import plot_onsets, plot_reduction, plot_restitution

    plot_restitution(fit, staging / "restitution.png")
    if inp.points:
        plot_reduction(inp.points, staging / "bounces.png")
    for i, (src, x, rate, t) in enumerate(inp.audio, 1):
        plot_onsets(x, rate, t, staging / f"audio_{i}_{Path(src).stem}.png",
                    title=f"{src}: {t.size} impacts found")
