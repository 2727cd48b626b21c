"""Sphinx configuration of the magrod documentation.

Build (the command in README.md):  python -m sphinx -W --keep-going -b html docs docs/_build/html
-W turns every warning into an error (tests/test_docs.py builds it so).  The notebooks in docs/notebooks are
executed during the build by myst-nb and rendered from their executed cells; a cell that raises fails the build.
The API reference (api.rst) is written here from magrod.__all__ at build time, the CLI reference (cli.md) by
sphinx-argparse from magrod.cli.build_parser(): neither is typed by hand.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # a source checkout documents itself (magrod/__init__.py maps derive/generated)

import magrod  # noqa: E402

project = "magrod"
author = "the magrod developers"
copyright = "the magrod developers"
release = version = magrod.__version__

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "numpydoc",
    "sphinx.ext.mathjax",
    "sphinxarg.ext",
]
exclude_patterns = ["_build", "_generated_cache", "**.ipynb_checkpoints", "Thumbs.db", ".DS_Store", "_templates",
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

# numpydoc renders the Parameters/Returns/Raises/Examples/Notes sections of the public docstrings
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks = set()
autodoc_typehints = "none"
autodoc_member_order = "bysource"
suppress_warnings = ["myst.header", "mystnb.unknown_mime_type"]
nitpicky = False
# Smart quotes would turn the "--json" of the help texts and prose into an en dash ("–json"), which a shell does
# not accept when pasted: keep quotes and ellipses, never dashes ("q" quotes, "e" ellipses; no "D"/"d").
smartquotes_action = "qe"


def _summary_table() -> list[str]:
    """A table at the top of the API page, as scipy's references open: every public name (linked to its entry)
    with the first line of its docstring."""
    import inspect

    rows = []
    for name in magrod.__all__:
        doc = inspect.getdoc(getattr(magrod, name)) or ""
        first = " ".join(doc.split("\n\n")[0].split()).replace("|", "/")
        if len(first) > 160:
            first = first[:160].rsplit(" ", 1)[0] + " ..."
        kind = "class" if isinstance(getattr(magrod, name), type) else "function"
        rows += [f"   * - `mr.{name} <#mr-{name.lower().replace('_', '-')}>`__", f"     - {kind}",
                 f"     - {first or '(no summary)'}"]
    return [".. list-table:: The public names", "   :header-rows: 1", "   :widths: 25 10 65", "",
            "   * - name", "     - kind", "     - what it is", *rows, ""]


def _write_api_page() -> None:
    """api.rst from magrod.__all__ (the pinned public names, tests/test_layout.py): one entry per name.

    The page is reStructuredText, not MyST: autodoc emits reST lines and parses them with the parser of the page
    that holds the directive.  Inside a MyST page that parser is MyST, which does not know reST directive
    syntax, so ``.. py:function::`` and numpydoc's ``:Parameters:`` fields came out as literal text (zero
    ``dl.py`` entries).  In an .rst page they become real signatures and definition lists."""
    stale = HERE / "api.md"  # written by earlier versions of this file; two sources for one page break -W
    if stale.exists() and stale.read_text().startswith("# API reference"):
        stale.unlink()
    lines = ["API reference", "=============", "",
             "The public API is the flat namespace ``import magrod as mr``; these are the names in "
             "``magrod.__all__``, documented from their docstrings (numpydoc).", ""]
    lines += _summary_table()
    for name in magrod.__all__:
        obj = getattr(magrod, name)
        kind = "autoclass" if isinstance(obj, type) else "autofunction"
        title = f"``mr.{name}``"
        lines += [title, "-" * len(title), "", f".. {kind}:: {obj.__module__}.{obj.__qualname__}", ""]
    # the second tier (docs/architecture.md): the numerics packages' public names that the commands, figures and
    # explorer use besides the face; listed, not autodoc'ed (their docstrings are one-paragraph, not numpydoc)
    import importlib

    lines += ["The second tier", "===============", "",
              "Besides the face, each numerics package has a small public namespace: what the command line, the "
              "figures and the explorer use (format helpers, the scans behind a figure, the prover and the "
              "verifier, constants of a picture).  ``from magrod.chaos import MAPPABLE`` is public; "
              "``magrod.chaos.section`` and the names it does not list are internals.", ""]
    for pkg in ("chaos", "orbits", "separatrix", "integrability", "proof"):
        mod = importlib.import_module(f"magrod.{pkg}")
        title = f"``magrod.{pkg}``"
        lines += [title, "-" * len(title), ""]
        for name in mod.__all__:
            target = mod._API[name]
            where, attr = (target, name) if isinstance(target, str) else target
            lines.append(f"* ``{name}`` (``magrod.{pkg}.{where}.{attr}``)")
        lines.append("")
    text = "\n".join(lines)
    path = HERE / "api.rst"
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


_write_api_page()
