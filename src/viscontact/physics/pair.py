"""Physical units: effective properties, the time scale T, and the map alpha <-> c.

Plain SI floats throughout (kg, m, s, Pa, N).  Hertz theory (K.L. Johnson, Contact Mechanics,
1985, ch. 4) and the scaling of Jian et al., Powder Technol. 356 (2019) 735.

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
from dataclasses import dataclass, replace

from . import domain
from .laws import lookup, resolve

__all__ = [
    "effective_mass", "effective_radius", "effective_modulus", "hertz_stiffness",
    "time_scale", "damping_coefficient", "damping_constants",
    "check_positive", "check_poisson", "drop_speed", "STANDARD_GRAVITY", "ContactPair",
    "contact_pair", "damping_unit", "hertz_limit", "HERTZ_TC", "HERTZ_XMAX",
]

#: g used for drop heights [m/s^2]; the study used 9.81 (981 cm/s^2).
STANDARD_GRAVITY = 9.81


def check_positive(name: str, value: float) -> float:
    """``value`` as float, or ValueError if it is not a finite real number > 0 (no range:
    parameters with a stated domain go through :func:`viscontact.physics.domain.check`)."""
    v = domain.check_number(name, value)
    if not math.isfinite(v) or v <= 0:
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return v


def check_poisson(name: str, nu: float) -> float:
    """``nu`` as float, or ValueError if it is not a Poisson ratio in (-1, 0.5]."""
    return domain.check("poisson", nu, label=name)


def _harmonic_pair(kind: str, label: str, a: float, b: float | None) -> float:
    """a b / (a + b), each in the domain of ``kind``; b = None (a wall) gives a.  The result
    lies between min(a, b) / 2 and min(a, b), so it may fall below the domain by a factor 2
    at most: harmless for every derived number."""
    a = domain.check(kind, a, label=label)
    if b is None:
        return a
    b = domain.check(kind, b, label=f"second {label}")
    return a / (1.0 + a / b)  # a b / (a + b) without overflow


def effective_mass(m1: float, m2: float | None = None) -> float:
    """m* = m1 m2 / (m1 + m2) [kg]; ``m2=None`` (a fixed wall) gives m1."""
    return _harmonic_pair("mass", "mass", m1, m2)


def effective_radius(r1: float, r2: float | None = None) -> float:
    """R* = R1 R2 / (R1 + R2) [m]; ``r2=None`` (a flat wall) gives R1."""
    return _harmonic_pair("radius", "radius", r1, r2)


def effective_modulus(e1: float, nu1: float, e2: float | None = None, nu2: float | None = None) -> float:
    """E* from 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 [Pa]; ``e2=None``: a rigid wall.

    With nu in (-1, 0.5], 1 - nu^2 lies in (0, 1], so E* is at least min(E1, E2) / 2 and finite
    (large for nu near -1; k_Hertz is checked against its own domain)."""
    return 1.0 / compliance(e1, nu1, e2, nu2)


def compliance(e1: float, nu1: float, e2: float | None = None, nu2: float | None = None) -> float:
    """1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 [1/Pa] (Hertz; Johnson, Contact Mechanics, 1985,
    eq. 4.22); ``e2=None``: a rigid wall."""
    a = domain.check("modulus", e1, label="Young's modulus")
    inv = (1.0 - check_poisson("Poisson ratio", nu1) ** 2) / a
    if e2 is not None:
        b = domain.check("modulus", e2, label="second Young's modulus")
        inv += (1.0 - check_poisson("second Poisson ratio", 0.0 if nu2 is None else nu2) ** 2) / b
    elif nu2 is not None:
        raise ValueError("a second Poisson ratio needs the second Young's modulus too")
    return inv


def shear_compliance(e1: float, nu1: float, e2: float, nu2: float) -> float:
    """1/G* = (2 - nu1)/G1 + (2 - nu2)/G2 = 2 (2 - nu1)(1 + nu1)/E1 + 2 (2 - nu2)(1 + nu2)/E2
    [1/Pa], G = E / (2 (1 + nu)) (Mindlin 1949; LAMMPS granular's G* of hertz/material)."""
    return 2 * (2 - nu1) * (1 + nu1) / e1 + 2 * (2 - nu2) * (1 + nu2) / e2


def hertz_stiffness(e_eff: float, r_eff: float) -> float:
    """k_Hertz = (4/3) E* sqrt(R*) [N/m^1.5] (Hertz 1882); the result must lie in the domain of
    k_Hertz (:mod:`viscontact.physics.domain`)."""
    e = check_positive("effective modulus", e_eff)
    r = check_positive("effective radius", r_eff)
    k = 4.0 / 3.0 * e * math.sqrt(r)
    return domain.check("k_hertz", k, label=f"k_Hertz = (4/3) E* sqrt(R*) from E* = {e:g} Pa, "
                        f"R* = {r:g} m")


@dataclass(frozen=True)
class ContactPair:
    """Effective properties of one contact (Hertz theory), SI units; the one physical
    description of a contact pair used by the audit, the fit and the DEM layer.

    Attributes:
        m_eff: m* [kg]; k_hertz: k_Hertz = (4/3) E* sqrt(R*) [N/m^1.5];
        r_eff: R* [m] (None when only k_Hertz was given);
        e_eff: E* [Pa] (None when k_Hertz was given directly);
        v: the normal impact speed v_i [m/s] when the pair describes one collision (None
        otherwise; :meth:`at` sets it).  Speed-dependent quantities (:attr:`T`) need it.

    Every given value must lie in its domain (:mod:`viscontact.physics.domain`; ValueError otherwise).
    """

    m_eff: float
    k_hertz: float
    r_eff: float | None = None
    e_eff: float | None = None
    v: float | None = None

    #: the domain (:mod:`viscontact.physics.domain`) of each field
    _DOMAIN = {"m_eff": "mass", "k_hertz": "k_hertz", "r_eff": "radius", "e_eff": "modulus",
               "v": "v"}

    def __post_init__(self) -> None:
        for name, kind in self._DOMAIN.items():
            value = getattr(self, name)
            if value is not None or name in ("m_eff", "k_hertz"):
                object.__setattr__(self, name, domain.check(kind, value, label=name))

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
        return replace(self, v=domain.check("v", v, label="impact speed v"))

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
        return ContactPair(m_eff=m_eff, k_hertz=domain.check("k_hertz", k_hertz, label="k_Hertz"),
                           r_eff=r_eff)
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


#: undamped contact time t_c / T = (4/5)^(3/5) sqrt(pi) Gamma(2/5) / Gamma(9/10) = 3.2180654597
#: (the undamped Hertz impact: K.L. Johnson, Contact Mechanics, 1985, sec. 11.4)
HERTZ_TC = (0.8 ** 0.6) * math.sqrt(math.pi) * math.gamma(0.4) / math.gamma(0.9)
#: undamped maximum overlap delta_max / (T v_i) = (5/4)^(2/5)
HERTZ_XMAX = 1.25 ** 0.4


def hertz_limit(m_eff: float, k_hertz: float, v: float) -> tuple[float, float, float]:
    """The undamped (elastic Hertz) impact in closed form: (t_c [s], delta_max [m], F_max [N]).

    t_c = 3.2180654597 T, delta_max = (5 m* v^2 / (4 k_Hertz))^(2/5), F_max = k_Hertz delta_max^(3/2).
    """
    T = time_scale(m_eff, k_hertz, v)
    dmax = HERTZ_XMAX * T * v  # (5 m* v^2 / (4 k_Hertz))^(2/5), without overflow
    return HERTZ_TC * T, dmax, k_hertz * dmax * math.sqrt(dmax)


def drop_speed(height: float, g: float = STANDARD_GRAVITY) -> float:
    """Impact speed sqrt(2 g h) [m/s] of a drop from rest through ``height`` [m], no drag.

    ``height`` and ``g`` inside their domain (:mod:`viscontact.physics.domain`) give a speed inside the
    domain of v."""
    return math.sqrt(2.0 * domain.check("gravity", g) * domain.check("drop_height", height,
                                                                       label="drop height"))


def time_scale(m_eff: float, k_hertz: float, v: float) -> float:
    """T = (m*^2 / (k_Hertz^2 v_i))^(1/5) [s] (the Hertz time scale; Jian et al. 2019).

    Computed as (m*/k_Hertz)^(2/5) v^(-1/5): no intermediate overflows or underflows inside
    the domain (m* in [1e-24, 1e12] kg, k_Hertz in [1e-6, 1e17] N/m^1.5, v in [1e-6, 1e4] m/s
    give T in [4e-18, 3e8] s)."""
    m = _mass(m_eff)
    k = domain.check("k_hertz", k_hertz)
    vi = domain.check("v", v, label="impact speed v")
    return (m / k) ** 0.4 / vi ** 0.2


def _mass(m_eff: float, label: str = "m_eff") -> float:
    """m* in the domain of masses, or at most a factor 2 below it (the m* of two masses)."""
    m = domain.check_number(label, m_eff)
    if 0.5 * domain.DOMAIN["mass"].lo <= m < domain.DOMAIN["mass"].lo:
        return m
    return domain.check("mass", m_eff, label=label)


def _prefactor(p: float, m: float, k: float, v: float) -> float:
    """c / alpha = m*^((3-2p)/5) v^((1-4p)/5) k^((2+2p)/5) (Jian et al. 2019); finite and > 0
    inside the domain (each factor is)."""
    return m ** ((3.0 - 2.0 * p) / 5.0) * v ** ((1.0 - 4.0 * p) / 5.0) * k ** ((2.0 + 2.0 * p) / 5.0)


def damping_coefficient(
    model: str, alpha: float, *, m_eff: float, k_hertz: float, v: float, p: float | None = None
) -> float:
    """Physical damping prefactor c [N s / m^(1+p)] of delta^p delta' for non-dimensional alpha.

    For Jian, c multiplies (1 - exp(-t/tau)) delta^(1/2) delta'; tau = beta T (see
    :func:`time_scale`).  LH: c = gamma m* (gamma = alpha/T); Hunt: c = lambda = alpha k_Hertz / v.
    """
    a = domain.check("alpha", alpha)
    time_scale(m_eff, k_hertz, v)  # validates the three
    return a * _prefactor(_exponent(model, p), float(m_eff), float(k_hertz), float(v))


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
    c_v = domain.check("c", c, label="damping coefficient c")
    T = time_scale(m_eff, k_hertz, v)
    exponent = _exponent(model, p)
    alpha = c_v / _prefactor(exponent, float(m_eff), float(k_hertz), float(v))
    if not domain.DOMAIN["alpha"].contains(alpha):
        raise ValueError(
            f"damping coefficient c = {c_v:g} {damping_unit(exponent)} gives alpha = {alpha:.6g} at "
            f"m* = {float(m_eff):g} kg, k_Hertz = {float(k_hertz):g} N/m^1.5, v = {float(v):g} m/s; "
            f"alpha must be in {domain.range_text('alpha')}")
    if not law.needs_beta:
        return alpha, None
    tau_v = domain.check("tau", tau)
    beta = tau_v / T
    if not domain.DOMAIN["beta"].contains(beta):
        raise ValueError(f"tau = {tau_v:g} s gives beta = tau / T = {beta:.6g} (T = {T:.6g} s); "
                         f"beta must be in {domain.range_text('beta')}")
    return alpha, beta
