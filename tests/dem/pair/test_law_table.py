"""The C++ law table (``viscontact_contact.h: LAW_TABLE``, the one place the plugin names a law)
against the Python registry ``viscontact.physics.laws``: the same laws in the same order, with the same
damping exponent, relaxation-time parameter and per-contact history.  A law added in one
language and not the other fails here."""

from __future__ import annotations

import ctypes

import viscontact
from viscontact.dem import plugin

from dem_util import needs_compiler

pytestmark = needs_compiler


def _cpp_table() -> list[tuple[str, float, bool, tuple[str, ...]]]:
    lib = ctypes.CDLL(str(plugin.kernel_library_path()))
    lib.vc_law_name.restype = ctypes.c_char_p
    lib.vc_law_history.restype = ctypes.c_char_p
    lib.vc_law_exponent.restype = ctypes.c_double
    rows = []
    for i in range(lib.vc_law_count()):
        hist = lib.vc_law_history(i).decode()
        rows.append((lib.vc_law_name(i).decode(), lib.vc_law_exponent(i), bool(lib.vc_law_needs_beta(i)),
                     tuple(h for h in hist.split(",") if h)))
    return rows


def test_cpp_law_table_equals_python_registry():
    py = [(law.name, -1.0 if law.p is None else float(law.p), bool(law.needs_beta), tuple(law.history))
          for law in viscontact.LAWS.values()]
    assert _cpp_table() == py
