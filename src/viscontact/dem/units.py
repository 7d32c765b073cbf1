"""LAMMPS unit styles for the plugin's input lines: the values a user gives in SI, printed in
the style the input uses (``si``, ``cgs``, ``micro``, ``nano``; ``lj`` is reduced units and is
left unchanged), and the one number format, ``repr`` (the shortest string that reads back as the
same double).  Knows no contact physics; the other ``dem`` modules call it.
"""

from __future__ import annotations

__all__ = ["UNIT_STYLES", "check_units", "convert"]


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
    # the sub-models' coefficients
    "surface_energy": (1, 0, -2),       # W [J/m^2 = N/m]
    "stiffness": (1, 0, -2),            # linear_history KT, rolling KR [N/m]
    "stiffness_area": (1, -1, -2),      # mindlin KT [N/m^2] (times the contact radius a)
    "damping": (1, 0, -1),              # rolling GAMMAR [N s/m]
    "torque_stiffness": (1, 2, -2),     # twisting sds KT [N m/rad]
    "torque_damping": (1, 2, -1),       # twisting sds GAMMAT [N m s]
    "conductance": (1, 0, -3),          # heat area K [W/(m^2 K)]
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
