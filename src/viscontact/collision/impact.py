"""One collision in SI units: the non-dimensional solution scaled back by the pair's T, v, m*.

Time by T, overlap by T v_i, speed by v_i, force by m* v_i / T (the scaling of Jian et al.,
Powder Technol. 356 (2019) 735, eq. 6); the pair's quantities come from
:mod:`viscontact.physics.pair`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..physics.pair import damping_constants, time_scale
from .single import CollisionResult, check_end, collide, result_dict

__all__ = ["ImpactResult", "impact", "to_physical"]


@dataclass
class ImpactResult:
    """One collision in SI units.

    Attributes:
        e: restitution coefficient v_out / v_i (0 when the contact does not separate).
        tc: contact time [s]; fmax [N] peak force at t_fmax [s]; dmax [m] peak overlap at
        t_dmax [s] (these four None with ``history=False``); residual [m] overlap left at the
        end; dissipated [J] damping work.
        T [s] time scale, alpha and beta the non-dimensional constants at this speed.
        t [s], delta [m], ddelta [m/s], force [N]: histories.
    """

    model: str
    v: float
    m_eff: float
    k_hertz: float
    c: float
    tau: float | None
    p: float
    end: str
    T: float
    alpha: float
    beta: float | None
    e: float
    tc: float
    fmax: float | None
    t_fmax: float | None
    dmax: float | None
    t_dmax: float | None
    residual: float
    dissipated: float
    separated: bool
    t: np.ndarray = field(repr=False, default_factory=lambda: np.empty(0))
    delta: np.ndarray = field(repr=False, default_factory=lambda: np.empty(0))
    ddelta: np.ndarray = field(repr=False, default_factory=lambda: np.empty(0))
    force: np.ndarray = field(repr=False, default_factory=lambda: np.empty(0))

    def to_dict(self, histories: bool = False) -> dict[str, Any]:
        """Plain JSON-ready dict; infinities become None."""
        return result_dict(self, ("t", "delta", "ddelta", "force"), histories)


def to_physical(r: CollisionResult, *, m_eff: float, k_hertz: float, v: float, c: float,
                tau: float | None) -> ImpactResult:
    """Scale a non-dimensional result: time by T, overlap by T v, speed by v, force by m* v / T."""
    T = time_scale(m_eff, k_hertz, v)
    L, F = T * v, m_eff * v / T

    def scaled(x: float | None, unit: float) -> float | None:
        return None if x is None else x * unit

    return ImpactResult(
        model=r.model, v=v, m_eff=m_eff, k_hertz=k_hertz, c=c, tau=tau, p=r.p, end=r.end, T=T,
        alpha=r.alpha, beta=r.beta, e=r.e, tc=r.tc * T, fmax=scaled(r.fmax, F),
        t_fmax=scaled(r.t_fmax, T), dmax=scaled(r.xmax, L), t_dmax=scaled(r.t_xmax, T),
        residual=r.residual * L,
        dissipated=r.dissipated * m_eff * v * v, separated=r.separated,
        t=r.t * T, delta=r.x * L, ddelta=r.v * v, force=r.f * F,
    )


def impact(
    model: str, *, m_eff: float, k_hertz: float, v: float, c: float, tau: float | None = None,
    p: float | None = None, end: str = "force", history: bool = True,
) -> ImpactResult:
    """Solve one collision given physical parameters; result in SI units.

    m_eff [kg], k_hertz [N/m^1.5], v impact speed [m/s], c damping prefactor
    [N s / m^(1+p)] (see :func:`damping_coefficient`), tau relaxation time [s] (Jian).
    """
    check_end(end)
    alpha, beta = damping_constants(model, c, m_eff=m_eff, k_hertz=k_hertz, v=v, tau=tau, p=p)
    r = collide(model, alpha, beta=beta, p=p, end=end, history=history)
    return to_physical(r, m_eff=float(m_eff), k_hertz=float(k_hertz), v=float(v), c=float(c),
                       tau=None if tau is None else float(tau))
