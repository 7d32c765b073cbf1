"""The kernels of :mod:`viscontact.physics.kernels` as plain Python functions, without numba.

Importing numba and initialising its compiler back end (LLVM) when the first cached
kernel is loaded costs about 0.5 s, twenty to fifty times what one collision with
histories costs (about 10^4 kernel calls).  The reference solver calls these instead for
a process's first few collisions, so that ``viscontact collide`` never loads numba.

There is still one expression of each force law: :func:`python_kernels` executes the
source of :mod:`viscontact.physics.kernels` itself, with ``numba.njit`` replaced by the identity,
so every function there is its own ``py_func`` and calls the others as plain Python.  The
numbers are the same as the compiled ones (IEEE arithmetic, no fast-math; tested).
"""

from __future__ import annotations

import builtins
import functools
import importlib.util
import types
from typing import Any

__all__ = ["python_kernels"]


def _identity_njit(*args: Any, **_options: Any) -> Any:
    """Stands in for ``numba.njit``: ``njit(f)`` and ``njit(**options)(f)`` both give f."""
    if len(args) == 1 and callable(args[0]):
        return args[0]
    return lambda func: func


_NUMBA_STAND_IN = types.SimpleNamespace(njit=_identity_njit)


@functools.cache
def python_kernels() -> types.ModuleType:
    """A module with every function of :mod:`viscontact.physics.kernels`, uncompiled.

    Built once per process (about a millisecond, from the cached bytecode); importing it
    neither imports numba nor touches ``sys.modules``.
    """
    spec = importlib.util.find_spec(f"{__package__}.kernels")
    if spec is None or spec.loader is None:  # pragma: no cover - the package is broken
        raise ImportError(f"cannot find {__package__}.kernels")
    code = spec.loader.get_code(spec.name)  # type: ignore[attr-defined]
    real_import = builtins.__import__

    def import_without_numba(name: str, *args: Any, **kwargs: Any) -> Any:
        if name == "numba":
            return _NUMBA_STAND_IN
        return real_import(name, *args, **kwargs)

    module = types.ModuleType(f"{__package__}.kernels_py.kernels",
                              "viscontact.physics.kernels as plain Python")
    module.__file__ = spec.origin
    # Only this module's own builtins see the stand-in; the interpreter's are untouched.
    module.__dict__["__builtins__"] = {**vars(builtins), "__import__": import_without_numba}
    exec(code, module.__dict__)
    return module
