"""Collapse of a granular column (Lube et al. 2005; Lajeunesse et al. 2005).

A column of frictional polydisperse spheres (diameters uniform in [0.8, 1.2] d0) is built
behind a gate on a rough floor (one layer of immobile spheres whose tops lie at z = d0) in a
slab periodic in y (``inputs/collapse_prepare.in``, one settled column per aspect ratio and
random seed, shared by all laws); the gate is removed and the column spreads
(``inputs/collapse.in``) until it rests.  Columns of several aspect ratios a = H0 / L0 hold the
same number of grains (L0 H0 fixed), H0 measured above the floor's top.

Every law is calibrated to the same e at v_ref = sqrt(g H0), the free-fall speed scale of
the column (a grain falling half the column's height); the e each law then has at the grains'
measured peak rms speed and at the grain scale sqrt(g d0) is stated too.  Observables of the deposit: the normalised run-out (L_f - L0) / L0 (L_f: the
front, the 99th percentile of x + radius), the final height H_f / L0 above the floor, the
angle of the free surface, and the time to rest (the kinetic energy per sphere falling below
a threshold, interpolated between samples 0.5 ms apart).  The published quasi-2D scaling they
are set against is in :func:`viscontact.demstudy.theory.collapse_runout` (Lube et al. 2005;
Lajeunesse et al. 2005).  Each law's difference from KK comes with a 95 % interval from the
seeds (:meth:`FlowStudy.law_differences`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..physics.pair import STANDARD_GRAVITY, effective_modulus, hertz_limit, hertz_stiffness
from ..physics.laws import STUDY_MODELS
from . import jobs
from .engine import LawSpec, Material, Wall, coeff_text, read_dump, read_thermo, run_lammps
from ..physics.laws import Jian, KK, Ts

__all__ = ["FlowSetup", "QUICK_FLOW", "FULL_FLOW", "CollapseRun", "FlowStudy", "LawDifference",
           "run_flow", "deposit_profile", "runout_and_slope", "rest_time"]

#: the published scaling is for the deposit above this much of the floor: the rough floor's top
FLOOR_TOP_D = 1.0  # in d0


@dataclass(frozen=True)
class FlowSetup:
    """Column collapse parameters (SI): mean diameter d0, density rho, columns of aspect
    ratios ``aspects`` (H0 / L0, nominal) holding ``area_d`` d0^2 each (L0 H0) in a slab of
    depth W (in d0), material E, nu, friction mu, restitution e at v_ref = sqrt(g H0) (Jian:
    beta), random seeds, steps per (fastest) contact.  ``compare`` is the aspect ratio at which
    every law runs; at the others only ``sweep_models`` run (None: every law)."""

    d0: float = 1e-3
    rho: float = 2500.0
    E: float = 1e6
    nu: float = 0.3
    mu: float = 0.5
    e: float = 0.5
    beta: float = 0.5
    aspects: tuple[float, ...] = (0.5, 1.0, 2.0)
    area_d: float = 50.0
    compare: float = 2.0
    sweep_models: tuple[str, ...] | None = (KK.name,)
    W_d: float = 4.0
    seeds: tuple[int, ...] = (11, 12)
    steps_per_contact: int = 50
    g: float = STANDARD_GRAVITY
    t_settle: float = 0.3
    t_max: float = 1.0
    sample_dt: float = 5e-4  # s between kinetic-energy samples (the rest test)

    def column(self, a: float) -> tuple[float, float]:
        """(L0, H0) [m] of the column of nominal aspect ratio a (H0 above the floor's top)."""
        L0 = math.sqrt(self.area_d / a) * self.d0
        return L0, a * L0

    def vref(self, a: float) -> float:
        """Calibration speed of the column of aspect ratio a: sqrt(g H0) [m/s]."""
        return math.sqrt(self.g * self.column(a)[1])

    @property
    def v_grain(self) -> float:
        """The grain-scale speed sqrt(g d0) [m/s] (the e of each law there is reported)."""
        return math.sqrt(self.g * self.d0)

    @property
    def mass0(self) -> float:
        return self.rho * math.pi * self.d0 ** 3 / 6.0

    @property
    def material(self) -> Material:
        return Material(E=self.E, nu=self.nu, mu=self.mu)

    def dt(self, a: float) -> float:
        """Time step: the fastest impacts, the smallest spheres falling from the top of the
        loose column (built up to twice H0)."""
        v = math.sqrt(2.0 * self.g * 2.0 * (self.column(a)[1] + FLOOR_TOP_D * self.d0))
        m = self.mass0 * 0.8 ** 3
        # the smallest spheres (0.8 d0) meeting: R* = 0.2 d0
        k = hertz_stiffness(effective_modulus(self.E, self.nu, self.E, self.nu), 0.2 * self.d0)
        return hertz_limit(m / 2.0, k, v)[0] / self.steps_per_contact

    def models_at(self, a: float, models: tuple[str, ...]) -> tuple[str, ...]:
        if a == self.compare or self.sweep_models is None:
            return models
        return tuple(m for m in models if m in self.sweep_models)


QUICK_FLOW = FlowSetup()
FULL_FLOW = FlowSetup(aspects=(0.5, 1.0, 2.0, 4.0), area_d=128.0, W_d=5.0,
                      seeds=(11, 12, 13, 14, 15))


@dataclass
class CollapseRun:
    """One collapse: law, seed, nominal aspect ratio; L0, H0 [m] (H0: the settled column's top
    above the floor's top); run-out (L_f - L0) / L0; final height H_f [m] above the floor's top;
    deposit angle [deg]; time to rest [s]; calibration speed v_ref and the grains' peak rms
    speed [m/s]."""

    model: str
    seed: int
    L0: float
    H0: float
    runout: float
    angle: float
    t_rest: float
    dump: Path | None
    aspect: float = math.nan
    height: float = math.nan
    vref: float = math.nan
    v_peak: float = math.nan
    final: dict[str, np.ndarray] = field(repr=False, default_factory=dict)
    wall_s: float = 0.0
    steps: int = 0

    @property
    def a(self) -> float:
        """Measured aspect ratio H0 / L0."""
        return self.H0 / self.L0

    @property
    def front(self) -> float:
        """L_f [m]."""
        return self.L0 * (1.0 + self.runout)


@dataclass(frozen=True)
class LawDifference:
    """A law's mean difference from the reference law over the same columns (seeds), with the
    half-width of its 95 % interval; NaN when it cannot be estimated."""

    model: str
    diff: float
    half95: float


@dataclass
class FlowStudy:
    setup: FlowSetup
    runs: list[CollapseRun]
    n_particles: int = 0
    e_grain: dict[str, float] = field(default_factory=dict)  # e of each law at sqrt(g d0)
    v_peak: float = math.nan  # mean peak rms grain speed at the comparison aspect ratio [m/s]
    e_peak: dict[str, float] = field(default_factory=dict)  # e of each law at v_peak

    def at(self, aspect: float) -> list[CollapseRun]:
        return [r for r in self.runs if r.aspect == aspect]

    def by_law(self, aspect: float | None = None) -> dict[str, list[CollapseRun]]:
        out: dict[str, list[CollapseRun]] = {}
        for r in (self.runs if aspect is None else self.at(aspect)):
            out.setdefault(r.model, []).append(r)
        return out

    def law_differences(self, attr: str, aspect: float | None = None, ref: str = KK.name
                        ) -> tuple[list[LawDifference], float]:
        """Each law's difference from ``ref`` in ``attr`` (``runout``, ``angle``, ``t_rest``,
        ``height``) at one aspect ratio (default: the comparison one), and the smallest
        difference the design detects.

        Every law collapses the same column of each seed, so the seed effect cancels: with Y
        (laws x seeds), the residual of the additive law + seed model gives the error variance
        s^2 (degrees of freedom nu = (laws - 1)(seeds - 1)); a difference of two law means has
        standard error SE = sqrt(2 s^2 / seeds), its 95 % interval is +- t(0.975, nu) SE, and
        the smallest difference a two-sided test at the 5 % level finds with 80 % power is
        (t(0.975, nu) + t(0.80, nu)) SE.  NaN with fewer than two laws or seeds.
        """
        from scipy.stats import t as tdist

        aspect = self.setup.compare if aspect is None else aspect
        by = self.by_law(aspect)
        laws = list(by)
        seeds = sorted({r.seed for r in self.at(aspect)})
        if ref not in by or len(laws) < 2 or len(seeds) < 2:
            return [LawDifference(m, math.nan, math.nan) for m in laws if m != ref], math.nan
        val = {(r.model, r.seed): getattr(r, attr) for r in self.at(aspect)}
        Y = np.array([[val[(m, sd)] for sd in seeds] for m in laws], dtype=float)
        resid = Y - Y.mean(1, keepdims=True) - Y.mean(0, keepdims=True) + Y.mean()
        nu = (len(laws) - 1) * (len(seeds) - 1)
        se = math.sqrt(2.0 * float((resid ** 2).sum()) / nu / len(seeds))
        t95 = float(tdist.ppf(0.975, nu))
        mdd = (t95 + float(tdist.ppf(0.80, nu))) * se
        i_ref = laws.index(ref)
        out = [LawDifference(m, float(Y[i].mean() - Y[i_ref].mean()), t95 * se)
               for i, m in enumerate(laws) if m != ref]
        return out, mdd


def deposit_profile(x: np.ndarray, ztop: np.ndarray, bin_w: float) -> tuple[np.ndarray, np.ndarray]:
    """Free-surface height (highest sphere top) in bins of width bin_w along x."""
    edges = np.arange(0.0, x.max() + bin_w, bin_w)
    idx = np.digitize(x, edges) - 1
    xs, hs = [], []
    for i in range(len(edges) - 1):
        s = idx == i
        if s.any():
            xs.append(0.5 * (edges[i] + edges[i + 1]))
            hs.append(ztop[s].max())
    return np.array(xs), np.array(hs)


def runout_and_slope(cols: dict[str, np.ndarray], L0: float, d0: float
                     ) -> tuple[float, float, float]:
    """(normalised run-out (L_f - L0) / L0, surface angle [deg], final height H_f [m]) of a
    deposit.

    L_f is the 99th percentile of the spheres' x + radius (a few grains rolling far ahead do
    not count); H_f the highest point of the free surface (highest sphere top in bins of 2 d0)
    above the rough floor's top (z = d0); the angle is that of the least-squares line through
    the free surface where its height above the floor lies between 20 % and 80 % of H_f (the
    single layer of grains spread beyond the foot is left out).
    """
    g = cols["type"] == 1 if "type" in cols else slice(None)
    x, z, r = cols["x"][g], cols["z"][g], cols["radius"][g]
    front = float(np.percentile(x + r, 99.0))
    xs, hs = deposit_profile(x, z + r, 2.0 * d0)
    hs = hs - FLOOR_TOP_D * d0
    hmax = float(hs.max())
    sel = (hs > 0.2 * hmax) & (hs < 0.8 * hmax)
    if sel.sum() >= 2:
        slope = np.polyfit(xs[sel], hs[sel], 1)[0]
        angle = math.degrees(math.atan(abs(slope)))
    else:
        angle = math.nan
    return (front - L0) / L0, angle, hmax


def rest_time(t: np.ndarray, ke: np.ndarray, threshold: float, t_min: float) -> float:
    """First time after ``t_min`` at which the kinetic energy ``ke`` falls below ``threshold``,
    interpolated linearly in ln(ke) between the two samples around the crossing [s]; the last
    sample time if it never does (NaN for no samples)."""
    t = np.asarray(t, dtype=float)
    ke = np.asarray(ke, dtype=float)
    if not t.size:
        return math.nan
    below = np.nonzero((t > t_min) & (ke < threshold))[0]
    if not below.size:
        return float(t[-1])
    i = int(below[0])
    if i == 0 or ke[i - 1] <= 0.0 or ke[i] <= 0.0:
        return float(t[i])
    f = (math.log(ke[i - 1]) - math.log(threshold)) / (math.log(ke[i - 1]) - math.log(ke[i]))
    return float(t[i - 1] + f * (t[i] - t[i - 1]))


def _e_at(law: LawSpec, s: FlowSetup, v: float) -> float:
    """e of two spheres of diameter d0 under ``law`` (c0, tau of that pair) at impact speed v."""
    from .. import dem
    from ..physics.pair import ContactPair
    from ..collision.impact import impact

    k = hertz_stiffness(effective_modulus(s.E, s.nu, s.E, s.nu), s.d0 / 4.0)
    m_eff = s.mass0 / 2.0
    dl = dem.contact_law(law.model, e=law.e, vref=law.vref, beta=law.beta)
    c0, tau = dl.physical(ContactPair.from_effective(m_eff=m_eff, k_hertz=k))
    return float(impact(law.model, m_eff=m_eff, k_hertz=k, v=v, c=c0, tau=tau,
                        history=False).e)


def run_flow(workdir: Path, setup: FlowSetup = QUICK_FLOW, *,
             models: tuple[str, ...] = STUDY_MODELS, np_: int = 1,
             step: Callable[[str], None] | None = None) -> FlowStudy:
    """Build one column per aspect ratio and seed, collapse it with every law that runs at
    that aspect ratio, measure the deposits."""
    import time

    s = setup
    d0 = s.d0
    W = s.W_d * d0
    mat = s.material
    m_eff, r_eff = s.mass0 / 2.0, d0 / 4.0

    def column(item: tuple[float, int]) -> list[tuple[CollapseRun, int]]:
        """Build one column (aspect ratio, seed) and collapse it with every law there:
        [(run, grains)]."""
        aspect, seed = item
        L0, H0 = s.column(aspect)
        xmax = L0 + 4.0 * (H0 + d0) + 4.0 * L0
        vref = s.vref(aspect)
        dt = s.dt(aspect)
        settle_law = LawSpec(Ts.name, s.e, vref)
        wd = workdir / f"column-a{aspect:g}-{seed}"
        wd.mkdir(parents=True, exist_ok=True)
        (wd / "coeffs-settle.lmp").write_text(coeff_text(
            settle_law, mat,
            [Wall("floor", "zplane 0.0 NULL"), Wall("gate", f"xplane 0.0 {L0!r}")],
            m_eff=m_eff, r_eff=r_eff))
        run_lammps("collapse_prepare.in", wd, {
            "d0": d0, "rho": s.rho, "L0": L0, "H0": H0 + FLOOR_TOP_D * d0, "W": W,
            "xmax": xmax, "seed": seed, "dt": dt, "g": s.g,
            "coeffs": "coeffs-settle.lmp", "tsettle": s.t_settle, "data": "column.data"},
            np_=np_, log="log-prepare.lammps", start=(lambda: step(
                f"flow: building the column a = {aspect:g} (seed {seed})")) if step else None)

        def collapse(m: str) -> tuple[CollapseRun, int]:
            law = LawSpec(m, s.e, vref, s.beta if m == Jian.name else None)
            d = wd / f"collapse-{m}"
            d.mkdir(exist_ok=True)
            (d / "column.data").write_bytes((wd / "column.data").read_bytes())
            (d / "coeffs.lmp").write_text(coeff_text(
                law, mat, [Wall("floor", "zplane 0.0 NULL"), Wall("back", "xplane 0.0 NULL")],
                m_eff=m_eff, r_eff=r_eff))
            nthermo = max(1, int(round(s.sample_dt / dt)))
            ndump = nthermo * max(1, int(round(0.05 / s.sample_dt)))
            kestop = 1e-4 * s.mass0 * s.g * d0  # J per sphere
            t1 = [time.perf_counter()]

            def started() -> None:  # the wall time counts from the start of LAMMPS
                t1[0] = time.perf_counter()
                if step:
                    step(f"flow: collapse a = {aspect:g} with {m} (seed {seed})")

            log = run_lammps("collapse.in", d, {
                "data": "column.data", "coeffs": "coeffs.lmp", "g": s.g, "dt": dt,
                "tmin": 0.1, "tmax": s.t_max, "kestop": kestop,
                "nthermo": nthermo, "ndump": ndump, "dump": f"collapse-{m}.dump"},
                np_=np_, start=started)
            wall = time.perf_counter() - t1[0]
            th = read_thermo(log)
            frames = read_dump(d / f"collapse-{m}.dump")
            first, last = frames[0].columns, frames[-1].columns
            grains = first["type"] == 1
            n_grains = int(grains.sum())
            H0_m = float(np.percentile((first["z"] + first["radius"])[grains], 99.0)
                         ) - FLOOR_TOP_D * d0
            ro, ang, hf = runout_and_slope(last, L0, d0)
            mass = float(np.sum(s.rho * math.pi / 6.0 * (2.0 * first["radius"][grains]) ** 3))
            v_peak = math.sqrt(2.0 * float(np.max(th["c_ke"])) / mass)
            t_rest = rest_time(th["Time"], th["c_ke"], kestop * n_grains, 0.1)
            return CollapseRun(
                m, seed, L0, H0_m, ro, ang, t_rest, d / f"collapse-{m}.dump", aspect=aspect,
                height=hf, vref=vref, v_peak=v_peak, final=last, wall_s=wall,
                steps=int(th["Step"][-1])), n_grains

        return jobs.pmap(collapse, s.models_at(aspect, models))

    done = [x for col in jobs.pmap(column, [(a, seed) for a in s.aspects for seed in s.seeds])
            for x in col]
    runs = [r for r, _ in done]
    n_part = done[-1][1] if done else 0  # grains of the last run
    # each law's e at the grain speed scale sqrt(g d0), calibrated as at the compared column
    e_grain = {m: _e_at(LawSpec(m, s.e, s.vref(s.compare), s.beta if m == Jian.name else None),
                        s, s.v_grain)
               for m in dict.fromkeys(r.model for r in runs if r.aspect == s.compare)}
    cmp_runs = [r for r in runs if r.aspect == s.compare]
    v_peak = float(np.mean([r.v_peak for r in cmp_runs])) if cmp_runs else math.nan
    e_peak = {m: _e_at(LawSpec(m, s.e, s.vref(s.compare), s.beta if m == Jian.name else None), s,
                       v_peak) for m in dict.fromkeys(r.model for r in cmp_runs)}
    return FlowStudy(s, runs, n_part, e_grain, v_peak, e_peak)
