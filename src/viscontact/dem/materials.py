"""The materials of a DEM input: one atom type's (:class:`ParticleType`), the (E, nu) that an
explicit mixed ``pair_coeff I J`` line needs (:func:`mixed_material`), and the walls of ``fix
viscontact/wall`` (:class:`Wall`: geometry, material, motion, temperature).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..physics import domain
from ..physics.pair import check_poisson, compliance, shear_compliance
from .units import _num, convert

if TYPE_CHECKING:
    from .submodels import SubModels

__all__ = ["ParticleType", "Wall", "mixed_material"]


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

def mixed_material(E1: float, nu1: float, E2: float, nu2: float) -> tuple[float, float]:
    """The (E, nu) whose explicit ``pair_coeff I J hertz/material E NU`` line reproduces the
    contact of two materials exactly.

    LAMMPS reads an explicit I J line as one material on both sides (as native ``pair granular``
    does: the LAMMPS granular docs, ``hertz/material``):
    E*_line = E / (2 (1 - nu^2)), G*_line = E / (4 (2 - nu) (1 + nu)).  The contact of the two
    materials has 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2 and 1/G* = (2-nu1)/G1 + (2-nu2)/G2,
    G = E / (2 (1 + nu)).  With r = G*/E* = (1 - nu) / (2 (2 - nu)) on the line's side,
    nu = (4 r - 1) / (2 r - 1) and E = 2 (1 - nu^2) E*.  r of the pair is a weighted harmonic
    mean of r1, r2 (each in [1/6, 1/3) for nu in (-1, 0.5]), so nu lies in (-1, 0.5] too.
    """
    inv_e = compliance(E1, nu1, E2, nu2)
    inv_g = shear_compliance(E1, nu1, E2, nu2)
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
    (LO, HI) (a coordinate [m] or None for NULL), zcylinder with (R,) [m], ``region`` with
    (REGION-ID,) (any LAMMPS region, moving or rotating; several contacts per sphere), or
    ``mesh`` with (FILE,) or (FILE, "mesh keywords") (an STL triangle mesh, in the file's own
    lengths: ``scale`` converts; ``move``/``rotate`` move it; docs/fix_viscontact_mesh.md);
    ``material`` ``"rigid"``, ``"same"`` or (E [Pa], nu).  ``wiggle`` (DIM, A [m], PERIOD [s])
    or ``shear`` (DIM, V [m/s]) move a plane or zcylinder (not a region: move the region);
    ``temperature`` T [K] or ``"v_name"`` (an equal-style variable) is needed with heat."""

    style: str
    args: tuple[Any, ...]
    material: Any = "rigid"
    wiggle: tuple[str, float, float] | None = None
    shear: tuple[str, float] | None = None
    temperature: float | str | None = None

    STYLES = ("xplane", "yplane", "zplane", "zcylinder", "region", "mesh")

    def __post_init__(self) -> None:
        if not isinstance(self.style, str) or self.style not in self.STYLES:
            raise ValueError(f"wall style must be one of {', '.join(self.STYLES)}, got {self.style!r}")
        args = tuple(self.args) if isinstance(self.args, (tuple, list)) else (self.args,)
        if self.style == "mesh":
            if not 1 <= len(args) <= 2 or not all(isinstance(a, str) for a in args) \
                    or not re.fullmatch(r"\S+", args[0]):
                raise ValueError("mesh wall needs (FILE,) or (FILE, 'mesh keywords'): an STL "
                                 "file name without spaces and optional keywords such as "
                                 "'scale 0.001 rotate v_th 0 0 0 0 0 1'")
        elif self.style == "region":
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
        if self.style in ("region", "mesh"):
            raise ValueError(f"{what} is for plane and zcylinder walls; move a {self.style} wall "
                             "with its own move/rotate keywords")
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
        if self.style == "mesh":    # the file's lengths: its scale keyword converts
            return " ".join(["mesh", *self.args])
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
