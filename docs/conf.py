"""Sphinx configuration of the planetary-fe docs (``make docs``; warnings are errors)."""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).parent / "_ext"))

project = "planetary-fe"
author = "planetary-fe developers"
copyright = "planetary-fe developers, LGPL-3.0-or-later"

# MyST: the pages are Markdown, like the README and the reports the pipeline writes.
extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "case_reference",
    "records_table",
]
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
source_suffix = {".md": "markdown"}
exclude_patterns = ["_build", "_ext"]
html_theme = "furo"
html_title = "planetary-fe"
autodoc_member_order = "bysource"
# Docstrings use :mod: / :func: roles that may point at modules not shown on a page.
nitpicky = False
suppress_warnings = ["myst.xref_missing"]
