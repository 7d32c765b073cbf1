"""viscontact: viscoelastic contact force models for the Discrete Element Method.

Exact single-collision solutions and calibration for the Hertzian damping laws compared by
Jian et al., Powder Technology 356 (2019) 735 (Lee-Herrmann, Tsuji, Kuwabara-Kono,
Lichtensteiger, Hunt-Crossley, and the relaxation-time law of Jian et al.), plus a general
power law.

The public names below are imported on first use (PEP 562), so that ``import viscontact``
and the command line pay only for what they use: the compiled batch solver (numba) and
scipy are loaded by the functions that need them, not by the package.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

#: module -> the public names it provides
_EXPORTS: dict[str, tuple[str, ...]] = {
    "calibration": ("ALPHA_MAX", "alpha_from_e", "restitution"),
    "collision": ("CollisionResult", "collide"),
    "dimensional": (
        "ContactPair", "ImpactResult", "contact_pair", "damping_coefficient", "damping_constants",
        "drop_speed", "effective_mass", "effective_modulus", "effective_radius", "hertz_stiffness",
        "impact", "time_scale",
    ),
    "experiment": ("Ball", "PhysicalCalibration", "calibrate_ball", "calibrate_physical",
                   "load_balls"),
    "laws": ("LAWS", "MODELS", "STUDY_MODELS", "ContactLaw"),
    "solvers": ("END_CRITERIA", "T_MAX"),
    "sweep": ("SweepResult", "velocity_sweep"),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = [*_MODULE_OF, "__version__"]

if TYPE_CHECKING:  # static analysers see the eager imports
    from .calibration import ALPHA_MAX, alpha_from_e, restitution
    from .collision import CollisionResult, collide
    from .dimensional import (
        ContactPair, ImpactResult, contact_pair, damping_coefficient, damping_constants,
        drop_speed, effective_mass, effective_modulus, effective_radius, hertz_stiffness, impact,
        time_scale,
    )
    from .experiment import (
        Ball, PhysicalCalibration, calibrate_ball, calibrate_physical, load_balls,
    )
    from .laws import LAWS, MODELS, STUDY_MODELS, ContactLaw
    from .solvers import END_CRITERIA, T_MAX
    from .sweep import SweepResult, velocity_sweep


def __getattr__(name: str) -> Any:
    """A public name, or a submodule (``viscontact.experiment``), imported on first access."""
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
