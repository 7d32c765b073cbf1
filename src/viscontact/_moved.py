"""Old module paths of the flat layout, kept importable for code written against them.

``import viscontact.laws`` (or ``from viscontact.dimensional import ContactPair``) yields the
module that now holds those names (:mod:`viscontact.physics.laws`, ...): the very same module
object, so attributes set on one are seen through the other.  New code imports the new paths;
nothing inside the package uses these.  The target is imported only when the old path is, so
``import viscontact`` stays as light as before.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from importlib.machinery import ModuleSpec
from types import ModuleType

#: old dotted path (below ``viscontact``) -> new one
MOVED: dict[str, str] = {
    "laws": "physics.laws",
    "kernels": "physics.kernels",
    "kernels_py": "physics.kernels_py",
    "domain": "physics.domain",
    "dimensional": "physics.pair",
    "sweep": "collision.sweep",
    "outputs": "_support.outputs",
    "parallel": "_support.parallel",
    "plotting": "collision.plots",
    "experiment": "paper.experiment",
    "study": "paper.study",
    "report": "paper",
    "report.build": "paper.report",
    "report.figures": "paper.figures",
    "report.html": "paper.html",
    "report.tables": "paper.tables",
}


class _OldPath:
    """Finds an old path and loads it as the module at the new one (a meta path finder and its
    loader, by protocol: importlib.abc itself costs start-up)."""

    def find_spec(self, fullname: str, path: object = None,
                  target: ModuleType | None = None) -> ModuleSpec | None:
        package, _, rest = fullname.partition(".")
        if package != __package__ or rest not in MOVED:
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec: ModuleSpec) -> ModuleType | None:
        return None  # a throw-away module: exec_module swaps in the real one

    def exec_module(self, module: ModuleType) -> None:
        # The import system returns whatever sys.modules holds under the name after this call.
        new = f"{__package__}.{MOVED[module.__name__.partition('.')[2]]}"
        sys.modules[module.__name__] = importlib.import_module(new)


def attribute(name: str) -> ModuleType:
    """``viscontact.<old name>`` as an attribute (the package's ``__getattr__``, PEP 562)."""
    if name not in MOVED or "." in name:
        raise AttributeError(f"module {__package__!r} has no attribute {name!r}")
    return importlib.import_module(f"{__package__}.{name}")


def install() -> None:
    """Put the finder first on ``sys.meta_path`` (once): an old path below a package that still
    exists (``viscontact.report.tables``, with ``viscontact.report`` now ``viscontact.paper``)
    would otherwise be found by the path finder and loaded a second time."""
    if not any(isinstance(f, _OldPath) for f in sys.meta_path):
        sys.meta_path.insert(0, _OldPath())
