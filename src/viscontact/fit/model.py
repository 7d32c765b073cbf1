"""Simulated force-plate traces: a law's collision, placed on a recording's time axis.

The collision comes from the public solver (:func:`viscontact.collide`, whose force history
is evaluated by the kernels) and is scaled to SI by :func:`viscontact.collision.impact.to_physical`.
Outside the contact the trace is ballistic: before the start t0 the ball approaches at v_i
(delta = v_i (t - t0) < 0, F = 0); after the zero-force end it leaves with the rebound speed
(F = 0).  The non-dimensional solve depends on (law, alpha, beta, p) only, so it is cached:
changing k_Hertz or the start time t0 in a fit costs no new solve.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..collision.single import CollisionResult, collide
from ..collision.impact import ImpactResult, to_physical
from ..physics.pair import damping_coefficient, time_scale

__all__ = ["Trace", "simulate", "FIT_RTOL"]

#: solver tolerance inside fits: far below 1 % noise, about half the cost of the default
FIT_RTOL = 1e-9


@lru_cache(maxsize=512)
def _solve(model: str, alpha: float, beta: float | None, p: float | None) -> CollisionResult:
    return collide(model, alpha, beta=beta, p=p, rtol=FIT_RTOL)


@dataclass(frozen=True)
class Trace:
    """One simulated impact in SI units, sampled anywhere in time (see module docstring)."""

    impact: ImpactResult

    def sample(self, t: np.ndarray, t0: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(force [N], overlap [m], overlap rate [m/s]) at times ``t`` [s] for a start at ``t0``."""
        r = self.impact
        s = np.asarray(t, dtype=float) - t0
        force = np.interp(s, r.t, r.force, left=0.0, right=0.0)
        delta = np.interp(s, r.t, r.delta)
        rate = np.interp(s, r.t, r.ddelta)
        before, after = s < 0, s > r.tc
        delta[before] = r.v * s[before]
        rate[before] = r.v
        delta[after] = r.delta[-1] + r.ddelta[-1] * (s[after] - r.tc)
        return force, delta, rate


def simulate(model: str, alpha: float, *, m_eff: float, k_hertz: float, v: float,
             beta: float | None = None, p: float | None = None) -> Trace:
    """The trace of ``model`` at non-dimensional alpha (beta, p) for m* [kg], k_Hertz, v [m/s]."""
    r = _solve(model, float(alpha), None if beta is None else float(beta),
               None if p is None else float(p))
    c = damping_coefficient(model, alpha, m_eff=m_eff, k_hertz=k_hertz, v=v, p=p)
    tau = None if r.beta is None else r.beta * time_scale(m_eff, k_hertz, v)
    return Trace(to_physical(r, m_eff=m_eff, k_hertz=k_hertz, v=v, c=c, tau=tau))
