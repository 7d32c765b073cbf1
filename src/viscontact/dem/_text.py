"""Text rules of a LAMMPS input line that the DEM layer writes: quoting paths, type specs.

What the pinned ``lmp`` does with a path in a line (tests/dem/python/test_driver.py runs each case):
(1) non-ASCII characters are replaced by ASCII look-alikes or mangled (``é`` cannot be
written; ``”`` becomes ``"``); (2) ``#`` starts a comment unless inside single, double or
triple quotes; (3) ``$`` is substituted outside quotes, and ``include`` / ``print``
substitute their argument once more even inside quotes; a ``'`` or ``"`` inside a path
unbalances the line whatever quotes enclose it.  So a path can be written literally only if it
is printable ASCII without ``$``, ``'`` and ``"``; it is then put in single quotes (spaces, ``#``
and ``;`` kept).  ``plugin load ${NAME}`` (unquoted; a quoted reference is not substituted)
with ``lmp -var NAME PATH`` reads any path without whitespace.  :mod:`viscontact.dem.run`
needs neither: it links the plugin and the input into a temporary directory of its own with a
plain name and writes those paths.
"""

from __future__ import annotations

import os
import re

__all__ = ["quote_path", "literal_path_ok", "check_type_spec", "INT_MAX"]

#: LAMMPS reads atom types into a C int
INT_MAX = 2**31 - 1
_FORBIDDEN = frozenset("$'\"")


def literal_path_ok(path: str | os.PathLike) -> bool:
    """True if LAMMPS reads ``path`` back unchanged from a quoted literal in an input line."""
    s = os.fspath(path)
    return isinstance(s, str) and bool(s) and all(" " <= c <= "~" and c not in _FORBIDDEN for c in s)


def quote_path(path: str | os.PathLike, what: str = "path") -> str:
    """``path`` in single quotes for a LAMMPS line; ValueError (one line, with the way out) when
    no literal can hold it (non-ASCII, ``$``, a quote character, a control character)."""
    s = os.fspath(path)
    if not literal_path_ok(s):
        raise ValueError(
            f"the {what} {s!r} has a character a LAMMPS input line cannot hold (non-ASCII, '$', a "
            f"quote or a control character); move it to a plain directory (for the plugin: set "
            f"VISCONTACT_CACHE_DIR), or pass it as lmp -var NAME PATH and write ${{NAME}} unquoted")
    return f"'{s}'"


# LAMMPS's utils::bounds: "*", "N", "*N", "N*", "M*N", ASCII digits only, 1 <= M <= N
_BOUND = re.compile(r"^(?:\*|([0-9]+)|\*([0-9]+)|([0-9]+)\*|([0-9]+)\*([0-9]+))$")


def _bound(token: str, ntypes: int | None) -> bool:
    m = _BOUND.match(token)
    if m is None:
        return False
    numbers = [int(g) for g in m.groups() if g is not None]
    if any(n < 1 or n > INT_MAX or (ntypes is not None and n > ntypes) for n in numbers):
        return False
    return len(numbers) < 2 or numbers[0] <= numbers[1]


def check_type_spec(types: object, ntypes: int | None = None) -> str:
    """A ``pair_coeff`` type pair as LAMMPS accepts it (``* *``, ``1 2``, ``1*3 *``, ``2*``),
    normalised to single spaces; TypeError for a non-string, ValueError otherwise."""
    if not isinstance(types, str):
        raise TypeError(f"types must be a string such as '* *' or '1 2', got {type(types).__name__}")
    parts = types.split()
    if len(parts) != 2 or not all(_bound(t, ntypes) for t in parts):
        limit = f"1..{ntypes}" if ntypes is not None else f"1..{INT_MAX}"
        raise ValueError(f"types must be two atom types or ranges ('* *', '1 2', '1*3 *', '2*'; "
                         f"ASCII digits, each type in {limit}, M <= N in M*N); got {types!r}")
    return " ".join(parts)
