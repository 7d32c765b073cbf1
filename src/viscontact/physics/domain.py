"""The domain: the range of every public numeric parameter, checked in one place.

Every public function validates its numbers here before any solver runs; outside the domain
it raises ``ValueError`` naming the parameter, the value given and the range allowed.  The
ranges are where the solvers were measured to answer right and promptly (README, section
"Domain"; ``tests/physics/test_domain_fuzz.py`` and ``scripts/fuzz_api.py`` check them):

- ``alpha`` <= 1000 (:data:`ALPHA_MAX`): the compiled batch solver's explicit steps fail past
  alpha ~ 3e4 (LH: e = 0 with t_c = inf, NaN work, e ~ 1e95 at 1e6), and heavily damped
  zero-overlap contacts cost ~alpha steps; at 1000 every law and end answers in milliseconds
  (batch) or well under a second (with histories), e to 1e-9.
- ``e`` (a target restitution) >= 1e-6 (:data:`E_MIN`): below it the zero-overlap end meets
  the give-up time T_MAX before the contact separates, so e(alpha) jumps to 0 and no alpha
  gives the target (LH, Ts, KK, Jian); at 1e-6 and above every inversion converges.
- ``p`` <= 10 (:data:`P_MAX`): the damping x^p x' grows like x_max^p (x_max ~ 1.09), so a
  huge p makes the equation stiff (p = 681 never finished; measured fine up to 20, batch and
  histories agreeing to 2e-11 in e); the fit's power law searches [0, 3].
- ``beta`` <= 1000: beyond, the relaxation factor 1 - exp(-t/beta) ~ t/beta stays below 3e-3
  over a contact of ordinary length (t_c ~ 3 T): practically undamped (measured correct up to
  beta = 1e12).
- ``friction`` mu <= 10: a Coulomb coefficient above a few is already "never slips" (the
  Mindlin spring alone acts); 10 leaves room for any measured value.
- physical inputs (SI): wide enough for any particle from a nanometre grain to a boulder and
  narrow enough that every derived number (T, c, forces, energies) stays a finite normal
  float; T is computed as (m*/k)^(2/5) v^(-1/5), which never overflows inside these ranges.

Numbers are ``int``, ``float`` or numpy real scalars (0-d real arrays too); ``bool``, strings,
``None``, complex numbers and containers raise ``ValueError`` where a number is expected.
Array parameters (``alpha`` of :func:`viscontact.restitution`, ``e`` of
:func:`viscontact.alpha_from_e`, impact speeds) take any array-like of real numbers of any
shape; ragged nesting, strings, booleans, objects and complex entries raise ``ValueError``.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass
from typing import Any

__all__ = [
    "Range", "DOMAIN", "ALPHA_MAX", "BETA_MAX", "P_MAX", "E_MIN", "check", "check_number",
    "check_array", "range_text", "help_text", "check_choice", "check_bool", "check_int",
    "domain_table", "NP_MAX",
]

ALPHA_MAX = 1000.0
BETA_MAX = 1000.0
P_MAX = 10.0
E_MIN = 1e-6
#: most MPI ranks ``dem run`` starts, all on this machine (a cluster runs mpirun itself)
NP_MAX = 256


@dataclass(frozen=True)
class Range:
    """One parameter's domain: lo <= x <= hi (``lo_open``: lo < x), in ``unit``."""

    name: str
    lo: float
    hi: float
    unit: str
    what: str
    lo_open: bool = False

    def text(self) -> str:
        """The interval as written in messages and ``--help``: ``[0, 1000]``, ``(-1, 0.5]``."""
        return f"{'(' if self.lo_open else '['}{_g(self.lo)}, {_g(self.hi)}]"

    def contains(self, v: float) -> bool:
        above = v > self.lo if self.lo_open else v >= self.lo
        return above and v <= self.hi  # False for NaN


def _g(x: float) -> str:
    return f"{x:g}"


_RANGES = (
    Range("alpha", 0.0, ALPHA_MAX, "1", "non-dimensional damping constant"),
    Range("beta", 0.0, BETA_MAX, "1", "Jian's relaxation time / T"),
    Range("p", 0.0, P_MAX, "1", "damping exponent of the power law"),
    Range("e", E_MIN, 1.0, "1", "target coefficient of restitution"),
    Range("rtol", 1e-13, 1e-5, "1", "relative tolerance of the integrator"),
    Range("mass", 1e-24, 1e12, "kg", "mass (m*, m1, m2)"),
    Range("radius", 1e-9, 1e4, "m", "radius (R*, R1, R2)"),
    Range("modulus", 1.0, 1e13, "Pa", "Young's modulus (E*, E1, E2)"),
    Range("poisson", -1.0, 0.5, "1", "Poisson ratio", lo_open=True),
    Range("k_hertz", 1e-6, 1e17, "N/m^1.5", "Hertz stiffness (4/3) E* sqrt(R*)"),
    Range("v", 1e-6, 1e4, "m/s", "impact speed"),
    Range("drop_height", 1e-9, 1e4, "m", "drop height"),
    Range("gravity", 1e-2, 1e3, "m/s^2", "gravitational acceleration"),
    Range("c", 0.0, 1e300, "N s/m^(1+p)", "physical damping prefactor (alpha must fall in its range)"),
    Range("tau", 0.0, 1e300, "s", "relaxation time (beta = tau / T must fall in its range)"),
    Range("weight", 0.0, 1e6, "1", "fit weight"),
    Range("margin", 0.0, 10.0, "t_c", "samples kept around the contact"),
    Range("friction", 0.0, 10.0, "1", "Coulomb friction coefficient mu (DEM)"),
)
#: parameter name -> its range (README section "Domain")
DOMAIN: dict[str, Range] = {r.name: r for r in _RANGES}


def _describe(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def check_number(label: str, value: Any) -> float:
    """``value`` as a float if it is a real number (not bool, str, None, complex, container)."""
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        raise ValueError(f"{label} must be a number, got the boolean {value!r}")
    if isinstance(value, numbers.Real):
        try:
            return float(value)
        except (OverflowError, ValueError, TypeError):
            raise ValueError(f"{label} must be a finite number, got {_describe(value)}") from None
    ndim = getattr(value, "ndim", None)
    kind = getattr(getattr(value, "dtype", None), "kind", None)
    if ndim == 0 and kind in ("i", "u", "f"):
        return float(value)
    raise ValueError(f"{label} must be a number, got {_describe(value)} ({type(value).__name__})")


def check(name: str, value: Any, *, label: str | None = None) -> float:
    """``value`` as a float inside the domain of parameter ``name``, else ValueError naming
    ``label`` (default ``name``), the value and the allowed range."""
    rng = DOMAIN[name]
    label = label or name
    v = check_number(label, value)
    if not rng.contains(v):
        unit = "" if rng.unit in ("1", "") else f" {rng.unit}"
        raise ValueError(f"{label} must be in {rng.text()}{unit}, got {_describe(value)}")
    return v


def check_array(name: str, value: Any, *, label: str | None = None):
    """``value`` as a float numpy array (any shape) whose every element is inside the domain of
    ``name``; ValueError names the first bad element."""
    import numpy as np

    rng = DOMAIN[name]
    label = label or name
    if isinstance(value, (str, bytes, dict, set, frozenset)) or value is None:
        raise ValueError(f"{label} must be a number or an array of numbers, got "
                         f"{_describe(value)} ({type(value).__name__})")
    try:
        raw = np.asarray(value)
    except (ValueError, TypeError, OverflowError):
        raise ValueError(f"{label} must be a number or a rectangular array of numbers, got "
                         f"{_describe(value)}") from None
    if raw.dtype.kind not in "iuf":
        if raw.dtype.kind == "O":  # e.g. a list of Python ints too large for int64
            flat = [check(name, v, label=label) for v in raw.ravel()]
            return np.array(flat, dtype=float).reshape(raw.shape)
        raise ValueError(f"{label} must be a number or an array of real numbers, got an array "
                         f"of {raw.dtype} ({_describe(value)})")
    a = raw.astype(float, copy=False)  # read only below: no copy of a float array
    if a.size == 0:
        return a
    lo_ok = (a.min() > rng.lo) if rng.lo_open else (a.min() >= rng.lo)
    if not (lo_ok and a.max() <= rng.hi):  # NaN fails too; no temporaries
        ok = (a > rng.lo if rng.lo_open else a >= rng.lo) & (a <= rng.hi)
        first = raw.ravel()[int(np.argmin(ok.ravel()))]
        check(name, first.item(), label=label)  # raises with the usual message
    return a


def check_choice(label: str, value: Any, choices: tuple[str, ...]) -> str:
    """``value`` if it is one of the strings ``choices``, else ValueError listing them."""
    if isinstance(value, str) and value in choices:
        return value
    raise ValueError(f"{label} must be one of {', '.join(choices)}; got {_describe(value)}")


def check_bool(label: str, value: Any) -> bool:
    """``value`` if it is a bool (or numpy bool), else ValueError."""
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        return bool(value)
    raise ValueError(f"{label} must be True or False, got {_describe(value)}")


def check_int(label: str, value: Any, lo: int, hi: int) -> int:
    """``value`` as an int in [lo, hi] (not bool, not a float), else ValueError."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{label} must be a whole number in [{lo}, {hi}], got {_describe(value)}")
    v = int(value)
    if not lo <= v <= hi:
        raise ValueError(f"{label} must be in [{lo}, {hi}], got {v}")
    return v


def range_text(name: str) -> str:
    """The allowed interval of ``name`` with its unit, e.g. ``[1e-06, 10000] m/s``."""
    rng = DOMAIN[name]
    return rng.text() + ("" if rng.unit in ("1", "") else f" {rng.unit}")


def help_text(name: str, what: str | None = None) -> str:
    """A ``--help`` string for an option taking parameter ``name``: what it is and its range."""
    rng = DOMAIN[name]
    return f"{what or rng.what}, in {range_text(name)}"


def domain_table() -> str:
    """The domain as a Markdown table (the README's section "Domain" is this table)."""
    rows = ["| parameter | allowed | unit | what |", "|---|---|---|---|"]
    for r in _RANGES:
        rows.append(f"| `{r.name}` | {r.text()} | {r.unit} | {r.what} |")
    return "\n".join(rows)
