"""Hints for words of native LAMMPS ``pair_style granular`` typed where viscontact expects its
own: ``tsuji`` as a law names ``Ts`` with the alpha that equals native's, ``hooke`` as a normal
model says that viscontact's spring is Hertz, and so on (docs/native.md, "Keyword by keyword").

The table is the plugin's own (``lammps/viscontact_native_hints.h``, which appends the same
hints to its ERROR lines): it is read from that header once, so the C++ and the Python messages
cannot drift apart.
"""

from __future__ import annotations

import functools
import re
from pathlib import Path

__all__ = ["native_hint", "native_hints"]

_HEADER = Path(__file__).parent / "lammps" / "viscontact_native_hints.h"
#: one entry of the header's table: {"word", "text" "text" ...},
_ENTRY = re.compile(r'\{\s*"([^"]+)"\s*,\s*((?:"(?:[^"\\]|\\.)*"\s*)+)\}', re.S)


@functools.cache
def native_hints() -> dict[str, str]:
    """Native word -> what to write instead, from the plugin's header."""
    table = _HEADER.read_text(encoding="utf-8").split("HINTS[] = {", 1)[1].split("};", 1)[0]
    return {word: "".join(re.findall(r'"((?:[^"\\]|\\.)*)"', text))
            for word, text in _ENTRY.findall(table)}


def native_hint(word: object) -> str:
    """``"; <hint>"`` for a native word (to append to an error message), ``""`` otherwise."""
    text = native_hints().get(word.strip().lower()) if isinstance(word, str) else None
    return f"; {text}" if text else ""
