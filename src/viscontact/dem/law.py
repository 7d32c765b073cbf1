"""The damping law of a DEM contact as the plugin takes it: :class:`DemLaw` (a law of
:mod:`viscontact.physics.laws` with its damping in the alpha form, alpha at a reference speed
vref, or the physical form, the prefactor c0) and :func:`contact_law`, which builds one from what
a user knows (a target restitution e at vref is calibrated exactly).

Per contact the plugin computes, with that contact's m* and k_Hertz = (4/3) E* sqrt(R*) (the
damping term c = alpha m*^((3-2p)/5) v^((1-4p)/5) k_Hertz^((2+2p)/5) delta^p of Jian et al.,
Powder Technol. 356 (2019) 735, evaluated at v = vref),

    c0  = alpha m*^((3-2p)/5) vref^((1-4p)/5) k_Hertz^((2+2p)/5)     [N s / m^(1+p); LH: kg/s]
    tau = beta T_ref,  T_ref = (m*^2 / (k_Hertz^2 vref))^(1/5)         [s]  (Jian)

so every pair, whatever its masses and radii, has restitution ``e`` when it meets at relative
normal speed ``vref`` (:meth:`DemLaw.physical` gives the same numbers in Python).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

from ..collision import check_end
from ..physics import domain
from ..physics.laws import MODELS, exponent, given_exponent, lookup, resolve
from ..physics.pair import ContactPair, damping_coefficient
from .native import native_hint
from .units import _num, convert

__all__ = ["DemLaw", "contact_law"]


@dataclass(frozen=True)
class DemLaw:
    """One normal contact law as the plugin takes it (SI units).

    Attributes:
        law: canonical name (``LH``, ``Ts``, ``KK``, ``Li``, ``Hunt``, ``Jian``, ``power``).
        p: damping exponent (fixed by the law; given for ``power``).
        end: ``force`` (clamp F_n >= 0, the zero-force end) or ``overlap`` (no clamp).
        alpha, vref, beta: the alpha form (alpha non-dimensional at the relative normal
            speed vref [m/s]; beta = tau / T_ref for Jian, else None).
        c0, tau: the physical form (c0 [N s / m^(1+p)], LH kg/s; tau [s] for Jian, else None).
        e: the restitution ``alpha`` was calibrated for at ``vref`` (None if alpha was given).
    """

    law: str
    p: float
    end: str = "force"
    alpha: float | None = None
    vref: float | None = None
    beta: float | None = None
    c0: float | None = None
    tau: float | None = None
    e: float | None = None

    def __post_init__(self) -> None:
        """Every value in its domain (a DemLaw built by hand never reaches a pair_coeff line
        with alpha = nan or an unknown law); ValueError says what is allowed."""
        if not isinstance(self.law, str):
            raise ValueError(f"law must be a law name ({', '.join(MODELS)}), got {self.law!r}")
        spec = lookup(self.law)
        object.__setattr__(self, "law", spec.name)
        check_end(self.end)
        p = domain.check("p", self.p, label="p")
        if exponent(spec, given_exponent(spec, p), noun="law") != p:
            raise ValueError(f"law {spec.name} has the fixed exponent p = {spec.p}, got p = {self.p!r}")
        object.__setattr__(self, "p", p)
        if (self.alpha is None) == (self.c0 is None):
            raise ValueError("a DemLaw has exactly one of alpha (with vref) and c0")
        if self.alpha is not None:
            stray = [k for k in ("c0", "tau") if getattr(self, k) is not None]
            needed = {"alpha": "alpha", "vref": "v"}
            if spec.needs_beta:
                needed["beta"] = "beta"
            elif self.beta is not None:
                stray.append("beta")
            if self.e is not None:
                needed["e"] = "e"
        else:
            stray = [k for k in ("vref", "beta", "e") if getattr(self, k) is not None]
            needed = {"c0": "c"}
            if spec.needs_beta:
                needed["tau"] = "tau"
            elif self.tau is not None:
                stray.append("tau")
        if stray:
            raise ValueError(f"law {spec.name} in the {'alpha' if self.alpha is not None else 'c0'} "
                             f"form takes no {', '.join(stray)}")
        for name, kind in needed.items():
            value = getattr(self, name)
            if value is None:
                raise ValueError(f"law {spec.name} needs {name} (in {domain.range_text(kind)})")
            object.__setattr__(self, name, domain.check(kind, value, label=name))

    @property
    def given_p(self) -> float | None:
        """p as the user gives it: for the power law, None for a law with a fixed exponent."""
        return given_exponent(lookup(self.law), self.p)

    @property
    def by_alpha(self) -> bool:
        """True for the alpha form (alpha at vref), False for the physical c0 form."""
        return self.alpha is not None

    def keywords(self, units: str = "si") -> str:
        """The law's part of a pair_coeff / wall-fix line, e.g.
        ``damping KK alpha 0.3 vref 1.5 end force``; vref, c0 and tau converted from SI to the
        LAMMPS ``units`` style (:func:`convert`; alpha, beta, p are dimensionless)."""
        words = ["damping", self.law]
        if self.given_p is not None:  # the law whose exponent the user gives
            words += ["p", _num(self.p)]
        if self.by_alpha:
            words += ["alpha", _num(self.alpha), "vref", _num(convert(self.vref, "velocity", units))]
            if self.beta is not None:
                words += ["beta", _num(self.beta)]
        else:
            words += ["c0", _num(convert(self.c0, ("c0", self.p), units))]
            if self.tau is not None:
                words += ["tau", _num(convert(self.tau, "time", units))]
        return " ".join(words + ["end", self.end])

    def physical(self, pair: ContactPair) -> tuple[float, float | None]:
        """(c0 [N s / m^(1+p)], tau [s] or None) of one contact ``pair`` (its m*, k_Hertz),
        as the plugin computes them (module docstring); the c0 form returns its own numbers.
        TypeError unless ``pair`` is a :class:`viscontact.dimensional.ContactPair`."""
        if not isinstance(pair, ContactPair):
            raise TypeError(f"physical needs the contact as a ContactPair (viscontact.contact_pair"
                            f"(mass, radius=..., modulus=..., poisson=...)), got {type(pair).__name__}")
        if not self.by_alpha:
            return self.c0, self.tau  # type: ignore[return-value]
        at_ref = pair.at(self.vref)  # type: ignore[arg-type]
        c0 = damping_coefficient(self.law, self.alpha, m_eff=pair.m_eff, k_hertz=pair.k_hertz,
                                 v=self.vref, p=self.given_p)
        return c0, (None if self.beta is None else self.beta * at_ref.T)

    def to_dict(self) -> dict[str, Any]:
        return {**asdict(self), "keywords": self.keywords()}


def contact_law(
    law: str, *, e: float | None = None, alpha: float | None = None, vref: float | None = None,
    c0: float | None = None, beta: float | None = None, tau: float | None = None,
    p: float | None = None, end: str = "force",
) -> DemLaw:
    """A :class:`DemLaw` from what the user knows; ValueError says what is wrong.

    Give exactly one of
      * ``e`` and ``vref`` [m/s]: the restitution wanted at relative normal impact speed vref;
        alpha = ``alpha_from_e(law, e, beta=beta, p=p, end=end)`` (exact, |e(alpha) - e| <=
        1e-9; an e below the law's reach is an error);
      * ``alpha`` and ``vref``: the non-dimensional damping constant at vref;
      * ``c0``: the physical prefactor [N s / m^(1+p)] (LH: kg/s), the same for every pair.
    Jian needs ``beta`` (tau / T at vref) with e or alpha, ``tau`` [s] with c0; ``power``
    needs ``p``; no other law takes beta, tau or p.  ``end``: ``force`` (clamp F_n >= 0,
    default) or ``overlap``.  Every number lies in its domain (:mod:`viscontact.domain`: e,
    alpha, beta, p, ``v`` for vref, ``c`` for c0, tau), else ValueError saying the range.
    """
    check_end(end)
    try:
        spec = lookup(law)
    except ValueError as err:
        raise ValueError(f"{err}{native_hint(law)}") from None
    name = spec.name
    forms = [k for k, v in (("e", e), ("alpha", alpha), ("c0", c0)) if v is not None]
    if len(forms) != 1:
        raise ValueError(f"give exactly one of e (with vref), alpha (with vref) or c0; got "
                         f"{', '.join(forms) if forms else 'none'}")
    p_v = exponent(spec, p, noun="law")
    if forms[0] == "c0":
        if vref is not None:
            raise ValueError("vref goes with e or alpha, not with c0 (c0 is already physical)")
        if beta is not None:
            raise ValueError("beta goes with e or alpha; with c0 give Jian's relaxation time tau [s]")
        if spec.needs_beta and tau is None:
            raise ValueError(f"law {name} with c0 needs tau (relaxation time, in "
                             f"{domain.range_text('tau')})")
        if not spec.needs_beta and tau is not None:
            raise ValueError(f"law {name} takes no tau; only Jian has a relaxation time")
        return DemLaw(law=name, p=p_v, end=end, c0=domain.check("c", c0, label="c0"),
                      tau=None if tau is None else domain.check("tau", tau))
    if tau is not None:
        raise ValueError("tau goes with c0; with e or alpha give Jian's beta (tau / T at vref)")
    if vref is None:
        raise ValueError(f"{forms[0]} needs vref, the relative normal impact speed (in "
                         f"{domain.range_text('v')}) at which it applies")
    vref_v = domain.check("v", vref, label="vref")
    if spec.needs_beta and beta is None:
        raise ValueError(f"law {name} with {forms[0]} needs beta (relaxation time / T at vref, "
                         f"in {domain.range_text('beta')})")
    lp = resolve(name, beta=beta, p=p)  # validates beta (Jian only, in its domain)
    beta_v = lp.beta if spec.needs_beta else None
    if forms[0] == "alpha":
        return DemLaw(law=name, p=p_v, end=end, alpha=domain.check("alpha", alpha),
                      vref=vref_v, beta=beta_v)
    from ..calibration import alpha_from_e

    e_v = domain.check("e", e)
    a = float(alpha_from_e(name, e_v, beta=beta_v, p=p, end=end))
    return DemLaw(law=name, p=p_v, end=end, alpha=a, vref=vref_v, beta=beta_v, e=e_v)
