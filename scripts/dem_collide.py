"""Single collisions inside LAMMPS (pair viscontact, fix viscontact/wall) measured the way an
experimenter would, for the DEM-versus-exact tests (``tests/dem/test_exact.py``) and the table
script (``scripts/dem_exact_table.py``), with the cases both use (at the end of this module).

Many independent collisions share one in-process LAMMPS run (one atom type, one law): equal
spheres head-on far apart from each other, and spheres falling on the wall z = 0.  The input is
exactly what a user pastes: ``viscontact.dem.coeff_lines(...)`` (``pair_coeff * *`` and the
``fix vcwall all viscontact/wall zplane 0.0 NULL ...`` line).  LAMMPS is advanced one step at a
time (``run 1 pre no post no``: the same trajectory as one long run); positions and forces are
recorded after every step, at t_n = n dt, velocities and spins before and after.

From those samples (no knowledge of the force law is used):
  * contact start: the overlap delta crosses 0 between two steps (linear interpolation; exact
    before contact, where no force acts);
  * end: ``end overlap`` -- delta crosses 0 again (linear interpolation); ``end force`` -- the
    (clamped) force reaches 0: the zero crossing of the straight line through the last two
    positive force samples (the force crosses 0 with a non-zero slope when p < 3/2; for
    p >= 3/2, F = delta^(3/2) (k + c delta^(p-3/2) delta') vanishes only with delta, and so does
    the undamped force: then the overlap crossing is used);
  * t_c = end - start; F_max, delta_max: the largest sample, refined by the parabola through
    it and its two neighbours; e = normal separation speed after the contact (when no force
    acts any more) / normal approach speed.
"""

from __future__ import annotations

import ctypes
import functools
import math
from dataclasses import dataclass, field

import numpy as np

import viscontact as vc
from viscontact import dem
from viscontact.dem import plugin as _plugin


@dataclass(frozen=True)
class Material:
    """A particle material: Young's modulus E [Pa], Poisson ratio nu, density rho [kg/m^3]."""

    E: float
    nu: float
    rho: float


@dataclass(frozen=True)
class Shot:
    """One collision: ``geometry`` "pair" (two equal spheres, head-on) or "wall" (a sphere on
    the plane z = 0); ``v`` the normal approach speed [m/s] (pair: relative); ``angle`` from the
    normal [deg] (wall only); ``omega0`` initial spin about y [rad/s] (wall only)."""

    geometry: str
    v: float
    angle: float = 0.0
    phase: float | None = None        # overrides Setup.phase


@dataclass
class Measured:
    """What LAMMPS gave for one shot (SI)."""

    shot: Shot
    m_eff: float
    r_eff: float
    k_hertz: float
    e: float
    tc: float
    fmax: float
    dmax: float
    vt_in: float = 0.0       # tangential speed of the centre before / after (wall, oblique)
    vt_out: float = 0.0
    spin_out: float = 0.0    # angular velocity about the axis n x t after [rad/s]
    steps_in_contact: int = 0


@dataclass
class Setup:
    """One LAMMPS run: one law, one material, one radius, several shots."""

    law: dem.DemLaw
    material: Material
    radius: float
    shots: list[Shot]
    wall: str | tuple[float, float] = "same"
    friction: float | None = None
    steps_per_tc: float = 1000.0      # dt = (shortest Hertz t_c of the shots) / steps_per_tc
    lead: float = 0.05                # the approach takes about lead * t_c ...
    phase: float = 0.5                # ... and contact begins this fraction of a step after a step
    exact_grid: bool = False          # dt = (shortest exact t_c) / steps_per_tc: one shot per
                                      # run then starts and ends its exact contact at one phase
    extra: list[str] = field(default_factory=list)


def _hertz_k(material: Material, r_eff: float, wall: str | tuple[float, float],
             geometry: str) -> float:
    E, nu = material.E, material.nu
    if geometry == "pair" or wall == "same":
        e_eff = vc.effective_modulus(E, nu, E, nu)
    elif wall == "rigid":
        e_eff = vc.effective_modulus(E, nu)
    else:
        e_eff = vc.effective_modulus(E, nu, wall[0], wall[1])
    return vc.hertz_stiffness(e_eff, r_eff)


def effective(setup: Setup, shot: Shot) -> tuple[float, float, float]:
    """(m*, R*, k_Hertz) of a shot (pair: two equal spheres; wall: R* = R, m* = m)."""
    m = 4.0 / 3.0 * math.pi * setup.radius**3 * setup.material.rho
    if shot.geometry == "pair":
        m_eff, r_eff = m / 2.0, setup.radius / 2.0
    else:
        m_eff, r_eff = m, setup.radius
    return m_eff, r_eff, _hertz_k(setup.material, r_eff, setup.wall, shot.geometry)


def hertz_tc(m_eff: float, k: float, v: float) -> float:
    """Elastic Hertz contact time t_c = 3.2180654597 (m*/k)^(2/5) v^(-1/5) [s] (docs/laws.md)."""
    return vc.physics.pair.hertz_limit(m_eff, k, v)[0]


def run(setup: Setup) -> list[Measured]:
    """Run every shot of ``setup`` in one in-process LAMMPS and measure each."""
    R, mat = setup.radius, setup.material
    lines = dem.coeff_lines(setup.law, E=mat.E, nu=mat.nu, friction=setup.friction,
                            wall=setup.wall)
    eff = [effective(setup, s) for s in setup.shots]
    tcs = [hertz_tc(m, k, s.v) for (m, _, k), s in zip(eff, setup.shots)]
    if setup.exact_grid:
        dt = min(exact(setup, s).tc for s in setup.shots) / setup.steps_per_tc
    else:
        dt = min(tcs) / setup.steps_per_tc
    spacing = 6.0 * R
    npair = sum(s.geometry == "pair" for s in setup.shots)
    nwall = len(setup.shots) - npair
    zpair = 10.0 * R      # pairs well above the wall
    half = spacing * (max(npair, nwall) + 2)
    atoms = []            # (x, y, z, vx, vy, vz) per atom
    index = []            # per shot: atom indices
    ip = iw = 0
    for s, (m_eff, r_eff, k), tc in zip(setup.shots, eff, tcs):
        # Contact begins at t = (n0 + phase) dt at every dt: the same phase of the contact
        # start on the step grid at every step size.  A law whose force jumps where the contact
        # begins or ends (LH, and Ts steeply) has an O(dt) error that depends on those phases
        # and hides the order unless they are held fixed (exact_grid: the exact end falls at
        # the same phase as the start).
        phase = setup.phase if s.phase is None else s.phase
        gap = (math.floor(setup.lead * tc / dt) + float(phase)) * dt * s.v
        if s.geometry == "pair":
            y = -half + spacing * (ip + 1)
            ip += 1
            index.append((len(atoms), len(atoms) + 1))
            atoms.append((-(R + gap / 2), y, zpair, s.v / 2, 0.0, 0.0))
            atoms.append((R + gap / 2, y, zpair, -s.v / 2, 0.0, 0.0))
        elif s.geometry == "wall":
            x = -half + spacing * (iw + 1)
            iw += 1
            th = math.radians(s.angle)
            vn = s.v
            index.append((len(atoms),))
            atoms.append((x, 0.0, R + gap, vn * math.tan(th), 0.0, -vn))
        else:
            raise ValueError(f"unknown geometry {s.geometry!r}")
    longest = max(tcs)
    lmp = _plugin.new_lammps()
    try:
        cmds = [
            "units si", "atom_style sphere", "atom_modify map array sort 0 0.0",
            "boundary f f f", "comm_modify vel yes",
            f"region box block {-half} {half} {-half} {half} {-2 * R} {zpair + 4 * R}",
            "create_box 1 box",
        ]
        for a in atoms:
            cmds.append(f"create_atoms 1 single {a[0]!r} {a[1]!r} {a[2]!r}")
        cmds += [f"set group all diameter {2 * R!r}", f"set group all density {mat.rho!r}"]
        for i, a in enumerate(atoms):
            cmds.append(f"set atom {i + 1} vx {a[3]!r} vy {a[4]!r} vz {a[5]!r}")
        cmds += [lines.pair_style, lines.pair_coeff]
        if nwall:
            cmds.append(lines.wall_fix)
        cmds += [f"neighbor {0.5 * R!r} bin", "neigh_modify every 1 delay 0 check yes",
                 "fix nve all nve/sphere", f"timestep {dt!r}", "thermo 0", *setup.extra,
                 "run 0"]
        for c in cmds:
            lmp.command(c)
        natoms = len(atoms)
        views = {}

        def view(name):
            # numpy views on LAMMPS's per-atom arrays, taken again only if LAMMPS reallocated
            # them (the address of the first row changes)
            ptr = lmp.extract_atom(name)
            addr = ctypes.cast(ptr[0], ctypes.c_void_p).value
            if name not in views or views[name][0] != addr:
                views[name] = (addr, lmp.numpy.extract_atom(name))
            return views[name][1][:natoms]

        xs, fs = [view("x").copy()], [view("f").copy()]
        v0, w0 = view("v").copy(), view("omega").copy()
        # run until every contact is over: at least (lead + 2.5) t_c, then until all overlaps
        # are negative (attraction with `end overlap` lengthens a contact)
        nmin = int(math.ceil((setup.lead + 2.5) * longest / dt))
        n = 0
        while True:
            lmp.command("run 1 pre no post no")
            xs.append(view("x").copy())
            fs.append(view("f").copy())
            n += 1
            if n >= nmin and n % 100 == 0:
                if _all_open(xs[-1], index, setup, R):
                    break
            if n > 50 * nmin:
                raise RuntimeError("a contact did not end within 50 contact times")
        v1, w1 = view("v").copy(), view("omega").copy()
    finally:
        lmp.close()
    X, F = np.array(xs), np.array(fs)
    t = dt * np.arange(len(X))
    return [_measure(setup, s, idx, e3, t, X, F, (v0, v1), (w0, w1))
            for s, idx, e3 in zip(setup.shots, index, eff)]


def _all_open(x: np.ndarray, index, setup: Setup, R: float) -> bool:
    for s, idx in zip(setup.shots, index):
        if s.geometry == "pair":
            if 2 * R - np.linalg.norm(x[idx[1]] - x[idx[0]]) > 0:
                return False
        elif R - x[idx[0], 2] > 0:
            return False
    return True


def _crossing(t: np.ndarray, y: np.ndarray, i: int) -> float:
    """Time where the straight line through (t[i-1], y[i-1]), (t[i], y[i]) crosses 0."""
    return t[i - 1] + (t[i] - t[i - 1]) * y[i - 1] / (y[i - 1] - y[i])


def _peak(t: np.ndarray, y: np.ndarray) -> float:
    """Largest sample refined by the parabola through it and its neighbours."""
    i = int(np.argmax(y))
    if i == 0 or i == len(y) - 1:
        return float(y[i])
    a, b, c = y[i - 1], y[i], y[i + 1]
    den = a - 2 * b + c
    if den >= 0:
        return float(b)
    s = 0.5 * (a - c) / den
    return float(b - 0.25 * (a - c) * s)


def _measure(setup: Setup, shot: Shot, idx, eff, t, X, F, V, W) -> Measured:
    """Measure one shot from the samples X, F (every step) and the velocities V and angular
    velocities W (before, after)."""
    m_eff, r_eff, k = eff
    R = setup.radius
    if shot.geometry == "pair":
        a, b = idx
        d_vec = X[:, a] - X[:, b]
        dist = np.linalg.norm(d_vec, axis=1)
        nrm = d_vec / dist[:, None]                   # from b to a
        delta = 2 * R - dist
        force = np.einsum("ij,ij->i", F[:, a], nrm)   # > 0: repulsion
        vn_out = float(np.dot(V[1][a] - V[1][b], nrm[-1]))   # > 0 separating
        vt_in = vt_out = spin = 0.0
    else:
        (a,) = idx
        delta = R - X[:, a, 2]
        force = F[:, a, 2]
        vn_out = V[1][a, 2]
        vt_in, vt_out = V[0][a, 0], V[1][a, 0]
        spin = W[1][a, 1]
    inside = np.nonzero(delta > 0)[0]
    if len(inside) == 0:
        raise RuntimeError(f"{shot}: no contact")
    i0 = inside[0]
    after = np.nonzero(delta[i0:] <= 0)[0]
    if len(after) == 0:
        raise RuntimeError(f"{shot}: the contact did not end")
    i1 = i0 + after[0]                                # first open sample
    start = _crossing(t, delta, i0)
    law = setup.law
    elastic = (law.c0 == 0.0) if law.c0 is not None else (law.alpha == 0.0)
    if law.end == "overlap" or law.p >= 1.5 or elastic:
        end = _crossing(t, delta, i1)
    else:
        zero = np.nonzero(force[i0:i1 + 1] <= 0)[0]
        j = i0 + zero[0]
        if j - 2 < i0:
            raise RuntimeError(f"{shot}: too few force samples before the force end")
        end = _crossing(t, force, j) if force[j] < 0 else (
            t[j - 1] + (t[j - 1] - t[j - 2]) * force[j - 1] / (force[j - 2] - force[j - 1]))
    e = vn_out / shot.v
    return Measured(shot=shot, m_eff=m_eff, r_eff=r_eff, k_hertz=k, e=float(e),
                    tc=float(end - start), fmax=_peak(t, force), dmax=_peak(t, delta),
                    vt_in=float(vt_in), vt_out=float(vt_out), spin_out=float(spin),
                    steps_in_contact=int(i1 - i0))


def exact(setup: Setup, shot: Shot) -> vc.ImpactResult:
    """The exact single collision (``viscontact.impact``) with this shot's m*, k_Hertz and the
    c0, tau that the law's FORM gives for them (docs/pair_viscontact.md, "Damping prefactor
    c0"; computed here by ``viscontact.damping_coefficient`` / ``time_scale``, not by the
    plugin)."""
    law = setup.law
    m_eff, _, k = effective(setup, shot)
    p = law.p if law.law == "power" else None
    if law.c0 is not None:
        c, tau = law.c0, law.tau
    else:
        c = vc.damping_coefficient(law.law, law.alpha, m_eff=m_eff, k_hertz=k, v=law.vref, p=p)
        tau = None if law.beta is None else law.beta * vc.time_scale(m_eff, k, law.vref)
    return _impact(law.law, m_eff, k, shot.v, c, tau, p, law.end)


@functools.lru_cache(maxsize=4096)
def _impact(model, m_eff, k, v, c, tau, p, end):
    return vc.impact(model, m_eff=m_eff, k_hertz=k, v=v, c=c, tau=tau, p=p, end=end)


# ---- the cases of tests/dem/test_exact.py and scripts/dem_exact_table.py ----------------------
MAT = Material(E=1.0e7, nu=0.3, rho=2500.0)    # soft spheres: overlaps of a few % of R
RADIUS = 0.01
VREF = 1.0
SPEEDS = (0.5, 1.0, 2.0)
E_TARGET = 0.7
LAWS = {"LH": {}, "Ts": {}, "KK": {}, "Li": {}, "Hunt": {}, "Jian": {"beta": 0.5},
        "power": {"p": 0.75}}
CASES = [(law, end) for end in ("force", "overlap") for law in LAWS]


def law_for(name: str, end: str) -> dem.DemLaw:
    """The law calibrated exactly to e = 0.7 at vref = 1 m/s (alpha_from_e)."""
    return dem.contact_law(name, e=E_TARGET, vref=VREF, end=end, **LAWS[name])


#: Chung & Ooi (2011) tests 1-3: the elastic contact
ELASTIC = dem.contact_law("KK", c0=0.0)
# test 4: oblique impacts, Al oxide on Al oxide, |v| = 3.9 m/s, mu = 0.092, e = 0.98 (Ts: e does
# not depend on the normal speed, so e = 0.98 at every angle)
MU, E4, V4, R4 = 0.092, 0.98, 3.9, 0.0025
ALOX = Material(380e9, 0.23, 4000)
ANGLES = tuple(range(5, 90, 5))
