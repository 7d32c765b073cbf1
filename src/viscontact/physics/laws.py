"""The contact laws: one registry, one frozen description per law.

Every law is a Hertzian spring plus a damping term.  In the non-dimensional form of
Jian et al., Powder Technol. 356 (2019) 735 (x = delta / (T v_i), t^ = t / T) all of them read

    F^ = x^(3/2) + alpha g(t^) x^p x',      g = 1, or g = 1 - exp(-t^/beta) (Jian)

so a law is fully described by its exponent ``p`` and whether it carries the relaxation
factor ``g``.  The arithmetic itself lives in :mod:`viscontact.physics.kernels`; this module only
says *which* numbers a law feeds into it.

Adding a law: (1) subclass :class:`ContactLaw` with its docstring (equation, units,
reference); (2) add it to ``_REGISTERED``; (3) add its reference value to the tests.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import ClassVar

from . import domain

__all__ = ["ContactLaw", "LawParams", "LAWS", "MODELS", "resolve", "check_finite_nonneg", "exponent",
           "given_exponent"]


@dataclass(frozen=True)
class ContactLaw:
    """Base description of a viscoelastic normal contact law (see module docstring)."""

    name: ClassVar[str]
    title: ClassVar[str]
    p: ClassVar[float | None]  # None: the user gives p (the general power law)
    needs_beta: ClassVar[bool] = False
    history: ClassVar[tuple[str, ...]] = ()  # per-contact memory a DEM engine must keep
    beta_zero: ClassVar[str | None] = None  # the law this one is at beta = 0 (needs_beta only)
    reference: ClassVar[str]


class LH(ContactLaw):
    """Lee & Herrmann: Hertz spring plus a linear dashpot (p = 0).

    F = k_Hertz delta^(3/2) + gamma m* delta',  gamma = alpha / T  [1/s].
    Non-dimensional: F^ = x^(3/2) + alpha x'.  Note F(0) = alpha m* v_i / T > 0.
    J. Lee, H.J. Herrmann, J. Phys. A 26 (1993) 373.
    """

    name = "LH"
    title = "Lee-Herrmann"
    p = 0.0
    reference = "J. Lee, H.J. Herrmann, J. Phys. A 26 (1993) 373"


class Ts(ContactLaw):
    """Tsuji, Tanaka & Ishida (p = 1/4).

    F = k_Hertz delta^(3/2) + c delta',  c = alpha sqrt(m* k_Hertz) delta^(1/4)  [kg/s].
    Non-dimensional: F^ = x^(3/2) + alpha x^(1/4) x'.
    Y. Tsuji, T. Tanaka, T. Ishida, Powder Technol. 71 (1992) 239.
    """

    name = "Ts"
    title = "Tsuji"
    p = 0.25
    reference = "Y. Tsuji, T. Tanaka, T. Ishida, Powder Technol. 71 (1992) 239"


class KK(ContactLaw):
    """Kuwabara & Kono; Brilliantov et al. (p = 1/2).

    F = k_Hertz delta^(3/2) + c delta',  c = alpha k_Hertz T delta^(1/2)  [kg/s].
    Non-dimensional: F^ = x^(3/2) + alpha x^(1/2) x'.
    G. Kuwabara, K. Kono, Jpn. J. Appl. Phys. 26 (1987) 1230;
    N.V. Brilliantov et al., Phys. Rev. E 53 (1996) 5382.
    """

    name = "KK"
    title = "Kuwabara-Kono"
    p = 0.5
    reference = "G. Kuwabara, K. Kono, Jpn. J. Appl. Phys. 26 (1987) 1230"


class Li(ContactLaw):
    """Lichtensteiger: many small dashpots over the contact area (p = 1).

    F = k_Hertz delta^(3/2) + c delta',  c = alpha (k_Hertz^2 T^3 / m*) delta  [kg/s].
    Non-dimensional: F^ = x^(3/2) + alpha x x'.
    As tabulated in B. Jian et al., Powder Technol. 356 (2019) 735.
    """

    name = "Li"
    title = "Lichtensteiger"
    p = 1.0
    reference = "Lichtensteiger, as in B. Jian et al., Powder Technol. 356 (2019) 735"


class Hunt(ContactLaw):
    """Hunt & Crossley (p = 3/2).

    F = k_Hertz delta^(3/2) + lambda delta^(3/2) delta',  lambda = alpha k_Hertz / v_i
    [N s / m^(5/2)].  Non-dimensional: F^ = x^(3/2) (1 + alpha x').
    K.H. Hunt, F.R.E. Crossley, J. Appl. Mech. 42 (1975) 440.
    """

    name = "Hunt"
    title = "Hunt-Crossley"
    p = 1.5
    reference = "K.H. Hunt, F.R.E. Crossley, J. Appl. Mech. 42 (1975) 440"


class Jian(ContactLaw):
    """Jian et al.: Kuwabara-Kono damping switched on with a relaxation time (p = 1/2).

    F = k_Hertz delta^(3/2) + c delta',
    c = alpha (1 - exp(-t/tau)) k_Hertz T delta^(1/2)  [kg/s],  tau = beta T  [s],
    t the time since this contact began (each contact remembers its start time).
    Non-dimensional: F^ = x^(3/2) + alpha (1 - exp(-t^/beta)) x^(1/2) x'; beta = 0 is KK.
    B. Jian, G.M. Hu, Z.Q. Fang, H.J. Zhou, R. Xia, Powder Technol. 356 (2019) 735.
    """

    name = "Jian"
    title = "Jian (relaxation time)"
    p = 0.5
    needs_beta = True
    history = ("contact_start_time",)
    beta_zero = KK.name
    reference = "B. Jian et al., Powder Technol. 356 (2019) 735, doi:10.1016/j.powtec.2019.08.110"


class Power(ContactLaw):
    """General power-law damping (any p >= 0).

    F = k_Hertz delta^(3/2) + c delta',
    c = alpha m*^((3-2p)/5) v_i^((1-4p)/5) k_Hertz^((2+2p)/5) delta^p  [kg/s].
    Non-dimensional: F^ = x^(3/2) + alpha x^p x'.  p = 0, 1/4, 1/2, 1, 3/2 give LH, Ts, KK,
    Li, Hunt.  B. Jian et al., Powder Technol. 356 (2019) 735.
    """

    name = "power"
    title = "power law"
    p = None
    reference = "B. Jian et al., Powder Technol. 356 (2019) 735 (general exponent)"


_REGISTERED: tuple[type[ContactLaw], ...] = (LH, Ts, KK, Li, Hunt, Jian, Power)
LAWS: dict[str, type[ContactLaw]] = {law.name: law for law in _REGISTERED}
MODELS: tuple[str, ...] = tuple(LAWS)
#: the laws the study compares (those with a fixed exponent)
STUDY_MODELS: tuple[str, ...] = tuple(name for name, law in LAWS.items() if law.p is not None)


@dataclass(frozen=True)
class LawParams:
    """A law with its numbers resolved: what the kernels need besides alpha.

    ``beta`` is 0 for laws without relaxation (g = 1); ``m`` is the substitution
    x = s^m that makes the equations polynomial (chosen so that m p is an integer).
    """

    law: type[ContactLaw]
    p: float
    beta: float
    m: int

    @property
    def name(self) -> str:
        return self.law.name


def check_finite_nonneg(name: str, value: float) -> float:
    """Return ``value`` as float, or raise ValueError if it is not a finite number >= 0
    (a real number: not bool, str, None or complex; see :mod:`viscontact.physics.domain`)."""
    v = domain.check_number(name, value)
    if not math.isfinite(v) or v < 0:
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    return v


def substitution_order(p: float) -> int:
    """Smallest even m <= 8 with m p an integer (x = s^m keeps the equations polynomial), else 2."""
    frac = Fraction(p).limit_denominator(64)
    if abs(float(frac) - p) < 1e-15:
        for m in (2, 4, 6, 8):
            if (frac * m).denominator == 1:
                return m
    return 2


def lookup(model: str) -> type[ContactLaw]:
    """The registered law named ``model`` (case-insensitive), or ValueError listing the valid names."""
    if isinstance(model, str):
        for name, law in LAWS.items():
            if name.lower() == model.strip().lower():
                return law
    raise ValueError(f"unknown model {model!r}; valid models are: {', '.join(MODELS)}")


def exponent(law: type[ContactLaw], p: float | None = None, *, noun: str = "model") -> float:
    """The damping exponent p of ``law`` in F_d = c delta^p d(delta)/dt: its fixed value, or
    the given ``p`` (inside its domain) for the power law; ValueError when p is missing for
    the power law or given for a law whose exponent is fixed (the messages call the law a
    ``noun``).  The one statement of this rule; :func:`given_exponent` is its inverse."""
    if law.p is None:
        if p is None:
            raise ValueError(f"{noun} power needs the exponent p (in {domain.range_text('p')})")
        return domain.check("p", p)
    if p is not None:
        raise ValueError(f"{noun} {law.name} has a fixed exponent p = {law.p}; p is only for 'power'")
    return float(law.p)


def given_exponent(law: type[ContactLaw], p: float) -> float | None:
    """The exponent as a user gives it for ``law`` with exponent ``p``: p for the power law,
    None for a law whose exponent is fixed (``exponent(law, given_exponent(law, p)) == p``)."""
    return p if law.p is None else None


def resolve(model: str, *, beta: float | None = None, p: float | None = None) -> LawParams:
    """Validate a model name and its extra parameters (beta, p inside their domain,
    :mod:`viscontact.physics.domain`); ValueError says what is wrong."""
    law = lookup(model)
    if law.needs_beta:
        if beta is None:
            raise ValueError(f"model {law.name} needs beta (relaxation time / T, "
                             f"in {domain.range_text('beta')})")
        beta_v = domain.check("beta", beta)
    else:
        if beta is not None:
            raise ValueError(f"model {law.name} takes no beta; only Jian has a relaxation time")
        beta_v = 0.0
    p_v = exponent(law, p)
    return LawParams(law=law, p=p_v, beta=beta_v, m=substitution_order(p_v))
