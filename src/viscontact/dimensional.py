"""Physical units: effective properties, the time scale T, and the map alpha <-> c.

Plain SI floats throughout (kg, m, s, Pa, N).  SPEC sections 1-3.

Two bodies (or a body on a wall) give

    m* = m1 m2 / (m1 + m2)            (wall: m* = m1)
    R* = R1 R2 / (R1 + R2)            (flat wall: R* = R1)
    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2   (rigid wall: second term 0)
    k_Hertz = (4/3) E* sqrt(R*)       [N / m^(3/2)]
    T = (m*^2 / (k_Hertz^2 v_i))^(1/5)   [s]

and the physical damping prefactor for exponent p (F_d = c delta^p delta', Jian:
F_d = c (1 - exp(-t/tau)) delta^(1/2) delta', tau = beta T):

    c = alpha m*^((3-2p)/5) v_i^((1-4p)/5) k_Hertz^((2+2p)/5)   [N s / m^(1+p)]

(LH: c = gamma m* in kg/s; Hunt: c = lambda = alpha k_Hertz / v_i in N s / m^(5/2)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .collision import CollisionResult, check_end, collide, result_dict
from .laws import check_finite_nonneg, lookup, resolve

__all__ = [
    "effective_mass", "effective_radius", "effective_modulus", "hertz_stiffness",
    "time_scale", "damping_coefficient", "damping_constants", "impact", "ImpactResult",
    "check_positive", "check_poisson", "drop_speed", "STANDARD_GRAVITY", "ContactPair",
    "contact_pair", "damping_unit", "hertz_limit", "HERTZ_TC", "HERTZ_XMAX",
]

#: g used for drop heights [m/s^2]; the study used 9.81 (981 cm/s^2).
STANDARD_GRAVITY = 9.81


def check_positive(name: str, value: float) -> float:
    """``value`` as float, or ValueError if it is not a finite number > 0."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v <= 0:
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return v


def check_poisson(name: str, nu: float) -> float:
    """``nu`` as float, or ValueError if it is not a Poisson ratio in (-1, 0.5]."""
    try:
        v = float(nu)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {nu!r}") from None
    if not (-1.0 < v <= 0.5):
        raise ValueError(f"{name} must be in (-1, 0.5], got {nu!r}")
    return v


def _harmonic_pair(name: str, a: float, b: float | None) -> float:
    """a b / (a + b), validated; b = None (a wall) gives a."""
    a = check_positive(name, a)
    if b is None:
        return a
    b = check_positive(f"second {name}", b)
    return a * b / (a + b)


def effective_mass(m1: float, m2: float | None = None) -> float:
    """m* = m1 m2 / (m1 + m2) [kg]; ``m2=None`` (a fixed wall) gives m1."""
    return _harmonic_pair("mass", m1, m2)


def effective_radius(r1: float, r2: float | None = None) -> float:
    """R* = R1 R2 / (R1 + R2) [m]; ``r2=None`` (a flat wall) gives R1."""
    return _harmonic_pair("radius", r1, r2)


def effective_modulus(e1: float, nu1: float, e2: float | None = None, nu2: float | None = None) -> float:
    """E* from 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 [Pa]; ``e2=None``: a rigid wall."""
    a = check_positive("Young's modulus", e1)
    inv = (1.0 - check_poisson("Poisson ratio", nu1) ** 2) / a
    if e2 is not None:
        b = check_positive("second Young's modulus", e2)
        inv += (1.0 - check_poisson("second Poisson ratio", 0.0 if nu2 is None else nu2) ** 2) / b
    return 1.0 / inv


def hertz_stiffness(e_eff: float, r_eff: float) -> float:
    """k_Hertz = (4/3) E* sqrt(R*) [N/m^1.5] (Hertz 1882)."""
    return 4.0 / 3.0 * check_positive("effective modulus", e_eff) * math.sqrt(
        check_positive("effective radius", r_eff))


@dataclass(frozen=True)
class ContactPair:
    """Effective properties of one contact (SPEC section 1), SI units; the one physical
    description of a contact pair used by the audit, the fit and the DEM layer.

    Attributes:
        m_eff: m* [kg]; k_hertz: k_Hertz = (4/3) E* sqrt(R*) [N/m^1.5];
        r_eff: R* [m] (None when only k_Hertz was given);
        e_eff: E* [Pa] (None when k_Hertz was given directly);
        v: the normal impact speed v_i [m/s] when the pair describes one collision (None
        otherwise; :meth:`at` sets it).  Speed-dependent quantities (:attr:`T`) need it.

    Every given value must be a finite number > 0 (ValueError otherwise).
    """

    m_eff: float
    k_hertz: float
    r_eff: float | None = None
    e_eff: float | None = None
    v: float | None = None

    def __post_init__(self) -> None:
        for name in ("m_eff", "k_hertz", "r_eff", "e_eff", "v"):
            value = getattr(self, name)
            if value is not None or name in ("m_eff", "k_hertz"):
                object.__setattr__(self, name, check_positive(name, value))

    @classmethod
    def from_effective(
        cls, *, m_eff: float, r_eff: float | None = None, e_eff: float | None = None,
        k_hertz: float | None = None, v: float | None = None,
    ) -> "ContactPair":
        """From the effective quantities: m* [kg], R* [m], and exactly one of E* [Pa]
        (k_Hertz = (4/3) E* sqrt(R*), needs R*) or k_Hertz [N/m^1.5]; optional speed v [m/s]."""
        if (e_eff is None) == (k_hertz is None):
            raise ValueError("give exactly one of E_eff (effective modulus E*) and k_Hertz")
        if e_eff is not None:
            if r_eff is None:
                raise ValueError("k_Hertz from E_eff needs the effective radius R*")
            k_hertz = hertz_stiffness(e_eff, r_eff)
        return cls(m_eff=m_eff, k_hertz=k_hertz, r_eff=r_eff, e_eff=e_eff, v=v)

    def at(self, v: float) -> "ContactPair":
        """The same pair at normal impact speed ``v`` [m/s] (> 0)."""
        return replace(self, v=check_positive("impact speed v", v))

    @property
    def T(self) -> float:
        """Time scale T = (m*^2 / (k_Hertz^2 v_i))^(1/5) [s] at the pair's impact speed."""
        if self.v is None:
            raise ValueError("the time scale T needs the impact speed v: use ContactPair.at(v)")
        return time_scale(self.m_eff, self.k_hertz, self.v)


def contact_pair(
    mass: float, *, radius: float | None = None, k_hertz: float | None = None,
    modulus: float | None = None, poisson: float | None = None, mass2: float | None = None,
    radius2: float | None = None, modulus2: float | None = None, poisson2: float | None = None,
) -> ContactPair:
    """m*, R*, E* and k_Hertz of a sphere hitting a second sphere or a wall.

    Give either ``k_hertz`` [N/m^1.5] directly, or ``modulus`` E [Pa] and ``poisson`` nu with
    ``radius`` [m].  Second body: ``mass2`` (None: a fixed wall), ``radius2`` (None: a flat),
    ``modulus2``/``poisson2`` (None: a rigid wall).  ValueError names what is missing or wrong.
    """
    m_eff = effective_mass(mass, mass2)
    r_eff = None if radius is None else effective_radius(radius, radius2)
    if radius is None and radius2 is not None:
        raise ValueError("a second radius needs the first radius too")
    if k_hertz is not None:
        if modulus is not None or poisson is not None or modulus2 is not None:
            raise ValueError("give either k_Hertz or the elastic constants (E, nu), not both")
        return ContactPair(m_eff=m_eff, k_hertz=check_positive("k_Hertz", k_hertz), r_eff=r_eff)
    if modulus is None or poisson is None:
        raise ValueError("give k_Hertz, or Young's modulus E and Poisson ratio nu (with the radius)")
    if modulus2 is not None and poisson2 is None:
        raise ValueError("the second body's modulus needs its Poisson ratio too")
    e_eff = effective_modulus(modulus, poisson, modulus2, poisson2)
    if r_eff is None:
        raise ValueError("k_Hertz from E and nu needs the radius")
    return ContactPair(m_eff=m_eff, k_hertz=hertz_stiffness(e_eff, r_eff), r_eff=r_eff, e_eff=e_eff)


def damping_unit(p: float) -> str:
    """SI unit of the damping prefactor c for exponent p: N s / m^(1+p) (LH: kg/s)."""
    if p == 0:
        return "kg/s"
    return f"N s/m^{1 + p:g}"


#: undamped contact time t_c / T = (4/5)^(3/5) sqrt(pi) Gamma(2/5) / Gamma(9/10) (SPEC section 2)
HERTZ_TC = (0.8 ** 0.6) * math.sqrt(math.pi) * math.gamma(0.4) / math.gamma(0.9)
#: undamped maximum overlap delta_max / (T v_i) = (5/4)^(2/5)
HERTZ_XMAX = 1.25 ** 0.4


def hertz_limit(m_eff: float, k_hertz: float, v: float) -> tuple[float, float, float]:
    """The undamped (elastic Hertz) impact in closed form: (t_c [s], delta_max [m], F_max [N]).

    t_c = 3.2180654597 T, delta_max = (5 m* v^2 / (4 k_Hertz))^(2/5), F_max = k_Hertz delta_max^(3/2).
    """
    T = time_scale(m_eff, k_hertz, v)
    dmax = (5.0 * m_eff * v * v / (4.0 * k_hertz)) ** 0.4
    return HERTZ_TC * T, dmax, k_hertz * dmax ** 1.5


def drop_speed(height: float, g: float = STANDARD_GRAVITY) -> float:
    """Impact speed sqrt(2 g h) [m/s] of a drop from rest through ``height`` [m], no drag."""
    return math.sqrt(2.0 * check_positive("gravity", g) * check_positive("drop height", height))


def time_scale(m_eff: float, k_hertz: float, v: float) -> float:
    """T = (m*^2 / (k_Hertz^2 v_i))^(1/5) [s] (SPEC section 2)."""
    m = check_positive("m_eff", m_eff)
    k = check_positive("k_hertz", k_hertz)
    vi = check_positive("impact speed v", v)
    return (m * m / (k * k * vi)) ** 0.2


def _prefactor(p: float, m: float, k: float, v: float) -> float:
    """c / alpha = m*^((3-2p)/5) v^((1-4p)/5) k^((2+2p)/5) (SPEC section 3)."""
    return m ** ((3.0 - 2.0 * p) / 5.0) * v ** ((1.0 - 4.0 * p) / 5.0) * k ** ((2.0 + 2.0 * p) / 5.0)


def damping_coefficient(
    model: str, alpha: float, *, m_eff: float, k_hertz: float, v: float, p: float | None = None
) -> float:
    """Physical damping prefactor c [N s / m^(1+p)] of delta^p delta' for non-dimensional alpha.

    For Jian, c multiplies (1 - exp(-t/tau)) delta^(1/2) delta'; tau = beta T (see
    :func:`time_scale`).  LH: c = gamma m* (gamma = alpha/T); Hunt: c = lambda = alpha k_Hertz / v.
    """
    a = check_finite_nonneg("alpha", alpha)
    time_scale(m_eff, k_hertz, v)  # validates the three
    return a * _prefactor(_exponent(model, p), m_eff, k_hertz, v)


def _exponent(model: str, p: float | None) -> float:
    """The damping exponent p of ``model`` (validated; beta is irrelevant here)."""
    return resolve(model, beta=0.0 if lookup(model).needs_beta else None, p=p).p


def damping_constants(
    model: str, c: float, *, m_eff: float, k_hertz: float, v: float, tau: float | None = None,
    p: float | None = None,
) -> tuple[float, float | None]:
    """Inverse of :func:`damping_coefficient`: (alpha, beta) at impact speed v.

    beta = tau / T for Jian (``tau`` in s, required), None for the other laws.
    """
    law = lookup(model)
    if law.needs_beta and tau is None:
        raise ValueError(f"model {law.name} needs tau (relaxation time in s, >= 0)")
    if not law.needs_beta and tau is not None:
        raise ValueError(f"model {law.name} takes no tau; only Jian has a relaxation time")
    c_v = check_finite_nonneg("damping coefficient c", c)
    T = time_scale(m_eff, k_hertz, v)
    alpha = c_v / _prefactor(_exponent(model, p), m_eff, k_hertz, v)
    beta = check_finite_nonneg("tau", tau) / T if law.needs_beta else None
    return alpha, beta


@dataclass
class ImpactResult:
    """One collision in SI units.

    Attributes:
        e: restitution coefficient v_out / v_i (0 when the contact does not separate).
        tc: contact time [s]; fmax [N] peak force at t_fmax [s]; dmax [m] peak overlap at
        t_dmax [s]; residual [m] overlap left at the end; dissipated [J] damping work.
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
    fmax: float
    t_fmax: float
    dmax: float
    t_dmax: float
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
    return ImpactResult(
        model=r.model, v=v, m_eff=m_eff, k_hertz=k_hertz, c=c, tau=tau, p=r.p, end=r.end, T=T,
        alpha=r.alpha, beta=r.beta, e=r.e, tc=r.tc * T, fmax=r.fmax * F, t_fmax=r.t_fmax * T,
        dmax=r.xmax * L, t_dmax=r.t_xmax * T, residual=r.residual * L,
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
    return to_physical(r, m_eff=m_eff, k_hertz=k_hertz, v=v, c=c, tau=tau)
