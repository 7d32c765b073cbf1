"""Every sub-model of ``pair_style viscontact`` next to native ``pair_style granular`` (pinned
LAMMPS), through the exact equivalences of the laws that native also has: LH ``c0`` = native
``damping velocity``, KK ``c0`` = native ``viscoelastic`` with eta0 = c0/(m* sqrt(R*)) (one m*
and R*: a monodisperse pack), Ts ``alpha A vref V`` = native ``tsuji`` with alpha_T(e) = A.

A dense, periodic, monodisperse pack of spheres with random velocities and spins keeps many
contacts sliding, rolling and twisting; ours and native start from the same data file and run
2,000 steps.  Forces and torques of the dumped steps (history loaded) agree to 1e-10 of the
largest force (torque), positions to 1e-8 of the diameter, on 1 and on 2 ranks.  The heat
model's per-atom heat flow equals native ``heat area``.

Every run of a rank count is one part of a single LAMMPS input (``clear`` between parts: each
starts from nothing but the loaded plugin), so the module starts LAMMPS twice, not 40 times;
each test reads its own parts' dumps.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from dem_util import MPIRUN, assert_ok, needs_lammps, plugin_line, run_lmp, write_sphere_data

pytestmark = needs_lammps

E, NU, RHO, D = 1.0e7, 0.3, 2500.0, 0.01
N_SIDE, SPACING = 3, 0.0099          # 27 spheres, 1 % overlap with each lattice neighbour
STEPS, EVERY, DT = 2000, 250, 2e-6
E_TSUJI = 0.7


def _kk_eta0(c0: float) -> float:
    """Native viscoelastic eta0 for our KK c0 (monodisperse: m* = m/2, R* = D/4)."""
    m = RHO * np.pi * D**3 / 6
    return float(c0 / (0.5 * m * np.sqrt(D / 4)))


def _ts_alpha() -> float:
    from viscontact.audit.formulas import tsuji_polynomial

    return tsuji_polynomial(E_TSUJI)


# (ours, native) pair_coeff tails, one per sub-model combination; every tangential, rolling,
# twisting and normal model appears at least once
CASES = {
    "LH_linear_history_rolling_twist_marshall": (
        f"hertz/material {E} {NU} damping LH c0 0.05 tangential linear_history 2e4 0.5 0.4 "
        "rolling sds 50 0.002 0.1 twisting marshall",
        f"hertz/material {E} 0.05 {NU} damping velocity tangential linear_history 2e4 0.5 0.4 "
        "rolling sds 50 0.002 0.1 twisting marshall limit_damping"),
    "LH_linear_nohistory": (
        f"hertz/material {E} {NU} damping LH c0 0.05 end overlap tangential linear_nohistory 0.5 0.3",
        f"hertz/material {E} 0.05 {NU} damping velocity tangential linear_nohistory 0.5 0.3"),
    "KK_mindlin_twist_sds": (
        f"hertz/material {E} {NU} damping KK c0 2.0 tangential mindlin NULL 0.5 0.4 "
        "rolling sds 50 0.002 0.1 twisting sds 1e-4 1e-7 0.02",
        f"hertz/material {E} {_kk_eta0(2.0)!r} {NU} damping viscoelastic tangential mindlin NULL "
        "0.5 0.4 rolling sds 50 0.002 0.1 twisting sds 1e-4 1e-7 0.02 limit_damping"),
    "KK_mindlin_rescale": (
        f"hertz/material {E} {NU} damping KK c0 2.0 tangential mindlin_rescale 3e6 0.2 0.3",
        f"hertz/material {E} {_kk_eta0(2.0)!r} {NU} damping viscoelastic tangential "
        "mindlin_rescale 3e6 0.2 0.3 limit_damping"),
    "Ts_mindlin_force_marshall": (
        f"hertz/material {E} {NU} damping Ts alpha {_ts_alpha()!r} vref 1 tangential "
        "mindlin/force NULL 0.3 0.4 twisting marshall",
        f"hertz/material {E} {E_TSUJI} {NU} damping tsuji tangential mindlin/force NULL 0.3 0.4 "
        "twisting marshall limit_damping"),
    "Ts_mindlin_rescale_force_short": (
        f"hertz/material {E} {NU} damping Ts alpha {_ts_alpha()!r} vref 1 tangential "
        "mindlin_rescale/force NULL 0.3 0.4 rolling sds 50 0.002 0.1",
        f"hertz/material {E} {E_TSUJI} {NU} damping tsuji tangential mindlin_rescale/force NULL "
        "0.3 0.4 rolling sds 50 0.002 0.1 limit_damping"),
    "mindlin_short_form": (
        f"hertz/material {E} {NU} damping LH c0 0.05 tangential mindlin 0.4",
        f"hertz/material {E} 0.05 {NU} damping velocity tangential mindlin NULL 0 0.4 "
        "limit_damping"),
    "jkr_LH_linear_history_rolling_twist": (
        f"jkr {E} {NU} 2.0 damping LH c0 0.05 tangential linear_history 2e4 0.5 0.4 "
        "rolling sds 50 0.002 0.1 twisting sds 1e-4 1e-7 0.02",
        f"jkr {E} 0.05 {NU} 2.0 damping velocity tangential linear_history 2e4 0.5 0.4 "
        "rolling sds 50 0.002 0.1 twisting sds 1e-4 1e-7 0.02"),
    "dmt_KK_mindlin_rescale_marshall": (
        f"dmt {E} {NU} 2.0 damping KK c0 2.0 tangential mindlin_rescale NULL 0.5 0.4 "
        "twisting marshall",
        f"dmt {E} {_kk_eta0(2.0)!r} {NU} 2.0 damping viscoelastic tangential mindlin_rescale NULL "
        "0.5 0.4 twisting marshall"),
}

_SCRIPT = """units si
atom_style sphere
atom_modify map array
boundary p p p
comm_modify vel yes
read_data {data}
pair_style {style}
pair_coeff * * {coeff}
neighbor 0.0005 bin
timestep {dt}
fix 1 all nve/sphere
dump d all custom {every} {out} id x y z fx fy fz tqx tqy tqz
dump_modify d format float %.17g sort id
run {steps}
"""


def _pack(path) -> None:
    rng = np.random.default_rng(2020)
    g = np.arange(N_SIDE) * SPACING + 0.5 * SPACING
    xyz = np.array([[x, y, z] for x in g for y in g for z in g])
    xyz += rng.uniform(-2e-5, 2e-5, xyz.shape)
    n = len(xyz)
    L = N_SIDE * SPACING
    write_sphere_data(path, (0, L, 0, L, 0, L), xyz, np.full(n, D), RHO,
                      v=rng.normal(0, 0.05, (n, 3)), omega=rng.normal(0, 20.0, (n, 3)))


def _frames(path) -> np.ndarray:
    """(frame, atom, 9): x y z fx fy fz tqx tqy tqz of every dumped step."""
    from viscontact import dem

    cols = ("x", "y", "z", "fx", "fy", "fz", "tqx", "tqy", "tqz")
    return np.array([np.stack([np.asarray(fr.columns[c]) for c in cols], 1)
                     for fr in dem.read_dump(path)])


def _part(name: str, body: str) -> str:
    """One run of the batch: its input lines, then a line that says it finished."""
    return f"{body}print \"part done: {name}\"\n"


@pytest.fixture(scope="module")
def batch(tmp_path_factory):
    """``batch(np_)``: every run on ``np_`` ranks in one LAMMPS input (built once per rank
    count): (directory with the dumps, finished process).  Parts: each case with native and
    ours; on 1 rank also the heat runs."""
    done = {}

    def get(np_: int):
        if np_ not in done:
            work = tmp_path_factory.mktemp(f"native-np{np_}")
            _pack(work / "pack.data")
            parts = []
            for case, (ours, native) in CASES.items():
                for style, coeff in (("granular", native), ("viscontact", ours)):
                    out = f"{case}.{style}"
                    parts.append(_part(out, _SCRIPT.format(
                        data="pack.data", style=style, coeff=coeff, dt=DT, every=EVERY, out=out,
                        steps=STEPS)))
            if np_ == 1:
                for case in HEAT_CASES:
                    for style, coeff in zip(("viscontact", "granular"), CASES[case]):
                        out = f"heat.{case}.{style}"
                        parts.append(_part(out, _HEAT.format(data="pack.data", style=style,
                                                             coeff=coeff, dt=DT, out=out)))
            script = plugin_line() + "\n" + "clear\n".join(parts)
            done[np_] = work, run_lmp(script, work, np=np_, name="in.all", timeout=900)
        return done[np_]

    return get


def _dump(batch_run, out: str) -> Path:
    """The dump of part ``out``, after checking that the part ran to its end."""
    work, proc = batch_run
    if f"part done: {out}" not in proc.stdout:
        assert_ok(proc)  # LAMMPS's own error text
        raise AssertionError(f"part {out} did not finish:\n{proc.stdout[-3000:]}")
    return work / out


def _run(batch, case: str, style: str, np_: int) -> np.ndarray:
    return _frames(_dump(batch(np_), f"{case}.{style}"))


@pytest.mark.parametrize("np_", [pytest.param(1, id="np1"), pytest.param(2, id="np2", marks=(
    pytest.mark.skipif(MPIRUN is None, reason="no mpirun")))])
@pytest.mark.parametrize("case", list(CASES))
def test_sub_models_as_native(batch, case, np_):
    """Forces, torques and positions of a sheared, spinning pack equal native's (see module)."""
    nat = _run(batch, case, "granular", np_)
    ours = _run(batch, case, "viscontact", np_)
    assert ours.shape == nat.shape and len(nat) == STEPS // EVERY + 1
    fpeak = np.abs(nat[:, :, 3:6]).max()
    tpeak = np.abs(nat[:, :, 6:9]).max()
    assert fpeak > 0 and tpeak > 0
    # the pack really has contacts that rub and twist: torques are not negligible
    assert tpeak > 1e-3 * fpeak * D
    dx = np.abs(ours[:, :, 0:3] - nat[:, :, 0:3]).max()
    df = np.abs(ours[:, :, 3:6] - nat[:, :, 3:6]).max() / fpeak
    dt = np.abs(ours[:, :, 6:9] - nat[:, :, 6:9]).max() / tpeak
    assert dx <= 1e-8 * D, dx / D
    assert df <= 1e-10, df
    assert dt <= 1e-10, dt


_HEAT = """units si
atom_style sphere
atom_modify map array
boundary p p p
comm_modify vel yes
fix p all property/atom temperature heatflow
read_data {data} fix p NULL NULL
set group all temperature 300
set atom 1*13 temperature 400
pair_style {style}
pair_coeff * * {coeff} heat area 3.0
neighbor 0.0005 bin
timestep {dt}
fix 1 all nve/sphere
fix h all heat/flow constant 1.0
compute hf all property/atom temperature heatflow
dump d all custom 50 {out} id c_hf[1] c_hf[2]
dump_modify d format float %.17g sort id
run 200
"""


HEAT_CASES = ("LH_linear_history_rolling_twist_marshall", "jkr_LH_linear_history_rolling_twist")


@pytest.mark.parametrize("case", HEAT_CASES)
def test_heat_area_as_native(batch, case):
    """heat area K with fix heat/flow: per-atom heat flow and temperature of every dumped step
    equal native's (Q = K pi a^2 (T_j - T_i), a the normal model's contact radius)."""
    from viscontact import dem

    got = {}
    for style in ("viscontact", "granular"):
        path = _dump(batch(1), f"heat.{case}.{style}")
        got[style] = np.array([np.stack([np.asarray(fr.columns[c]) for c in ("c_hf[1]", "c_hf[2]")], 1)
                               for fr in dem.read_dump(path)])
    ours, nat = got["viscontact"], got["granular"]
    qpeak = np.abs(nat[:, :, 1]).max()
    assert qpeak > 0 and np.abs(nat[-1, :, 0] - nat[0, :, 0]).max() > 0    # heat flows
    assert np.abs(ours[:, :, 1] - nat[:, :, 1]).max() <= 1e-10 * qpeak
    assert np.abs(ours[:, :, 0] - nat[:, :, 0]).max() <= 1e-12 * 400
