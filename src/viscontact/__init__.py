"""viscontact: viscoelastic contact force models for the Discrete Element Method.

Exact single-collision solutions and calibration for the Hertzian damping laws compared by
Jian et al., Powder Technology 356 (2019) 735 (Lee-Herrmann, Tsuji, Kuwabara-Kono,
Lichtensteiger, Hunt-Crossley, and the relaxation-time law of Jian et al.), plus a general
power law.
"""

from .calibration import ALPHA_MAX, alpha_from_e, restitution
from .collision import CollisionResult, collide
from .dimensional import (
    ContactPair, ImpactResult, contact_pair, damping_coefficient, damping_constants, drop_speed,
    effective_mass, effective_modulus, effective_radius, hertz_stiffness, impact, time_scale,
)
from .experiment import Ball, PhysicalCalibration, calibrate_ball, calibrate_physical, load_balls
from .laws import LAWS, MODELS, STUDY_MODELS, ContactLaw
from .solvers import END_CRITERIA, T_MAX
from .sweep import SweepResult, velocity_sweep

__version__ = "0.1.0"

__all__ = [
    "ALPHA_MAX", "CollisionResult", "ContactLaw", "END_CRITERIA", "LAWS", "MODELS",
    "STUDY_MODELS", "ImpactResult", "damping_coefficient", "damping_constants", "drop_speed",
    "effective_mass", "effective_modulus", "effective_radius", "hertz_stiffness", "impact",
    "time_scale", "T_MAX", "ContactPair", "contact_pair", "Ball", "PhysicalCalibration",
    "calibrate_ball", "calibrate_physical", "load_balls", "SweepResult", "velocity_sweep", "alpha_from_e", "collide", "restitution", "__version__",
]
