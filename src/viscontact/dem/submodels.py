"""Everything of a DEM contact but the damping law, as the plugin's ``pair_coeff`` and wall fix
take it: the normal model (:class:`Normal`: Hertz, DMT or JKR), the tangential model
(:class:`Tangential`), rolling and twisting resistance (:class:`Rolling`, :class:`Twisting`),
heat conduction and the cutoff, bundled in :class:`SubModels`.  Each class checks its numbers
once and writes its own keywords; :func:`viscontact.dem.coeff.contact_words` puts them together.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from ..physics import domain
from .law import DemLaw
from .native import native_hint
from .units import _num, convert

__all__ = ["Normal", "Tangential", "Rolling", "Twisting", "SubModels", "NORMAL_MODELS",
           "TANGENTIAL_MODELS", "SPRING_MODELS"]

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


def _set_sds(obj: Any, what: str, fields: tuple[str, str, str], names: tuple[str, str, str]) -> None:
    """Check and store, on the frozen dataclass ``obj``, the three numbers of ``WHAT sds K
    GAMMA MU`` held in ``fields``: the spring K > 0 (the slip update divides by it), the
    dashpot and the limit >= 0; the messages name them ``WHAT sds NAME``."""
    k = _nonneg(f"{what} sds {names[0]}", getattr(obj, fields[0]))
    if k == 0:
        raise ValueError(f"{what} sds {names[0]} must be > 0 (the slip update divides by it)")
    object.__setattr__(obj, fields[0], k)
    for field, name in zip(fields[1:], names[1:]):
        object.__setattr__(obj, field, _nonneg(f"{what} sds {name}", getattr(obj, field)))


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
        try:
            domain.check_choice("normal model", self.model, NORMAL_MODELS)
        except ValueError as err:
            raise ValueError(f"{err}{native_hint(self.model)}") from None
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
        _set_sds(self, "rolling", ("kr", "gammar", "mur"), ("KR", "GAMMAR", "MUR"))

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
        _set_sds(self, "twisting", ("kt", "gammat", "mut"), ("KT", "GAMMAT", "MUT"))

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
