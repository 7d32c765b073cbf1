"""What a user knows about a contact, turned into the LAMMPS lines of the viscontact plugin.

:func:`contact_law` takes a law and either a target restitution ``e`` at a reference speed
``vref`` (calibrated exactly: alpha = :func:`viscontact.alpha_from_e`), a non-dimensional
``alpha`` at ``vref``, or the physical damping prefactor ``c0`` (Jian: and ``tau``); the result
is a frozen :class:`DemLaw`.  :func:`coeff_lines` adds the material (E, nu), the friction and
an optional wall and gives the ``plugin load``, ``pair_style``, ``pair_coeff`` and wall-fix
lines (syntax: ``pair_coeff I J hertz/material E NU damping LAW [p P] FORM [end force|overlap]
tangential none|mindlin MU``, FORM = ``alpha A vref V [beta B]`` or ``c0 C [tau S]``).

Per contact the plugin computes, with that contact's m* and k_Hertz = (4/3) E* sqrt(R*)
(SPEC sections 3 and 9),

    c0  = alpha m*^((3-2p)/5) vref^((1-4p)/5) k_Hertz^((2+2p)/5)     [N s / m^(1+p); LH: kg/s]
    tau = beta T_ref,  T_ref = (m*^2 / (k_Hertz^2 vref))^(1/5)         [s]  (Jian)

so every pair, whatever its masses and radii, has restitution ``e`` when it meets at relative
normal speed ``vref`` (:meth:`DemLaw.physical` gives the same numbers in Python).  Numbers are
written with ``repr`` (the shortest string that reads back as the same double).
"""

from __future__ import annotations

import re
from dataclasses import asdict, dataclass
from typing import Any

from ..collision import check_end
from ..dimensional import ContactPair, check_poisson, check_positive, damping_coefficient
from ..laws import check_finite_nonneg, lookup, resolve

__all__ = ["DemLaw", "CoeffLines", "contact_law", "coeff_lines", "WALL_FIX_ID"]

#: the id of the wall fix :func:`coeff_lines` writes
WALL_FIX_ID = "vcwall"


def _num(x: float) -> str:
    """A float as LAMMPS reads it back exactly (repr: shortest round-tripping form)."""
    return repr(float(x))


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

    @property
    def by_alpha(self) -> bool:
        """True for the alpha form (alpha at vref), False for the physical c0 form."""
        return self.alpha is not None

    def keywords(self) -> str:
        """The law's part of a pair_coeff / wall-fix line, e.g.
        ``damping KK alpha 0.3 vref 1.5 end force``."""
        words = ["damping", self.law]
        if self.law == "power":
            words += ["p", _num(self.p)]
        if self.by_alpha:
            words += ["alpha", _num(self.alpha), "vref", _num(self.vref)]
            if self.beta is not None:
                words += ["beta", _num(self.beta)]
        else:
            words += ["c0", _num(self.c0)]
            if self.tau is not None:
                words += ["tau", _num(self.tau)]
        return " ".join(words + ["end", self.end])

    def physical(self, pair: ContactPair) -> tuple[float, float | None]:
        """(c0 [N s / m^(1+p)], tau [s] or None) of one contact ``pair`` (its m*, k_Hertz),
        as the plugin computes them (module docstring); the c0 form returns its own numbers."""
        if not self.by_alpha:
            return self.c0, self.tau  # type: ignore[return-value]
        at_ref = pair.at(self.vref)  # type: ignore[arg-type]
        c0 = damping_coefficient(self.law, self.alpha, m_eff=pair.m_eff, k_hertz=pair.k_hertz,
                                 v=self.vref, p=self.p if self.law == "power" else None)
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
      * ``e`` in (0, 1] and ``vref`` > 0 [m/s]: the restitution wanted at relative normal
        impact speed vref; alpha = ``alpha_from_e(law, e, beta=beta, p=p, end=end)`` (exact,
        |e(alpha) - e| <= 1e-9; an e below the law's reach is an error);
      * ``alpha`` >= 0 and ``vref`` > 0: the non-dimensional damping constant at vref;
      * ``c0`` >= 0: the physical prefactor [N s / m^(1+p)] (LH: kg/s), the same for every pair.
    Jian needs ``beta`` >= 0 (tau / T at vref) with e or alpha, ``tau`` >= 0 [s] with c0;
    ``power`` needs ``p`` >= 0; no other law takes beta, tau or p.  ``end``: ``force`` (clamp
    F_n >= 0, default) or ``overlap``.
    """
    check_end(end)
    spec = lookup(law)
    name = spec.name
    forms = [k for k, v in (("e", e), ("alpha", alpha), ("c0", c0)) if v is not None]
    if len(forms) != 1:
        raise ValueError(f"give exactly one of e (with vref), alpha (with vref) or c0; got "
                         f"{', '.join(forms) if forms else 'none'}")
    if spec.p is None:
        if p is None:
            raise ValueError("law power needs the exponent p (a finite number >= 0)")
        p_v = check_finite_nonneg("p", p)
    elif p is not None:
        raise ValueError(f"law {name} has a fixed exponent p = {spec.p}; p is only for 'power'")
    else:
        p_v = float(spec.p)
    if forms[0] == "c0":
        if vref is not None:
            raise ValueError("vref goes with e or alpha, not with c0 (c0 is already physical)")
        if beta is not None:
            raise ValueError("beta goes with e or alpha; with c0 give Jian's relaxation time tau [s]")
        if spec.needs_beta and tau is None:
            raise ValueError(f"law {name} with c0 needs tau (relaxation time [s], >= 0)")
        if not spec.needs_beta and tau is not None:
            raise ValueError(f"law {name} takes no tau; only Jian has a relaxation time")
        return DemLaw(law=name, p=p_v, end=end, c0=check_finite_nonneg("c0", c0),
                      tau=None if tau is None else check_finite_nonneg("tau", tau))
    if tau is not None:
        raise ValueError("tau goes with c0; with e or alpha give Jian's beta (tau / T at vref)")
    if vref is None:
        raise ValueError(f"{forms[0]} needs vref, the relative normal impact speed [m/s] (> 0) "
                         "at which it applies")
    vref_v = check_positive("vref", vref)
    if spec.needs_beta and beta is None:
        raise ValueError(f"law {name} with {forms[0]} needs beta (relaxation time / T at vref, >= 0)")
    lp = resolve(name, beta=beta, p=p)  # validates beta (Jian only, >= 0)
    beta_v = lp.beta if spec.needs_beta else None
    if forms[0] == "alpha":
        return DemLaw(law=name, p=p_v, end=end, alpha=check_finite_nonneg("alpha", alpha),
                      vref=vref_v, beta=beta_v)
    from ..calibration import alpha_from_e

    a = float(alpha_from_e(name, e, beta=beta_v, p=p, end=end))
    return DemLaw(law=name, p=p_v, end=end, alpha=a, vref=vref_v, beta=beta_v, e=float(e))


@dataclass(frozen=True)
class CoeffLines:
    """The input lines for one material and law; ``str()`` joins them, one per line."""

    plugin_load: str
    pair_style: str
    pair_coeff: str
    wall_fix: str | None = None

    def lines(self) -> list[str]:
        return [x for x in (self.plugin_load, self.pair_style, self.pair_coeff, self.wall_fix) if x]

    def __str__(self) -> str:
        return "\n".join(self.lines())

    def to_dict(self) -> dict[str, str | None]:
        return asdict(self)


_TYPE = re.compile(r"^(\*|\d+|\d*\*\d*)$")


def _tangential(friction: float | None) -> str:
    if friction is None:
        return "tangential none"
    return f"tangential mindlin {_num(check_finite_nonneg('friction coefficient mu', friction))}"


def _wall_material(wall: Any, E: float, nu: float) -> str:
    if isinstance(wall, str):
        w = wall.strip().lower()
        if w == "same":
            return f"wall_material {_num(E)} {_num(nu)}"
        if w == "rigid":
            return "wall_material rigid"
        raise ValueError(f"wall must be 'same', 'rigid' or (E_wall, nu_wall); got {wall!r}")
    try:
        ew, nw = wall
    except (TypeError, ValueError):
        raise ValueError(f"wall must be 'same', 'rigid' or (E_wall, nu_wall); got {wall!r}") from None
    return (f"wall_material {_num(check_positive('wall E', ew))} "
            f"{_num(check_poisson('wall nu', nw))}")


def coeff_lines(
    law: DemLaw, *, E: float, nu: float, friction: float | None = None,
    wall: str | tuple[float, float] | None = None, types: str = "* *",
    plugin: str | None = None,
) -> CoeffLines:
    """The lines that set up ``law`` for particles of Young's modulus ``E`` [Pa] (> 0, finite)
    and Poisson ratio ``nu`` in (-1, 0.5].

    ``friction``: Coulomb coefficient mu >= 0 with Mindlin no-slip tangential stiffness
    (None: smooth spheres, no tangential force).  ``wall``: None (no wall), ``"same"`` (a wall
    of the particles' material), ``"rigid"``, or ``(E_wall, nu_wall)``; gives
    ``fix vcwall all viscontact/wall zplane 0.0 NULL wall_material ...`` with the same law and
    friction (a floor at z = 0; edit the plane to suit).  ``types``: the pair_coeff type pair
    (``"* *"``, ``"1 2"``, ``"1*3 *"``).  ``plugin``: the plugin file; None builds or finds
    it (:func:`viscontact.dem.plugin_path`).
    """
    if not isinstance(law, DemLaw):
        raise ValueError(f"law must be a DemLaw from contact_law(...); got {type(law).__name__}")
    E = check_positive("E (Young's modulus)", E)
    nu = check_poisson("nu (Poisson ratio)", nu)
    parts = str(types).split()
    if len(parts) != 2 or not all(_TYPE.match(t) for t in parts):
        raise ValueError(f"types must be two atom types or ranges such as '* *', '1 2', '1*3 *'; "
                         f"got {types!r}")
    tang = _tangential(friction)
    wall_fix = None
    if wall is not None:
        wall_fix = (f"fix {WALL_FIX_ID} all viscontact/wall zplane 0.0 NULL "
                    f"{_wall_material(wall, E, nu)} {law.keywords()} {tang}")
    if plugin is None:
        from .plugin import plugin_load_line

        load = plugin_load_line()
    else:
        load = f'plugin load "{plugin}"' if any(c.isspace() for c in str(plugin)) else f"plugin load {plugin}"
    return CoeffLines(
        plugin_load=load, pair_style="pair_style viscontact",
        pair_coeff=f"pair_coeff {' '.join(parts)} hertz/material {_num(E)} {_num(nu)} "
                   f"{law.keywords()} {tang}",
        wall_fix=wall_fix,
    )
