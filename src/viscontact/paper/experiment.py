"""The lacrosse-ball drop tests as data, and the study's calibration workflow.

Jian et al., Powder Technol. 356 (2019) 735.  The measurements ship in ``data/lacrosse_balls.csv`` (published units, with
a ``# source:`` line); :func:`load_balls` converts them to SI.  The workflow for one ball
(:func:`calibrate_ball`): compute T; for each law find alpha from the measured e (Jian with
its beta); tau = beta T; c from the law's dimensional form.
"""

from __future__ import annotations

import csv
from dataclasses import asdict, dataclass
from functools import lru_cache
from importlib import resources
from typing import Any

from ..physics import domain
from ..calibration.inverse import alpha_from_e
from ..collision.single import check_end
from ..physics.pair import (
    damping_coefficient, damping_unit, time_scale,
)
from ..physics.laws import STUDY_MODELS, lookup, resolve

__all__ = [
    "Ball", "PhysicalCalibration", "load_balls", "ball", "data_source", "calibrate_physical",
    "calibrate_ball", "DATA_FILE",
]

DATA_FILE = "lacrosse_balls.csv"


@dataclass(frozen=True)
class Ball:
    """One ball of the drop tests, SI units (the plate is rigid: m* = m, R* = R).

    Attributes:
        key: short name (ILB, OLB); name: description.
        mass [kg], radius [m], k_hertz [N/m^1.5] (from the measured force at maximum overlap).
        v_in, v_out [m/s] measured impact and rebound speeds; e = v_out / v_in as published.
        tc [s] measured contact time; beta the Jian relaxation constant the study used.
        drop_height [m]; v_min, v_max [m/s] the range of impact speeds measured.
    """

    key: str
    name: str
    mass: float
    radius: float
    v_in: float
    v_out: float
    e: float
    tc: float
    k_hertz: float
    beta: float
    drop_height: float
    v_min: float
    v_max: float

    @property
    def m_eff(self) -> float:
        """m* [kg]: a ball on a rigid plate, m* = m."""
        return self.mass

    @property
    def r_eff(self) -> float:
        """R* [m]: a ball on a flat, R* = R."""
        return self.radius

    @property
    def T(self) -> float:
        """Time scale T [s] at the measured impact speed."""
        return time_scale(self.m_eff, self.k_hertz, self.v_in)


def _data_text() -> str:
    return resources.files("viscontact").joinpath("data", DATA_FILE).read_text(encoding="utf-8")


def data_source() -> str:
    """The ``# source:`` line of the data file (the study the numbers come from)."""
    for line in _data_text().splitlines():
        if line.startswith("# source:"):
            return line[len("# source:"):].strip()
    raise RuntimeError(f"{DATA_FILE} states no source")  # pragma: no cover - packaging bug


@lru_cache(maxsize=1)
def load_balls() -> dict[str, Ball]:
    """The balls of the drop tests, keyed by short name, in SI units."""
    rows = [line for line in _data_text().splitlines() if line and not line.startswith("#")]
    out: dict[str, Ball] = {}
    for r in csv.DictReader(rows):
        out[r["key"]] = Ball(
            key=r["key"], name=r["name"], mass=float(r["mass_g"]) * 1e-3,
            radius=float(r["radius_mm"]) * 1e-3, v_in=float(r["v_in_cm_s"]) * 1e-2,
            v_out=float(r["v_out_cm_s"]) * 1e-2, e=float(r["e"]), tc=float(r["tc_ms"]) * 1e-3,
            k_hertz=float(r["k_hertz_1e6_N_m1.5"]) * 1e6, beta=float(r["beta"]),
            drop_height=float(r["drop_height_cm"]) * 1e-2, v_min=float(r["v_min_cm_s"]) * 1e-2,
            v_max=float(r["v_max_cm_s"]) * 1e-2,
        )
    return out


def ball(key: str) -> Ball:
    """One ball by short name (case-insensitive), or ValueError listing the known ones."""
    balls = load_balls()
    for k, b in balls.items():
        if isinstance(key, str) and k.lower() == key.strip().lower():
            return b
    raise ValueError(f"unknown ball {key!r}; known balls are: {', '.join(balls)}")


@dataclass(frozen=True)
class PhysicalCalibration:
    """One law calibrated to a measured e at impact speed v (SI units).

    Attributes:
        model, p: the law and its damping exponent; e: the target restitution coefficient.
        v [m/s], m_eff [kg], k_hertz [N/m^1.5]; T [s] the time scale at v.
        alpha, beta: non-dimensional constants (beta None except for Jian).
        tau [s] = beta T (Jian, else None); c the damping prefactor in ``c_unit``.
    """

    model: str
    p: float
    e: float
    v: float
    m_eff: float
    k_hertz: float
    T: float
    alpha: float
    beta: float | None
    tau: float | None
    c: float
    c_unit: str
    end: str = "force"

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def calibrate_physical(
    model: str, e: float, *, m_eff: float, k_hertz: float, v: float, beta: float | None = None,
    p: float | None = None, end: str = "force",
) -> PhysicalCalibration:
    """The study's workflow for one law: T, alpha from e (Jian: at ``beta``), tau = beta T, c.

    Every number must lie in its domain (:mod:`viscontact.physics.domain`), else ValueError."""
    check_end(end)
    lp = resolve(model, beta=beta, p=p)
    e = domain.check("e", e)
    T = time_scale(m_eff, k_hertz, v)
    # one value: the exact solver answers in milliseconds and needs no table built first
    alpha = float(alpha_from_e(model, e, beta=beta, p=p, end=end, exact=True))
    c = damping_coefficient(model, alpha, m_eff=m_eff, k_hertz=k_hertz, v=v, p=p)
    law = lookup(model)
    return PhysicalCalibration(
        model=law.name, p=lp.p, e=float(e), v=float(v), m_eff=float(m_eff),
        k_hertz=float(k_hertz), T=T, alpha=alpha, beta=lp.beta if law.needs_beta else None,
        tau=lp.beta * T if law.needs_beta else None, c=c, c_unit=damping_unit(lp.p), end=end,
    )


def calibrate_ball(
    b: Ball | str, models: tuple[str, ...] = STUDY_MODELS, *, end: str = "force",
) -> dict[str, PhysicalCalibration]:
    """Every law calibrated to one ball's measured e at its measured impact speed."""
    b = ball(b) if isinstance(b, str) else b
    if not isinstance(b, Ball):
        raise ValueError(f"ball must be a Ball or a ball's name, got {b!r}")
    if (isinstance(models, str) or not isinstance(models, (tuple, list))
            or not all(isinstance(m, str) for m in models)):
        raise ValueError(f"models must be a sequence of model names, got {models!r}")
    out = {}
    for m in models:
        beta = b.beta if lookup(m).needs_beta else None
        cal = calibrate_physical(m, b.e, m_eff=b.m_eff, k_hertz=b.k_hertz, v=b.v_in, beta=beta,
                                 end=end)
        out[cal.model] = cal
    return out

