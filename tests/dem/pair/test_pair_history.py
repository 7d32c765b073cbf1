"""``pair_style viscontact`` inside LAMMPS: per-contact history across neighbour-list rebuilds,
MPI ranks (newton on and off), restart files and a second ``run``; Jian's contact clock (input
errors: test_pair_errors.py; next to native: test_native_*.py).

Real LAMMPS runs (the ``lmp`` and ``mpirun`` of ``lammps[mpi]==2025.7.22.4.0``; skipped with the
reason when absent).  The settling pack: 480 frictional spheres (mu = 0.5, two radii) with random
velocities and spins, read from one data file so that every run starts from the same atoms, on
a frictionless floor (native ``fix wall/gran``, no history) under gravity, drifting along x at
1 m/s, 400 steps with ~30 neighbour-list rebuilds and about a fifth of the atoms crossing the
boundary between two ranks (``processors 2 1 1``, moved every 50 steps by ``fix balance``, which
migrates atoms in its pre_exchange: the history fix must, and does, come before it).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from dem_util import (
    DROP_HISTORY, SETTLE, assert_ok, drifting_pack, needs_lammps, needs_mpirun, plugin_line,
    rank_head, read_atoms, run_inprocess, run_lmp, sphere_head,
)
from viscontact.physics.pair import damping_coefficient, time_scale

pytestmark = needs_lammps

# ---------------------------------------------------------------------------- settling pack
NX, NY, NZ, SPACING = 10, 6, 8, 0.002
BOX = (0.0, NX * SPACING, 0.0, NY * SPACING, 0.0, 3 * NZ * SPACING)
STEPS = 400
DRIFT = 1.0  # m/s
COLUMNS = ("xu", "yu", "zu", "vx", "vy", "vz", "omegax", "omegay", "omegaz")
#: 1 against 2 ranks, restart, rebuilds: measured differences up to 2.6e-12 (velocities, spins;
#: relative to the largest value of each quantity), from the order of force sums; asserted 1e-10
TOL = 1e-10

#: the settling pack with the plugin's pair style ({pstyle}: its options), then {setup}
_PACK_HEAD = rank_head("p p f", "read_data pack.data") + """\
pair_style viscontact {pstyle}
pair_coeff * * hertz/material 1e7 0.3 damping {law} tangential mindlin 0.5
{setup}
"""
_PACK = _PACK_HEAD + """\
run {steps}
write_dump all custom {out} id xu yu zu vx vy vz omegax omegay omegaz modify sort id format float %.17g
"""
_SETUP = "fix bal all balance 50 1.0 shift x 5 1.02\n" + SETTLE + "thermo 100"
LAWS = {"KK": "KK alpha 0.3 vref 1.0", "Jian": "Jian alpha 0.3 vref 1.0 beta 0.5"}


@pytest.fixture(scope="module")
def pack(tmp_path_factory):
    """Directory with pack.data; returns (dir, initial positions)."""
    d = tmp_path_factory.mktemp("pack")
    return d, drifting_pack(d / "pack.data", (NX, NY, NZ), SPACING, 7, v_sd=0.5, drift=DRIFT)


def _run_pack(d, out, *, np_=1, newton="off", law="KK", pstyle="", steps=STEPS, env=None):
    script = _PACK.format(plugin=plugin_line(), newton=newton, pstyle=pstyle, law=LAWS[law],
                          setup=_SETUP, steps=steps, out=out)
    proc = run_lmp(script, d, np=np_, name=f"in.{out}", env=env)
    assert_ok(proc)
    return read_atoms(d / out), proc


def _max_rel_diff(a, b) -> dict[str, float]:
    """Per quantity (positions, velocities, spins): max |a - b| / max |a|."""
    assert np.array_equal(a["id"], b["id"])
    out = {}
    for group in (COLUMNS[:3], COLUMNS[3:6], COLUMNS[6:]):
        ref = np.stack([a[c] for c in group])
        diff = np.abs(ref - np.stack([b[c] for c in group]))
        out[group[0]] = float(diff.max() / np.abs(ref).max())
    return out


def _builds(proc) -> int:
    m = re.search(r"Neighbor list builds = (\d+)", proc.stdout)
    return int(m.group(1)) if m else 0


@needs_mpirun
@pytest.mark.parametrize("law", ["KK", "Jian"])
@pytest.mark.parametrize("newton", ["off", "on"])
def test_one_rank_equals_two_ranks(pack, newton, law):
    d, xyz0 = pack
    one, proc = _run_pack(d, f"one.{newton}.{law}", newton=newton, law=law)
    two, _ = _run_pack(d, f"two.{newton}.{law}", np_=2, newton=newton, law=law)
    diffs = _max_rel_diff(one, two)
    assert max(diffs.values()) <= TOL, diffs
    # the run exercises what it claims: rebuilds, and atoms that changed rank (the ranks split
    # the box at x = Lx/2 and at the periodic boundary)
    assert _builds(proc) >= 10
    half = BOX[1] / 2
    crossed = np.count_nonzero(np.floor(one["xu"] / half) != np.floor(xyz0[:, 0] / half))
    assert crossed >= 20, crossed


@pytest.mark.parametrize("newton", ["off", "on"])
def test_history_survives_rebuilds_exactly(pack, newton):
    """Rebuilding the neighbour lists at every step (each contact's history goes through the
    per-atom partner lists 400 times; newton on: half of them through the ghost atoms' reverse
    communication) gives the run that rebuilds only when needed (~30 times): the round trip
    list -> partner lists -> new list keeps every value."""
    d, _ = pack
    ref, proc = _run_pack(d, f"rebuild.some.{newton}", law="Jian", newton=newton)
    assert 10 <= _builds(proc) < STEPS / 4
    script = _PACK.format(plugin=plugin_line(), newton=newton, pstyle="", law=LAWS["Jian"],
                          setup=_SETUP.replace("check yes", "check no"), steps=STEPS,
                          out=f"rebuild.every.{newton}")
    proc = run_lmp(script, d, name=f"in.rebuild.every.{newton}")
    assert_ok(proc)
    assert _builds(proc) >= STEPS
    diffs = _max_rel_diff(ref, read_atoms(d / f"rebuild.every.{newton}"))
    assert max(diffs.values()) <= TOL, diffs


def test_history_matters_negative_control(pack):
    """The same run with every contact's history dropped at each rebuild (DROP_HISTORY, a
    negative control reached through the environment only) differs grossly: the test above
    could fail."""
    d, _ = pack
    kept, _ = _run_pack(d, "kept.KK")
    dropped, _ = _run_pack(d, "dropped.KK", env=DROP_HISTORY)
    diffs = _max_rel_diff(kept, dropped)
    assert min(diffs.values()) > 1e-3, diffs


def test_in_process_equals_lmp(pack):
    """The lammps Python module (plugin loaded by viscontact.dem.new_lammps) gives the lmp run."""
    d, _ = pack
    ref, _ = _run_pack(d, "lmp.Jian", law="Jian", steps=200)
    script = _PACK.format(plugin="", newton="off", pstyle="", law=LAWS["Jian"], setup=_SETUP,
                          steps=200, out="inproc.Jian")
    run_inprocess(script, d)
    got = read_atoms(d / "inproc.Jian")
    diffs = _max_rel_diff(ref, got)
    assert max(diffs.values()) <= TOL, diffs


_RESTART_A = _PACK_HEAD + """\
{write}
run {n}
write_dump all custom {tag}.ref id xu yu zu vx vy vz omegax omegay omegaz modify sort id format float %.17g
"""
_RESTART_B = """\
{plugin}
read_restart {tag}.restart
{pstyle}
{setup}
run {n}
write_dump all custom {tag}.{out} id xu yu zu vx vy vz omegax omegay omegaz modify sort id format float %.17g
"""

@pytest.mark.parametrize("newton,np_,mode", [("off", 1, "command"), ("on", 2, "command"),
                                             ("on", 2, "periodic")])
def test_restart_continues_exactly(pack, newton, np_, mode):
    """N steps, write_restart, N steps in one process against read_restart + N steps: equal.
    ``mode``: the write_restart command after the run, or a restart file written during the
    run's last step by ``restart N``.

    The reference continues with a second ``run`` (not one run of 2N steps) because every
    ``run`` starts by recomputing the forces from the full-step velocities (LAMMPS's setup; the
    same for pair granular), which differs from the half-step velocities the integrator used
    inside a run; a restarted run does the same, so the comparison isolates the restart.
    Negative control: the restarted run with its history dropped differs grossly.
    """
    d, _ = pack
    tag = f"rs.{newton}.{np_}.{mode}"
    law = LAWS["Jian"]
    n = STEPS // 2
    write = (f"run {n}\nwrite_restart {tag}.restart" if mode == "command" else
             f"restart {n} {tag}.*\nrun {n}\nrestart 0\nshell mv {tag}.{n} {tag}.restart")
    proc = run_lmp(_RESTART_A.format(plugin=plugin_line(), newton=newton, law=law, pstyle="",
                                     setup=_SETUP,
                                     n=n, tag=tag, write=write), d, np=np_, name=f"in.{tag}.a")
    assert_ok(proc)
    proc = run_lmp(_RESTART_B.format(plugin=plugin_line(), tag=tag, pstyle="", setup=_SETUP,
                                     n=STEPS // 2, out="restarted"), d, np=np_, name=f"in.{tag}.b")
    assert_ok(proc)
    assert "VISCONTACT_HISTORY" in proc.stdout  # LAMMPS: per-atom fix info reset from restart
    ref = read_atoms(d / f"{tag}.ref")
    diffs = _max_rel_diff(ref, read_atoms(d / f"{tag}.restarted"))
    assert max(diffs.values()) <= TOL, diffs
    proc = run_lmp(_RESTART_B.format(plugin=plugin_line(), tag=tag, pstyle="", setup=_SETUP,
                                     n=STEPS // 2, out="dropped"), d, np=np_, name=f"in.{tag}.c",
                   env=DROP_HISTORY)
    assert_ok(proc)
    diffs = _max_rel_diff(ref, read_atoms(d / f"{tag}.dropped"))
    assert min(diffs.values()) > 1e-3, diffs


# ---------------------------------------------------------------------------- Jian's clock
R, RHO, E, NU, G = 0.005, 2500.0, 1.0e7, 0.3, 50.0
GAP, DT = 1.0e-3, 1.0e-6

_BOUNCE = sphere_head("f f f", "-0.02 0.02 -0.02 0.02 -0.02 0.05") + """\
create_atoms 1 single 0 0 0
create_atoms 1 single 0 0 {z0:.17g}
set group all diameter {d:.17g}
set group all density {rho:.17g}
group high id 2
pair_style viscontact
pair_coeff * * hertz/material {E:.17g} {nu} damping Jian c0 {c0:.17g} tau {tau:.17g} tangential none
fix 1 high nve/sphere
fix g high gravity {g} vector 0 0 -1
timestep {dt}
neighbor 0.001 bin
dump d high custom 1 contact.dump id mass z vz fz
dump_modify d thresh z < {d:.17g} format float %.17g
run {steps}
"""


def _jian_bounce(tmp_path, runs: str):
    """The falling sphere of the Jian tests, LAMMPS ``runs`` (its run and timestep commands):
    (k, c0, tau, frames in contact: step, mass, z, vz, fz arrays; the first frame of a step)."""
    mass = 4.0 / 3.0 * math.pi * R**3 * RHO
    meff, reff = mass / 2, R / 2
    estar = 1.0 / (2 * (1 - NU**2) / E)
    k = 4.0 / 3.0 * estar * math.sqrt(reff)
    v1 = math.sqrt(2 * G * GAP)
    c0 = damping_coefficient("Jian", 0.4, m_eff=meff, k_hertz=k, v=v1)
    tau = 0.5 * time_scale(meff, k, v1)
    script = _BOUNCE.format(plugin=plugin_line(), z0=2 * R + GAP, d=2 * R, rho=RHO, E=E, nu=NU,
                            c0=c0, tau=tau, g=G, dt=DT, steps=0).replace("run 0\n", runs)
    proc = run_lmp(script, tmp_path)
    assert_ok(proc)
    from viscontact import dem

    frames, seen = [], set()
    for f in dem.read_dump(tmp_path / "contact.dump"):
        # in contact; a second run's setup dumps its first step again (full-step velocities)
        if f.natoms and f.step not in seen:
            seen.add(f.step)
            frames.append(f)
    cols = (np.array([f.step for f in frames]),) + tuple(
        np.array([f[c][0] for f in frames]) for c in ("mass", "z", "vz", "fz"))
    return k, c0, tau, cols


def _jian_force(k, c0, tau, delta, ddelta, tc):
    """Jian's normal force with the clamp (end force) at contact time tc."""
    f = k * (delta * np.sqrt(delta)) + c0 * (-np.expm1(-tc / tau)) * np.sqrt(delta) * ddelta
    return np.maximum(f, 0.0)


def test_jian_clock_restarts_on_recontact(tmp_path):
    """A sphere falls on a fixed one, bounces off and lands again.  At every step of both
    contacts the force is k delta^1.5 + c0 (1 - exp(-t_c/tau)) delta^0.5 delta' with t_c the
    time since *that* contact began (t0 = first step in contact minus delta/delta', at most
    one step back: viscontact_contact.h contact_start_time), to 1e-9 of the peak force; a clock
    that kept running from the first contact would be wrong by orders of magnitude more."""
    k, c0, tau, (step, m, z, vz, fz) = _jian_bounce(tmp_path, "run 22000\n")
    starts = np.flatnonzero(np.diff(step, prepend=-10) != 1)
    assert len(starts) >= 2, f"expected two contacts, got {len(starts)}"
    fcontact = fz + m * G  # the dump's force includes gravity
    vhalf = vz - 0.5 * DT * fz / m  # the force used the half-step velocity
    delta = 2 * R - z
    ddelta = -vhalf
    peak = np.abs(fcontact).max()

    def expected(t0):
        return _jian_force(k, c0, tau, delta, ddelta, step * DT - t0)

    t0s = []
    for s in starts[:2]:
        t_first = step[s] * DT
        t0s.append(t_first - min(delta[s] / ddelta[s], DT))
    ends = list(starts[1:2]) + [len(step)]
    for (s, e), t0 in zip(zip(starts[:2], ends), t0s):
        err = np.abs(fcontact[s:e] - expected(t0)[s:e]).max()
        assert err <= 1e-9 * peak, (err / peak, s)
    # the clock of the second contact is not the first one's
    s, e = starts[1], ends[1]
    wrong = np.abs(fcontact[s:e] - expected(t0s[0])[s:e]).max()
    assert wrong > 1e-4 * peak, wrong / peak


def test_jian_clock_across_a_change_of_time_step(tmp_path):
    """The time step drops to a third in the middle of the first contact (``timestep`` between
    two runs).  Each step advances the stored relaxation g by exp(-dt/tau) of its own dt, so
    that at every step of the contact g = 1 - exp(-t_c/tau) with t_c the simulated time since
    the contact began, to 1e-9 of the peak force as without the change; a clock that counted
    the later steps at the old dt would be wrong by far more."""
    n1, dt2 = 6700, DT / 3  # the sphere lands at about step 6320; the contact lasts ~1300 steps
    k, c0, tau, (step, m, z, vz, fz) = _jian_bounce(
        tmp_path, f"run {n1}\ntimestep {dt2!r}\nrun 6000\n")
    first = np.flatnonzero(np.diff(step, prepend=-10) != 1)
    s, e = first[0], (first[1] if len(first) > 1 else len(step))
    assert step[s] < n1 < step[e - 1], "the change must fall inside the first contact"
    dt = np.where(step <= n1, DT, dt2)  # the step that led to each frame
    t = np.where(step <= n1, step * DT, n1 * DT + (step - n1) * dt2)
    fcontact = fz + m * G
    vhalf = vz - 0.5 * dt * fz / m
    delta, ddelta = 2 * R - z, -vhalf
    peak = np.abs(fcontact[s:e]).max()
    t0 = t[s] - min(delta[s] / ddelta[s], DT)
    err = np.abs(fcontact - _jian_force(k, c0, tau, delta, ddelta, t - t0))[s:e].max()
    assert err <= 1e-9 * peak, err / peak
    wrong = np.abs(fcontact - _jian_force(k, c0, tau, delta, ddelta, step * DT - t0))[s:e].max()
    assert wrong > 1e-4 * peak, wrong / peak


@needs_mpirun
def test_second_run_with_pre_no_keeps_history(pack):
    """``run N`` then ``run N pre no post no`` (no rebuild at the second run's start: the
    per-neighbour history stays in use after the first run stored it) runs, and gives the same
    on 1 and 2 ranks.  (It is not compared with a second ``run N``: with ``pre no`` LAMMPS does not
    refresh the ghost atoms' velocities before the setup forces, for pair granular as for us.)"""
    d, _ = pack
    results = {}
    for nproc in (1, 2):
        setup = _SETUP + f"\nrun {STEPS // 2}"
        script = _PACK.format(plugin=plugin_line(), newton="off", pstyle="", law=LAWS["Jian"],
                              setup=setup, steps=f"{STEPS // 2} pre no post no",
                              out=f"twice.{nproc}")
        proc = run_lmp(script, d, np=nproc, name=f"in.twice.{nproc}")
        assert_ok(proc)
        results[nproc] = read_atoms(d / f"twice.{nproc}")
    diffs = _max_rel_diff(results[1], results[2])
    assert max(diffs.values()) <= TOL, diffs
