"""The documentation site builds with no warning and no broken internal link.

Sphinx builds ``docs/`` from scratch (``-E``) with warnings as errors (``-W --keep-going``) and
every cross-reference checked (``-n``): a page outside the table of contents, a Markdown link to
a page or heading that does not exist, a bad ``toctree`` entry, a docstring autodoc cannot
import, each fails.  The README's own relative links, outside the site, are checked here.
External links (DOIs) are not checked: publishers refuse link checkers; the separate, manual
``sphinx -b linkcheck`` is described in docs/architecture.md.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from sphinx.cmd.build import build_main

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
#: a Markdown link [text](target), not an image or an absolute URL
LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)")
#: Sphinx's and MyST's notes about their own future APIs are not the docs' concern
pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning",
                                        "ignore::PendingDeprecationWarning")


def test_site_builds_without_warnings(tmp_path, capsys):
    rc = build_main(["-E", "-W", "--keep-going", "-n", "-q", "-b", "html", "-d",
                     str(tmp_path / "doctrees"), str(DOCS), str(tmp_path / "html")])
    err = capsys.readouterr().err
    assert rc == 0, err
    assert (tmp_path / "html" / "index.html").is_file()
    # every page of docs/ is a page of the site (none left out of the build)
    pages = {p.stem for p in DOCS.glob("*.md")} - {"README"}
    built = {p.stem for p in (tmp_path / "html").glob("*.html")}
    assert pages <= built, pages - built


def _relative_links(path: Path) -> list[str]:
    return [t for t in LINK.findall(path.read_text(encoding="utf-8"))
            if "://" not in t and not t.startswith(("#", "mailto:"))]


def test_readme_links_exist():
    """The README's links into the docs and the repository point at files that exist."""
    links = _relative_links(ROOT / "README.md")
    assert links, "the README links into the documentation"
    missing = [t for t in links if not (ROOT / t.split("#")[0]).exists()]
    assert not missing, missing


def test_link_check_can_fail(tmp_path):
    """The build fails on a link to a page that does not exist (the check is live)."""
    src = tmp_path / "src"
    src.mkdir()
    (src / "conf.py").write_text((DOCS / "conf.py").read_text())
    (src / "index.md").write_text("# Index\n\nSee [](missing.md).\n")
    rc = build_main(["-E", "-W", "--keep-going", "-n", "-q", "-b", "html", "-d",
                     str(tmp_path / "doctrees"), str(src), str(tmp_path / "html")])
    assert rc != 0
