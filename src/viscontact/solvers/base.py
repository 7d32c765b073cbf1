"""The solver contract and its result type."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np

from ..physics.laws import LawParams

#: The two end-of-contact criteria: zero force, or zero overlap (Jian et al. 2019).
END_CRITERIA: tuple[str, ...] = ("force", "overlap")
#: A contact still going at this non-dimensional time is reported as not separating.
T_MAX: float = 1000.0
#: Default relative tolerance of the step-size control; meets |e - exact| <= 1e-8.
DEFAULT_RTOL: float = 1e-12


def force_end_is_overlap_end(lp: LawParams) -> bool:
    """True where the zero-force end is the zero-overlap end: Hunt-Crossley damping (p = 3/2,
    g = 1), F = x^(3/2) (1 + alpha x').  The line x' = -1/alpha solves the equation (F = 0
    there, so x'' = 0), so no solution starting at x' = 1 reaches it: F > 0 until x = 0.
    Solvers then locate only x = 0; a zero-force event would fire where x' comes within
    rounding of -1/alpha, long before the contact ends (t_c and residual wrong at alpha > ~50)."""
    return lp.p == 1.5 and lp.beta == 0.0


@dataclass
class Contact:
    """Raw outcome of one non-dimensional collision: e, t_c, peak force and overlap, residual, dissipation.

    All quantities non-dimensional: time in T, overlap in T v_i, speed in v_i,
    force in m* v_i / T, energy in m* v_i^2.
    """

    e: float
    tc: float
    separated: bool
    residual: float
    dissipated: float
    xmax: float = float("nan")
    t_xmax: float = float("nan")
    fmax: float = float("nan")
    t_fmax: float = float("nan")
    history: dict[str, np.ndarray] = field(default_factory=dict)


class SolveFn(Protocol):
    """Contract for a solver.

    1. Integrate x'' = -F(x, x', t) from x = 0, x' = 1 with F from :mod:`viscontact.physics.kernels`.
    2. Stop at the first zero of F (``end="force"``) or of x (``end="overlap"``) after the
       start; if neither happens before t = T_MAX, return ``separated=False, e=0, tc=inf``.
    3. With ``detail=True`` also fill xmax, t_xmax, fmax, t_fmax and the histories
       t, x, v, f; with ``detail=False`` only e, tc, separated, residual, dissipated.
    """

    def __call__(
        self, lp: LawParams, alpha: float, end: str, *, rtol: float = ..., detail: bool = ...
    ) -> Contact: ...


SolveCallable = Callable[..., Contact]
