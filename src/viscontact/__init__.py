"""viscontact: viscoelastic contact force models for the Discrete Element Method.

Exact single-collision solutions and calibration for the Hertzian damping laws compared by
Jian et al., Powder Technology 356 (2019) 735 (Lee-Herrmann, Tsuji, Kuwabara-Kono,
Lichtensteiger, Hunt-Crossley, and the relaxation-time law of Jian et al.), plus a general
power law.  ARCHITECTURE.md at the repository root shows the packages and who may import whom.

Importing the package is light: the compiled batch solver (numba), scipy and matplotlib are
imported inside the functions that need them.
"""

from __future__ import annotations

from ._version import __version__

from . import _moved
from .calibration.inverse import ALPHA_MAX, alpha_from_e, restitution
from .collision import (
    CollisionResult, ImpactResult, SweepResult, collide, impact, velocity_sweep,
)
from .paper.experiment import (
    Ball, PhysicalCalibration, calibrate_ball, calibrate_physical, load_balls,
)
from .physics.laws import LAWS, MODELS, STUDY_MODELS, ContactLaw
from .physics.pair import (
    ContactPair, contact_pair, damping_coefficient, damping_constants, drop_speed,
    effective_mass, effective_modulus, effective_radius, hertz_stiffness, time_scale,
)
from .solvers import END_CRITERIA, T_MAX

_moved.install()


def __getattr__(name: str):
    """Old module paths as attributes (``viscontact.experiment``), through :mod:`._moved`."""
    return _moved.attribute(name)


__all__ = [
    "ALPHA_MAX", "alpha_from_e", "restitution",
    "CollisionResult", "collide",
    "ContactPair", "ImpactResult", "contact_pair", "damping_coefficient", "damping_constants",
    "drop_speed", "effective_mass", "effective_modulus", "effective_radius", "hertz_stiffness",
    "impact", "time_scale",
    "Ball", "PhysicalCalibration", "calibrate_ball", "calibrate_physical", "load_balls",
    "LAWS", "MODELS", "STUDY_MODELS", "ContactLaw",
    "END_CRITERIA", "T_MAX",
    "SweepResult", "velocity_sweep",
    "__version__",
]
