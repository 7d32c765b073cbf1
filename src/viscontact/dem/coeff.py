"""What a user knows about a contact, turned into the LAMMPS lines of the viscontact plugin.

:func:`contact_law` takes a law and either a target restitution ``e`` at a reference speed
``vref`` (calibrated exactly: alpha = :func:`viscontact.alpha_from_e`), a non-dimensional
``alpha`` at ``vref``, or the physical damping prefactor ``c0`` (Jian: and ``tau``); the result
is a frozen :class:`DemLaw`.  :func:`coeff_lines` adds the material (E, nu), the other
sub-models (:class:`SubModels`: :class:`Normal` hertz/dmt/jkr, :class:`Tangential`,
:class:`Rolling`, :class:`Twisting`, heat, cutoff) and an optional wall and gives the ``plugin
load``, ``pair_style``, ``pair_coeff`` and wall-fix lines, all written by :func:`contact_words`
(syntax: ``pair_coeff I J NORMAL damping LAW [p P] FORM [end force|overlap] tangential TMODEL
[rolling sds KR GAMMAR MUR] [twisting marshall|sds KT GAMMAT MUT] [heat area K] [cutoff C]``,
NORMAL = ``hertz/material E NU | dmt E NU W | jkr E NU W``, FORM = ``alpha A vref V [beta B]``
or ``c0 C [tau S]``).

Per contact the plugin computes, with that contact's m* and k_Hertz = (4/3) E* sqrt(R*)
(SPEC sections 3 and 9),

    c0  = alpha m*^((3-2p)/5) vref^((1-4p)/5) k_Hertz^((2+2p)/5)     [N s / m^(1+p); LH: kg/s]
    tau = beta T_ref,  T_ref = (m*^2 / (k_Hertz^2 vref))^(1/5)         [s]  (Jian)

so every pair, whatever its masses and radii, has restitution ``e`` when it meets at relative
normal speed ``vref`` (:meth:`DemLaw.physical` gives the same numbers in Python).  Numbers are
written with ``repr`` (the shortest string that reads back as the same double).
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

from .. import domain
from ..collision import check_end
from ..dimensional import HERTZ_TC, ContactPair, check_poisson, damping_coefficient
from ..laws import MODELS, lookup, resolve
from ._text import check_type_spec, quote_path

__all__ = ["DemLaw", "CoeffLines", "contact_law", "coeff_lines", "WALL_FIX_ID", "UNIT_STYLES",
           "convert", "check_units", "mixed_material", "ParticleType", "Wall", "PairLine", "CoeffSet",
           "coeff_set", "Normal", "Tangential", "Rolling", "Twisting", "SubModels", "contact_words",
           "NORMAL_MODELS", "TANGENTIAL_MODELS"]

#: the id of the wall fix :func:`coeff_lines` writes
WALL_FIX_ID = "vcwall"


def _num(x: float) -> str:
    """A float as LAMMPS reads it back exactly (repr: shortest round-tripping form)."""
    return repr(float(x))


#: LAMMPS unit styles the plugin accepts -> (mass, length, time) of the style in SI
#: (kg, m, s); lj has no SI equivalent: values are taken as reduced units and not converted.
UNIT_STYLES: dict[str, tuple[float, float, float] | None] = {
    "si": (1.0, 1.0, 1.0),
    "cgs": (1e-3, 1e-2, 1.0),           # g, cm, s (pressure dyne/cm^2 = 0.1 Pa)
    "micro": (1e-15, 1e-6, 1e-6),       # pg, um, us (pressure 1e3 Pa, velocity m/s)
    "nano": (1e-21, 1e-9, 1e-9),        # ag, nm, ns (pressure 1e6 Pa, velocity m/s)
    "lj": None,
}
#: quantity -> exponents of (mass, length, time)
_DIMS: dict[str, tuple[float, float, float]] = {
    "pressure": (1, -1, -2), "velocity": (0, 1, -1), "length": (0, 1, 0), "time": (0, 0, 1),
    "density": (1, -3, 0), "mass": (1, 0, 0),
}


def check_units(units: object) -> str:
    """A LAMMPS unit style the plugin takes (:data:`UNIT_STYLES`), else ValueError."""
    if not isinstance(units, str) or units.strip().lower() not in UNIT_STYLES:
        raise ValueError(f"units must be one of {', '.join(UNIT_STYLES)}, got {units!r}")
    return units.strip().lower()


def convert(value: float, quantity: str | tuple[str, float], units: str) -> float:
    """``value`` of ``quantity`` from SI into the LAMMPS ``units`` style (lj: unchanged).

    ``quantity``: pressure, velocity, length, time, density, mass, or ``("c0", p)``, the damping
    prefactor [N s / m^(1+p)] = kg m^-p s^-1.
    """
    base = UNIT_STYLES[check_units(units)]
    if base is None:
        return float(value)
    if isinstance(quantity, tuple):
        dims: tuple[float, float, float] = (1, -quantity[1], -1)
    else:
        dims = _DIMS[quantity]
    scale = base[0] ** dims[0] * base[1] ** dims[1] * base[2] ** dims[2]
    return float(value) / scale


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
        if spec.p is not None and p != spec.p:
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
    def by_alpha(self) -> bool:
        """True for the alpha form (alpha at vref), False for the physical c0 form."""
        return self.alpha is not None

    def keywords(self, units: str = "si") -> str:
        """The law's part of a pair_coeff / wall-fix line, e.g.
        ``damping KK alpha 0.3 vref 1.5 end force``; vref, c0 and tau converted from SI to the
        LAMMPS ``units`` style (:func:`convert`; alpha, beta, p are dimensionless)."""
        words = ["damping", self.law]
        if self.law == "power":
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
    spec = lookup(law)
    name = spec.name
    forms = [k for k, v in (("e", e), ("alpha", alpha), ("c0", c0)) if v is not None]
    if len(forms) != 1:
        raise ValueError(f"give exactly one of e (with vref), alpha (with vref) or c0; got "
                         f"{', '.join(forms) if forms else 'none'}")
    if spec.p is None:
        if p is None:
            raise ValueError(f"law power needs the exponent p (in {domain.range_text('p')})")
        p_v = domain.check("p", p)
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


def _load_line(plugin: str | os.PathLike | None) -> str:
    """``plugin load '<path>'`` (the cached plugin when ``plugin`` is None), quoted for LAMMPS."""
    if plugin is None:
        from .plugin import plugin_path

        plugin = plugin_path()
    if not isinstance(plugin, (str, os.PathLike)):
        raise TypeError(f"plugin must be a file path, got {type(plugin).__name__}")
    return f"plugin load {quote_path(plugin, 'plugin path')}"


def _wall_pair(wall: Any, E: float | None, nu: float | None) -> tuple[float, float] | None:
    """The wall's (E, nu) or None for rigid; ``same``: the particles' (E, nu)."""
    text = "wall material must be 'same', 'rigid' or (E_wall, nu_wall)"
    if isinstance(wall, str):
        w = wall.strip().lower()
        if w == "rigid":
            return None
        if w == "same":
            if E is None:
                raise ValueError("wall material 'same' needs one particle material; give 'rigid' "
                                 "or (E_wall, nu_wall)")
            return E, nu  # type: ignore[return-value]
        raise ValueError(f"{text}; got {wall!r}")
    if isinstance(wall, (bytes, Mapping)) or not isinstance(wall, Sequence) or len(wall) != 2:
        raise ValueError(f"{text}; got {wall!r}")
    return (domain.check("modulus", wall[0], label="wall E"), check_poisson("wall nu", wall[1]))


def _material_words(pair: tuple[float, float] | None, units: str) -> str:
    if pair is None:
        return "wall_material rigid"
    return f"wall_material {_num(convert(pair[0], 'pressure', units))} {_num(pair[1])}"


# ------------------------------------------------------------------ the other sub-models
#: quantity -> exponents of (mass, length, time) for the sub-models' coefficients
_DIMS.update({
    "surface_energy": (1, 0, -2),       # W [J/m^2 = N/m]
    "stiffness": (1, 0, -2),            # linear_history KT, rolling KR [N/m]
    "stiffness_area": (1, -1, -2),      # mindlin KT [N/m^2] (times the contact radius a)
    "damping": (1, 0, -1),              # rolling GAMMAR [N s/m]
    "torque_stiffness": (1, 2, -2),     # twisting sds KT [N m/rad]
    "torque_damping": (1, 2, -1),       # twisting sds GAMMAT [N m s]
    "conductance": (1, 0, -3),          # heat area K [W/(m^2 K)]
})

NORMAL_MODELS = ("hertz", "dmt", "jkr")
TANGENTIAL_MODELS = ("none", "linear_nohistory", "linear_history", "mindlin", "mindlin_rescale",
                     "mindlin/force", "mindlin_rescale/force")
#: tangential models with an elastic spring (the ones twisting marshall needs)
SPRING_MODELS = TANGENTIAL_MODELS[2:]


def _nonneg(label: str, value: Any) -> float:
    """A finite number >= 0, else ValueError naming ``label``."""
    v = domain.check_number(label, value)
    if not (math.isfinite(v) and v >= 0):
        raise ValueError(f"{label} must be a finite number >= 0, got {value!r}")
    return v


@dataclass(frozen=True)
class Normal:
    """The normal model: ``hertz`` (Hertz, no cohesion), ``dmt`` or ``jkr`` with the surface
    energy ``W`` [J/m^2] (native's gamma; the work of adhesion is 2W).  Pull-off forces:
    DMT 4 pi W R*, JKR 3 pi W R* (Derjaguin, Muller & Toporov 1975; Johnson, Kendall & Roberts
    1971).  The damping law's k_Hertz ignores adhesion, so a calibrated e is that of the Hertz
    part."""

    model: str = "hertz"
    W: float | None = None

    def __post_init__(self) -> None:
        domain.check_choice("normal model", self.model, NORMAL_MODELS)
        if self.model == "hertz":
            if self.W is not None:
                raise ValueError("normal hertz takes no surface energy W (dmt W or jkr W do)")
        elif self.W is None:
            raise ValueError(f"normal {self.model} needs the surface energy W (J/m^2, >= 0)")
        else:
            object.__setattr__(self, "W", _nonneg(f"normal {self.model} W", self.W))

    @property
    def cohesive(self) -> bool:
        return self.model != "hertz"

    @classmethod
    def from_any(cls, spec: Any) -> "Normal":
        """From a Normal, ``"hertz"``, or ``("dmt", W)`` / ``("jkr", W)``."""
        if isinstance(spec, cls):
            return spec
        if spec is None:
            return cls()
        if isinstance(spec, str):
            return cls(spec)
        if isinstance(spec, Sequence) and not isinstance(spec, bytes) and 1 <= len(spec) <= 2:
            return cls(*spec)
        raise ValueError(f"normal must be 'hertz', ('dmt', W) or ('jkr', W); got {spec!r}")

    def pair_words(self, E: float, nu: float, units: str) -> str:
        """``hertz/material E NU``, ``dmt E NU W`` or ``jkr E NU W`` of a pair_coeff line."""
        words = ["hertz/material" if self.model == "hertz" else self.model,
                 _num(convert(E, "pressure", units)), _num(nu)]
        if self.cohesive:
            words.append(_num(convert(self.W, "surface_energy", units)))
        return " ".join(words)

    def wall_words(self, units: str) -> str:
        """``normal dmt W`` / ``normal jkr W`` of a wall fix ('' for hertz, the default)."""
        if not self.cohesive:
            return ""
        return f"normal {self.model} {_num(convert(self.W, 'surface_energy', units))}"


@dataclass(frozen=True)
class Tangential:
    """The tangential model (Mindlin 1949; Cundall & Strack 1979 for the linear spring).

    ``model`` in :data:`TANGENTIAL_MODELS`; ``kt``: the spring, N/m for ``linear_history``
    (required), N/m^2 for the mindlin family (k_t = kt a; None = NULL: k_t = 8 G* a);
    ``xgamma``: tangential damping eta_t = xgamma eta_n (the law's normal prefactor);
    ``mu``: Coulomb coefficient.  ``none`` has no force.  ``mindlin`` with kt None and
    xgamma 0 is written in the short form ``tangential mindlin MU``.
    """

    model: str = "none"
    kt: float | None = None
    xgamma: float = 0.0
    mu: float = 0.0

    def __post_init__(self) -> None:
        domain.check_choice("tangential model", self.model, TANGENTIAL_MODELS)
        m = self.model
        object.__setattr__(self, "xgamma", _nonneg(f"tangential {m} XGAMMA", self.xgamma))
        object.__setattr__(self, "mu", domain.check("friction", self.mu, label=f"tangential {m} MU"))
        if m == "none":
            if self.kt is not None or self.xgamma or self.mu:
                raise ValueError("tangential none takes no KT, XGAMMA or MU")
        elif m == "linear_nohistory":
            if self.kt is not None:
                raise ValueError("tangential linear_nohistory takes XGAMMA MU, no spring KT")
        elif m == "linear_history":
            if self.kt is None:
                raise ValueError("tangential linear_history needs the spring KT (N/m, >= 0)")
            object.__setattr__(self, "kt", _nonneg("tangential linear_history KT", self.kt))
        elif self.kt is not None:
            object.__setattr__(self, "kt", _nonneg(f"tangential {m} KT", self.kt))

    @classmethod
    def from_any(cls, spec: Any) -> "Tangential":
        """From a Tangential, a model name, or (model, *numbers) as on the line
        (``("mindlin", 0.5)`` is the short form; ``"NULL"`` or None for a mindlin KT)."""
        if isinstance(spec, cls):
            return spec
        if spec is None:
            return cls()
        if isinstance(spec, str):
            spec = (spec,)
        if not isinstance(spec, Sequence) or isinstance(spec, bytes) or not spec:
            raise ValueError(f"tangential must be a model name or (model, numbers...); got {spec!r}")
        model, *nums = spec
        domain.check_choice("tangential model", model, TANGENTIAL_MODELS)
        nums = [None if (isinstance(x, str) and x.upper() == "NULL") else x for x in nums]
        want = {"none": 0, "linear_nohistory": 2, "linear_history": 3}.get(model, 3)
        if model == "mindlin" and len(nums) == 1:
            return cls("mindlin", mu=nums[0])
        if len(nums) != want:
            usage = {0: "", 2: " XGAMMA MU", 3: " KT XGAMMA MU" if model == "linear_history"
                     else " KT|NULL XGAMMA MU"}[want]
            raise ValueError(f"tangential {model} takes{usage or ' no numbers'}"
                             + (" (or the short form: mindlin MU)" if model == "mindlin" else "")
                             + f"; got {len(nums)} number(s)")
        if want == 2:
            return cls(model, xgamma=nums[0], mu=nums[1])
        if want == 3:
            return cls(model, kt=nums[0], xgamma=nums[1], mu=nums[2])
        return cls(model)

    @property
    def spring(self) -> bool:
        return self.model in SPRING_MODELS

    def words(self, units: str) -> str:
        m = self.model
        if m == "none":
            return "tangential none"
        if m == "mindlin" and self.kt is None and self.xgamma == 0:
            return f"tangential mindlin {_num(self.mu)}"
        words = ["tangential", m]
        if m != "linear_nohistory":
            dims = "stiffness" if m == "linear_history" else "stiffness_area"
            words.append("NULL" if self.kt is None else _num(convert(self.kt, dims, units)))
        return " ".join(words + [_num(self.xgamma), _num(self.mu)])


@dataclass(frozen=True)
class Rolling:
    """Rolling resistance ``sds`` (spring-dashpot-slider, Luding 2008; Wang et al. 2015):
    spring ``kr`` [N/m] (> 0), dashpot ``gammar`` [N s/m], friction ``mur``; the resisting
    torque is at most mur R* F0."""

    kr: float
    gammar: float
    mur: float

    def __post_init__(self) -> None:
        kr = _nonneg("rolling sds KR", self.kr)
        if kr == 0:
            raise ValueError("rolling sds KR must be > 0 (the slip update divides by it)")
        object.__setattr__(self, "kr", kr)
        object.__setattr__(self, "gammar", _nonneg("rolling sds GAMMAR", self.gammar))
        object.__setattr__(self, "mur", _nonneg("rolling sds MUR", self.mur))

    @classmethod
    def from_any(cls, spec: Any) -> "Rolling | None":
        """From a Rolling, None, or (KR, GAMMAR, MUR) (optionally led by ``"sds"``)."""
        if spec is None or isinstance(spec, cls):
            return spec
        if isinstance(spec, Sequence) and not isinstance(spec, (str, bytes)):
            nums = list(spec[1:]) if spec and spec[0] == "sds" else list(spec)
            if len(nums) == 3:
                return cls(*nums)
        raise ValueError(f"rolling must be sds KR GAMMAR MUR; got {spec!r}")

    def words(self, units: str) -> str:
        return (f"rolling sds {_num(convert(self.kr, 'stiffness', units))} "
                f"{_num(convert(self.gammar, 'damping', units))} {_num(self.mur)}")


@dataclass(frozen=True)
class Twisting:
    """Twisting resistance: ``marshall`` (Marshall 2009; stiffness, damping and limit from the
    tangential model) or ``sds`` with ``kt`` [N m/rad] (> 0), ``gammat`` [N m s] and ``mut``,
    a LENGTH [m] (the torque limit is mut F0, as native's code)."""

    model: str = "marshall"
    kt: float | None = None
    gammat: float | None = None
    mut: float | None = None

    def __post_init__(self) -> None:
        domain.check_choice("twisting model", self.model, ("marshall", "sds"))
        nums = (self.kt, self.gammat, self.mut)
        if self.model == "marshall":
            if any(x is not None for x in nums):
                raise ValueError("twisting marshall takes no numbers (they come from the tangential model)")
            return
        if any(x is None for x in nums):
            raise ValueError("twisting sds needs KT GAMMAT MUT")
        kt = _nonneg("twisting sds KT", self.kt)
        if kt == 0:
            raise ValueError("twisting sds KT must be > 0 (the slip update divides by it)")
        object.__setattr__(self, "kt", kt)
        object.__setattr__(self, "gammat", _nonneg("twisting sds GAMMAT", self.gammat))
        object.__setattr__(self, "mut", _nonneg("twisting sds MUT", self.mut))

    @classmethod
    def from_any(cls, spec: Any) -> "Twisting | None":
        """From a Twisting, None, ``"marshall"`` or ``("sds", KT, GAMMAT, MUT)``."""
        if spec is None or isinstance(spec, cls):
            return spec
        if isinstance(spec, str):
            spec = (spec,)
        if isinstance(spec, Sequence) and not isinstance(spec, bytes) and spec:
            if spec[0] == "marshall" and len(spec) == 1:
                return cls("marshall")
            if spec[0] == "sds" and len(spec) == 4:
                return cls("sds", *spec[1:])
        raise ValueError(f"twisting must be marshall or sds KT GAMMAT MUT; got {spec!r}")

    def words(self, units: str) -> str:
        if self.model == "marshall":
            return "twisting marshall"
        return (f"twisting sds {_num(convert(self.kt, 'torque_stiffness', units))} "
                f"{_num(convert(self.gammat, 'torque_damping', units))} "
                f"{_num(convert(self.mut, 'length', units))}")


@dataclass(frozen=True)
class SubModels:
    """Everything of a contact but the damping law: normal, tangential, rolling, twisting,
    heat conduction ``heat`` K [W/(m^2 K)] (Q = K pi a^2 (T_j - T_i)) and the pair
    ``cutoff`` [m] (None: automatic).  :meth:`build` takes the loose forms the public functions
    accept; :func:`contact_words` writes them for a pair or a wall."""

    normal: Normal = Normal()
    tangential: Tangential = Tangential()
    rolling: Rolling | None = None
    twisting: Twisting | None = None
    heat: float | None = None
    cutoff: float | None = None

    def __post_init__(self) -> None:
        if self.twisting is not None and self.twisting.model == "marshall" and not self.tangential.spring:
            raise ValueError("twisting marshall needs a tangential spring (linear_history or a "
                             f"mindlin model), got tangential {self.tangential.model}")
        if self.heat is not None:
            object.__setattr__(self, "heat", _nonneg("heat area K", self.heat))
        if self.cutoff is not None:
            c = _nonneg("cutoff", self.cutoff)
            if c == 0:
                raise ValueError("cutoff must be > 0 (leave it out for the automatic cutoff)")
            object.__setattr__(self, "cutoff", c)

    @classmethod
    def build(cls, *, normal: Any = None, tangential: Any = None, friction: float | None = None,
              rolling: Any = None, twisting: Any = None, heat: float | None = None,
              cutoff: float | None = None) -> "SubModels":
        """From the keyword arguments of :func:`coeff_lines` / :func:`coeff_set`
        (``friction`` MU is the short form ``tangential mindlin MU``)."""
        if friction is not None and tangential is not None:
            raise ValueError("give friction (the short form tangential mindlin MU) or tangential, not both")
        if friction is not None:
            tang = Tangential("mindlin", mu=domain.check("friction", friction,
                                                        label="friction coefficient mu"))
        else:
            tang = Tangential.from_any(tangential)
        return cls(Normal.from_any(normal), tang, Rolling.from_any(rolling),
                   Twisting.from_any(twisting), heat, cutoff)

    def check_law(self, law: DemLaw) -> None:
        """dmt and jkr take no clamp (``end force``), as native refuses limit_damping there."""
        if self.normal.cohesive and law.end == "force":
            raise ValueError(f"normal {self.normal.model} needs end overlap (no clamp with "
                             "cohesion): contact_law(..., end='overlap') or --end overlap")

    def tail(self, law: DemLaw, units: str, *, pair: bool) -> str:
        """``damping ... tangential ... [rolling ...] [twisting ...] [heat area K]`` (pair: and
        ``[cutoff C]``)."""
        self.check_law(law)
        words = [law.keywords(units), self.tangential.words(units)]
        words += [m.words(units) for m in (self.rolling, self.twisting) if m is not None]
        if self.heat is not None:
            words.append(f"heat area {_num(convert(self.heat, 'conductance', units))}")
        if pair and self.cutoff is not None:
            words.append(f"cutoff {_num(convert(self.cutoff, 'length', units))}")
        return " ".join(words)


def contact_words(law: DemLaw, sub: SubModels, units: str, *, E: float | None = None,
                  nu: float | None = None, wall: "Wall | None" = None,
                  wall_material: tuple[float, float] | None = None) -> str:
    """The one writer of contact keywords: a pair_coeff line's after the types
    (``NORMAL E NU [W] damping ... tangential ...``) or, with ``wall``, a wall fix's after
    ``viscontact/wall`` (``GEOMETRY wall_material ... [normal dmt|jkr W] damping ...
    [temperature T] [wiggle|shear ...]``); ``wall_material`` None is rigid."""
    if wall is None:
        return f"{sub.normal.pair_words(E, nu, units)} {sub.tail(law, units, pair=True)}"
    if sub.heat is not None and wall.temperature is None:
        raise ValueError("a wall with heat conduction needs its temperature (Wall(..., "
                         "temperature=T) or --wall-temperature T)")
    words = [wall.geometry(units), _material_words(wall_material, units), sub.normal.wall_words(units),
             sub.tail(law, units, pair=False), wall.motion_words(sub, units)]
    return " ".join(w for w in words if w)


def coeff_lines(
    law: DemLaw, *, E: float, nu: float, friction: float | None = None,
    wall: str | tuple[float, float] | None = None, types: str = "* *",
    plugin: str | os.PathLike | None = None, units: str = "si", normal: Any = None,
    tangential: Any = None, rolling: Any = None, twisting: Any = None,
    heat: float | None = None, cutoff: float | None = None,
) -> CoeffLines:
    """The lines that set up ``law`` for particles of Young's modulus ``E`` [Pa] and Poisson
    ratio ``nu`` (each in its domain, :mod:`viscontact.domain`: modulus, poisson).

    ``friction``: Coulomb coefficient mu (domain ``friction``) with Mindlin no-slip tangential stiffness
    (None: smooth spheres, no tangential force).  ``wall``: None (no wall), ``"same"`` (a wall
    of the particles' material), ``"rigid"``, or ``(E_wall, nu_wall)``; gives
    ``fix vcwall all viscontact/wall zplane 0.0 NULL wall_material ...`` with the same law and
    friction (a floor at z = 0; :func:`coeff_set` puts walls anywhere).  ``types``: the
    pair_coeff type pair as LAMMPS reads it (``"* *"``, ``"1 2"``, ``"1*3 *"``).  ``plugin``:
    the plugin file; None builds or finds it (:func:`viscontact.dem.plugin_path`); the path is
    quoted (:func:`viscontact.dem._text.quote_path`).  ``units``: the LAMMPS unit style the
    numbers are printed in (values given in SI; ``lj``: reduced units, unchanged).

    The other sub-models (SI values; :class:`SubModels`): ``normal`` ``"hertz"`` (default),
    ``("dmt", W)`` or ``("jkr", W)`` (W [J/m^2]; needs ``end="overlap"``); ``tangential`` a
    :class:`Tangential` or ``(MODEL, numbers...)`` as on the line, e.g.
    ``("linear_history", KT, XGAMMA, MU)`` (``friction`` MU is the short form mindlin MU);
    ``rolling`` ``(KR, GAMMAR, MUR)`` (sds); ``twisting`` ``"marshall"`` or
    ``("sds", KT, GAMMAT, MUT)``; ``heat`` K (conduction ``heat area K``); ``cutoff`` [m].
    The wall fix gets the same sub-models (one writer: :func:`contact_words`).
    """
    if not isinstance(law, DemLaw):
        raise ValueError(f"law must be a DemLaw from contact_law(...); got {type(law).__name__}")
    units = check_units(units)
    E = domain.check("modulus", E, label="E (Young's modulus)")
    nu = check_poisson("nu (Poisson ratio)", nu)
    spec = check_type_spec(types)
    sub = SubModels.build(normal=normal, tangential=tangential, friction=friction,
                          rolling=rolling, twisting=twisting, heat=heat, cutoff=cutoff)
    wall_fix = None
    if wall is not None:
        floor = Wall("zplane", (0.0, None), "rigid")
        wall_fix = (f"fix {WALL_FIX_ID} all viscontact/wall "
                    + contact_words(law, sub, units, wall=floor, wall_material=_wall_pair(wall, E, nu)))
    return CoeffLines(
        plugin_load=_load_line(plugin), pair_style="pair_style viscontact",
        pair_coeff=f"pair_coeff {spec} {contact_words(law, sub, units, E=E, nu=nu)}",
        wall_fix=wall_fix,
    )


# ------------------------------------------------------------------ several particle types
def mixed_material(E1: float, nu1: float, E2: float, nu2: float) -> tuple[float, float]:
    """The (E, nu) whose explicit ``pair_coeff I J hertz/material E NU`` line reproduces the
    contact of two materials exactly.

    LAMMPS reads an explicit I J line as one material on both sides (SPEC 10.6):
    E*_line = E / (2 (1 - nu^2)), G*_line = E / (4 (2 - nu) (1 + nu)).  The contact of the two
    materials has 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2 and 1/G* = (2-nu1)/G1 + (2-nu2)/G2,
    G = E / (2 (1 + nu)).  With r = G*/E* = (1 - nu) / (2 (2 - nu)) on the line's side,
    nu = (4 r - 1) / (2 r - 1) and E = 2 (1 - nu^2) E*.  r of the pair is a weighted harmonic
    mean of r1, r2 (each in [1/6, 1/3) for nu in (-1, 0.5]), so nu lies in (-1, 0.5] too.
    """
    inv_e = (1 - nu1 ** 2) / E1 + (1 - nu2 ** 2) / E2
    inv_g = 2 * (2 - nu1) * (1 + nu1) / E1 + 2 * (2 - nu2) * (1 + nu2) / E2
    r = inv_e / inv_g
    nu = min(0.5, (4 * r - 1) / (2 * r - 1))
    return 2 * (1 - nu ** 2) / inv_e, nu


def _positive(label: str, value: Any) -> float:
    v = domain.check_number(label, value)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{label} must be a finite number > 0, got {value!r}")
    return v


@dataclass(frozen=True)
class ParticleType:
    """One atom type's material: E [Pa], nu, and optionally density [kg/m^3] and the diameter
    range (lo, hi) [m] (used only for the contact time and the time step the lines suggest)."""

    E: float
    nu: float
    density: float | None = None
    diameter: tuple[float, float] | None = None

    #: keys a mapping may use (``d`` is the diameter: a number or (lo, hi))
    KEYS = ("E", "nu", "density", "d")

    def __post_init__(self) -> None:
        object.__setattr__(self, "E", domain.check("modulus", self.E, label="E"))
        object.__setattr__(self, "nu", check_poisson("nu", self.nu))
        if self.density is not None:
            object.__setattr__(self, "density", _positive("density", self.density))
        if self.diameter is not None:
            d = self.diameter
            if isinstance(d, (tuple, list)):
                if len(d) != 2:
                    raise ValueError(f"diameter must be a number or (lo, hi), got {d!r}")
                lo, hi = (_positive("diameter", x) for x in d)
            else:
                lo = hi = _positive("diameter", d)
            if lo > hi:
                raise ValueError(f"diameter range lo:hi needs lo <= hi, got {lo!r}:{hi!r}")
            object.__setattr__(self, "diameter", (lo, hi))
        if (self.density is None) != (self.diameter is None):
            raise ValueError("give density and diameter together (they set the contact time), or neither")

    @classmethod
    def from_any(cls, spec: Any, index: int) -> "ParticleType":
        """A ParticleType from itself or a mapping with the keys :attr:`KEYS`."""
        if isinstance(spec, cls):
            return spec
        if not isinstance(spec, Mapping):
            raise TypeError(f"particle type {index} must be a ParticleType or a mapping with keys "
                            f"{', '.join(cls.KEYS)}, got {type(spec).__name__}")
        unknown = [k for k in spec if k not in cls.KEYS]
        if unknown:
            raise ValueError(f"particle type {index}: unknown key {unknown[0]!r}; allowed: "
                             f"{', '.join(cls.KEYS)}")
        missing = [k for k in ("E", "nu") if k not in spec]
        if missing:
            raise ValueError(f"particle type {index}: missing {' and '.join(missing)}")
        try:
            return cls(E=spec["E"], nu=spec["nu"], density=spec.get("density"), diameter=spec.get("d"))
        except ValueError as exc:
            raise ValueError(f"particle type {index}: {exc}") from None


_DIMS_XYZ = ("x", "y", "z")


@dataclass(frozen=True)
class Wall:
    """A wall of ``fix viscontact/wall``: ``style`` xplane|yplane|zplane with ``args``
    (LO, HI) (a coordinate [m] or None for NULL), zcylinder with (R,) [m], or ``region`` with
    (REGION-ID,) (any LAMMPS region, moving or rotating; several contacts per sphere);
    ``material`` ``"rigid"``, ``"same"`` or (E [Pa], nu).  ``wiggle`` (DIM, A [m], PERIOD [s])
    or ``shear`` (DIM, V [m/s]) move a plane or zcylinder (not a region: move the region);
    ``temperature`` T [K] or ``"v_name"`` (an equal-style variable) is needed with heat."""

    style: str
    args: tuple[Any, ...]
    material: Any = "rigid"
    wiggle: tuple[str, float, float] | None = None
    shear: tuple[str, float] | None = None
    temperature: float | str | None = None

    STYLES = ("xplane", "yplane", "zplane", "zcylinder", "region")

    def __post_init__(self) -> None:
        if not isinstance(self.style, str) or self.style not in self.STYLES:
            raise ValueError(f"wall style must be one of {', '.join(self.STYLES)}, got {self.style!r}")
        args = tuple(self.args) if isinstance(self.args, (tuple, list)) else (self.args,)
        if self.style == "region":
            if len(args) != 1 or not isinstance(args[0], str) or not re.fullmatch(r"[A-Za-z0-9_]+", args[0]):
                raise ValueError("region wall needs the region ID (letters, digits and _)")
        elif self.style == "zcylinder":
            if len(args) != 1 or args[0] is None:
                raise ValueError("zcylinder needs its radius R (> 0)")
            r = domain.check_number("zcylinder R", args[0])
            if not (math.isfinite(r) and r > 0):
                raise ValueError(f"zcylinder R must be a finite length > 0, got {args[0]!r}")
            args = (r,)
        else:
            if len(args) != 2:
                raise ValueError(f"{self.style} needs LO HI (a coordinate or NULL each)")
            vals = [None if a is None else domain.check_number(f"{self.style} coordinate", a) for a in args]
            if any(v is not None and not math.isfinite(v) for v in vals):
                raise ValueError(f"{self.style} LO and HI must be finite or NULL, got {args!r}")
            if vals[0] is None and vals[1] is None:
                raise ValueError(f"{self.style}: LO and HI cannot both be NULL")
            if vals[0] is not None and vals[1] is not None and not vals[0] < vals[1]:
                raise ValueError(f"{self.style}: LO must be below HI, got {args!r}")
            args = tuple(vals)
        object.__setattr__(self, "args", args)
        object.__setattr__(self, "material", "rigid" if self.material is None else self.material)
        _wall_pair(self.material, 1.0, 0.0)  # validates (same is resolved by the caller)
        self._check_motion()
        t = self.temperature
        if isinstance(t, str):
            if not re.fullmatch(r"v_[A-Za-z0-9_]+", t):
                raise ValueError(f"wall temperature must be a number (K) or v_NAME, got {t!r}")
        elif t is not None:
            object.__setattr__(self, "temperature", _positive("wall temperature", t))

    def _check_motion(self) -> None:
        if self.wiggle is not None and self.shear is not None:
            raise ValueError("a wall takes wiggle or shear, not both")
        motion = self.wiggle if self.wiggle is not None else self.shear
        if motion is None:
            return
        what = "wiggle" if self.wiggle is not None else "shear"
        if self.style == "region":
            raise ValueError(f"{what} is for plane and zcylinder walls; move a region wall with "
                             "the region's own move/rotate keywords")
        want = 3 if what == "wiggle" else 2
        if isinstance(motion, (str, bytes)) or not isinstance(motion, Sequence) or len(motion) != want:
            raise ValueError(f"{what} needs {'DIM A PERIOD' if what == 'wiggle' else 'DIM V'}")
        dim = motion[0]
        if dim not in _DIMS_XYZ:
            raise ValueError(f"{what} DIM must be x, y or z, got {dim!r}")
        if what == "wiggle":
            if self.style == "zcylinder" and dim != "z":
                raise ValueError("a zcylinder wiggles only along z")
            amp = domain.check_number("wiggle A", motion[1])
            period = _positive("wiggle PERIOD", motion[2])
            if not math.isfinite(amp):
                raise ValueError(f"wiggle A must be a finite length, got {motion[1]!r}")
            object.__setattr__(self, "wiggle", (dim, amp, period))
        else:
            if self.style != "zcylinder" and dim == self.style[0]:
                raise ValueError(f"a {self.style} shears in its plane: DIM must not be {dim}")
            v = domain.check_number("shear V", motion[1])
            if not math.isfinite(v):
                raise ValueError(f"shear V must be a finite velocity, got {motion[1]!r}")
            object.__setattr__(self, "shear", (dim, v))

    def geometry(self, units: str) -> str:
        """``zplane 0.0 NULL`` / ``zcylinder 0.05`` / ``region drum`` with lengths in ``units``."""
        if self.style == "region":
            return f"region {self.args[0]}"
        words = ["NULL" if a is None else _num(convert(a, "length", units)) for a in self.args]
        return " ".join([self.style, *words])

    def motion_words(self, sub: "SubModels", units: str) -> str:
        """``[temperature T] [wiggle DIM A PERIOD | shear DIM V]`` (temperature only with heat)."""
        words = []
        if sub.heat is not None and self.temperature is not None:
            t = self.temperature
            words.append(f"temperature {t if isinstance(t, str) else _num(t)}")
        if self.wiggle is not None:
            dim, amp, period = self.wiggle
            words.append(f"wiggle {dim} {_num(convert(amp, 'length', units))} "
                         f"{_num(convert(period, 'time', units))}")
        if self.shear is not None:
            words.append(f"shear {self.shear[0]} {_num(convert(self.shear[1], 'velocity', units))}")
        return " ".join(words)


@dataclass(frozen=True)
class PairLine:
    """One ``pair_coeff I J`` line: the types, the material on the line, target e, the law."""

    types: tuple[int, int]
    E: float
    nu: float
    law: DemLaw
    line: str


@dataclass(frozen=True)
class CoeffSet:
    """Every line for several particle types: plugin load, pair_style, one pair_coeff per type
    pair (I <= J), the groups and wall fixes; comments with the contact times when known."""

    units: str
    pairs: tuple[PairLine, ...]
    comments: tuple[str, ...]
    plugin_load: str
    wall_lines: tuple[str, ...]

    def lines(self) -> list[str]:
        return [self.plugin_load, "pair_style viscontact", *(p.line for p in self.pairs),
                *self.wall_lines]

    def __str__(self) -> str:
        return "\n".join([*self.comments, *self.lines()])

    def to_dict(self) -> dict[str, Any]:
        return {"units": self.units, "comments": list(self.comments),
                "pairs": [{"types": list(p.types), "E": p.E, "nu": p.nu, "law": p.law.to_dict(),
                           "line": p.line} for p in self.pairs],
                "wall_lines": list(self.wall_lines), "lines": self.lines(), "text": str(self)}


def _pair_key(key: Any, ntypes: int) -> tuple[int, int]:
    if (isinstance(key, (str, bytes)) or not isinstance(key, Sequence) or len(key) != 2
            or not all(isinstance(k, int) and not isinstance(k, bool) for k in key)):
        raise TypeError(f"a pair is two atom types (I, J), got {key!r}")
    i, j = sorted(key)
    if i < 1 or j > ntypes:
        raise ValueError(f"pair ({key[0]}, {key[1]}): atom types go from 1 to {ntypes}")
    return i, j


def _type_key(key: Any, ntypes: int) -> int:
    if not isinstance(key, int) or isinstance(key, bool):
        raise TypeError(f"a wall target e is keyed by one atom type, got {key!r}")
    if not 1 <= key <= ntypes:
        raise ValueError(f"wall e for type {key}: atom types go from 1 to {ntypes}")
    return key


def _contact_time(m_eff: float, r_eff: float, e_eff: float, v: float) -> float:
    """Undamped Hertz contact duration t_c = HERTZ_TC (m*^2 / (k^2 v))^(1/5) (SPEC section 2)."""
    k = 4.0 / 3.0 * e_eff * math.sqrt(r_eff)
    return HERTZ_TC * (m_eff ** 2 / (k ** 2 * v)) ** 0.2


def coeff_set(
    law: str, particles: Sequence[Any], *, e: float | None = None,
    e_pair: Mapping[tuple[int, int], float] | None = None,
    e_wall: Mapping[int, float] | None = None, vref: float | None = None,
    alpha: float | None = None, c0: float | None = None, beta: float | None = None,
    tau: float | None = None, p: float | None = None, end: str = "force",
    friction: float | None = None, walls: Sequence[Wall] = (), units: str = "si",
    plugin: str | os.PathLike | None = None, pair_types: str = "* *", normal: Any = None,
    tangential: Any = None, rolling: Any = None, twisting: Any = None,
    heat: float | None = None, cutoff: float | None = None,
) -> CoeffSet:
    """The lines of one law for several particle types, with exact restitution per pair.

    ``particles``: one :class:`ParticleType` (or mapping with keys E, nu, density, d) per atom
    type, in order (type 1 first).  Damping as in :func:`contact_law`: ``e`` with ``vref``
    (every pair and wall contact unless overridden), ``alpha`` with ``vref`` or ``c0``.
    ``e_pair``: {(I, J): e} and ``e_wall``: {I: e} override ``e`` for a type pair / for type
    I at every wall (e form only); without ``e`` every pair (and with walls every type) needs
    its own.  Each pair_coeff I J gets the alpha of its own e: exact at vref for any sizes and
    masses (SPEC 9).  Mixed pairs I < J are written explicitly with :func:`mixed_material`, so
    E* and G* are those of the two materials.  ``walls``: :class:`Wall` objects; one fix per
    wall on group ``all`` when every type has the same wall e, else one group ``vctypeI`` and
    one fix per type.  ``units``: the style the numbers are printed in (given in SI; lj:
    reduced units, unchanged).  ``pair_types``: with one particle type, the type pair of its
    line (default ``* *``: every type).  ``normal``, ``tangential``, ``rolling``, ``twisting``,
    ``heat``, ``cutoff``: the other sub-models, as in :func:`coeff_lines`, the same for every
    pair and wall.  ValueError / TypeError say what is wrong.
    """
    units = check_units(units)
    sub = SubModels.build(normal=normal, tangential=tangential, friction=friction,
                          rolling=rolling, twisting=twisting, heat=heat, cutoff=cutoff)
    if isinstance(particles, (str, bytes, Mapping)) or not isinstance(particles, Sequence):
        raise TypeError("particles must be a list of particle types (ParticleType or mappings)")
    types = [ParticleType.from_any(t, k + 1) for k, t in enumerate(particles)]
    n = len(types)
    if n == 0:
        raise ValueError("give at least one particle type")
    if isinstance(walls, Wall) or not isinstance(walls, Sequence):
        raise TypeError("walls must be a list of Wall objects")
    for w in walls:
        if not isinstance(w, Wall):
            raise TypeError(f"walls must be Wall objects, got {type(w).__name__}")
    if not isinstance(e_pair, (Mapping, type(None))) or not isinstance(e_wall, (Mapping, type(None))):
        raise TypeError("e_pair must map (I, J) -> e and e_wall I -> e")
    pair_e = {_pair_key(k, n): v for k, v in (e_pair or {}).items()}
    wall_e = {_type_key(k, n): v for k, v in (e_wall or {}).items()}
    if (pair_e or wall_e) and (alpha is not None or c0 is not None):
        raise ValueError("e_pair / e_wall set a target e; they do not go with alpha or c0")
    by_e = alpha is None and c0 is None
    laws: dict[float | None, DemLaw] = {}

    def law_for(target: float | None) -> DemLaw:
        if target not in laws:
            laws[target] = contact_law(law, e=target, alpha=alpha, vref=vref, c0=c0, beta=beta,
                                       tau=tau, p=p, end=end)
        return laws[target]

    def target(what: str, override: dict, key: Any) -> float | None:
        if not by_e:
            return None
        value = override.get(key, e)
        if value is None:
            raise ValueError(f"no target e for {what}: give e (all contacts) or its own")
        return value

    pairs = []
    for i in range(1, n + 1):
        for j in range(i, n + 1):
            dl = law_for(target(f"the pair {i} {j}", pair_e, (i, j)))
            a, b = types[i - 1], types[j - 1]
            E, nu = (a.E, a.nu) if i == j else mixed_material(a.E, a.nu, b.E, b.nu)
            spec = check_type_spec(pair_types) if n == 1 else f"{i} {j}"
            line = f"pair_coeff {spec} {contact_words(dl, sub, units, E=E, nu=nu)}"
            pairs.append(PairLine(types=(i, j), E=E, nu=nu, law=dl, line=line))
    wall_lines: list[str] = []
    wall_laws = {t: law_for(target(f"type {t} at the walls", wall_e, t)) for t in range(1, n + 1)} if walls else {}
    per_type = len({id(v) for v in wall_laws.values()}) > 1
    if per_type:  # static groups: insert type I atoms into group vctypeI (fix pour ID vctypeI ...)
        wall_lines += [f"group vctype{t} type {t}" for t in range(1, n + 1)]
    own = (types[0].E, types[0].nu) if n == 1 else (None, None)  # what 'same' means
    wall_mats = [_wall_pair(w.material, *own) for w in walls]
    for k, w in enumerate(walls):
        fid = WALL_FIX_ID if k == 0 else f"{WALL_FIX_ID}{k + 1}"
        groups = [(f"{fid}_t{t}", f"vctype{t}", wall_laws[t]) for t in range(1, n + 1)] if per_type \
            else [(fid, "all", wall_laws[1])]
        for fix_id, group, dl in groups:
            wall_lines.append(f"fix {fix_id} {group} viscontact/wall "
                              + contact_words(dl, sub, units, wall=w, wall_material=wall_mats[k]))
    return CoeffSet(units=units, pairs=tuple(pairs),
                    comments=_time_comments(types, wall_mats, pairs, vref, units),
                    plugin_load=_load_line(plugin), wall_lines=tuple(wall_lines))


def _time_comments(types: list[ParticleType], wall_mats: list[tuple[float, float] | None],
                   pairs: list[PairLine],
                   vref: float | None, units: str) -> tuple[str, ...]:
    """``# `` lines: the shortest Hertz contact time at vref (smallest spheres of each pair and
    at each wall) and a time step of t_c / 50, when every type has density and diameter."""
    if vref is None or any(t.density is None for t in types):
        return ()
    shortest = math.inf
    for pl in pairs:
        a, b = (types[k - 1] for k in pl.types)
        ma, mb = (t.density * math.pi / 6 * t.diameter[0] ** 3 for t in (a, b))  # type: ignore[index, operator]
        ra, rb = a.diameter[0] / 2, b.diameter[0] / 2  # type: ignore[index]
        shortest = min(shortest, _contact_time(ma * mb / (ma + mb), ra * rb / (ra + rb),
                                               pl.E / (2 * (1 - pl.nu ** 2)), vref))
    for wall in wall_mats:
        for t in types:
            inv = (1 - t.nu ** 2) / t.E + (0.0 if wall is None else (1 - wall[1] ** 2) / wall[0])
            m = t.density * math.pi / 6 * t.diameter[0] ** 3  # type: ignore[index, operator]
            shortest = min(shortest, _contact_time(m, t.diameter[0] / 2, 1 / inv, vref))  # type: ignore[index]
    tc = convert(shortest, "time", units)
    return (f"# shortest Hertz contact time t_c at vref (smallest spheres): {tc:.4g} ({units} time units)",
            f"# a time step of t_c/50 resolves every contact: timestep {tc / 50:.3g}")
