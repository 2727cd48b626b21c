"""The faces of magrod are thin clients (issue 25, item 1): the command wing (magrod/cli), the figures wing
(magrod/figures) and the explorer (magrod/explorer) import the public face (`magrod`), `magrod.core`, the generated
names and each other as docs/architecture.md documents, and the numerics only through their packages' public
second tier (`from magrod.chaos import MAPPABLE`: a name in `magrod.chaos.__all__`, listed in
docs/architecture.md) -- never a numerics module
(`magrod.chaos.section`), a private name, or a numerics package as an object (`from magrod import chaos`, through
which any module is reachable).

The rule is read from the source (AST), lazy imports included, and it has no exceptions: the list of debts issue 25
started with (56 pairs) is empty."""
from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

import magrod

ROOT = Path(magrod.__file__).resolve().parent

# wing -> what it may import besides itself, magrod (the face), magrod.core.* and magrod.generated.names
ALLOWED = {
    "cli": ("figures", "explorer", "store"),  # the commands draw (figures), serve (explorer), store maps (store)
    "figures": (),
    "explorer": ("figures",),  # the explorer's pictures share the figures' colour scales
}
# the face, the vocabulary, and what derive/ wrote as plain data and closed forms (never the heyoka builders)
ALWAYS = ("magrod.core", "magrod.generated.names", "magrod.generated.scalars")
# the numerics packages whose second tier (__all__) the wings may use: docs/architecture.md
NUMERICS = ("chaos", "orbits", "separatrix", "integrability", "proof", "paper")  # paper: the paper's own package


def public(package: str) -> set:
    """The public names of `package` (the face or a numerics package): its lazy namespace's __all__."""
    return set(importlib.import_module(package).__all__)


def _targets(path: Path, pkg: str, root: Path):
    """(imported module, name or None) for every import of the module at `path` (package `pkg`, e.g. magrod.cli):
    `from PKG import name` is an import of the module PKG.name when that is a module (name None), else of the
    name `name` of PKG; `import PKG` imports the module PKG."""
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
            for a in node.names:
                sub = f"{mod}.{a.name}"
                if mod == "magrod.generated":  # installed as magrod.generated, a top-level folder in a checkout
                    yield sub, None
                    continue
                rel = Path(*sub.split(".")[1:])
                is_module = (root / rel).with_suffix(".py").exists() or (root / rel).is_dir() \
                    or (mod == "magrod" and a.name in NUMERICS)
                yield (sub, None) if is_module else (mod, a.name)
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("magrod"):
                    yield a.name, None


def _allowed(wing: str, target: str, name: str | None) -> bool:
    if target == "magrod":
        return name is None or name in public("magrod") or name == "__version__"
    if any(target == a or target.startswith(a + ".") for a in ALWAYS):
        return True
    if target in {f"magrod.{p}" for p in NUMERICS}:  # the second tier: public names only, never the package object
        return name is not None and name in public(target)
    return any(target == f"magrod.{w}" or target.startswith(f"magrod.{w}.") for w in (wing, *ALLOWED[wing]))


def wing_imports(root: Path = ROOT) -> set:
    """{(importing module, imported module or module.name)} of every import of the three wings the rule forbids."""
    out = set()
    for wing in ALLOWED:
        for path in sorted((root / wing).rglob("*.py")):
            rel = path.relative_to(root).with_suffix("")
            name = ".".join(("magrod", *rel.parts)).removesuffix(".__init__")
            pkg = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
            for t, n in _targets(path, pkg, root):
                if not _allowed(wing, t, n):
                    named = n is not None and t in {"magrod", *(f"magrod.{p}" for p in NUMERICS)}
                    out.add((name, f"{t}.{n}" if named else t))
    return out


def test_the_wings_import_only_the_face_core_and_each_other():
    found = wing_imports()
    assert not found, "imports past the face (use the face, or a name of a numerics package's __all__; " \
                      "docs/architecture.md): " + "; ".join(f"{a} -> {b}" for a, b in sorted(found))


def test_the_rule_finds_a_violation(tmp_path):
    """Seen to fail: a figure builder that imports a numerics module, in each spelling (a module path, a module as a
    name of its package, the package as an object, a private or unknown name of the second tier, a name the face
    does not export), is found; the face, the second tier's public names, core, the generated names and the
    command wing's allowed wings pass."""
    for w in ALLOWED:
        (tmp_path / w).mkdir()
    (tmp_path / "figures" / "a.py").write_text("from ..chaos.section import _assemble\n")
    (tmp_path / "figures" / "b.py").write_text("def f():\n    import magrod.orbits.shooting\n")
    (tmp_path / "figures" / "e.py").write_text("from ..chaos import section\nfrom .. import orbits\n"
                                               "from ..proof import _private, MAPPABLE\nfrom .. import no_such_name\n"
                                               "from ..chaos import MAPPABLE, GROWTH_THRESHOLD\n"
                                               "from .. import poincare_section, __version__\n")
    (tmp_path / "cli" / "options.py").write_text("")
    (tmp_path / "explorer" / "c.py").write_text("from ..cli import options\n")
    (tmp_path / "cli" / "d.py").write_text("from ..figures.chaos import draw_map\nfrom ..core.io import x\n"
                                           "import magrod as mr\nfrom ..generated.names import PARAMS\n"
                                           "from ..store.resumable import stored_map\n"
                                           "from ..separatrix import melnikov_amplitude\n")
    assert wing_imports(tmp_path) == {("magrod.figures.a", "magrod.chaos.section"),
                                      ("magrod.figures.b", "magrod.orbits.shooting"),
                                      ("magrod.figures.e", "magrod.chaos.section"),
                                      ("magrod.figures.e", "magrod.orbits"),
                                      ("magrod.figures.e", "magrod.proof._private"),
                                      ("magrod.figures.e", "magrod.proof.MAPPABLE"),
                                      ("magrod.figures.e", "magrod.no_such_name"),
                                      ("magrod.explorer.c", "magrod.cli.options")}


@pytest.mark.parametrize("package", ["magrod", *(f"magrod.{p}" for p in NUMERICS)])
def test_every_public_name_resolves_and_is_not_a_submodule(package):
    """Each name of a lazy namespace resolves to what its table says, and none is also a submodule's name: after
    `import magrod.separatrix.splitting` the import system binds the module as `splitting` on the package, and a
    public function of that name would silently become the module (magrod.core.lazy).  Seen to fail with
    "splitting_scan" renamed "splitting" in magrod/separatrix/__init__.py."""
    mod = importlib.import_module(package)
    here = Path(mod.__file__).parent
    subs = {p.stem for p in here.glob("*.py")} | {p.name for p in here.iterdir() if (p / "__init__.py").exists()}
    assert not (set(mod.__all__) & subs), f"{package}: public names that are submodules: {set(mod.__all__) & subs}"
    for name in mod.__all__:
        value = getattr(mod, name)
        target = mod._API[name]
        module, attr = (target, name) if isinstance(target, str) else target
        assert value is getattr(importlib.import_module(f"{package}.{module}"), attr), (package, name)
        if callable(value) and not isinstance(value, type(ast)):
            assert (value.__doc__ or "").strip(), f"{package}.{name} has no docstring"


def test_the_second_tier_is_the_documented_one():
    """docs/architecture.md lists each numerics package's public names (the second tier) exactly: a name added to
    or removed from a package's `_API` without the docs fails here.  Seen to fail with "OK" deleted from the list."""
    import re

    # The docs live in the checkout, not in the installed package (CI installs magrod non-editable: the package's
    # parent there is site-packages, which has no docs/).
    text = (Path(__file__).resolve().parents[1] / "docs" / "architecture.md").read_text()
    for p in NUMERICS:
        m = re.search(rf"^- `magrod\.{p}`: (.+)$", text, re.M)
        assert m, f"docs/architecture.md has no line for magrod.{p}"
        listed = set(re.findall(r"`([A-Za-z_][A-Za-z0-9_]*)`", m.group(1)))
        assert listed == public(f"magrod.{p}"), (p, sorted(listed ^ public(f"magrod.{p}")))
