"""A freely cooling granular gas (Haff 1983; Brilliantov and Poschel 2004).

Smooth monodisperse spheres in a periodic box: placed at random, thermalised by elastic
collisions (``inputs/gas_prepare.in``), then cooled by each law calibrated to the same e at the
rms normal impact speed of the initial gas, v_ref = sqrt(<g_n^2>) = 2 sqrt(T0 / m)
(``inputs/gas_cool.in``).  T(t) = m <v^2> / 3 of every law is compared with the kinetic theory
of its own e(v) (:func:`.theory.kinetic_temperature`, e from the exact solver), and its local
exponent over the last half decade with the same slope of that theory and with the asymptote
-2 / (1 + q) (:mod:`.theory`).

Haff's law (Ts: constant e) is checked on separate runs (:class:`HaffCheck`): several
realisations of the same gas with stiffer contacts.  Soft contacts cool slower than Enskog's
hard spheres (measured on 4000 spheres, e = 0.8, phi = 0.05: T lies about 8 %, 5 % and 2.5 %
above Haff's law by 4 tau0 for contact times of 0.04, 0.02 and 0.005 mean free times;
``scripts/haff_probe.py``), and one realisation of a few thousand spheres scatters by about
2 %, so the check uses contact times of 0.005 mean free times and the mean of the realisations.

Homogeneity is checked on the dumps: the variance over the mean of the number of spheres in
cubic cells (about 8 spheres per cell; an ideal gas gives 1 - 1/cells, excluded volume less,
clusters more), and the kinetic energy of the cell-averaged flow over the value for
independent velocities, 1 / (spheres per cell) (1 while there is no large-scale flow; shear
bands and vortices raise it).  Both are set against the noise band of an ideal gas sampled
with the same number of spheres and cells (:func:`ideal_gas_band`).  The velocity
distribution's departure from a Maxwellian, a2 = (3/5) <v^4> / <v^2>^2 - 1, is measured on the
same dumps and set next to the homogeneous-cooling value of a constant e
(:func:`.theory.a2_homogeneous_cooling`) at each law's effective e at that temperature.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..physics.pair import HERTZ_TC, hertz_limit
from ..physics.laws import STUDY_MODELS
from . import jobs, theory
from .engine import (
    LawSpec, Material, coeff_text, read_dump, read_thermo, run_lammps, sim_time_ticker,
)
from ..physics.laws import Jian, LH, Ts

__all__ = ["GasSetup", "GasRun", "GasStudy", "HaffCheck", "QUICK_GAS", "FULL_GAS", "QUICK_HAFF",
           "FULL_HAFF", "run_gas", "run_haff", "homogeneity", "haff_deviation",
           "restitution_of_speed", "late_window", "local_exponents", "ideal_gas_band"]


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
        t_c = HERTZ_TC (m* / k)^(2/5) v^(-1/5), HERTZ_TC = 3.218."""
        tc = self.tc_ratio * self.free_time
        return (self.mass / 2.0) * (HERTZ_TC / (tc * self.vref ** 0.2)) ** 2.5

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


QUICK_GAS = GasSetup(n=2000, phi=0.05, t_end_tau0=4.0, tc_ratio=0.01, dumps=16)
FULL_GAS = GasSetup(n=4000, phi=0.05, t_end_tau0=100.0, tc_ratio=0.02, dumps=24)


@dataclass(frozen=True)
class HaffCheck:
    """Haff's law on ``realisations`` independent Ts gases (seeds ``seed + 1 ...``) of the
    study's gas with ``n`` spheres and contacts lasting ``tc_ratio`` mean free times, over
    ``window`` tau0; the check is the mean of their T / T_Haff - 1 (blocks of tau0 / 4)."""

    n: int = 2000
    tc_ratio: float = 0.005
    realisations: int = 3
    window: float = 4.0

    def setup(self, gas: GasSetup, k: int) -> GasSetup:
        """Realisation k (0-based) of ``gas`` for this check."""
        return replace(gas, n=self.n, tc_ratio=self.tc_ratio, t_end_tau0=self.window, dumps=2,
                       seed=gas.seed + 1 + k)


QUICK_HAFF = HaffCheck(n=2000, realisations=3)
FULL_HAFF = HaffCheck(n=4000, realisations=4)


@dataclass
class GasRun:
    """One law's cooling: time [s], T [J], the dump path and homogeneity measures per dump;
    ``T_theory`` the kinetic theory of the law's e(v) at the same times; ``slope`` (+- err)
    the local exponent d ln T / d ln t fitted over [fit_from, t_end], ``slope_theory`` the
    same fit to ``T_theory``."""

    model: str
    law: LawSpec
    t: np.ndarray
    T: np.ndarray
    dump: Path
    dump_t: np.ndarray = field(default_factory=lambda: np.empty(0))
    density_index: np.ndarray = field(default_factory=lambda: np.empty(0))  # var/mean per dump
    flow_ratio: np.ndarray = field(default_factory=lambda: np.empty(0))
    a2: np.ndarray = field(default_factory=lambda: np.empty(0))  # measured, per dump
    a2_theory: np.ndarray = field(default_factory=lambda: np.empty(0))  # HCS at e_eff(T)
    e_eff: np.ndarray = field(default_factory=lambda: np.empty(0))  # per dump
    L_over_Lc_end: float = math.nan  # box over the shear-instability length at the end
    T_theory: np.ndarray = field(default_factory=lambda: np.empty(0))
    slope: float = math.nan
    slope_err: float = math.nan
    slope_theory: float = math.nan
    wall_s: float = 0.0
    steps: int = 0
    fit_from: float = math.nan  # start of the late-time fit [s]
    final: dict[str, np.ndarray] = field(repr=False, default_factory=dict)  # last dump's columns

    @property
    def theory_dev(self) -> float:
        """Largest |T / T_theory - 1| over the run (T averaged over blocks of 1/20 of ln t)."""
        return _max_block_dev(self.t, self.T, self.T_theory)


@dataclass
class GasStudy:
    setup: GasSetup
    runs: dict[str, GasRun]
    elastic_density_var: float  # var/mean of cell counts in the thermalised elastic gas
    band: dict[str, tuple[float, float, float]] = field(default_factory=dict)  # ideal gas
    haff: HaffCheck | None = None
    haff_t: np.ndarray = field(default_factory=lambda: np.empty(0))  # block centres / tau0
    haff_dev: np.ndarray = field(default_factory=lambda: np.empty((0, 0)))  # realisation x block
    particle_steps: float = 0.0
    wall_s: float = 0.0

    @property
    def haff_window(self) -> float:
        return self.haff.window if self.haff is not None else math.nan

    @property
    def haff_mean_dev(self) -> np.ndarray:
        """Mean over the realisations of T / T_Haff - 1 per block."""
        return self.haff_dev.mean(axis=0) if self.haff_dev.size else np.empty(0)

    @property
    def haff_max_dev(self) -> float:
        """The check: max over blocks of |mean over realisations of T / T_Haff - 1|."""
        d = self.haff_mean_dev
        return float(np.max(np.abs(d))) if d.size else math.nan

    @property
    def haff_max_dev_each(self) -> list[float]:
        """Largest |T / T_Haff - 1| of each realisation."""
        return [float(np.max(np.abs(d))) for d in self.haff_dev]


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


def ideal_gas_band(n: int, cells: int, draws: int = 400, seed: int = 7, dumps: int = 1,
                   q: tuple[float, float, float] = (2.5, 50.0, 97.5)
                   ) -> dict[str, tuple[float, float, float]]:
    """Sampling noise of the homogeneity measures and of a2 in an ideal gas of ``n`` spheres
    (positions uniform in the unit box, velocities Maxwellian) with ``cells`` cells per side:
    the ``q`` percentiles over ``draws`` samples of ``density`` (var/mean of cell counts, about
    1 - 1/cells^3), ``flow`` (about 1) and ``a2`` (0 on average).  A measured value outside
    the band differs from a homogeneous, Maxwellian gas by more than one sample's noise.

    ``density_max`` and ``flow_max`` (three equal numbers): the value the largest of ``dumps``
    independent samples stays below with 97.5 % probability, median + z sd with
    z = Phi^-1(0.975^(1/dumps)) (the samples' spread is close to Gaussian); the test for the
    largest value over a run's dumps.
    """
    from scipy.stats import norm

    rng = np.random.default_rng(seed)
    dens, flow, a2 = [], [], []
    for _ in range(draws):
        x = rng.random((n, 3))
        v = rng.normal(size=(n, 3))
        dn, fl = homogeneity(x, v, 1.0, cells)
        dens.append(dn)
        flow.append(fl)
        a2.append(theory.sonine_a2(v))
    out = {k: tuple(float(x) for x in np.percentile(vals, q))
           for k, vals in (("density", dens), ("flow", flow), ("a2", a2))}
    z = float(norm.ppf(0.975 ** (1.0 / max(1, dumps))))
    for k, vals in (("density", dens), ("flow", flow)):
        top = float(np.median(vals) + z * np.std(vals, ddof=1))
        out[f"{k}_max"] = (top, top, top)
    return out


def restitution_of_speed(law: LawSpec, setup: GasSetup, v_min: float, v_max: float,
                         points: int = 241) -> Callable[[np.ndarray], np.ndarray]:
    """e(g_n) of two of the gas's spheres under ``law`` as the plugin applies it (c0, tau of
    the pair from the calibration at v_ref), at ``points`` speeds spaced evenly in ln g_n over
    [v_min, v_max] [m/s] and interpolated in ln g_n (held constant outside).

    Each speed is one non-dimensional collision (alpha, beta) = (c / (m* v^(1-p) ...), tau / T)
    (:func:`viscontact.physics.pair.damping_constants`); e comes from
    :func:`viscontact.calibration.inverse.restitution` (the precomputed tables, within 1e-10 of
    the exact solver, or the compiled batch solver outside them: within 1e-8), all speeds at
    once instead of one exact solve each."""
    from .. import dem
    from ..calibration.inverse import restitution
    from ..physics.pair import ContactPair, damping_constants

    m_eff = setup.mass / 2.0
    dl = dem.contact_law(law.model, e=law.e, vref=law.vref, beta=law.beta)
    c0, tau = dl.physical(ContactPair.from_effective(m_eff=m_eff, k_hertz=setup.k_hertz))
    speeds = np.geomspace(v_min, v_max, points)
    ln_v = np.log(speeds)
    ab = [damping_constants(law.model, c0, m_eff=m_eff, k_hertz=setup.k_hertz, v=float(v),
                            tau=tau) for v in speeds]
    beta = None if ab[0][1] is None else np.array([b for _, b in ab])
    e = np.asarray(restitution(law.model, np.array([a for a, _ in ab]), beta=beta),
                   dtype=float)

    def e_of_speed(v: np.ndarray) -> np.ndarray:
        return np.interp(np.log(np.asarray(v, dtype=float)), ln_v, e)

    return e_of_speed


def late_window(t_end: float) -> float:
    """Start of the late-time fit: the last half decade, [t_end / sqrt(10), t_end]."""
    return t_end / math.sqrt(10.0)


def local_exponents(t: np.ndarray, T: np.ndarray, width: float = 1.0 / 3.0, points: int = 30
                    ) -> tuple[np.ndarray, np.ndarray]:
    """d ln T / d ln t as least-squares slopes over windows ``width`` decades wide, centred at
    ``points`` times evenly spaced in ln t from the first sample after t = 0 (the window
    inside the run): (centres [s], slopes)."""
    pos = t[t > 0]
    half = 0.5 * width * math.log(10.0)
    lo, hi = math.log(pos[0]) + half, math.log(pos[-1]) - half
    if hi <= lo:
        return np.empty(0), np.empty(0)
    centres = np.exp(np.linspace(lo, hi, points))
    k = np.array([theory.log_slope(t, T, c * math.exp(-half), c * math.exp(half))[0]
                  for c in centres])
    return centres, k


def _block_deviations(t: np.ndarray, T: np.ndarray, T_ref: np.ndarray, edges: np.ndarray,
                      min_samples: int) -> tuple[np.ndarray, np.ndarray]:
    """<T> / <T_ref> - 1 over the samples in each block [edges[i], edges[i+1]) holding at least
    ``min_samples`` samples (both averaged over the same samples): (block centres, deviations)."""
    mids, dev = [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (t >= lo) & (t < hi)
        if sel.sum() >= min_samples:
            mids.append(0.5 * (lo + hi))
            dev.append(T[sel].mean() / T_ref[sel].mean() - 1.0)
    return np.array(mids), np.array(dev)


def _max_block_dev(t: np.ndarray, T: np.ndarray, T_ref: np.ndarray, blocks: int = 20) -> float:
    """Largest |<T> / <T_ref> - 1| over ``blocks`` blocks evenly spaced in ln t (t > 0)."""
    if not len(T_ref):
        return math.nan
    pos = t[t > 0]
    edges = np.geomspace(pos[0], pos[-1], blocks + 1)
    edges[-1] = np.nextafter(edges[-1], np.inf)  # the last sample belongs to the last block
    _, dev = _block_deviations(t, T, T_ref, edges, 1)
    return float(np.max(np.abs(dev))) if len(dev) else math.nan


def haff_deviation(t: np.ndarray, T: np.ndarray, T0: float, tau0: float, window: float,
                   block: float = 0.25) -> tuple[np.ndarray, np.ndarray]:
    """T / T_Haff - 1 averaged over blocks of ``block`` tau0 up to ``window`` tau0 (both the
    measured and Haff's T averaged over the same samples): (block centres / tau0, deviations)."""
    edges = np.arange(0.0, window + 1e-12, block) * tau0
    mids, dev = _block_deviations(t, T, theory.haff_temperature(t, T0, tau0), edges, 2)
    return mids / tau0, dev


def _prepare(workdir: Path, s: GasSetup, np_: int, start: Callable[[], None] | None = None
             ) -> tuple[int, float]:
    """Thermalise the elastic gas into ``workdir/gas-start.data``; (steps, its density var).
    ``start``: see :func:`~viscontact.demstudy.engine.run_lammps`."""
    mat = s.material
    (workdir / "coeffs-elastic.lmp").write_text(
        coeff_text(LawSpec(LH.name, 1.0, s.vref), mat, m_eff=s.mass / 2.0, r_eff=s.sigma / 4.0))
    pv = s.prepare_variables("coeffs-elastic.lmp", "gas-start.data")
    run_lammps("gas_prepare.in", workdir, pv, np_=np_, log="log-prepare.lammps", start=start)
    start = _read_data_xv(workdir / "gas-start.data", s.n)
    dens0, _ = homogeneity(start[0], start[1], s.box, _cells(s))
    return int(pv["nequil"]), dens0


def _cool(workdir: Path, s: GasSetup, model: str, np_: int,
          step: Callable[[str], None] | None, label: str) -> tuple[GasRun, dict[str, np.ndarray]]:
    """Cool the prepared gas of ``workdir`` with one law in ``workdir/gas-MODEL``: the run
    with T(t), and the thermo columns of its log."""
    import time

    law = LawSpec(model, s.e, s.vref, s.beta if model == Jian.name else None)
    d = workdir / f"gas-{model}"
    d.mkdir(exist_ok=True)
    (d / "coeffs.lmp").write_text(coeff_text(law, s.material, m_eff=s.mass / 2.0,
                                             r_eff=s.sigma / 4.0))
    (d / "gas-start.data").write_bytes((workdir / "gas-start.data").read_bytes())
    tau0 = s.tau0()
    tick = sim_time_ticker(d / "log.lammps", s.t_end_tau0 * tau0, tau0, f"{label} (t in tau0)",
                           step)
    t1 = [time.perf_counter()]

    def started() -> None:  # the wall time counts from the start of LAMMPS, not of a wait
        t1[0] = time.perf_counter()
        if step:
            step(label)

    log = run_lammps("gas_cool.in", d, s.cool_variables("coeffs.lmp", "gas-start.data",
                                                         f"gas-{model}.dump"), np_=np_, tick=tick,
                     start=started)
    wall = time.perf_counter() - t1[0]
    th = read_thermo(log)
    t, keep = np.unique(th["Time"], return_index=True)  # a segment's first line repeats the last
    run = GasRun(model, law, t, th["v_Tg"][keep], d / f"gas-{model}.dump", wall_s=wall,
                 steps=int(th["Step"][-1]))
    return run, th


def run_haff(workdir: Path, setup: GasSetup, check: HaffCheck, *, np_: int = 1,
             step: Callable[[str], None] | None = None) -> tuple[np.ndarray, np.ndarray, float]:
    """Run the realisations of ``check``: (block centres / tau0, deviations realisation x
    block, particle-steps)."""
    def one(k: int) -> tuple[np.ndarray, np.ndarray, float]:
        s = check.setup(setup, k)
        d = workdir / f"haff-{k + 1}"
        d.mkdir(parents=True, exist_ok=True)
        label = f"gas: Haff's law, realisation {k + 1} of {check.realisations}"
        nequil, _ = _prepare(d, s, np_, start=(lambda: step(f"{label}: elastic thermalisation"))
                             if step else None)
        run, _ = _cool(d, s, Ts.name, np_, step, label)
        mids, dev = haff_deviation(run.t, run.T, s.T0, s.tau0(), check.window)
        return mids, dev, float(nequil + run.steps) * s.n

    done = jobs.pmap(one, range(check.realisations))
    devs = [dev for _, dev, _ in done]
    mids = done[-1][0] if done else np.empty(0)
    steps = sum(st for _, _, st in done)
    width = min(len(d) for d in devs)
    return mids[:width], np.array([d[:width] for d in devs]), steps


def run_gas(workdir: Path, setup: GasSetup = QUICK_GAS, *, models: tuple[str, ...] = STUDY_MODELS,
            np_: int = 1, step: Callable[[str], None] | None = None,
            haff: HaffCheck | None = None) -> GasStudy:
    """Prepare the thermalised gas once, cool it with every law; analyse T(t) and the dumps
    against the kinetic theory of each law; then, if ``haff`` is given, the realisations of
    Haff's check (Ts)."""
    workdir.mkdir(parents=True, exist_ok=True)
    s = setup
    cells = _cells(s)

    def cool(m: str) -> GasRun:
        """Cool the prepared gas with law ``m``; T(t), the dumps and the theory of its e(v)."""
        run, th = _cool(workdir, s, m, np_, step, f"gas: cooling with {m}")
        frames = read_dump(run.dump)
        run.dump_t = _step_times(th, np.array([f.step for f in frames]))
        dn_, fr_, a2_ = [], [], []
        for f in frames:
            cols = f.columns
            x = np.stack([cols["x"], cols["y"], cols["z"]], 1)
            v = np.stack([cols["vx"], cols["vy"], cols["vz"]], 1)
            dn, fl = homogeneity(x, v, s.box, cells)
            dn_.append(dn)
            fr_.append(fl)
            a2_.append(theory.sonine_a2(v - v.mean(0)))
        run.density_index, run.flow_ratio, run.a2 = np.array(dn_), np.array(fr_), np.array(a2_)
        run.final = frames[-1].columns
        # kinetic theory of this law's e(v) down to speeds well below the coldest sample
        v_low = s.vref * math.sqrt(max(float(np.min(run.T)) / s.T0, 1e-12)) * 0.05
        e_of_v = restitution_of_speed(run.law, s, v_low, 12.0 * s.vref)
        run.T_theory = theory.kinetic_temperature(e_of_v, run.t, T0=s.T0, n=s.n_density,
                                                  sigma=s.sigma, m=s.mass, phi=s.phi)
        # a2 of the homogeneous cooling state at the law's effective e at each dump's T
        T_dump = np.interp(run.dump_t, run.t, run.T)
        run.e_eff = np.array([theory.effective_restitution(e_of_v, 2.0 * math.sqrt(T / s.mass))
                              for T in T_dump])
        run.a2_theory = np.array([theory.a2_homogeneous_cooling(e) for e in run.e_eff])
        run.L_over_Lc_end = s.box / theory.shear_instability_length(
            min(float(run.e_eff[-1]), 1.0 - 1e-12), n=s.n_density, sigma=s.sigma, phi=s.phi)
        run.fit_from = late_window(float(run.t[-1]))
        run.slope, run.slope_err = theory.log_slope(run.t, run.T, run.fit_from)
        run.slope_theory, _ = theory.log_slope(run.t, run.T_theory, run.fit_from)
        return run

    def laws() -> tuple[int, float, dict[str, GasRun]]:
        steps, dens0 = _prepare(workdir, s, np_, start=(
            lambda: step(f"gas: {s.n} spheres, elastic thermalisation")) if step else None)
        return steps, dens0, dict(zip(models, jobs.pmap(cool, models)))

    def haff_check() -> tuple[np.ndarray, np.ndarray, float] | None:
        return None if haff is None else run_haff(workdir, s, haff, np_=np_, step=step)

    (steps_total, dens0, runs), haff_res = jobs.run_each(laws, haff_check)
    steps_total += sum(r.steps for r in runs.values())
    n_dumps = max(len(r.dump_t) - 1 for r in runs.values())  # after t = 0
    st = GasStudy(s, runs, dens0, ideal_gas_band(s.n, cells, dumps=n_dumps),
                  particle_steps=float(steps_total) * s.n)
    st.wall_s = sum(r.wall_s for r in runs.values())
    if haff is not None:
        st.haff = haff
        st.haff_t, st.haff_dev, hsteps = haff_res
        st.particle_steps += hsteps
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
