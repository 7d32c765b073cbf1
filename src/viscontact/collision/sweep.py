"""Velocity sweeps: one set of physical parameters, many impact speeds.

Jian et al., Powder Technol. 356 (2019) 735: with m*, k_Hertz, c (and tau) fixed in physical units, alpha and
(for Jian) beta = tau / T change with the impact speed through T, so a calibrated law
predicts e(v_i), t_c(v_i) and F_max(v_i).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..physics import domain
from .single import check_end
from ..physics.pair import _mass
from .impact import impact
from ..physics.laws import lookup

__all__ = ["SweepResult", "velocity_sweep", "study_speeds", "SWEEP_FIELDS", "MAX_SPEEDS"]

#: most impact speeds one sweep takes (each is one collision with histories, ~10 ms)
MAX_SPEEDS = 10_000

#: columns of :meth:`SweepResult.rows`, with units
SWEEP_FIELDS = (
    ("v", "m/s"), ("e", "1"), ("tc", "s"), ("fmax", "N"), ("dmax", "m"), ("residual", "m"),
    ("alpha", "1"), ("beta", "1"), ("T", "s"),
)


def study_speeds(n: int = 24) -> np.ndarray:
    """The study's sweep range, 30 to 260 cm/s, as ``n`` speeds in m/s (default every 10 cm/s)."""
    return np.linspace(0.30, 2.60, n)


@dataclass
class SweepResult:
    """A law with fixed physical constants at several impact speeds (SI units).

    Attributes:
        model, p, end; m_eff [kg], k_hertz [N/m^1.5], c (unit N s / m^(1+p)), tau [s] (Jian).
        v [m/s]; e; tc [s]; fmax [N]; dmax [m]; residual [m]; alpha, beta (None for a law
        without one) and T [s] at each speed.  A contact that does not separate (zero-overlap end) has
        e = 0 and tc = inf.
    """

    model: str
    p: float
    end: str
    m_eff: float
    k_hertz: float
    c: float
    tau: float | None
    v: np.ndarray = field(repr=False)
    e: np.ndarray = field(repr=False)
    tc: np.ndarray = field(repr=False)
    fmax: np.ndarray = field(repr=False)
    dmax: np.ndarray = field(repr=False)
    residual: np.ndarray = field(repr=False)
    alpha: np.ndarray = field(repr=False)
    beta: np.ndarray | None = field(repr=False)
    T: np.ndarray = field(repr=False)

    def rows(self) -> list[dict[str, Any]]:
        """One dict per speed: model, then the columns of :data:`SWEEP_FIELDS`."""
        out = []
        for i in range(self.v.size):
            row: dict[str, Any] = {"model": self.model}
            for name, _unit in SWEEP_FIELDS:
                col = getattr(self, name)
                if col is None:
                    row[name] = None
                    continue
                x = float(col[i])
                row[name] = x if math.isfinite(x) else None
            out.append(row)
        return out

    def to_dict(self) -> dict[str, Any]:
        return {
            "model": self.model, "p": self.p, "end": self.end, "m_eff": self.m_eff,
            "k_hertz": self.k_hertz, "c": self.c, "tau": self.tau,
            "units": dict(SWEEP_FIELDS), "points": self.rows(),
        }


def velocity_sweep(
    model: str, speeds: ArrayLike, *, m_eff: float, k_hertz: float, c: float,
    tau: float | None = None, p: float | None = None, end: str = "force",
) -> SweepResult:
    """e, t_c, F_max, delta_max at each impact speed [m/s] with m*, k_Hertz, c, tau held fixed.

    Every number must lie in its domain (:mod:`viscontact.physics.domain`), and c (tau) must give an
    alpha (beta) inside its domain at every speed, else ValueError.  At most
    :data:`MAX_SPEEDS` speeds (each is one collision with histories)."""
    check_end(end)
    v = np.atleast_1d(domain.check_array("v", speeds, label="impact speed")).ravel()
    if v.size == 0:
        raise ValueError("give at least one impact speed")
    if v.size > MAX_SPEEDS:
        raise ValueError(f"give at most {MAX_SPEEDS} impact speeds, got {v.size}")
    m_eff = _mass(m_eff)
    k_hertz = domain.check("k_hertz", k_hertz)
    c = domain.check("c", c, label="damping coefficient c")
    name = lookup(model).name
    cols = {k: np.empty(v.size) for k, _ in SWEEP_FIELDS}
    p_val = math.nan
    for i, vi in enumerate(v):
        r = impact(model, m_eff=m_eff, k_hertz=k_hertz, v=float(vi), c=c, tau=tau, p=p, end=end)
        p_val = r.p
        for k in ("e", "tc", "fmax", "dmax", "residual", "alpha", "T"):
            cols[k][i] = getattr(r, k)
        cols["v"][i] = vi
        cols["beta"][i] = math.nan if r.beta is None else r.beta
    if not lookup(model).needs_beta:
        cols["beta"] = None
    return SweepResult(model=name, p=p_val, end=end, m_eff=m_eff, k_hertz=k_hertz, c=c, tau=tau,
                       **cols)
