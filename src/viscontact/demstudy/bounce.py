"""A lacrosse ball dropped onto a rigid plate, bouncing until it rests.

Each ball of the drop tests (:mod:`viscontact.paper.experiment`) falls from 15 cm onto a rigid plate
under gravity; every law is calibrated to the ball's measured e at v_i = 171.6 cm/s (Jian with
the study's beta), the plugin computing c (and tau) from m* = m, k_Hertz = (4/3) E* sqrt(R),
exactly as :func:`viscontact.paper.experiment.calibrate_ball` does.  Two DEM runs per law:

* ``gic = 1``: the physical drop, gravity acting during contact too;
* ``gic = 0``: gravity only in flight.  Every bounce is then an isolated collision, so the DEM
  sequence must equal the exact one of :func:`viscontact.demstudy.theory.bounce_sequence`
  (single collisions by the exact solver, flights in closed form) up to the time step.

Bounces are read from the steps next to each change of sign of the overlap: in flight the
motion is a parabola (velocity Verlet is exact there), so the start and end of each overlap
and the speeds there are found to rounding.  The force contact ends earlier, at the zero-force
end: the first step in which the ball still overlaps the plate but the contact force is zero
(the ball then recovers the leftover overlap force-free); it is resolved to one time step.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..physics.pair import STANDARD_GRAVITY, hertz_limit
from ..paper.experiment import Ball, PhysicalCalibration, calibrate_ball, load_balls
from ..physics.laws import STUDY_MODELS
from . import jobs, theory
from .engine import LawSpec, Material, Wall, coeff_text, read_dump, run_lammps

__all__ = ["DROP_HEIGHT", "NU", "H_MIN", "GRAVITY_SMALL", "DemBounces", "BounceCase", "ball_material",
           "parse_crossings", "run_drop", "run_bounces"]

DROP_HEIGHT = 0.15  # m, as in the drop tests
NU = 0.49  # Poisson ratio of the rubber ball (only E* = E / (1 - nu^2) matters on a rigid plate)
H_MIN = 1e-5  # m: a bounce counts when its flight rises at least this (10 um)
#: g t_c / v below which gravity during contact is a small correction: there the drop of e it
#: causes stays below (1 - e) g t_c / v (observed for every law and both balls; tested)
GRAVITY_SMALL = 0.25


def ball_material(b: Ball) -> Material:
    """E and nu that give the ball's measured k_Hertz on a rigid plate:
    k = (4/3) E* sqrt(R), E* = E / (1 - nu^2)."""
    estar = 3.0 * b.k_hertz / (4.0 * math.sqrt(b.radius))
    return Material(E=estar * (1.0 - NU ** 2), nu=NU)


@dataclass
class DemBounces:
    """Contacts seen in a DEM run: start and end times of the overlap [s], impact and rebound
    speeds [m/s] (NaN rebound for a contact that never ends), the end of the force contact
    (zero-force end) [s], and the bounces that count (apex >= h_min)."""

    t_start: np.ndarray
    t_end: np.ndarray
    v_in: np.ndarray
    v_out: np.ndarray
    g: float
    h_min: float
    t_force_end: np.ndarray = field(default_factory=lambda: np.empty(0))

    @property
    def e(self) -> np.ndarray:
        return self.v_out / self.v_in

    @property
    def tc(self) -> np.ndarray:
        """Overlap time [s]: first to last overlap, the force-free recovery included."""
        return self.t_end - self.t_start

    @property
    def tc_force(self) -> np.ndarray:
        """Force contact time [s]: first overlap to the zero-force end (+- one time step)."""
        return self.t_force_end - self.t_start

    @property
    def apex(self) -> np.ndarray:
        return self.v_out ** 2 / (2.0 * self.g)

    @property
    def n(self) -> int:
        """Bounces whose flight reached h_min, counted up to the first that did not."""
        ok = np.nan_to_num(self.apex, nan=0.0) >= self.h_min
        return int(np.argmin(ok)) if not ok.all() else len(ok)

    @property
    def t_rest(self) -> float:
        """When the last counted flight lands (the start of the contact after it) [s]."""
        n = self.n
        return float(self.t_start[n]) if n < len(self.t_start) else math.nan


def _solve_parabola(z0: float, v0: float, g: float, target: float, dt: float, forward: bool
                    ) -> float:
    """tau in [0, dt] with z0 + s v0 tau - g tau^2 / 2 = target (s = +1 forward, -1 backward)."""
    s = 1.0 if forward else -1.0
    a, b, c = -0.5 * g, s * v0, z0 - target
    disc = max(b * b - 4.0 * a * c, 0.0)
    roots = [(-b + r) / (2.0 * a) for r in (math.sqrt(disc), -math.sqrt(disc))] if a else [-c / b]
    ok = [r for r in roots if -1e-9 * dt <= r <= dt * (1 + 1e-9)]
    return min(ok) if ok else min(max(-c / b if b else 0.0, 0.0), dt)


def parse_crossings(path: Path, *, radius: float, dt: float, g: float, h_min: float = H_MIN
                    ) -> DemBounces:
    """Contacts from the crossings dump of ``bounce.in`` (see the module docstring)."""
    frames = read_dump(path)
    steps = np.array([f.step for f in frames], dtype=np.int64)
    z = np.array([f["z"][0] for f in frames])
    vz = np.array([f["vz"][0] for f in frames])
    fc = (np.array([f["v_fc"][0] for f in frames]) if frames and "v_fc" in frames[0].columns
          else np.full(len(frames), np.nan))
    # zero contact force: the clamped force is exactly 0 (rounding of fz - gravity aside)
    zero = np.abs(fc) <= 1e-12 * (np.nanmax(np.abs(fc)) if np.isfinite(fc).any() else 0.0)
    t_start, t_end, v_in, v_out, t_free = [], [], [], [], []
    for i in range(len(steps) - 1):
        if (t_start and len(t_free) < len(t_start) and z[i] <= radius and zero[i]
                and steps[i] * dt > t_start[-1]):
            t_free.append(steps[i] * dt - 0.5 * dt)  # the force ended during the step before
        if steps[i + 1] != steps[i] + 1:
            continue
        above0, above1 = z[i] > radius, z[i + 1] > radius
        if above0 and not above1:  # landing: the last flight step is i
            tau = _solve_parabola(z[i], vz[i], g, radius, dt, forward=True)
            t_start.append(steps[i] * dt + tau)
            v_in.append(-(vz[i] - g * tau))
        elif above1 and not above0 and t_start:  # take-off: the first flight step is i + 1
            tau = _solve_parabola(z[i + 1], vz[i + 1], g, radius, dt, forward=False)
            t_end.append(steps[i + 1] * dt - tau)
            v_out.append(vz[i + 1] + g * tau)
            if len(t_free) < len(t_start):  # no force-free overlap: the force ended with it
                t_free.append(t_end[-1])
    n = len(t_start)
    t_end += [math.nan] * (n - len(t_end))
    v_out += [math.nan] * (n - len(v_out))
    t_free += [math.nan] * (n - len(t_free))
    return DemBounces(np.array(t_start), np.array(t_end[:n]), np.array(v_in), np.array(v_out[:n]),
                      g=g, h_min=h_min, t_force_end=np.array(t_free[:n]))


def run_drop(b: Ball, law: LawSpec, workdir: Path, *, gic: int, dt: float, t_max: float,
             g: float = STANDARD_GRAVITY, h_min: float = H_MIN, np_: int = 1,
             tick: Callable[[float], None] | None = None,
             start: Callable[[], None] | None = None) -> DemBounces:
    """One DEM drop of ball ``b`` with ``law`` (see ``inputs/bounce.in``); ``tick`` and
    ``start`` as for :func:`~viscontact.demstudy.engine.run_lammps`."""
    workdir.mkdir(parents=True, exist_ok=True)
    mat = ball_material(b)
    (workdir / "coeffs.lmp").write_text(coeff_text(
        law, mat, [Wall("plate", "zplane 0.0 NULL")], m_eff=b.mass / 2.0, r_eff=b.radius / 2.0))
    run_lammps("bounce.in", workdir, {
        "coeffs": "coeffs.lmp", "radius": b.radius, "mass": b.mass, "height": DROP_HEIGHT,
        "dt": dt, "tmax": t_max, "g": g, "gic": gic, "kh": b.k_hertz, "hrest": h_min * 1e-2,
        "crossings": "crossings.txt"}, np_=1, tick=tick, start=start)
    return parse_crossings(workdir / "crossings.txt", radius=b.radius, dt=dt, g=g, h_min=h_min)


@dataclass
class BounceCase:
    """One ball and one law: the exact sequence and the two DEM runs."""

    ball: str
    model: str
    law: LawSpec
    exact: theory.BounceSequence
    dem: DemBounces  # gravity during contact (the physical drop)
    isolated: DemBounces | None = None  # gravity only in flight (the check against exact)
    exact_at_dem: list[float] = field(default_factory=list)  # exact e at each DEM impact speed
    exact_at_isolated: list[float] = field(default_factory=list)  # same for the check run
    dt: float = 0.0
    tc_at_dem: list[float] = field(default_factory=list)  # exact force contact time there [s]

    def gravity_drop(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(e_exact(v) - e_DEM, (1 - e_exact(v)) g t_c / v, g t_c / v) at each DEM impact
        (gravity during contact), t_c the exact force contact time at v: the drop of e that
        gravity during contact causes, the bound the study states for it while g t_c / v is
        small (:data:`GRAVITY_SMALL`), and g t_c / v."""
        ex = np.array(self.exact_at_dem, dtype=float)
        gtv = self.dem.g * np.array(self.tc_at_dem, dtype=float) / self.dem.v_in
        return ex - self.dem.e, (1.0 - ex) * gtv, gtv


def run_bounces(workdir: Path, *, balls: tuple[str, ...] = ("ILB", "OLB"),
                models: tuple[str, ...] = STUDY_MODELS, steps_per_contact: int = 1000,
                t_cap: float = 30.0, check: bool = True, h_min: float = H_MIN,
                step: Callable[[str], None] | None = None) -> list[BounceCase]:
    """Every ball with every law: exact sequence, DEM with gravity in contact, and (``check``)
    DEM with gravity only in flight.  dt = t_c(elastic, 171.6 cm/s) / steps_per_contact."""
    from ..collision.impact import impact

    def one(item: tuple[Ball, float, str, PhysicalCalibration]) -> BounceCase:
        """One ball with one law: the exact sequence and its two DEM drops (concurrently)."""
        b, dt, m, cal = item
        key = b.key
        law = LawSpec(m, b.e, b.v_in, cal.beta)
        ex = theory.bounce_sequence(m, m=b.mass, k_hertz=b.k_hertz, c=cal.c, tau=cal.tau,
                                    height=DROP_HEIGHT, h_min=h_min)
        t_max = min(ex.t_rest + 0.2, t_cap)

        def drop(gic: int) -> DemBounces:
            what, sub = (("DEM with gravity", "") if gic else
                         ("DEM, gravity only in flight", "-isolated"))
            return run_drop(b, law, workdir / f"bounce-{key}-{m}{sub}", gic=gic, dt=dt,
                            t_max=t_max, h_min=h_min,
                            start=(lambda: step(f"bounce {key} {m}: {what}")) if step else None)

        dem, iso = jobs.pmap(drop, (1, 0)) if check else (drop(1), None)

        def exact_at(run: DemBounces | None) -> tuple[list[float], list[float]]:
            # the exact single collision at each impact speed the DEM run saw: (e, t_c)
            if run is None:
                return [], []
            res = [impact(m, m_eff=b.mass, k_hertz=b.k_hertz, v=float(v), c=cal.c,
                          tau=cal.tau, history=False) if math.isfinite(e) else None
                   for v, e in zip(run.v_in, run.e)]
            return ([math.nan if r is None else r.e for r in res],
                    [math.nan if r is None else r.tc for r in res])

        e_dem, tc_dem = exact_at(dem)
        return BounceCase(key, m, law, ex, dem, iso, e_dem, exact_at(iso)[0], dt, tc_dem)

    items = []
    for key in balls:
        b = load_balls()[key]
        cals = calibrate_ball(b, models)
        dt = hertz_limit(b.mass, b.k_hertz, b.v_in)[0] / steps_per_contact
        items += [(b, dt, m, cal) for m, cal in cals.items()]
    return jobs.pmap(one, items)
