"""User-facing text says what a thing is, never which internal work item it came from: no "issue N" in the README,
the docs (pages, notebooks, the docs configuration's page text), the command line's help (every subcommand), the
text REPORT.md is made of (the string constants of figures/report.py that are not docstrings) or the docstrings of
the public names (the API reference).  A reader has no issue tracker to look them up in.  Cheap: no docs build.
Seen to fail before the rewording (39 hits in README and docs, 3 in the face's docstrings)."""
from __future__ import annotations

import argparse
import ast
import inspect
import re
from pathlib import Path

import magrod

ROOT = Path(__file__).resolve().parents[1]
ISSUE = re.compile(r"\b[Ii]ssues?[ -]?#?\d+")


def _hits(text: str) -> list[str]:
    return [text[max(0, m.start() - 50):m.end() + 20].replace("\n", " ") for m in ISSUE.finditer(text)]


def test_readme_and_docs():
    files = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md")), *sorted((ROOT / "docs").rglob("*.ipynb")),
             ROOT / "docs" / "conf.py"]
    bad = {str(p.relative_to(ROOT)): _hits(p.read_text()) for p in files if "_build" not in p.parts}
    assert not {k: v for k, v in bad.items() if v}


def _helps(p: argparse.ArgumentParser, path=("magrod",)):
    yield " ".join(path), p.format_help()
    for a in p._actions:
        if isinstance(a, argparse._SubParsersAction):
            for name, sub in a.choices.items():
                yield from _helps(sub, (*path, name))


def test_cli_help():
    from magrod.cli import build_parser

    bad = {path: _hits(h) for path, h in _helps(build_parser())}
    assert not {k: v for k, v in bad.items() if v}


def test_report_text():
    tree = ast.parse((ROOT / "magrod/figures/report.py").read_text())
    docstrings = {id(n.body[0].value) for n in ast.walk(tree)
                  if isinstance(n, (ast.FunctionDef, ast.ClassDef, ast.Module)) and n.body
                  and isinstance(n.body[0], ast.Expr) and isinstance(n.body[0].value, ast.Constant)}
    texts = [n.value for n in ast.walk(tree)
             if isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docstrings]
    assert not [h for t in texts for h in _hits(t)]


def test_public_docstrings():
    bad = {name: _hits(inspect.getdoc(getattr(magrod, name)) or "") for name in magrod.__all__}
    assert not {k: v for k, v in bad.items() if v}
