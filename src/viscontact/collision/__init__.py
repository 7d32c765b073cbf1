"""One binary collision and sweeps of many (imports physics,
solvers and _support).

:mod:`.single`: the non-dimensional collision of a law at given alpha (and beta, p), solved by a
solver from :data:`viscontact.solvers.SOLVERS`; :mod:`.impact`: the same in SI units for a
physical pair; :mod:`.sweep`: restitution against impact speed at fixed physical damping.
"""

from .impact import ImpactResult, impact
from .single import CollisionResult, check_end, collide, collide_params, result_dict
from .sweep import SweepResult, velocity_sweep

__all__ = ["CollisionResult", "check_end", "collide", "collide_params", "result_dict",
           "ImpactResult", "impact", "SweepResult", "velocity_sweep"]
