"""Code inside the package imports package paths only, never an old path of the flat layout.

``viscontact._moved`` keeps the old module paths (``viscontact.laws``, ``viscontact.domain``,
...) importable for code written against them, through an import hook.  import-linter does not
see through that hook: an import of an old path from inside the package would cross the layers
of ARCHITECTURE.md unseen (``physics`` importing ``viscontact.report``, now ``paper``, is
reported as kept).  So every import statement of every module is read here (``ast``, relative
imports resolved against the module's own package) and any that names an old path, as a module
(``from ..domain import check``) or as a name taken from a package (``from .. import laws``),
fails, with the file, the line and the new path to use.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import viscontact
from viscontact._moved import MOVED

ROOT = Path(viscontact.__file__).parent
#: the old absolute paths -> their new ones
OLD = {f"viscontact.{old}": f"viscontact.{new}" for old, new in MOVED.items()}


def _module_name(path: Path, root: Path) -> str:
    parts = path.relative_to(root.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _package(path: Path, root: Path) -> str:
    """The package a relative import in ``path`` (a module below ``root``) starts from."""
    name = _module_name(path, root)
    return name if path.name == "__init__.py" else name.rpartition(".")[0]


def imported_paths(path: Path, root: Path) -> list[tuple[int, str]]:
    """(line, absolute dotted path) of every module or package member ``path`` imports."""
    found: list[tuple[int, str]] = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = _package(path, root).split(".")
                base = base[:len(base) - (node.level - 1)]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            found.append((node.lineno, module))
            found += [(node.lineno, f"{module}.{alias.name}") for alias in node.names]
    return found


def old_path_uses(root: Path = ROOT) -> list[str]:
    """Every import of an old path inside ``root``: 'file:line: old -> use new'."""
    uses = []
    for path in sorted(root.rglob("*.py")):
        if path.name == "_moved.py":
            continue
        seen = set()
        for line, name in imported_paths(path, root):
            hit = next((old for old in OLD if name == old or name.startswith(old + ".")), None)
            if hit and line not in seen:  # one report per import statement
                seen.add(line)
                uses.append(f"{path.relative_to(root.parent)}:{line}: {name} -> use "
                            f"{OLD[hit]}{name[len(hit):]}")
    return uses


def test_no_old_path_inside_the_package():
    uses = old_path_uses()
    assert not uses, "old module paths of _moved.MOVED imported inside the package:\n" + \
        "\n".join(uses)


def _package_with(tmp: Path, source: str) -> Path:
    """A package ``viscontact`` under ``tmp`` whose module ``cli/mod.py`` is ``source``."""
    pkg = tmp / "viscontact"
    (pkg / "cli").mkdir(parents=True)
    for init in (pkg / "__init__.py", pkg / "cli" / "__init__.py"):
        init.write_text("")
    (pkg / "cli" / "mod.py").write_text(source)
    return pkg


@pytest.mark.parametrize("source, old", [
    ("from ..domain import check\n", "viscontact.domain"),
    ("from .. import laws\n", "viscontact.laws"),
    ("import viscontact.dimensional\n", "viscontact.dimensional"),
    ("from viscontact.report.tables import x\n", "viscontact.report.tables"),
    ("def f():\n    from ..sweep import velocity_sweep\n", "viscontact.sweep"),
])
def test_an_old_path_is_found(tmp_path, source, old):
    """The check can fail: a module below a copy of the package that imports an old path, at
    module level or inside a function, absolutely or relatively, is reported."""
    uses = old_path_uses(_package_with(tmp_path, source))
    assert len(uses) == 1 and f": {old} -> use " in uses[0], uses


def test_new_paths_pass(tmp_path):
    """Package paths, including names that merely share an old path's last word
    (``viscontact.collision.sweep``, ``viscontact._support.report``), are not reported."""
    source = ("from ..physics.domain import check\nfrom ..collision import sweep\n"
              "from .._support.report import Report\nimport viscontact.physics.laws\n")
    assert old_path_uses(_package_with(tmp_path, source)) == []
