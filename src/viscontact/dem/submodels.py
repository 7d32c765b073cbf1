"""Everything of a DEM contact but the damping law, as the plugin's ``pair_coeff`` and wall fix
take it, one class per sub-model as the plugin has one C++ type per sub-model
(``dem/lammps/viscontact_<kind>.h``): each knows its keyword, its numbers and their domains,
and writes its words.  The normal models :class:`NormalHertz`, :class:`NormalDMT`,
:class:`NormalJKR`; the tangential models :class:`TangentialNone`, :class:`LinearNoHistory`,
:class:`LinearHistory`, :class:`Mindlin`, :class:`MindlinRescale`, :class:`MindlinForce`,
:class:`MindlinRescaleForce`; rolling :class:`RollingSDS`; twisting :class:`TwistingMarshall`,
:class:`TwistingSDS`; heat :class:`HeatArea`.  Each kind's table (``NORMAL``, ``TANGENTIAL``,
``TWISTING``) registers its models by keyword.

The values users build are :class:`Normal`, :class:`Tangential`, :class:`Rolling`,
:class:`Twisting` (a model name and its numbers) and :class:`SubModels` (all of them, heat and
the cutoff); they check and write themselves through their model's class;
:func:`viscontact.dem.coeff.contact_words` puts them together.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

from ..physics import domain
from .law import DemLaw
from .native import native_hint
from .units import _num, convert

__all__ = ["Normal", "Tangential", "Rolling", "Twisting", "SubModels", "NORMAL_MODELS",
           "TANGENTIAL_MODELS", "SPRING_MODELS", "NORMAL", "TANGENTIAL", "TWISTING",
           "NormalHertz", "NormalDMT", "NormalJKR", "TangentialNone", "LinearNoHistory",
           "LinearHistory", "Mindlin", "MindlinRescale", "MindlinForce", "MindlinRescaleForce",
           "RollingSDS", "TwistingMarshall", "TwistingSDS", "HeatArea"]


def _nonneg(label: str, value: Any) -> float:
    """A finite number >= 0, else ValueError naming ``label``."""
    v = domain.check_number(label, value)
    if not (math.isfinite(v) and v >= 0):
        raise ValueError(f"{label} must be a finite number >= 0, got {value!r}")
    return v


def _set(obj: Any, field: str, value: Any) -> None:
    object.__setattr__(obj, field, value)


# ---------------------------------------------------------------------------- normal models


class NormalHertz:
    """``hertz/material E NU`` (pair) / ``normal hertz`` (wall, the default): Hertz, no
    cohesion (Johnson, Contact Mechanics, 1985, ch. 4)."""

    keyword: ClassVar[str] = "hertz"
    pair_keyword: ClassVar[str] = "hertz/material"
    cohesive: ClassVar[bool] = False

    @classmethod
    def check(cls, n: "Normal") -> None:
        if n.W is not None:
            raise ValueError("normal hertz takes no surface energy W (dmt W or jkr W do)")


class NormalDMT:
    """``dmt E NU W``: Hertz minus the pull-off force 4 pi W R* (Derjaguin, Muller & Toporov,
    J. Colloid Interface Sci. 53 (1975) 314); W [J/m^2] >= 0."""

    keyword: ClassVar[str] = "dmt"
    pair_keyword: ClassVar[str] = "dmt"
    cohesive: ClassVar[bool] = True

    @classmethod
    def check(cls, n: "Normal") -> None:
        if n.W is None:
            raise ValueError(f"normal {cls.keyword} needs the surface energy W (J/m^2, >= 0)")
        _set(n, "W", _nonneg(f"normal {cls.keyword} W", n.W))


class NormalJKR(NormalDMT):
    """``jkr E NU W``: the JKR branch, pull-off force 3 pi W R* (Johnson, Kendall & Roberts,
    Proc. R. Soc. A 324 (1971) 301); W [J/m^2] >= 0."""

    keyword: ClassVar[str] = "jkr"
    pair_keyword: ClassVar[str] = "jkr"


#: the normal models by keyword (the registration)
NORMAL: dict[str, Any] = {c.keyword: c for c in (NormalHertz, NormalDMT, NormalJKR)}
NORMAL_MODELS = tuple(NORMAL)


# ------------------------------------------------------------------------ tangential models


class TangentialNone:
    """``tangential none``: no tangential force."""

    keyword: ClassVar[str] = "none"
    usage: ClassVar[str] = ""
    spring: ClassVar[bool] = False
    nnumbers: ClassVar[int] = 0

    @classmethod
    def check(cls, t: "Tangential") -> None:
        if t.kt is not None or t.xgamma or t.mu:
            raise ValueError("tangential none takes no KT, XGAMMA or MU")

    @classmethod
    def from_numbers(cls, nums: list[Any]) -> "Tangential":
        return Tangential(cls.keyword)

    @classmethod
    def words(cls, t: "Tangential", units: str) -> str:
        return "tangential none"


class LinearNoHistory(TangentialNone):
    """``tangential linear_nohistory XGAMMA MU``: a dashpot eta_t = XGAMMA eta_n capped at MU
    F0, no spring."""

    keyword: ClassVar[str] = "linear_nohistory"
    usage: ClassVar[str] = " XGAMMA MU"
    nnumbers: ClassVar[int] = 2

    @classmethod
    def check(cls, t: "Tangential") -> None:
        if t.kt is not None:
            raise ValueError("tangential linear_nohistory takes XGAMMA MU, no spring KT")

    @classmethod
    def from_numbers(cls, nums: list[Any]) -> "Tangential":
        return Tangential(cls.keyword, xgamma=nums[0], mu=nums[1])

    @classmethod
    def words(cls, t: "Tangential", units: str) -> str:
        return " ".join(["tangential", cls.keyword, _num(t.xgamma), _num(t.mu)])


class LinearHistory(LinearNoHistory):
    """``tangential linear_history KT XGAMMA MU``: a spring KT [N/m] (Cundall & Strack 1979)
    with the dashpot, capped at MU F0."""

    keyword: ClassVar[str] = "linear_history"
    usage: ClassVar[str] = " KT XGAMMA MU"
    spring: ClassVar[bool] = True
    nnumbers: ClassVar[int] = 3
    #: KT's unit dimension (units.convert)
    kt_dims: ClassVar[str] = "stiffness"

    @classmethod
    def check(cls, t: "Tangential") -> None:
        if t.kt is None:
            raise ValueError("tangential linear_history needs the spring KT (N/m, >= 0)")
        _set(t, "kt", _nonneg(f"tangential {cls.keyword} KT", t.kt))

    @classmethod
    def from_numbers(cls, nums: list[Any]) -> "Tangential":
        return Tangential(cls.keyword, kt=nums[0], xgamma=nums[1], mu=nums[2])

    @classmethod
    def words(cls, t: "Tangential", units: str) -> str:
        kt = "NULL" if t.kt is None else _num(convert(t.kt, cls.kt_dims, units))
        return " ".join(["tangential", cls.keyword, kt, _num(t.xgamma), _num(t.mu)])


class MindlinRescale(LinearHistory):
    """``tangential mindlin_rescale KT|NULL XGAMMA MU``: Mindlin's spring k_t = KT a
    [N/m^2] (NULL: 8 G* a; Mindlin 1949), the displacement scaled down with a shrinking
    contact."""

    keyword: ClassVar[str] = "mindlin_rescale"
    usage: ClassVar[str] = " KT|NULL XGAMMA MU"
    kt_dims: ClassVar[str] = "stiffness_area"

    @classmethod
    def check(cls, t: "Tangential") -> None:
        if t.kt is not None:
            _set(t, "kt", _nonneg(f"tangential {cls.keyword} KT", t.kt))


class MindlinForce(MindlinRescale):
    """``tangential mindlin/force KT|NULL XGAMMA MU``: Mindlin's spring, the history kept as
    the elastic force."""

    keyword: ClassVar[str] = "mindlin/force"


class MindlinRescaleForce(MindlinRescale):
    """``tangential mindlin_rescale/force KT|NULL XGAMMA MU``: both of the above."""

    keyword: ClassVar[str] = "mindlin_rescale/force"


class Mindlin(MindlinRescale):
    """``tangential mindlin KT|NULL XGAMMA MU``, or the short form ``mindlin MU`` (= ``mindlin
    NULL 0 MU``)."""

    keyword: ClassVar[str] = "mindlin"

    @classmethod
    def from_numbers(cls, nums: list[Any]) -> "Tangential":
        if len(nums) == 1:
            return Tangential(cls.keyword, mu=nums[0])
        return super().from_numbers(nums)

    @classmethod
    def words(cls, t: "Tangential", units: str) -> str:
        if t.kt is None and t.xgamma == 0:
            return f"tangential mindlin {_num(t.mu)}"
        return super().words(t, units)


#: the tangential models by keyword (the registration)
TANGENTIAL: dict[str, Any] = {c.keyword: c for c in (
    TangentialNone, LinearNoHistory, LinearHistory, Mindlin, MindlinRescale, MindlinForce,
    MindlinRescaleForce)}
TANGENTIAL_MODELS = tuple(TANGENTIAL)
#: tangential models with an elastic spring (the ones twisting marshall needs)
SPRING_MODELS = tuple(k for k, c in TANGENTIAL.items() if c.spring)


# ----------------------------------------------------------------- rolling, twisting, heat


def _check_sds(obj: Any, what: str, fields: tuple[str, str, str], names: tuple[str, str, str]) -> None:
    """Check and store, on the frozen dataclass ``obj``, the three numbers of ``WHAT sds K
    GAMMA MU`` held in ``fields``: the spring K > 0 (the slip update divides by it), the
    dashpot and the limit >= 0; the messages name them ``WHAT sds NAME``."""
    k = _nonneg(f"{what} sds {names[0]}", getattr(obj, fields[0]))
    if k == 0:
        raise ValueError(f"{what} sds {names[0]} must be > 0 (the slip update divides by it)")
    _set(obj, fields[0], k)
    for field, name in zip(fields[1:], names[1:]):
        _set(obj, field, _nonneg(f"{what} sds {name}", getattr(obj, field)))


class RollingSDS:
    """``rolling sds KR GAMMAR MUR`` (spring-dashpot-slider, Luding 2008; Wang et al. 2015):
    KR [N/m] > 0, GAMMAR [N s/m], MUR >= 0."""

    keyword: ClassVar[str] = "sds"
    names: ClassVar[tuple[str, str, str]] = ("KR", "GAMMAR", "MUR")
    fields: ClassVar[tuple[str, str, str]] = ("kr", "gammar", "mur")
    dims: ClassVar[tuple[str, str, str | None]] = ("stiffness", "damping", None)

    @classmethod
    def check(cls, r: Any) -> None:
        _check_sds(r, "rolling", cls.fields, cls.names)

    @classmethod
    def words(cls, r: Any, units: str, kind: str = "rolling") -> str:
        nums = [getattr(r, f) for f in cls.fields]
        return " ".join([kind, cls.keyword] + [_num(x if d is None else convert(x, d, units))
                                                for x, d in zip(nums, cls.dims)])


class TwistingMarshall:
    """``twisting marshall`` (Marshall, J. Comput. Phys. 228 (2009) 1541): stiffness, damping
    and limit from the tangential spring; no numbers."""

    keyword: ClassVar[str] = "marshall"

    @classmethod
    def check(cls, t: "Twisting") -> None:
        if any(x is not None for x in (t.kt, t.gammat, t.mut)):
            raise ValueError("twisting marshall takes no numbers (they come from the tangential model)")

    @classmethod
    def words(cls, t: "Twisting", units: str) -> str:
        return "twisting marshall"


class TwistingSDS(RollingSDS):
    """``twisting sds KT GAMMAT MUT``: KT [N m/rad] > 0, GAMMAT [N m s], MUT a LENGTH [m] (the
    torque limit is MUT F0, as native's code)."""

    names: ClassVar[tuple[str, str, str]] = ("KT", "GAMMAT", "MUT")
    fields: ClassVar[tuple[str, str, str]] = ("kt", "gammat", "mut")
    dims: ClassVar[tuple[str, str, str | None]] = ("torque_stiffness", "torque_damping", "length")

    @classmethod
    def check(cls, t: Any) -> None:
        if any(getattr(t, f) is None for f in cls.fields):
            raise ValueError("twisting sds needs KT GAMMAT MUT")
        _check_sds(t, "twisting", cls.fields, cls.names)

    @classmethod
    def words(cls, t: Any, units: str, kind: str = "twisting") -> str:
        return super().words(t, units, kind)


#: the twisting models by keyword (the registration)
TWISTING: dict[str, Any] = {c.keyword: c for c in (TwistingMarshall, TwistingSDS)}


class HeatArea:
    """``heat area K``: heat flow Q = K pi a^2 (T_j - T_i), K [W/(m^2 K)] >= 0."""

    keyword: ClassVar[str] = "area"

    @staticmethod
    def check(k: Any) -> float:
        return _nonneg("heat area K", k)

    @staticmethod
    def words(k: float, units: str) -> str:
        return f"heat area {_num(convert(k, 'conductance', units))}"


# ----------------------------------------------------------------- what users build


@dataclass(frozen=True)
class Normal:
    """The normal model: ``hertz`` (Hertz, no cohesion), ``dmt`` or ``jkr`` with the surface
    energy ``W`` [J/m^2] (native's gamma; the work of adhesion is 2W).  Pull-off forces:
    DMT 4 pi W R*, JKR 3 pi W R* (:class:`NormalDMT`, :class:`NormalJKR`).  The damping law's
    k_Hertz ignores adhesion, so a calibrated e is that of the Hertz part."""

    model: str = "hertz"
    W: float | None = None

    def __post_init__(self) -> None:
        try:
            domain.check_choice("normal model", self.model, NORMAL_MODELS)
        except ValueError as err:
            raise ValueError(f"{err}{native_hint(self.model)}") from None
        NORMAL[self.model].check(self)

    @property
    def cohesive(self) -> bool:
        return NORMAL[self.model].cohesive

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
        words = [NORMAL[self.model].pair_keyword, _num(convert(E, "pressure", units)), _num(nu)]
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
    """The tangential model: ``model`` in :data:`TANGENTIAL_MODELS` (one class each in
    :data:`TANGENTIAL`, which checks and writes it); ``kt``: the spring, N/m for
    ``linear_history`` (required), N/m^2 for the mindlin family (k_t = kt a; None = NULL:
    k_t = 8 G* a); ``xgamma``: tangential damping eta_t = xgamma eta_n (the law's normal
    prefactor); ``mu``: Coulomb coefficient.  ``none`` has no force.  ``mindlin`` with kt None
    and xgamma 0 is written in the short form ``tangential mindlin MU``.
    """

    model: str = "none"
    kt: float | None = None
    xgamma: float = 0.0
    mu: float = 0.0

    def __post_init__(self) -> None:
        domain.check_choice("tangential model", self.model, TANGENTIAL_MODELS)
        m = self.model
        _set(self, "xgamma", _nonneg(f"tangential {m} XGAMMA", self.xgamma))
        _set(self, "mu", domain.check("friction", self.mu, label=f"tangential {m} MU"))
        TANGENTIAL[m].check(self)

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
        sub = TANGENTIAL[model]
        nums = [None if (isinstance(x, str) and x.upper() == "NULL") else x for x in nums]
        if len(nums) != sub.nnumbers and not (sub is Mindlin and len(nums) == 1):
            raise ValueError(f"tangential {model} takes{sub.usage or ' no numbers'}"
                             + (" (or the short form: mindlin MU)" if sub is Mindlin else "")
                             + f"; got {len(nums)} number(s)")
        return sub.from_numbers(nums)

    @property
    def spring(self) -> bool:
        return TANGENTIAL[self.model].spring

    def words(self, units: str) -> str:
        return TANGENTIAL[self.model].words(self, units)


@dataclass(frozen=True)
class Rolling:
    """Rolling resistance ``sds`` (:class:`RollingSDS`): spring ``kr`` [N/m] (> 0), dashpot
    ``gammar`` [N s/m], friction ``mur``; the resisting torque is at most mur R* F0."""

    kr: float
    gammar: float
    mur: float

    def __post_init__(self) -> None:
        RollingSDS.check(self)

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
        return RollingSDS.words(self, units)


@dataclass(frozen=True)
class Twisting:
    """Twisting resistance: ``marshall`` (:class:`TwistingMarshall`) or ``sds``
    (:class:`TwistingSDS`) with ``kt`` [N m/rad] (> 0), ``gammat`` [N m s] and ``mut``, a
    LENGTH [m]."""

    model: str = "marshall"
    kt: float | None = None
    gammat: float | None = None
    mut: float | None = None

    def __post_init__(self) -> None:
        domain.check_choice("twisting model", self.model, tuple(TWISTING))
        TWISTING[self.model].check(self)

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
        return TWISTING[self.model].words(self, units)


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
            _set(self, "heat", HeatArea.check(self.heat))
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
            words.append(HeatArea.words(self.heat, units))
        if pair and self.cutoff is not None:
            words.append(f"cutoff {_num(convert(self.cutoff, 'length', units))}")
        return " ".join(words)
