"""Sphinx configuration of the magrod documentation.

Build (the command in README.md):  python -m sphinx -W --keep-going -b html docs docs/_build/html
-W turns every warning into an error (tests/test_docs.py builds it so).  The notebooks in docs/notebooks are
executed during the build by myst-nb and rendered from their executed cells; a cell that raises fails the build.
The API reference (api.rst and a page per name under api/) is written at build time from magrod.__all__ and the
result types found in the packages (docs/_ext/magrod_api.py), the CLI reference (cli.md) by sphinx-argparse from
magrod.cli.build_parser(): neither is typed by hand.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # a source checkout documents itself (magrod/__init__.py maps derive/generated)
sys.path.insert(0, str(HERE / "_ext"))  # local extensions (magrod_api: the API reference)

import magrod  # noqa: E402
from magrod_api import write_api_page, xref_aliases  # noqa: E402  (docs/_ext/magrod_api.py)

project = "magrod"
author = "the magrod developers"
copyright = "the magrod developers"
release = version = magrod.__version__

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
    "magrod_api",
    "sphinx.ext.mathjax",
    "sphinxarg.ext",
]
exclude_patterns = ["_build", "_generated_cache", "_ext", "**.ipynb_checkpoints", "Thumbs.db", ".DS_Store",
                    "_templates",
                    # the source of the six theory/*.md pages (each includes its part): not a page of its own
                    "nonintegrability.md"]
html_theme = "pydata_sphinx_theme"
html_title = f"magrod {release}"
# a short top bar (the five parts of the root toctree, no "More" menu), the whole site in the left sidebar of every
# page (_templates/site-nav.html), anchors scrolled clear of the sticky header (_static/magrod.css)
html_theme_options = {"navigation_with_keys": False, "show_toc_level": 2, "header_links_before_dropdown": 5,
                      "secondary_sidebar_items": ["page-toc"]}
html_sidebars = {"**": ["site-nav"]}
templates_path = ["_templates"]
html_static_path = ["_static"]
html_css_files = ["magrod.css"]

# myst / myst-nb: notebooks executed at build time, rendered from their executed cells
# $...$ and $$...$$ (dollarmath) and LaTeX environments (amsmath), typeset by MathJax (sphinx.ext.mathjax; the
# script comes from MathJax's CDN when a page with mathematics is opened)
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 3
nb_execution_mode = os.environ.get("MAGROD_NB_EXECUTION", "force")
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True
nb_execution_in_temp = True  # notebooks write their files into a temporary directory, never into docs/

# The API reference (docs/_ext/magrod_api.py): api.rst holds summary tables by topic (autosummary), each name has
# a page of its own under api/ (stubs from _templates/autosummary/, regenerated on every build, not checked in).
# numpydoc renders the Parameters/Returns/Raises/Examples/Notes sections of the docstrings; magrod_api fills in
# the member sections of the classes (Parameters or Attributes from dataclass fields, properties, Methods), so
# numpydoc's own member listing stays off; the types of Parameters/Returns link to the classes' pages.
autosummary_generate = True
autosummary_generate_overwrite = True
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks = set()
numpydoc_xref_param_type = True
# only the documented classes become links: "float", "optional" stay text, and numpydoc's default links into the
# Python and NumPy inventories (no intersphinx here: nothing is fetched at build time) are turned off
numpydoc_xref_aliases = {**{k: k for k in __import__("numpydoc.xref").xref.DEFAULT_LINKS}, **xref_aliases()}
numpydoc_xref_ignore = "all"
# `name` in a docstring is code, as the docstrings mean it (reST only: the MyST pages have their own syntax).  Not
# py:obj: `plot()` or `accuracy` in prose would be an ambiguous reference to 28 result types' members (an error
# under -W), or a link to the wrong one
default_role = "literal"
autodoc_typehints = "none"
autodoc_member_order = "bysource"
suppress_warnings = ["myst.header", "mystnb.unknown_mime_type"]
nitpicky = False
# Smart quotes would turn the "--json" of the help texts and prose into an en dash ("–json"), which a shell does
# not accept when pasted: keep quotes and ellipses, never dashes ("q" quotes, "e" ellipses; no "D"/"d").
smartquotes_action = "qe"

write_api_page(HERE)
