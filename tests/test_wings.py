"""The faces of magrod are thin clients (issue 25, item 1): the command wing (magrod/cli), the figures wing
(magrod/figures) and the explorer (magrod/explorer) import the public face (`magrod`), `magrod.core`, the generated
names and each other as docs/architecture.md documents -- never the numerics' modules directly.

The rule is read from the source (AST), lazy imports included.  What still reaches past the face is listed in
PENDING, by importing module and imported module, as a debt with its reason in docs/architecture.md; the list may
only shrink: an import that is neither allowed nor listed fails, and so does a listed import that is gone (so the
list stays exact)."""
from __future__ import annotations

import ast
from pathlib import Path

import magrod

ROOT = Path(magrod.__file__).resolve().parent

# wing -> what it may import besides itself, magrod (the face), magrod.core.* and magrod.generated.names
ALLOWED = {
    "cli": ("figures", "explorer", "store"),  # the commands draw (figures), serve (explorer), store maps (store)
    "figures": (),
    "explorer": ("figures",),  # the explorer's pictures share the figures' colour scales
}
# the face, the vocabulary, and what derive/ wrote as plain data and closed forms (never the heyoka builders)
ALWAYS = ("magrod", "magrod.core", "magrod.generated.names", "magrod.generated.scalars")

# (importing module, imported module): reaches past the face today; each is a debt (docs/architecture.md)
PENDING = {
    ("magrod.cli.chaosmap", "magrod.chaos.fields"),
    ("magrod.cli.chaosmap", "magrod.chaos.maps"),
    ("magrod.cli.chaosmap", "magrod.chaos.refine"),
    ("magrod.cli.check", "magrod.integrability.first_integrals"),
    ("magrod.cli.check", "magrod.integrability.model_search"),
    ("magrod.cli.check", "magrod.integrability.report"),
    ("magrod.cli.continuation", "magrod.orbits.continuation"),
    ("magrod.cli.continuation", "magrod.orbits.equilibrium"),
    ("magrod.cli.continuation", "magrod.orbits.multipulse"),
    ("magrod.cli.continuation", "magrod.orbits.periodic"),
    ("magrod.cli.continuation", "magrod.orbits.periodic_multipulse"),
    ("magrod.cli.homoclinic", "magrod.orbits.homoclinic"),
    ("magrod.cli.landscape", "magrod.integrability.first_integrals"),
    ("magrod.cli.landscape", "magrod.integrability.landscape"),
    ("magrod.cli.melnikov", "magrod.orbits.homoclinic"),
    ("magrod.cli.melnikov", "magrod.separatrix.melnikov"),
    ("magrod.cli.multipulse", "magrod.orbits.multipulse"),
    ("magrod.cli.orbitdiagram", "magrod.chaos.portrait"),
    ("magrod.cli.poincare", "magrod.chaos.portrait"),
    ("magrod.cli.poincare", "magrod.chaos.section"),
    ("magrod.cli.prove", "magrod.proof.fields"),
    ("magrod.cli.prove", "magrod.proof.periodic"),
    ("magrod.cli.prove", "magrod.proof.search"),
    ("magrod.cli.prove", "magrod.proof.verify"),
    ("magrod.cli.spectrum", "magrod.chaos.spectrum"),
    ("magrod.cli.splitting", "magrod.separatrix.splitting"),
    ("magrod.explorer.app", "magrod.chaos.indicators"),
    ("magrod.explorer.model", "magrod.chaos.section"),
    ("magrod.explorer.model", "magrod.orbits.rod"),
    ("magrod.explorer.worker", "magrod.chaos.lyapunov"),
    ("magrod.figures.chaos", "magrod.chaos.fields"),
    ("magrod.figures.chaos", "magrod.chaos.indicators"),
    ("magrod.figures.chaos", "magrod.chaos.maps"),
    ("magrod.figures.continuation", "magrod.orbits.continuation"),
    ("magrod.figures.continuation", "magrod.orbits.equilibrium"),
    ("magrod.figures.continuation", "magrod.orbits.multipulse"),
    ("magrod.figures.continuation", "magrod.orbits.periodic_multipulse"),
    ("magrod.figures.homoclinic", "magrod.orbits.homoclinic"),
    ("magrod.figures.melnikov", "magrod.separatrix.melnikov"),
    ("magrod.figures.models", "magrod.chaos.model_chaos"),
    ("magrod.figures.models", "magrod.integrability.landscape"),
    ("magrod.figures.multipulse", "magrod.orbits.multipulse"),
    ("magrod.figures.multipulse", "magrod.orbits.shooting"),
    ("magrod.figures.poincare", "magrod.chaos.section"),
    ("magrod.figures.portrait", "magrod.chaos.indicators"),
    ("magrod.figures.portrait", "magrod.chaos.maps"),
    ("magrod.figures.portrait", "magrod.chaos.portrait"),
    ("magrod.figures.portrait", "magrod.chaos.section"),
    ("magrod.figures.proof", "magrod.proof.verify"),
    ("magrod.figures.proof", "magrod.separatrix.splitting"),
    ("magrod.figures.report", "magrod.integrability.report"),
    ("magrod.figures.report", "magrod.proof.statements"),
    ("magrod.figures.rod", "magrod.orbits.rod"),
    ("magrod.figures.splitting", "magrod.separatrix.enclosure"),
    ("magrod.figures.splitting", "magrod.separatrix.generic"),
    ("magrod.figures.splitting", "magrod.separatrix.splitting"),
}


def _targets(path: Path, pkg: str, root: Path):
    """Absolute module names imported by the module at `path` (package `pkg`, e.g. magrod.cli)."""
    here = pkg.split(".")
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[:len(here) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            if not mod.startswith("magrod"):
                continue
            for a in node.names:  # `from PKG import name` is an import of PKG.name when that is a module
                sub = f"{mod}.{a.name}"
                if mod == "magrod.generated":  # installed as magrod.generated, a top-level folder in a checkout
                    yield sub
                    continue
                rel = Path(*sub.split(".")[1:])
                yield sub if (root / rel).with_suffix(".py").exists() or (root / rel).is_dir() else mod
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("magrod"):
                    yield a.name


def _allowed(wing: str, target: str) -> bool:
    if target == "magrod" or any(target == a or target.startswith(a + ".") for a in ALWAYS[1:]):
        return True
    return any(target == f"magrod.{w}" or target.startswith(f"magrod.{w}.") for w in (wing, *ALLOWED[wing]))


def wing_imports(root: Path = ROOT) -> set:
    """{(importing module, imported module)} of every import of the three wings that the rule does not allow."""
    out = set()
    for wing in ALLOWED:
        for path in sorted((root / wing).rglob("*.py")):
            rel = path.relative_to(root).with_suffix("")
            name = ".".join(("magrod", *rel.parts)).removesuffix(".__init__")
            pkg = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
            for t in _targets(path, pkg, root):
                if not _allowed(wing, t):
                    out.add((name, t))
    return out


def test_the_wings_import_only_the_face_core_and_each_other():
    found = wing_imports()
    new = sorted(found - PENDING)
    assert not new, "imports past the face (use the public API, or list the debt in PENDING and architecture.md): " \
                    + "; ".join(f"{a} -> {b}" for a, b in new)
    gone = sorted(PENDING - found)
    assert not gone, "PENDING lists imports that are gone (remove them): " + "; ".join(f"{a} -> {b}" for a, b in gone)


def test_the_rule_finds_a_violation(tmp_path):
    """Seen to fail: a figure builder that imports a numerics module, in each spelling, is found; the face, core,
    the generated names and the command wing's allowed wings pass."""
    for w in ALLOWED:
        (tmp_path / w).mkdir()
    (tmp_path / "figures" / "a.py").write_text("from ..chaos.section import _assemble\n")
    (tmp_path / "figures" / "b.py").write_text("def f():\n    import magrod.orbits.shooting\n")
    (tmp_path / "cli" / "options.py").write_text("")
    (tmp_path / "explorer" / "c.py").write_text("from ..cli import options\n")
    (tmp_path / "cli" / "d.py").write_text("from ..figures.chaos import draw_map\nfrom ..core.io import x\n"
                                           "import magrod as mr\nfrom ..generated.names import PARAMS\n"
                                           "from ..store.resumable import stored_map\n")
    assert wing_imports(tmp_path) == {("magrod.figures.a", "magrod.chaos.section"),
                                      ("magrod.figures.b", "magrod.orbits.shooting"),
                                      ("magrod.explorer.c", "magrod.cli.options")}
