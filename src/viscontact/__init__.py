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

from typing import TYPE_CHECKING

from ._lazy import lazy_exports

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
__all__ = [name for names in _EXPORTS.values() for name in names] + ["__version__"]

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


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
