"""LAMMPS's own granular pair-style unit tests as a peer suite: their geometry and settings
rebuilt here, run with native ``pair_style granular`` and with ``pair_style viscontact`` in the
pinned LAMMPS (``lammps[mpi]==2025.7.22.4.0``), forces and torques equal to 1e-10 of the
largest.  Nothing of LAMMPS's test files is copied (LAMMPS is GPL, this project MIT): the
geometry is rebuilt from its description and native's numbers are computed, not stored.

The unit tests (``unittest/force-styles/tests/atomic-pair-gran*.yaml`` in the LAMMPS
sources) share one geometry: 32 spheres of diameter 1.25 and mass 1 on an fcc lattice of
reduced density 0.8442 (2 x 2 x 2 cells, LJ units, periodic), each displaced at random by up
to 0.05, atoms 17-32 of type 2 where a test has two types, velocities from ``velocity create
3.0 4534624`` (no spins), so that every sphere overlaps its lattice neighbours.  Each test
computes the forces of a ``run 0 post no``, then of ``run 4 post no`` with ``fix nve``, and
again after ``write_restart``, ``clear`` and ``read_restart``.  Which of them translate:

- ``gran_hooke``, ``gran_hooke_history``, ``gran_hooke_tri``: a Hooke (linear) normal spring,
  which the plugin does not have (hertz, dmt, jkr only): not translated.
- ``gran_hertz_history`` (``pair_style gran/hertz/history``, kn 1000, kt 350, gamma_n 50,
  gamma_t 30, mu 0.5, limit_damping): its forces are ours with hertz/material (4/3 E* = kn),
  ``KK c0 = gamma_n m* sqrt(R*)``, ``end force`` and ``mindlin 350 0.6 0.5`` at the first
  force call (3e-16), but the classic styles put the tangential force's torque at the lever
  arm R_i (ours and ``pair_style granular``: R_i - delta/2; torques differ by 14 %) and keep
  the classic tangential history rule (forces differ by 2e-5 from the second step), measured
  on the pinned LAMMPS: not translated.
- ``granular_epa_linear``, ``granular_epa_nonlinear``, ``granular_linear_history_static``,
  ``granular_mindlin_static``: their normal models (epa/*) and tangential models (*/static)
  are in LAMMPS's development sources, not in the pinned release, and not in the plugin: not
  translated as they are.  Their other settings are: two types (E 2000 and 3000, nu 0.3 and
  0.25, restitution 0.5 and 0.7 with ``damping tsuji``; ``damping viscoelastic``; tangential
  ``mindlin NULL 1.0 MU``, ``linear_history KT 1.0 MU``).  Those run here on the same
  geometry with the nearest released models (``hertz/material`` for epa, the plain
  tangential model for */static): cases ``hertz_tsuji_mindlin``,
  ``hertz_viscoelastic_mindlin`` and ``hertz_tsuji_linear_history``.
- The cohesive models on the same geometry (no LAMMPS unit test has them; the
  ``pair_granular`` documentation's example lines): ``jkr_mindlin_rolling_marshall`` and
  ``dmt_mindlin_rolling_marshall``; jkr is the case where a contact present at the setup
  opens to a negative overlap in the first step, and keeps its attraction there.

Translations (docs/pair_viscontact.md): native ``tsuji`` with restitution e = ``Ts alpha
alpha_T(e)``; ``viscoelastic`` eta0 = ``KK c0`` = eta0 m* sqrt(R*) (one size and mass:
m* = 1/2, R* = 0.3125); ``velocity`` = ``LH c0``; ``limit_damping`` = ``end force`` (absent:
``end overlap``).  Type pair 1-2 is given explicitly to both (one material, read alike):
native mixes the restitution of tsuji and the NULL Mindlin stiffness differently from ours
(documented differences).  Each case runs with newton on and off, all in one LAMMPS input.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from dem_util import assert_ok, needs_lammps, plugin_line, run_lmp

pytestmark = needs_lammps

TOL = 1e-10
M_EFF, R_EFF = 0.5, 0.3125    # the unit tests' spheres: mass 1, diameter 1.25

_GEOMETRY = """atom_modify map array
units lj
atom_style sphere
comm_modify vel yes
lattice fcc 0.8442
region box block 0 2 0 2 0 2
create_box 2 box
create_atoms 1 box
displace_atoms all random 0.05 0.05 0.05 623426
set atom 17*32 type 2
set group all diameter 1.25
set group all mass 1.0
velocity all create 3.0 4534624 loop all
"""


def _alpha(e: float) -> float:
    from viscontact.audit.formulas import tsuji_polynomial

    return tsuji_polynomial(e)


def _kk(eta0: float) -> float:
    """Our KK c0 for native viscoelastic eta0 (one m* and R*)."""
    return eta0 * M_EFF * math.sqrt(R_EFF)


def _tsuji(E, e, nu, tang_nat, tang_our):
    return (f"hertz/material {E} {e} {nu} tangential {tang_nat} damping tsuji",
            f"hertz/material {E} {nu} damping Ts alpha {_alpha(e)!r} vref 1 end overlap "
            f"tangential {tang_our}")


def _visco(E, eta0, nu, mu):
    return (f"hertz/material {E} {eta0} {nu} tangential mindlin NULL 1.0 {mu} "
            "damping viscoelastic",
            f"hertz/material {E} {nu} damping KK c0 {_kk(eta0)!r} end overlap "
            f"tangential mindlin NULL 1.0 {mu}")


def _cohesive(normal, E, eta0, nu, W, kt, mu, mur):
    roll = f"rolling sds 500.0 200.0 {mur} twisting marshall"
    return (f"{normal} {E} {eta0} {nu} {W} tangential mindlin {kt} 1.0 {mu} {roll}",
            f"{normal} {E} {nu} {W} damping KK c0 {_kk(eta0)!r} tangential mindlin {kt} 1.0 "
            f"{mu} {roll}")


#: case -> {type pair: (native pair_coeff tail, ours)}
CASES = {
    "hertz_tsuji_mindlin": {
        "1 1": _tsuji(2000.0, 0.5, 0.3, "mindlin NULL 1.0 0.3", "mindlin NULL 1.0 0.3"),
        "2 2": _tsuji(3000.0, 0.7, 0.25, "mindlin NULL 1.0 0.4", "mindlin NULL 1.0 0.4"),
        "1 2": _tsuji(2500.0, 0.6, 0.275, "mindlin NULL 1.0 0.35", "mindlin NULL 1.0 0.35")},
    "hertz_tsuji_linear_history": {
        "1 1": _tsuji(2000.0, 0.5, 0.3, "linear_history 500.0 1.0 0.3",
                      "linear_history 500.0 1.0 0.3"),
        "2 2": _tsuji(3000.0, 0.7, 0.25, "linear_history 700.0 1.0 0.4",
                      "linear_history 700.0 1.0 0.4"),
        "1 2": _tsuji(2500.0, 0.6, 0.275, "linear_history 600.0 1.0 0.35",
                      "linear_history 600.0 1.0 0.35")},
    "hertz_viscoelastic_mindlin": {
        "1 1": _visco(2000.0, 20.0, 0.3, 0.4),
        "2 2": _visco(3000.0, 30.0, 0.25, 0.5),
        "1 2": _visco(2500.0, 25.0, 0.275, 0.45)},
    "jkr_mindlin_rolling_marshall": {
        "* *": _cohesive("jkr", 1000.0, 50.0, 0.3, 10.0, 800.0, 0.5, 0.5)},
    "dmt_mindlin_rolling_marshall": {
        "1 1": _cohesive("dmt", 1000.0, 50.0, 0.3, 0.0, "NULL", 0.5, 0.5),
        "2 2": _cohesive("dmt", 1000.0, 50.0, 0.3, 10.0, "NULL", 0.1, 0.1),
        "1 2": _cohesive("dmt", 1000.0, 50.0, 0.3, 5.0, "NULL", 0.3, 0.3)},
}

_DUMP = ("dump d all custom 1 {out} id fx fy fz tqx tqy tqz\n"
         "dump_modify d format float %.17g sort id\n")


def _part(case: str, style: str, newton: str) -> str:
    """The unit test's three force computations, as three dumps: init (run 0), run (4 steps
    of fix nve), restart (run 0 after read_restart)."""
    out = f"{case}.{newton}.{style}"
    pair = f"pair_style {style}\n" + "".join(
        f"pair_coeff {types} {coeffs[0 if style == 'granular' else 1]}\n"
        for types, coeffs in CASES[case].items())
    return (f"newton {newton}\n{_GEOMETRY}{pair}" + _DUMP.format(out=out + ".init")
            + f"run 0 post no\nwrite_restart {out}.restart\nundump d\n"
            + "fix 1 all nve\n" + _DUMP.format(out=out + ".run") + "run 4 post no\n"
            # the pair lines again after read_restart, as LAMMPS's test does with pair_coeff
            # (native's pair read back from a restart file has no cutoff until then)
            + f"clear\nnewton {newton}\nread_restart {out}.restart\ncomm_modify vel yes\n{pair}"
            + _DUMP.format(out=out + ".restart") + "run 0 post no\n"
            + f'print "part done: {out}"\n')


@pytest.fixture(scope="module")
def batch(tmp_path_factory):
    work = tmp_path_factory.mktemp("lammps-unittests")
    parts = [_part(case, style, newton) for case in CASES for newton in ("on", "off")
             for style in ("granular", "viscontact")]
    script = plugin_line() + "\n" + "clear\n".join(parts)
    return work, run_lmp(script, work, name="in.all", timeout=900)


def _frames(batch, out: str) -> np.ndarray:
    from viscontact import dem

    work, proc = batch
    if f"part done: {out}" not in proc.stdout:
        assert_ok(proc)
        raise AssertionError(f"part {out} did not finish:\n{proc.stdout[-3000:]}")
    res = []
    for stage in ("init", "run", "restart"):
        frames = dem.read_dump(work / f"{out}.{stage}")
        res.append(np.array([np.stack([np.asarray(fr.columns[c]) for c in
                                       ("fx", "fy", "fz", "tqx", "tqy", "tqz")], 1)
                             for fr in frames]))
    return res


@pytest.mark.parametrize("newton", ["on", "off"])
@pytest.mark.parametrize("case", list(CASES))
def test_unit_test_case_as_native(batch, case, newton):
    """Init, run and restart forces and torques of the rebuilt unit test equal native's."""
    nat = _frames(batch, f"{case}.{newton}.granular")
    ours = _frames(batch, f"{case}.{newton}.viscontact")
    for stage, a, b in zip(("init", "run", "restart"), nat, ours):
        assert a.shape == b.shape, stage
        for name, cols in (("force", slice(0, 3)), ("torque", slice(3, 6))):
            peak = np.abs(a[:, :, cols]).max()
            assert peak > 0, (stage, name)
            diff = np.abs(b[:, :, cols] - a[:, :, cols]).max()
            assert diff <= TOL * peak, (stage, name, diff / peak)
    # the restart reproduces the first force call (as LAMMPS's test requires)
    assert np.abs(nat[2][0] - nat[0][0]).max() <= TOL * np.abs(nat[0][0]).max()
