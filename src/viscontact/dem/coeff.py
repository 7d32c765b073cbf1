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
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

from ..physics import domain
from ..physics.pair import (
    check_poisson, effective_mass, effective_modulus, effective_radius, hertz_limit, hertz_stiffness,
)
from ._text import check_type_spec, quote_path
from .law import DemLaw, contact_law
from .materials import ParticleType, Wall, _wall_pair, mixed_material
from .submodels import (
    NORMAL_MODELS, TANGENTIAL_MODELS, Normal, Rolling, SubModels, Tangential, Twisting,
)
from .units import UNIT_STYLES, _num, check_units, convert

__all__ = ["DemLaw", "CoeffLines", "contact_law", "coeff_lines", "WALL_FIX_ID", "UNIT_STYLES",
           "convert", "check_units", "mixed_material", "ParticleType", "Wall", "PairLine", "CoeffSet",
           "coeff_set", "Normal", "Tangential", "Rolling", "Twisting", "SubModels", "contact_words",
           "NORMAL_MODELS", "TANGENTIAL_MODELS"]

#: the id of the wall fix :func:`coeff_lines` writes
WALL_FIX_ID = "vcwall"


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


def _material_words(pair: tuple[float, float] | None, units: str) -> str:
    if pair is None:
        return "wall_material rigid"
    return f"wall_material {_num(convert(pair[0], 'pressure', units))} {_num(pair[1])}"


def contact_words(law: DemLaw, sub: SubModels, units: str, *, E: float | None = None,
                  nu: float | None = None, wall: Wall | None = None,
                  wall_material: tuple[float, float] | None = None,
                  particle: tuple[float, float] | None = None) -> str:
    """The one writer of contact keywords: a pair_coeff line's after the types
    (``NORMAL E NU [W] damping ... tangential ...``) or, with ``wall``, a wall fix's after
    ``viscontact/wall`` (``GEOMETRY wall_material ... [normal dmt|jkr W] damping ...
    [temperature T] [wiggle|shear ...] [particle E NU]``); ``wall_material`` None is rigid;
    ``particle`` (E [Pa], nu): the particles' material on the wall line (None: the fix takes
    it from the pair_coeff lines)."""
    if wall is None:
        return f"{sub.normal.pair_words(E, nu, units)} {sub.tail(law, units, pair=True)}"
    if sub.heat is not None and wall.temperature is None:
        raise ValueError("a wall with heat conduction needs its temperature (Wall(..., "
                         "temperature=T) or --wall-temperature T)")
    words = [wall.geometry(units), _material_words(wall_material, units), sub.normal.wall_words(units),
             sub.tail(law, units, pair=False), wall.motion_words(sub, units)]
    if particle is not None:
        words.append(f"particle {_num(convert(particle[0], 'pressure', units))} {_num(particle[1])}")
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
    """Undamped Hertz contact duration t_c = 3.2180654597 T at speed v, k_Hertz and T as
    :mod:`viscontact.physics.pair` has them (:func:`hertz_limit`)."""
    return hertz_limit(m_eff, hertz_stiffness(e_eff, r_eff), v)[0]


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
    masses (the damping is computed per contact from its own m* and k_Hertz, :mod:`viscontact.dem.law`).  Mixed pairs I < J are written explicitly with :func:`mixed_material`, so
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
        shortest = min(shortest, _contact_time(effective_mass(ma, mb), effective_radius(ra, rb),
                                               effective_modulus(pl.E, pl.nu, pl.E, pl.nu), vref))
    for wall in wall_mats:
        for t in types:
            e_eff = effective_modulus(t.E, t.nu, *(wall or (None, None)))
            m = t.density * math.pi / 6 * t.diameter[0] ** 3  # type: ignore[index, operator]
            shortest = min(shortest, _contact_time(m, t.diameter[0] / 2, e_eff, vref))  # type: ignore[index]
    tc = convert(shortest, "time", units)
    return (f"# shortest Hertz contact time t_c at vref (smallest spheres): {tc:.4g} ({units} time units)",
            f"# a time step of t_c/50 resolves every contact: timestep {tc / 50:.3g}")
