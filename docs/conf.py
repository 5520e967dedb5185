"""Sphinx configuration of lamodel's documentation (Markdown pages through MyST)."""
import os
import re
import sys

# The package from this checkout, not an installed copy: autodoc documents what is here.
sys.path.insert(0, os.path.abspath(".."))
# Importing a module must not open windows or start solvers: pictures draw off-screen.
os.environ.setdefault("MPLBACKEND", "Agg")

import lamodel  # noqa: E402  (after the path is set)

project = "lamodel"
author = "the lamodel authors"
copyright = "2026, the lamodel authors"
release = lamodel.__version__
version = ".".join(release.split(".")[:2])

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax shipped with the site: equations render offline
    "sphinx.ext.viewcode",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "_intersphinx", "_templates", "Thumbs.db", ".DS_Store"]
templates_path = ["_templates"]

# MyST: $...$ and $$...$$ maths, ::: fences, definition lists, anchors for ## and ### headings
# so that pages can link to a section (page.md#section).
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist", "attrs_inline"]
myst_heading_anchors = 3

# API reference: one page per module, generated at build time from the docstrings.
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_preserve_defaults = True
# Solvers that may be missing on a documentation machine: a mock lets the modules import.
autodoc_mock_imports = ["cyipopt"]

# Links into other projects' documentation. The first location is the project's own
# inventory (fetched when online); the second, a copy kept here, makes the build work
# offline (a CI machine without network) without a warning.
_INV = os.path.join(os.path.dirname(__file__), "_intersphinx")
intersphinx_mapping = {
    "python": ("https://docs.python.org/3", (None, os.path.join(_INV, "python.inv"))),
    "numpy": ("https://numpy.org/doc/stable", (None, os.path.join(_INV, "numpy.txt"))),
    "pyomo": ("https://pyomo.readthedocs.io/en/stable", (None, os.path.join(_INV, "pyomo.txt"))),
}
intersphinx_timeout = 5

html_theme = "sphinx_rtd_theme"
html_title = f"lamodel {release}"
html_static_path = ["_static"]
html_css_files = ["custom.css"]
html_theme_options = {"navigation_depth": 3, "collapse_navigation": False}


# Docstrings write absolute values as |x| (|V| <= -mu N), which reStructuredText would read
# as substitutions; lamodel defines none, so a bar outside literals and roles is a bar.
_LITERAL = re.compile(r"(``.+?``|`[^`]+`)")


def _escape_bars(app, what, name, obj, options, lines):
    for i, line in enumerate(lines):
        if "|" in line:
            parts = _LITERAL.split(line)
            lines[i] = "".join(p if k % 2 else p.replace("|", r"\|") for k, p in enumerate(parts))


def setup(app):
    app.connect("autodoc-process-docstring", _escape_bars)
