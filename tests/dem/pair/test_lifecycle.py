"""The life of a ``pair viscontact`` / ``fix viscontact/wall`` simulation across LAMMPS commands:
restart files and runs split into several ``run`` commands continue the straight run to
1e-12 (sliding, sticking and Jian-clock contacts, pair and wall, 1 and 2 ranks); removing or
unloading the history fix, changing ``pair_style``, ``delete_atoms`` and ``fix pour`` adding
atoms mid-run give an ``ERROR:`` line or the right physics, never a crash.

What "the straight run" is (LAMMPS's semantics, the same for native pair granular): ``run 2N``
equals ``run N`` + ``run N pre no`` (no setup between them), and a restarted ``run N`` equals
the second ``run N`` of ``run N`` + ``write_restart`` + ``run N`` in one process (every run
with setup recomputes the forces from the full-step velocities, a restarted one too).
"""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import (
    DROP_HISTORY, assert_ok, error_lines, needs_lammps, needs_mpirun, plugin_line, rank_head,
    read_atoms, run_lmp, write_sphere_data,
)

pytestmark = needs_lammps

R, RHO, E, NU = 0.001, 2500.0, 1.0e7, 0.3
COLUMNS = ("x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz")
#: measured differences: 0 (split runs, bit-identical) and <= 1e-14 (restarts: read_restart
#: orders the atoms differently, so force sums round differently)
TOL = 1e-12
N = 300

_HEAD = rank_head("p p f") + """\
{lines}
fix g all gravity 9.81 vector 0 0 -1
fix 1 all nve/sphere
neighbor 0.0003 bin
neigh_modify delay 0 every 1 check yes
timestep 2e-6
thermo 0
"""
_TAIL = ("write_dump all custom {out} id x y z vx vy vz omegax omegay omegaz modify sort id "
         "format float %.17g\n")
#: the laws under test: Jian's clock with sliding (mu 0.05) and with sticking (mu 10) contacts
MU = {"sliding": 0.05, "sticking": 10.0}


def _lines(mu: float) -> str:
    law = f"damping Jian alpha 0.4 vref 0.5 beta 0.5 end force tangential mindlin {mu}"
    return (f"pair_style viscontact\npair_coeff * * hertz/material {E} {NU} {law}\n"
            f"fix vcwall all viscontact/wall zplane 0.0 NULL wall_material rigid {law}")


@pytest.fixture(scope="module")
def pile(tmp_path_factory):
    """A small pile: 60 spheres (two radii) in a periodic 12 x 6 mm column, falling onto the
    wall with random velocities and spins; in N steps they hit the floor and each other."""
    d = tmp_path_factory.mktemp("pile")
    rng = np.random.default_rng(3)
    g = np.stack(np.meshgrid(np.arange(6), np.arange(3), np.arange(4), indexing="ij"),
                 -1).reshape(-1, 3)[:60]
    xyz = (g + 0.5) * 0.002 + rng.uniform(-1e-4, 1e-4, g.shape)
    xyz[:, 2] += 0.0002
    diam = rng.choice([1.6e-3, 2.0e-3], len(xyz))
    write_sphere_data(d / "pile.data", (0, 0.012, 0, 0.006, -0.001, 0.02), xyz, diam, RHO,
                      v=rng.normal(0, 0.3, xyz.shape), omega=rng.normal(0, 300, xyz.shape))
    return d


def _run(d, out, body, *, mu, np_=1, newton="off", start="read_data pile.data", env=None,
         lines=None):
    script = _HEAD.format(plugin=plugin_line(), newton=newton, start=start,
                          lines=_lines(mu) if lines is None else lines) + body + _TAIL.format(out=out)
    proc = run_lmp(script, d, np=np_, name=f"in.{out}", env=env)
    assert_ok(proc)
    return read_atoms(d / out)


def _rel_diff(a, b) -> float:
    assert np.array_equal(a["id"], b["id"])
    return max(float(np.max(np.abs(a[c] - b[c])) / max(np.max(np.abs(a[c])), 1e-300))
               for c in COLUMNS)


@pytest.mark.parametrize("np_,newton", [(1, "off"), pytest.param(2, "on", marks=needs_mpirun)])
@pytest.mark.parametrize("regime", list(MU))
def test_split_and_restarted_runs_equal_the_straight_run(pile, regime, np_, newton):
    """Pair and wall with Jian's clock, sliding or sticking: ``run 2N`` = ``run N`` + ``run N pre
    no``; ``run N`` + ``write_restart`` + ``run N`` = ``read_restart`` + ``run N``; to 1e-12.
    Negative control: the restarted run without the pair history (DROP_HISTORY) differs."""
    mu, tag = MU[regime], f"{regime}.{np_}"
    kw = dict(mu=mu, np_=np_, newton=newton)
    straight = _run(pile, f"straight.{tag}", f"run {2 * N}\n", **kw)
    split = _run(pile, f"split.{tag}", f"run {N}\nrun {N} pre no post no\n", **kw)
    assert _rel_diff(straight, split) <= TOL
    ref = _run(pile, f"ref.{tag}", f"run {N}\nwrite_restart {tag}.restart\nrun {N}\n", **kw)
    restarted = _run(pile, f"restarted.{tag}", f"run {N}\n", start=f"read_restart {tag}.restart",
                     lines=_lines(mu).split("\n", 2)[2], **kw)
    assert _rel_diff(ref, restarted) <= TOL
    dropped = _run(pile, f"dropped.{tag}", f"run {N}\n", start=f"read_restart {tag}.restart",
                   lines=_lines(mu).split("\n", 2)[2], env=DROP_HISTORY, **kw)
    assert _rel_diff(ref, dropped) > 1e-6


# ---------------------------------------------------------------------------- lifecycle
LIFECYCLE = {
    # the history fix removed behind the pair's back: one ERROR line at the next run
    "unfix_history": ("run 50\nunfix VISCONTACT_HISTORY\nrun 50\n", "was deleted"),
    "unload_history": ("run 50\nplugin unload fix VISCONTACT_HISTORY\nrun 50\n", "was deleted"),
    # ... and given again: a fresh pair with fresh contacts runs
    "unfix_then_new_pair": ("run 50\nunfix VISCONTACT_HISTORY\n{pair}\nrun 50\n", None),
    "define_history_fix": ("fix h all VISCONTACT_HISTORY\nrun 10\n", "internal to pair viscontact"),
    # pair style swapped mid-input and back
    "pair_style_change": ("run 50\npair_style granular\npair_coeff * * hertz/material 1e7 0.3 0.3 "
                          "tangential mindlin NULL 0 0.5\nrun 50\n{pair}\nrun 50\n", None),
    "pair_style_none": ("run 50\npair_style none\nrun 10\n{pair}\nrun 50\n", None),
    "unload_pair": ("run 50\nplugin unload pair viscontact\nrun 10\n", None),
    "delete_atoms": ("run 100\nregion del block INF INF INF INF INF 0.003\n"
                     "delete_atoms region del\nrun 100\n", None),
    "pour_mid_run": ("region slab block 0 0.012 0 0.006 0.012 0.019\n"
                     "fix p all pour 15 1 11 region slab diam one 0.002 dens 2500 2500\n"
                     "run 4000\n", None),
    "unfix_wall_then_again": ("run 50\nunfix vcwall\nrun 10\n{wall}\nrun 50\n", None),
}


@pytest.mark.parametrize("case", list(LIFECYCLE))
def test_lifecycle_error_or_right_physics(pile, case):
    """Each command sequence ends with exit 0 and finite atoms (every atom kept, none through the
    floor) or with exactly one ERROR line naming the cause; never a crash or a hang."""
    body, message = LIFECYCLE[case]
    # the wall has its own particle material: it runs on while the pair style changes
    lines = _lines(0.5) + f" particle {E} {NU}"
    pair, wall = lines.split("\n", 2)[:2], lines.split("\n", 2)[2]
    assert wall.startswith("fix vcwall")
    body = body.format(pair="\n".join(pair), wall=wall)
    script = _HEAD.format(plugin=plugin_line(), newton="off", start="read_data pile.data",
                          lines=lines) + body + _TAIL.format(out=f"life.{case}")
    proc = run_lmp(script, pile, name=f"in.life.{case}", timeout=120)
    errs = error_lines(proc)
    assert proc.returncode >= 0, f"crashed with signal {-proc.returncode}"
    if message is None:
        assert proc.returncode == 0 and not errs, (errs, proc.stdout[-1500:])
        at = read_atoms(pile / f"life.{case}")
        xyz = np.stack([at["x"], at["y"], at["z"]], 1)
        assert np.isfinite(xyz).all() and (at["z"] > 0).all()
        if case == "pour_mid_run":
            assert len(at["id"]) == 75
    else:
        assert proc.returncode != 0 and len(errs) == 1, (errs, proc.stdout[-1500:])
        assert message in errs[0], errs
