"""A freely cooling granular gas (issue 12, item 1).

Smooth monodisperse spheres in a periodic box: placed at random, thermalised by elastic
collisions (``inputs/gas_prepare.in``), then cooled by each law calibrated to the same e at the
rms normal impact speed of the initial gas, v_ref = sqrt(<g_n^2>) = 2 sqrt(T0 / m)
(``inputs/gas_cool.in``).  T(t) = m <v^2> / 3 is compared with Haff's law (Ts: constant e) and
the late-time exponent of every law with -2 / (1 + q) (:mod:`.theory`).

Homogeneity is checked on the dumps: the variance of the number of spheres in cubic cells
(about 8 spheres per cell) over its value in the thermalised elastic gas (1 while the density
stays as uniform as at the start; clusters raise it), and the kinetic energy of the
cell-averaged flow over the value for independent velocities, 1 / (spheres per cell)
(1 while there is no large-scale flow; shear bands and vortices raise it).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..dimensional import hertz_limit
from ..laws import STUDY_MODELS
from . import theory
from .engine import (
    LawSpec, Material, coeff_text, read_dump, read_thermo, run_lammps, sim_time_ticker,
)

__all__ = ["GasSetup", "GasRun", "GasStudy", "QUICK_GAS", "FULL_GAS", "run_gas", "homogeneity",
           "fit_late_exponent", "haff_deviation"]


@dataclass(frozen=True)
class GasSetup:
    """Parameters of the gas (SI).

    n spheres of diameter sigma and density rho at volume fraction phi; initial granular
    temperature from the rms speed v_rms = sqrt(<v^2>); restitution e at v_ref (Jian: beta);
    stiffness chosen so that the contact time at v_ref is ``tc_ratio`` mean free times;
    ``steps_per_contact`` time steps per contact; simulated time ``t_end_tau0`` Haff times of
    the Ts gas; ``thermo_per_tau0`` samples of T per tau0 (at the start).
    """

    n: int = 2000
    phi: float = 0.1
    sigma: float = 1e-3
    rho: float = 2500.0
    nu: float = 0.3
    v_rms: float = 1.0
    e: float = 0.8
    beta: float = 0.5
    tc_ratio: float = 0.04
    steps_per_contact: int = 50
    t_end_tau0: float = 5.0
    equil_collisions: float = 5.0
    seed: int = 2024
    samples_per_tau0: int = 40
    dumps: int = 8

    @property
    def mass(self) -> float:
        return self.rho * math.pi * self.sigma ** 3 / 6.0

    @property
    def T0(self) -> float:
        return self.mass * self.v_rms ** 2 / 3.0

    @property
    def n_density(self) -> float:
        return 6.0 * self.phi / (math.pi * self.sigma ** 3)

    @property
    def box(self) -> float:
        return (self.n / self.n_density) ** (1.0 / 3.0)

    @property
    def vref(self) -> float:
        """rms normal relative speed of colliding pairs in a Maxwellian gas: 2 sqrt(T0 / m)."""
        return 2.0 * math.sqrt(self.T0 / self.mass)

    @property
    def free_time(self) -> float:
        return 1.0 / theory.collision_frequency(self.T0, n=self.n_density, sigma=self.sigma,
                                                m=self.mass, phi=self.phi)

    @property
    def k_hertz(self) -> float:
        """k of a pair (m* = m / 2) whose elastic contact time at v_ref is tc_ratio free times:
        t_c = 3.218 (m* / k)^(2/5) v^(-1/5)."""
        tc = self.tc_ratio * self.free_time
        return (self.mass / 2.0) * (3.2180654597 / (tc * self.vref ** 0.2)) ** 2.5

    @property
    def material(self) -> Material:
        r = self.sigma / 4.0  # R* of two equal spheres
        estar = 3.0 * self.k_hertz / (4.0 * math.sqrt(r))
        return Material(E=2.0 * estar * (1.0 - self.nu ** 2), nu=self.nu)

    @property
    def dt0(self) -> float:
        # the fastest impacts of a Maxwellian gas (about 3 v_ref) last 3^(-1/5) as long
        tc = hertz_limit(self.mass / 2.0, self.k_hertz, 3.0 * self.vref)[0]
        return tc / self.steps_per_contact

    def prepare_variables(self, coeffs: str, data: str) -> dict[str, object]:
        """The ``-var`` values of ``inputs/gas_prepare.in`` for this gas."""
        nequil = int(math.ceil(self.equil_collisions * self.free_time / self.dt0))
        return {"n": self.n, "phi": self.phi, "sigma": self.sigma, "rho": self.rho,
                "seed": self.seed, "T0": self.T0, "dt": self.dt0, "nequil": nequil,
                "coeffs": coeffs, "data": data}

    def cool_variables(self, coeffs: str, data: str, dump: str) -> dict[str, object]:
        """The ``-var`` values of ``inputs/gas_cool.in``: T sampled ``samples_per_tau0`` times
        per tau0 at the start, the time step updated every 4 samples, ``dumps`` dumps."""
        tau0 = self.tau0()
        per_tau0 = tau0 / self.dt0
        nthermo = max(1, int(per_tau0 / self.samples_per_tau0))
        nseg = nthermo * 4
        # dumps spread over the run at equal step counts (the time step grows slowly)
        est_steps = per_tau0 * _haff_step_integral(self.t_end_tau0)
        ndump = max(nseg, int(est_steps / max(1, self.dumps)) // nseg * nseg)
        return {"data": data, "coeffs": coeffs, "T0": self.T0, "dt0": self.dt0,
                "tend": self.t_end_tau0 * tau0, "nseg": nseg, "nthermo": nthermo,
                "ndump": ndump, "dump": dump}

    def tau0(self, e: float | None = None) -> float:
        return theory.haff_tau0(self.e if e is None else e, n=self.n_density, sigma=self.sigma,
                                m=self.mass, T0=self.T0, phi=self.phi)


QUICK_GAS = GasSetup(n=2000, phi=0.05, t_end_tau0=4.0, tc_ratio=0.01, dumps=4)
FULL_GAS = GasSetup(n=4000, phi=0.05, t_end_tau0=100.0, tc_ratio=0.02, dumps=12)


@dataclass
class GasRun:
    """One law's cooling: time [s], T [J], the dump path and homogeneity measures per dump."""

    model: str
    law: LawSpec
    t: np.ndarray
    T: np.ndarray
    dump: Path
    dump_t: np.ndarray = field(default_factory=lambda: np.empty(0))
    density_ratio: np.ndarray = field(default_factory=lambda: np.empty(0))
    flow_ratio: np.ndarray = field(default_factory=lambda: np.empty(0))
    exponent: float = math.nan
    exponent_err: float = math.nan
    wall_s: float = 0.0
    steps: int = 0
    fit_from: float = math.nan  # start of the late-time fit [s]


@dataclass
class GasStudy:
    setup: GasSetup
    runs: dict[str, GasRun]
    elastic_density_var: float  # var/mean of cell counts in the thermalised elastic gas
    haff_max_dev: float = math.nan  # Ts: max |T / T_Haff - 1| over t <= haff_window tau0
    haff_window: float = 4.0
    particle_steps: float = 0.0
    wall_s: float = 0.0


def _cells(setup: GasSetup) -> int:
    return max(2, round((setup.n / 8.0) ** (1.0 / 3.0)))


def homogeneity(x: np.ndarray, v: np.ndarray, box: float, cells: int) -> tuple[float, float]:
    """(var/mean of sphere counts per cell, flow energy / (thermal energy / spheres per cell)).

    x, v: (N, 3) positions in [0, box) and velocities.  The second is the kinetic energy of
    the cell-averaged velocity field (mass-weighted) over the total, divided by 1/<n_cell>:
    about 1 for independent velocities, larger when a large-scale flow has formed.
    """
    idx = np.floor(np.mod(x, box) / box * cells).astype(int).clip(0, cells - 1)
    flat = (idx[:, 0] * cells + idx[:, 1]) * cells + idx[:, 2]
    counts = np.bincount(flat, minlength=cells ** 3).astype(float)
    mean = counts.mean()
    dens = counts.var() / mean
    mom = np.stack([np.bincount(flat, weights=v[:, j], minlength=cells ** 3) for j in range(3)], 1)
    ok = counts > 0
    flow = (np.sum(mom[ok] ** 2 / counts[ok, None]))  # sum over cells n |u|^2
    total = np.sum(v ** 2)
    return float(dens), float(flow / total * mean)


def fit_late_exponent(t: np.ndarray, T: np.ndarray, t_from: float) -> tuple[float, float]:
    """Exponent a of T = A (1 + t / tau)^(-a) fitted (least squares in log T, tau free) to the
    samples with t >= t_from; returns (-a, one-sigma uncertainty)."""
    from scipy.optimize import curve_fit

    sel = (t >= t_from) & (T > 0)
    if sel.sum() < 6:
        return math.nan, math.nan
    tt, lt = t[sel], np.log(T[sel])

    def model(x, lnA, a, lntau):
        return lnA - a * np.log1p(x / np.exp(lntau))

    p0 = [lt[0] + 2.0 * math.log1p(1.0), 2.0, math.log(t_from)]
    try:
        p, cov = curve_fit(model, tt, lt, p0=p0, maxfev=20000)
    except (RuntimeError, ValueError):
        return math.nan, math.nan
    err = math.sqrt(cov[1, 1]) if np.all(np.isfinite(cov)) else math.nan
    return -float(p[1]), err


def haff_deviation(t: np.ndarray, T: np.ndarray, T0: float, tau0: float, window: float,
                   block: float = 0.25) -> tuple[np.ndarray, np.ndarray]:
    """T / T_Haff - 1 averaged over blocks of ``block`` tau0 up to ``window`` tau0 (both the
    measured and Haff's T averaged over the same samples): (block centres / tau0, deviations)."""
    edges = np.arange(0.0, window + 1e-12, block) * tau0
    mids, dev = [], []
    th_T = theory.haff_temperature(t, T0, tau0)
    for a, b in zip(edges[:-1], edges[1:]):
        s = (t >= a) & (t < b)
        if s.sum() >= 2:
            mids.append(0.5 * (a + b) / tau0)
            dev.append(T[s].mean() / th_T[s].mean() - 1.0)
    return np.array(mids), np.array(dev)


def run_gas(workdir: Path, setup: GasSetup = QUICK_GAS, *, models: tuple[str, ...] = STUDY_MODELS,
            np_: int = 1, step: Callable[[str], None] | None = None) -> GasStudy:
    """Prepare the thermalised gas once, cool it with every law; analyse T(t) and the dumps."""
    import time

    workdir.mkdir(parents=True, exist_ok=True)
    s = setup
    mat = s.material
    m_eff, r_eff = s.mass / 2.0, s.sigma / 4.0
    tau0 = s.tau0()
    if step:
        step(f"gas: {s.n} spheres, elastic thermalisation")
    (workdir / "coeffs-elastic.lmp").write_text(
        coeff_text(LawSpec("LH", 1.0, s.vref), mat, m_eff=m_eff, r_eff=r_eff))
    pv = s.prepare_variables("coeffs-elastic.lmp", "gas-start.data")
    run_lammps("gas_prepare.in", workdir, pv, np_=np_, log="log-prepare.lammps")
    steps_total = int(pv["nequil"])
    start = _read_data_xv(workdir / "gas-start.data", s.n)
    cells = _cells(s)
    dens0, _ = homogeneity(start[0], start[1], s.box, cells)
    runs = {}
    for m in models:
        if step:
            step(f"gas: cooling with {m}")
        law = LawSpec(m, s.e, s.vref, s.beta if m == "Jian" else None)
        d = workdir / f"gas-{m}"
        d.mkdir(exist_ok=True)
        (d / "coeffs.lmp").write_text(coeff_text(law, mat, m_eff=m_eff, r_eff=r_eff))
        (d / "gas-start.data").write_bytes((workdir / "gas-start.data").read_bytes())
        t1 = time.perf_counter()
        tick = sim_time_ticker(d / "log.lammps", s.t_end_tau0 * tau0, tau0,
                               f"gas: cooling with {m} (t in tau0)", step)
        log = run_lammps("gas_cool.in", d, s.cool_variables("coeffs.lmp", "gas-start.data",
                                                             f"gas-{m}.dump"), np_=np_, tick=tick)
        wall = time.perf_counter() - t1
        th = read_thermo(log)
        t, T = th["Time"], th["v_Tg"]
        t, keep = np.unique(t, return_index=True)  # a segment's first line repeats the last
        T = T[keep]
        steps_total += int(th["Step"][-1])
        run = GasRun(m, law, t, T, d / f"gas-{m}.dump", wall_s=wall, steps=int(th["Step"][-1]))
        frames = read_dump(run.dump)
        dt_list, dr, fr = [], [], []
        for f in frames:
            step_no, cols = f.step, f.columns
            x = np.stack([cols["x"], cols["y"], cols["z"]], 1)
            v = np.stack([cols["vx"], cols["vy"], cols["vz"]], 1)
            dn, fl = homogeneity(x, v, s.box, cells)
            dt_list.append(step_no)
            dr.append(dn / dens0)
            fr.append(fl)
        run.dump_t = _step_times(th, np.array(dt_list))
        run.density_ratio, run.flow_ratio = np.array(dr), np.array(fr)
        # late times: from 10 tau0 (or the last 70 % of a shorter run)
        run.fit_from = min(0.3 * t[-1], 10.0 * tau0)
        run.exponent, run.exponent_err = fit_late_exponent(t, T, run.fit_from)
        runs[m] = run
    st = GasStudy(s, runs, dens0, haff_window=min(4.0, s.t_end_tau0),
                  particle_steps=float(steps_total) * s.n)
    if "Ts" in runs:
        _, dev = haff_deviation(runs["Ts"].t, runs["Ts"].T, s.T0, tau0, st.haff_window)
        st.haff_max_dev = float(np.max(np.abs(dev))) if len(dev) else math.nan
    st.wall_s = sum(r.wall_s for r in runs.values())
    return st


def _haff_step_integral(x_end: float) -> float:
    """Steps in units of tau0/dt0 up to x_end tau0 when dt grows as (1 + t/tau0)^(1/5)."""
    return ((1.0 + x_end) ** 0.8 - 1.0) / 0.8


def _step_times(th: dict[str, np.ndarray], steps: np.ndarray) -> np.ndarray:
    return np.interp(steps, th["Step"], th["Time"])


def _read_data_xv(path: Path, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Positions and velocities from a LAMMPS data file written by write_data (atom_style sphere)."""
    lines = path.read_text().splitlines()
    atoms, vels = {}, {}
    i = 0
    while i < len(lines):
        head = lines[i].strip().split("#")[0].strip()
        if head in ("Atoms", "Velocities"):
            block = atoms if head == "Atoms" else vels
            i += 2
            while i < len(lines) and lines[i].strip():
                f = lines[i].split()
                # Atoms (sphere): id type diameter density x y z ...; Velocities: id vx vy vz ...
                block[int(f[0])] = [float(x) for x in (f[4:7] if head == "Atoms" else f[1:4])]
                i += 1
        else:
            i += 1
    ids = sorted(atoms)
    if len(ids) != n:
        raise RuntimeError(f"{path}: {len(ids)} atoms, expected {n}")
    return np.array([atoms[k] for k in ids]), np.array([vels[k] for k in ids])
