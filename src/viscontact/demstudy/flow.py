"""Collapse of a granular column (issue 12, item 3).

A column of frictional polydisperse spheres (diameters uniform in [0.8, 1.2] d0) is built
behind a gate on a frictional floor in a slab periodic in y (``inputs/collapse_prepare.in``,
one settled column per random seed, shared by all laws); the gate is removed and the column
spreads (``inputs/collapse.in``) until it rests.  Every law is calibrated to the same e at the
flow's typical impact speed v_ref = sqrt(g d0) (the velocity scale of grains in the flowing
layer).  Observables of the deposit: the normalised run-out (L_f - L0) / L0 (L_f: the front,
the 99th percentile of x; laboratory and DEM collapses of aspect ratio a = H0 / L0 below about
3 give about 1.2 a (Lube et al., J. Fluid Mech. 508 (2004) 175; Lajeunesse et al., Phys. Fluids
17 (2005) 103302)), and the angle of the deposit's free surface.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..dimensional import STANDARD_GRAVITY, hertz_limit
from ..laws import STUDY_MODELS
from .engine import LawSpec, Material, Wall, coeff_text, read_dump, read_thermo, run_lammps

__all__ = ["FlowSetup", "QUICK_FLOW", "FULL_FLOW", "CollapseRun", "FlowStudy", "run_flow",
           "deposit_profile", "runout_and_slope"]


@dataclass(frozen=True)
class FlowSetup:
    """Column collapse parameters (SI): mean diameter d0, density rho, column L0 x H0 (in d0)
    in a slab of depth W (in d0), material E, nu, friction mu, restitution e at v_ref =
    sqrt(g d0) (Jian: beta), random seeds, steps per (fastest) contact."""

    d0: float = 1e-3
    rho: float = 2500.0
    E: float = 1e6
    nu: float = 0.3
    mu: float = 0.5
    e: float = 0.5
    beta: float = 0.5
    L0_d: float = 5.0
    H0_d: float = 10.0
    W_d: float = 4.0
    seeds: tuple[int, ...] = (11, 12)
    steps_per_contact: int = 50
    g: float = STANDARD_GRAVITY
    t_settle: float = 0.3
    t_max: float = 1.0

    @property
    def vref(self) -> float:
        return math.sqrt(self.g * self.d0)

    @property
    def mass0(self) -> float:
        return self.rho * math.pi * self.d0 ** 3 / 6.0

    @property
    def material(self) -> Material:
        return Material(E=self.E, nu=self.nu, mu=self.mu)

    @property
    def dt(self) -> float:
        # the fastest impacts: the smallest spheres falling from the top of the loose column
        v = math.sqrt(2.0 * self.g * 2.0 * self.H0_d * self.d0)
        m = self.mass0 * 0.8 ** 3
        estar = self.E / (2.0 * (1.0 - self.nu ** 2))
        k = 4.0 / 3.0 * estar * math.sqrt(0.2 * self.d0)
        return hertz_limit(m / 2.0, k, v)[0] / self.steps_per_contact


QUICK_FLOW = FlowSetup()
FULL_FLOW = FlowSetup(L0_d=8.0, H0_d=16.0, W_d=5.0, seeds=(11, 12, 13, 14, 15))


@dataclass
class CollapseRun:
    model: str
    seed: int
    L0: float
    H0: float
    runout: float  # (L_f - L0) / L0
    angle: float  # deposit surface angle [deg]
    t_rest: float
    dump: Path
    final: dict[str, np.ndarray] = field(repr=False, default_factory=dict)
    wall_s: float = 0.0
    steps: int = 0


@dataclass
class FlowStudy:
    setup: FlowSetup
    runs: list[CollapseRun]
    n_particles: int = 0

    def law_effect(self, attr: str) -> tuple[float, float]:
        """(F, p) of a two-way analysis of variance of ``attr`` (``runout``, ``angle``) with the
        law and the seed as factors (every law collapses the same column of each seed): p is
        the probability of law means at least this different if the law changed nothing.
        NaN with fewer than two laws or seeds."""
        from scipy.stats import f as fdist

        laws = list(self.by_law())
        seeds = sorted({r.seed for r in self.runs})
        if len(laws) < 2 or len(seeds) < 2:
            return math.nan, math.nan
        val = {(r.model, r.seed): getattr(r, attr) for r in self.runs}
        Y = np.array([[val[(m, sd)] for sd in seeds] for m in laws])
        a, b = Y.shape
        gm = Y.mean()
        ss_law = b * ((Y.mean(1) - gm) ** 2).sum()
        ss_seed = a * ((Y.mean(0) - gm) ** 2).sum()
        ss_err = ((Y - gm) ** 2).sum() - ss_law - ss_seed
        if ss_err <= 0:
            return math.nan, math.nan
        F = (ss_law / (a - 1)) / (ss_err / ((a - 1) * (b - 1)))
        return float(F), float(fdist.sf(F, a - 1, (a - 1) * (b - 1)))

    def by_law(self) -> dict[str, list[CollapseRun]]:
        out: dict[str, list[CollapseRun]] = {}
        for r in self.runs:
            out.setdefault(r.model, []).append(r)
        return out


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


def runout_and_slope(cols: dict[str, np.ndarray], L0: float, d0: float) -> tuple[float, float]:
    """(normalised run-out (L_f - L0) / L0, surface angle [deg]) of a deposit.

    L_f is the 99th percentile of the spheres' x + radius (a few grains rolling far ahead do
    not count); the angle is that of the least-squares line through the free surface where its
    height above the rough floor (whose top is at d0) lies between 20 % and 80 % of its
    largest (the single layer of grains spread beyond the foot is left out).
    """
    g = cols["type"] == 1 if "type" in cols else slice(None)
    x, z, r = cols["x"][g], cols["z"][g], cols["radius"][g]
    front = float(np.percentile(x + r, 99.0))
    xs, hs = deposit_profile(x, z + r, 2.0 * d0)
    hs = hs - d0
    hmax = hs.max()
    sel = (hs > 0.2 * hmax) & (hs < 0.8 * hmax)
    if sel.sum() >= 2:
        slope = np.polyfit(xs[sel], hs[sel], 1)[0]
        angle = math.degrees(math.atan(abs(slope)))
    else:
        angle = math.nan
    return (front - L0) / L0, angle


def run_flow(workdir: Path, setup: FlowSetup = QUICK_FLOW, *,
             models: tuple[str, ...] = STUDY_MODELS, np_: int = 1,
             step: Callable[[str], None] | None = None) -> FlowStudy:
    """Build one column per seed, collapse it with every law, measure the deposits."""
    import time

    s = setup
    d0 = s.d0
    L0, H0, W = s.L0_d * d0, s.H0_d * d0, s.W_d * d0
    xmax = L0 + 4.0 * H0
    mat = s.material
    m_eff, r_eff = s.mass0 / 2.0, d0 / 4.0
    runs: list[CollapseRun] = []
    n_part = 0
    settle_law = LawSpec("Ts", s.e, s.vref)
    for seed in s.seeds:
        wd = workdir / f"column-{seed}"
        wd.mkdir(parents=True, exist_ok=True)
        if step:
            step(f"flow: building the column (seed {seed})")
        (wd / "coeffs-settle.lmp").write_text(coeff_text(
            settle_law, mat, [Wall("floor", "zplane 0.0 NULL"), Wall("gate", f"xplane 0.0 {L0!r}")],
            m_eff=m_eff, r_eff=r_eff))
        run_lammps("collapse_prepare.in", wd, {
            "d0": d0, "rho": s.rho, "L0": L0, "H0": H0, "W": W, "xmax": xmax, "seed": seed,
            "dt": s.dt, "g": s.g, "coeffs": "coeffs-settle.lmp", "tsettle": s.t_settle,
            "data": "column.data"}, np_=np_, log="log-prepare.lammps")
        for m in models:
            if step:
                step(f"flow: collapse with {m} (seed {seed})")
            law = LawSpec(m, s.e, s.vref, s.beta if m == "Jian" else None)
            d = wd / f"collapse-{m}"
            d.mkdir(exist_ok=True)
            (d / "column.data").write_bytes((wd / "column.data").read_bytes())
            (d / "coeffs.lmp").write_text(coeff_text(
                law, mat, [Wall("floor", "zplane 0.0 NULL"), Wall("back", "xplane 0.0 NULL")],
                m_eff=m_eff, r_eff=r_eff))
            nthermo = max(1, int(0.005 / s.dt))
            kestop = 1e-4 * s.mass0 * s.g * d0  # J per sphere
            t1 = time.perf_counter()
            log = run_lammps("collapse.in", d, {
                "data": "column.data", "coeffs": "coeffs.lmp", "g": s.g, "dt": s.dt,
                "tmin": 0.1, "tmax": s.t_max, "kestop": kestop,
                "nthermo": nthermo, "ndump": nthermo * 10, "dump": f"collapse-{m}.dump"},
                np_=np_)
            wall = time.perf_counter() - t1
            th = read_thermo(log)
            frames = read_dump(d / f"collapse-{m}.dump")
            first, last = frames[0].columns, frames[-1].columns
            grains = first["type"] == 1
            n_part = int(grains.sum())
            H0_actual = float(np.percentile((first["z"] + first["radius"])[grains], 99.0))
            ro, ang = runout_and_slope(last, L0, d0)
            runs.append(CollapseRun(m, seed, L0, H0_actual, ro, ang, float(th["Time"][-1]),
                                    d / f"collapse-{m}.dump", last, wall, int(th["Step"][-1])))
    return FlowStudy(s, runs, n_part)
