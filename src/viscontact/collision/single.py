"""One collision, non-dimensional: :func:`collide` and its result.

Jian et al., Powder Technol. 356 (2019) 735 (the non-dimensional law, the two end criteria
and the outputs).  Units: time in T, overlap in T v_i, speed in v_i, force in
m* v_i / T, energy in m* v_i^2 (T = (m*^2 / (k_Hertz^2 v_i))^(1/5)).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
import math
from typing import Any

import numpy as np

from ..physics import domain
from ..physics.laws import LawParams, resolve
from ..solvers import END_CRITERIA, SOLVERS

__all__ = ["CollisionResult", "collide", "check_end", "result_dict", "solver_for"]


def solver_for(history: bool) -> str:
    """The solver used: the reference (scipy, histories) or the compiled batch solver."""
    return "reference" if history else "batch"


@dataclass
class CollisionResult:
    """Outcome of one non-dimensional collision.

    Attributes (non-dimensional):
        e: restitution coefficient -x'(t_c) (0 when the contact does not separate).
        tc: contact time t_c / T (inf when the contact does not separate).
        fmax, t_fmax: peak force F^ = F T / (m* v_i) and when it occurs (None with
            ``history=False``: not computed).
        xmax, t_xmax: maximum overlap x = delta / (T v_i) and when it occurs (None with
            ``history=False``).
        residual: overlap x(t_c) left at the end (zero-force end; 0 for zero overlap).
        dissipated: work of the damping force, in m* v_i^2.
        separated: False when the contact was still closing at t = T_MAX (zero-overlap end).
        t, x, v, f: histories over the contact (v = x', f = F^), uniform in t.
    """

    model: str
    alpha: float
    beta: float | None
    p: float
    end: str
    e: float
    tc: float
    fmax: float | None
    t_fmax: float | None
    xmax: float | None
    t_xmax: float | None
    residual: float
    dissipated: float
    separated: bool
    t: np.ndarray = field(repr=False, default_factory=lambda: np.empty(0))
    x: np.ndarray = field(repr=False, default_factory=lambda: np.empty(0))
    v: np.ndarray = field(repr=False, default_factory=lambda: np.empty(0))
    f: np.ndarray = field(repr=False, default_factory=lambda: np.empty(0))

    @property
    def status(self) -> str:
        """A sentence a user can act on."""
        if self.separated:
            return "separated"
        return (
            "no rebound: the overlap decays without reaching zero (heavily damped, zero-overlap "
            "criterion); e = 0 is reported. Use end='force' for the zero-force criterion."
        )

    @property
    def energy_error(self) -> float:
        """Energy balance 1/2 - e^2/2 - (2/5) x(t_c)^(5/2) - dissipated; ~0 (energy conservation of the
        damped oscillator)."""
        return 0.5 - 0.5 * self.e**2 - 0.4 * self.residual**2.5 - self.dissipated

    def to_dict(self, histories: bool = False) -> dict[str, Any]:
        """Plain JSON-ready dict; infinities become None."""
        return result_dict(self, ("t", "x", "v", "f"), histories) | {"status": self.status}


def result_dict(result: Any, history_keys: tuple[str, ...], histories: bool) -> dict[str, Any]:
    """A result dataclass as a JSON-ready dict: histories as lists (or left out), inf as None."""
    d = asdict(result)
    for key in history_keys:
        d.pop(key)
        if histories:
            d[key] = getattr(result, key).tolist()
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in d.items()}


def check_end(end: str) -> str:
    """Validate the end-of-contact criterion."""
    return domain.check_choice("end", end, END_CRITERIA)


def collide_params(
    lp: LawParams, alpha: float, end: str = "force", *, rtol: float | None = None,
    history: bool = True,
) -> CollisionResult:
    """:func:`collide` for an already validated law."""
    solve = SOLVERS[solver_for(history)]
    tol = {} if rtol is None else {"rtol": rtol}
    raw = solve(lp, alpha, end, detail=history, **tol)
    hist = raw.history
    scalars = {k: float(getattr(raw, k)) for k in ("e", "tc", "residual", "dissipated")}
    # peaks: computed with histories only (None, not NaN, when they were not)
    scalars |= {k: float(getattr(raw, k)) if history else None
                for k in ("fmax", "t_fmax", "xmax", "t_xmax")}
    return CollisionResult(
        model=lp.name, alpha=alpha, beta=lp.beta if lp.law.needs_beta else None, p=lp.p, end=end,
        separated=bool(raw.separated), **scalars,
        **{k: hist[k] for k in ("t", "x", "v", "f") if k in hist},
    )


def collide(
    model: str, alpha: float, *, beta: float | None = None, p: float | None = None,
    end: str = "force", rtol: float | None = None, history: bool = True,
) -> CollisionResult:
    """Solve one normal collision exactly (to the solver tolerance).

    Solves x'' + x^(3/2) + alpha g(t) x^p x' = 0, x(0) = 0, x'(0) = 1 (the non-dimensional
    form of Jian et al. 2019) until the force (``end="force"``, default) or the overlap (``end="overlap"``) returns
    to zero.  ``history=False`` skips peak force, peak overlap and histories and uses the
    compiled batch solver (:func:`viscontact.solvers.batch.solve_batch`).  ``rtol`` is the
    integrator's relative tolerance; by default 1e-12 with histories (e to about 1e-11) and
    the batch solver's ``BATCH_RTOL`` without (e to about 1e-9).

    Raises ValueError for an unknown model, alpha, beta, p or rtol outside their domain
    (:mod:`viscontact.physics.domain`: alpha in [0, 1000], beta in [0, 1000], p in [0, 10], rtol in
    [1e-13, 1e-5]), beta given to a law without one, or p missing for ``power``.
    """
    lp = resolve(model, beta=beta, p=p)
    a = domain.check("alpha", alpha)
    check_end(end)
    if rtol is not None:
        rtol = domain.check("rtol", rtol)
    return collide_params(lp, a, end, rtol=rtol, history=domain.check_bool("history", history))
