"""Restart files and rank changes with the full contact history and the energy arrays: a
cohesive (jkr), frictional (mindlin_rescale: spring and previous contact radius), rolling- and
twisting-resistant settling pack with ``compute viscontact/energy``.

* ``run N`` + ``write_restart`` + ``run N`` in one process equals ``read_restart`` + ``run N``
  (positions, velocities, spins, forces, torques, the 12-vector and the per-atom array), on 1
  rank (newton off) and 2 ranks (newton on);
* 2 ranks with ~a fifth of the atoms crossing the boundary between them (the pack drifts along
  x; ``fix balance`` migrates atoms) equals 1 rank, energies included: the per-contact history
  and the per-atom cumulative dissipation travel with the atoms.

Tolerances: differences come only from the order of force sums across ranks (measured below);
a restart must not add any.
"""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import (
    assert_ok, drifting_pack, needs_lammps, needs_mpirun, plugin_line, rank_head, read_atoms,
    run_lmp,
)

pytestmark = needs_lammps

NX, NY, NZ, SPACING = 8, 4, 5, 0.002
BOX = (0.0, NX * SPACING, 0.0, NY * SPACING, 0.0, 3 * NZ * SPACING)
STEPS = 300
COLUMNS = ("xu", "yu", "zu", "vx", "vy", "vz", "omegax", "omegay", "omegaz", "fx", "fy", "fz",
           "tqx", "tqy", "tqz") + tuple(f"c_e[{k}]" for k in range(1, 13))
#: 1 against 2 ranks: the order of force sums only (measured <= 8.5e-13 relative to the largest
#: value of each quantity); asserted 1e-10.  Restart against straight run: the atom order (and
#: so the order of force sums) changes at read_restart: measured up to 1.8e-12; asserted 1e-10.
TOL_RANKS = 1e-10
TOL_RESTART = 1e-10

_HEAD = rank_head("p p f", "read_data pack.data")
_MODEL = """\
pair_style viscontact
pair_coeff * * jkr 1e7 0.3 0.05 damping KK alpha 0.3 vref 1.0 tangential mindlin_rescale NULL 0.5 0.4 rolling sds 200 0.01 0.1 twisting sds 0.001 1e-9 0.05
"""
_SETUP = """\
compute e all viscontact/energy
fix bal all balance 50 1.0 shift x 5 1.02
fix floor all wall/gran granular hertz/material 1e7 0.3 0.3 tangential linear_nohistory 0 0 zplane 0.0 NULL
fix g all gravity 9.81 vector 0 0 -1
fix 1 all nve/sphere
neighbor 0.0004 bin
neigh_modify delay 0 every 1 check yes
timestep 5e-6
thermo_style custom step c_e[*]
thermo_modify format float %.17g
thermo {n}
"""
_DUMP = ("write_dump all custom {out} id xu yu zu vx vy vz omegax omegay omegaz fx fy fz "
         "tqx tqy tqz c_e[*] modify sort id format float %.17g\n")


@pytest.fixture(scope="module")
def pack(tmp_path_factory):
    """Directory with pack.data (overlapping spheres of two sizes, random velocities and spins,
    the whole pack drifting along x so that atoms change rank); returns (dir, positions)."""
    d = tmp_path_factory.mktemp("restart_pack")
    return d, drifting_pack(d / "pack.data", (NX, NY, NZ), SPACING, 11, v_sd=0.3, drift=1.0)


def _vector(log: str, step: int | None = None) -> np.ndarray:
    """The 12-vector of the last thermo line of a log (columns: step, c_e[1..12]), or of the
    last line of that step."""
    rows = []
    for line in log.splitlines():
        parts = line.split()
        if len(parts) == 13 and parts[0].isdigit() and (step is None or int(parts[0]) == step):
            rows.append([float(p) for p in parts[1:]])
    assert rows, log[-2000:]
    return np.array(rows[-1])


def _max_rel_diff(a: dict, b: dict) -> dict[str, float]:
    """Per column: max |a - b| / max |a| (0 where a is all zero and b too)."""
    assert np.array_equal(a["id"], b["id"])
    out = {}
    for c in COLUMNS:
        scale = np.abs(a[c]).max()
        diff = np.abs(a[c] - b[c]).max()
        out[c] = float(diff / scale) if scale > 0 else float(diff)
    return out


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(a).max())


def _straight(d, tag: str, np_: int, newton: str, steps: int, restart_at: int | None = None,
              mode: str = "command"):
    """``run`` (and, with restart_at, a restart file then a second run: mode "command", the
    write_restart command after the first run; "periodic", written by ``restart N`` during the
    first run's last step); returns the atoms, the final 12-vector and the process."""
    body = _HEAD + _MODEL + _SETUP
    if restart_at is None:
        body += f"run {steps}\n"
    elif mode == "command":
        body += f"run {restart_at}\nwrite_restart {tag}.restart\nrun {steps - restart_at}\n"
    else:
        body += (f"restart {restart_at} {tag}.*\nrun {restart_at}\nrestart 0\n"
                 f"shell mv {tag}.{restart_at} {tag}.restart\nrun {steps - restart_at}\n")
    script = (body + _DUMP).format(plugin=plugin_line(), newton=newton, n=STEPS, out=f"{tag}.dump")
    proc = run_lmp(script, d, np=np_, name=f"in.{tag}")
    assert_ok(proc)
    return read_atoms(d / f"{tag}.dump"), _vector(proc.stdout), proc


@needs_mpirun
@pytest.mark.parametrize("np_,newton,mode", [(1, "off", "command"), (2, "on", "command"),
                                             (2, "on", "periodic")])
def test_restart_continues_exactly(pack, np_, newton, mode):
    """read_restart + run N continues run N + write_restart + run N exactly, energies
    included; the dissipated energy is real and every mechanism saw work (the test can fail)."""
    d, _ = pack
    tag = f"rs.{np_}.{newton}.{mode}"
    half = STEPS // 2
    ref, vec_ref, proc = _straight(d, tag, np_, newton, STEPS, restart_at=half, mode=mode)
    vec_half = _vector(proc.stdout, half)
    script = (f"{{plugin}}\nread_restart {tag}.restart\n" + _MODEL + _SETUP + f"run {half}\n"
              + _DUMP).format(plugin=plugin_line(), n=STEPS, out=f"{tag}.restarted.dump")
    proc = run_lmp(script, d, np=np_, name=f"in.{tag}.b")
    assert_ok(proc)
    got, vec = read_atoms(d / f"{tag}.restarted.dump"), _vector(proc.stdout)
    diffs = _max_rel_diff(ref, got)
    assert max(diffs.values()) <= TOL_RESTART, diffs
    assert _rel(vec_ref, vec) <= TOL_RESTART, (vec_ref, vec)
    # what the comparison covers: dissipation by every mechanism, elastic energy in contacts
    assert vec_ref[0] > 0 and vec_ref[7] > 0, vec_ref
    assert np.all(vec_ref[1:6] > 0), vec_ref
    # per-atom columns sum to the vector (half of each contact's energy to each partner)
    for k in (0, 7):
        assert got[f"c_e[{k + 1}]"].sum() == pytest.approx(vec[k], rel=1e-12)
    # a restart that lost the cumulative per-atom dissipation would fail the comparison: the
    # first half (written to the restart file) holds a real part of the total
    assert 0.05 * vec_ref[0] < vec_half[0] < 0.95 * vec_ref[0], (vec_half, vec_ref)


@needs_mpirun
def test_two_ranks_equal_one_energies_included(pack):
    """Atoms crossing between two ranks (history and cumulative dissipation migrate) give the
    one-rank run, newton on and off."""
    d, xyz0 = pack
    one, vec1, _ = _straight(d, "ranks.1", 1, "off", STEPS)
    for newton in ("off", "on"):
        two, vec2, _ = _straight(d, f"ranks.2.{newton}", 2, newton, STEPS)
        diffs = _max_rel_diff(one, two)
        assert max(diffs.values()) <= TOL_RANKS, (newton, diffs)
        assert _rel(vec1, vec2) <= TOL_RANKS, (newton, vec1, vec2)
    half = BOX[1] / 2
    crossed = np.count_nonzero(np.floor(one["xu"] / half) != np.floor(xyz0[:, 0] / half))
    assert crossed >= 15, crossed
