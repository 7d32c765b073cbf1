"""Calibration audit: what published alpha(e) formulas and DEM-engine settings really deliver.

* :mod:`.formulas`: each published closed form alpha(e) as a function with its reference,
  in one registry, and :func:`audit_formula` (alpha, delivered e, exact alpha).
* :mod:`.engines`: DEM-engine presets mapped to (law, alpha, end criterion), with
  :func:`audit_engine` (delivered e and the input that gives the target e).
* :mod:`.report`: the full tables (CSV, Markdown) and plots.

Imports the layers below it: physics, solvers, collision, calibration, paper, _support.  An engine
preset is one :class:`Preset` entry in :mod:`.engines` (ARCHITECTURE.md).
"""

from .formulas import FORMULAS, Formula, FormulaAudit, audit_formula, get_formula
from .engines import ENGINES, EngineAudit, Preset, audit_engine, get_preset

__all__ = [
    "ENGINES", "EngineAudit", "FORMULAS", "Formula", "FormulaAudit", "Preset",
    "audit_engine", "audit_formula", "get_formula", "get_preset",
]
