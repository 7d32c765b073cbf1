"""The energy balance of a settling granular bed, every law, with every dissipation mechanism on.

A small bed (30 spheres of 8 to 12 mm, E = 10 MPa, nu = 0.3, 2500 kg/m^3) drops onto a rigid
floor (``fix viscontact/wall``, the same contact model) in a box periodic in x and y and settles
to rest.  Contacts: JKR cohesion (W = 2 J/m^2), the law's normal damping (e = 0.8 at 1 m/s, no
clamp), tangential ``linear_history`` with tangential damping (XGAMMA 0.5) and Coulomb friction,
rolling ``sds`` and twisting ``sds``.  Energy conservation is the independent reference:

    E(t) = KE + rotational KE + m g z + elastic(t) + dissipated(t) = E(0),

with the elastic (normal JKR potential, tangential, rolling and twisting springs) and the
cumulative dissipated energy (normal and tangential damping, sliding, rolling and twisting
resistance, JKR snap-in and pull-off hysteresis) of ``compute viscontact/energy`` (read back with
``viscontact.dem.read_energy``).  The explicit integrator conserves E only approximately: the
largest |E(t) - E(0)| over the run must stay below 1e-3 of the energy dissipated at dt = t_c/50
(t_c: the Hertz contact time of the smallest pair at 1 m/s) and shrink at least linearly when dt
halves (an accounting hole, e.g. a wall contact's spring energy dropped when it ends, gives a
residual that does not shrink).  Measured: 0.9e-4 to 1.4e-4 at t_c/50, and 3.2 to 3.6 times
less at t_c/100 (second order: each force's work is counted as velocity Verlet does it, so what
is left is the normal spring's exact potential against the integrator's trapezoid).  Both time
steps of every law run in one LAMMPS process.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from dem_examples import plugin_lacks
from laws_util import law_kwargs
from dem_util import assert_ok, needs_lammps, plugin_line, run_lmp
from viscontact import dem
from viscontact.physics.pair import HERTZ_TC

pytestmark = needs_lammps

LAWS = ("LH", "Ts", "KK", "Li", "Hunt", "Jian", "power")
E, NU, RHO, D_LO, D_HI, W = 1e7, 0.3, 2500.0, 0.008, 0.012, 2.0
N, G, SEED = 30, 9.81, 80431
#: simulated time: the bed falls (0.15 s) and comes to rest (kinetic energy below 1e-3 of the
#: dissipated energy with native granular and the same sub-models)
T_END = 0.5
TANGENTIAL = ("linear_history", 1000.0, 0.5, 0.5)
ROLLING = (200.0, 0.05, 0.1)
TWISTING = ("sds", 1e-5, 1e-7, 1e-3)


def contact_time() -> float:
    """Hertz contact time of the smallest pair at 1 m/s: 2.94 (m*^2/(k^2 v))^(1/5) with
    k = (4/3) E* sqrt(R*), E* = E/(2(1 - nu^2))."""
    m = RHO * math.pi / 6 * D_LO**3
    k = 4.0 / 3.0 * E / (2 * (1 - NU**2)) * math.sqrt(D_LO / 4)
    return HERTZ_TC * ((m / 2) ** 2 / k**2) ** 0.2


def _law(law: str) -> dem.DemLaw:
    return dem.contact_law(law, e=0.8, vref=1.0, **law_kwargs(law), end="overlap")


def _case(law: str, dt: float) -> str:
    cs = dem.coeff_set(law, [dict(E=E, nu=NU)], alpha=_law(law).alpha, vref=1.0,
                       **law_kwargs(law),
                       end="overlap", normal=("jkr", W), tangential=TANGENTIAL, rolling=ROLLING,
                       twisting=TWISTING, plugin="-",
                       walls=[dem.Wall("zplane", (0.0, None), "rigid")])
    steps = int(round(T_END / dt))
    return "\n".join([
        "clear", "units si", "atom_style sphere", "atom_modify map array", "boundary p p f",
        "comm_modify vel yes", "newton off", "region box block 0 0.04 0 0.04 0 0.12",
        "create_box 1 box", *cs.lines()[1:],
        "region cloud block 0.006 0.034 0.006 0.034 0.006 0.11",
        f"create_atoms 1 random {N} {SEED} cloud overlap 0.0125 maxtry 500",
        f"variable d atom {D_LO}+{D_HI - D_LO}*random(0,1,{SEED})",
        "set group all diameter v_d", f"set group all density {RHO}",
        f"fix gravity all gravity {G} vector 0 0 -1", "fix move all nve/sphere",
        "neighbor 0.002 bin", "neigh_modify delay 0", f"timestep {dt!r}",
        "compute ke all ke", "compute rke all erotate/sphere",
        f"variable pz atom mass*{G}*z", "compute pg all reduce sum v_pz",
        dem.energy_compute("en"),
        f"thermo_style custom step atoms c_ke c_rke c_pg {dem.energy_thermo('en')}",
        "thermo_modify format float %.17g lost error", f"thermo {steps // 100}",
        f"run {steps}",
    ])


def residual(thermo: dict) -> tuple[float, float, float]:
    """(max |E(t) - E(0)| / dissipated(end), dissipated(end) / E lost from potential,
    kinetic energy left / dissipated(end))."""
    en = dem.read_energy(thermo, "en")
    total = thermo["c_ke"] + thermo["c_rke"] + thermo["c_pg"] + en["elastic"] + en["dissipated"]
    lost = en["dissipated"][-1]
    # the parts add up to the totals (columns 2-7 and 9-12)
    parts = sum(en[k] for k in dem.ENERGY_COLUMNS[1:7])
    assert np.allclose(parts, en["dissipated"], rtol=1e-12, atol=1e-15 * lost)
    assert np.allclose(sum(en[k] for k in dem.ENERGY_COLUMNS[8:]), en["elastic"], rtol=1e-12,
                       atol=1e-15 * lost)
    drop = thermo["c_pg"][0] - thermo["c_pg"][-1]
    ke = thermo["c_ke"][-1] + thermo["c_rke"][-1]
    return float(np.max(np.abs(total - total[0])) / lost), float(lost / drop), float(ke / lost)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """law -> [thermo at t_c/50, thermo at t_c/100], all in one LAMMPS process."""
    tmp = tmp_path_factory.mktemp("energy")
    why = plugin_lacks("pair_coeff * * hertz/material 1e7 0.3 damping LH c0 1.0 tangential none\n"
                       "compute en all viscontact/energy", tmp / "probe")
    if why:
        pytest.skip(f"this plugin build has no compute viscontact/energy yet ({why})")
    dt = contact_time() / 50
    script = plugin_line() + "\n" + "\n".join(_case(law, f * dt) for law in LAWS for f in (1, 0.5))
    proc = run_lmp(script + "\n", tmp, name="in.energy", timeout=900)
    assert_ok(proc)
    tables = dem.read_log_runs(tmp / "in.energy.log")
    assert len(tables) == 2 * len(LAWS)
    return {law: tables[2 * k:2 * k + 2] for k, law in enumerate(LAWS)}


@pytest.mark.parametrize("law", LAWS)
def test_energy_balance_closes(runs, law):
    """Residual below 1e-3 of the dissipated energy at t_c/50, at least halved at t_c/100;
    the bed comes to rest (kinetic energy left well below what was dissipated), every
    mechanism dissipates, and no sphere is lost."""
    coarse, fine = runs[law]
    r1, share, left = residual(coarse)
    r2, _, _ = residual(fine)
    en = dem.read_energy(coarse, "en")
    print(f"{law}: residual {r1:.2e} at t_c/50, {r2:.2e} at t_c/100 (ratio {r1 / r2:.2f}); "
          f"dissipated / potential drop {share:.3f}; KE left / dissipated {left:.1e}; "
          + ", ".join(f"{k} {en[k][-1] / en['dissipated'][-1]:.3f}" for k in dem.ENERGY_COLUMNS[1:7]))
    assert coarse["Atoms"][-1] == N and fine["Atoms"][-1] == N
    assert left < 1e-2
    for k in dem.ENERGY_COLUMNS[1:7]:
        assert en[k][-1] > 0, k
    assert np.all(np.diff(en["dissipated"]) >= -1e-12 * en["dissipated"][-1])
    # the balance converges (an accounting hole, e.g. a wall contact's spring energy dropped
    # when it ends, gives 1e-2 that does not shrink with dt)
    assert r1 < 1e-3
    assert r2 <= r1 / 2, f"{law}: residual {r1:.2e} at t_c/50, {r2:.2e} at t_c/100"

