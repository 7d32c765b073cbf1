"""Sphinx configuration of viscontact's documentation (build: see docs/README.md).

Sphinx, because the project is a scientific Python package whose reference lives in its
docstrings: autodoc renders them as the API reference, MyST-parser reads the
existing Markdown pages unchanged, and Furo is a light, readable theme.  ``-W -n`` turns every
warning (a broken cross-reference, a page outside the table of contents) into an error.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "src"))  # document this checkout, not an installed copy

from viscontact import __version__  # noqa: E402

project = "viscontact"
author = "viscontact contributors"
copyright = "viscontact contributors, MIT licence"
release = version = __version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
]
source_suffix = {".md": "markdown"}
master_doc = "index"
exclude_patterns = ["_build", "README.md"]
myst_heading_anchors = 3  # [text](page.md#a-heading) links are checked too
suppress_warnings = ["myst.xref_ambiguous", "ref.python"]  # a re-exported name resolves in two modules

# API reference: the signatures, and the docstrings exactly as written.  They are plain text
# with equations such as c = alpha m*^((3-2p)/5) ... and unit lists (the project's style), not
# reStructuredText, so each is shown as a preformatted block instead of being parsed.
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_default_options = {"members": True, "show-inheritance": False}


def _docstring_as_written(app, what, name, obj, options, lines):
    if lines:
        lines[:] = ["::", ""] + ["    " + line for line in lines] + [""]


def setup(app):
    app.connect("autodoc-process-docstring", _docstring_as_written)

# -n (nitpicky) checks every cross-reference; types of the standard library and numpy are not
# documented here (intersphinx would need the network), so they are not targets
nitpick_ignore_regex = [(r"py:.*", r"(numpy|np|collections|os|pathlib|subprocess|typing|"
                         r"types|builtins|argparse|io|matplotlib|scipy)(\..*)?")]

html_theme = "furo"
html_title = f"viscontact {release}"
html_static_path: list[str] = []
