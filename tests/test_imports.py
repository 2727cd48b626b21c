"""No import circles inside magrod (issue 25: orbits/multipulse.py and orbits/periodic_multipulse.py imported each
other, one of the two imports hidden inside a function).

The graph counts every import, at module level and inside functions alike (a lazy import that closes a circle is
still a circle: it only moves the failure to run time).  `from PKG import name` is an edge to PKG.name when that
is a module, else to PKG; a package's own __init__ is not an edge of its submodules (Python imports a parent
package first, whatever imports the child).  Read from the source (AST), so nothing is imported."""
import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _modules(root: Path) -> dict:
    out = {}
    for top, pkg in (("magrod", "magrod"), ("derive", "magrod.derive"), ("generated", "magrod.generated")):
        base = root / top
        for p in base.rglob("*.py"):
            parts = p.with_suffix("").relative_to(base).parts
            name = ".".join((pkg, *parts))
            out[name.removesuffix(".__init__")] = p
    return out


def import_graph(root: Path = ROOT) -> dict:
    mods = _modules(root)
    graph = {m: set() for m in mods}
    for name, path in mods.items():
        here = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        for node in ast.walk(ast.parse(path.read_text())):
            targets = []
            if isinstance(node, ast.ImportFrom):
                base = ".".join(here[:len(here) - node.level + 1] + ([node.module] if node.module else [])) \
                    if node.level else (node.module or "")
                for a in node.names:
                    targets.append(f"{base}.{a.name}" if f"{base}.{a.name}" in mods else base)
            elif isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            for t in targets:
                # an edge to a module, never to a package that contains the importer (its parent is loaded first)
                if t in mods and t != name and not name.startswith(t + "."):
                    graph[name].add(t)
    return graph


def circles(graph: dict) -> list:
    """The strongly connected components with more than one module (Tarjan), each sorted; sorted."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(out)


def test_no_import_circles():
    found = circles(import_graph())
    assert found == [], "import circles (break them: move the shared piece down, e.g. into the engine module): " \
                        + "; ".join(" <-> ".join(c) for c in found)


def test_the_finder_finds_a_circle(tmp_path):
    """The check itself, on a synthetic tree: a lazy import inside a function closes a circle, and is found."""
    pkg = tmp_path / "magrod" / "orbits"
    pkg.mkdir(parents=True)
    (tmp_path / "magrod" / "__init__.py").write_text("")
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from .b import g\n")
    (pkg / "b.py").write_text("def g():\n    from . import a\n    return a\n")
    (pkg / "c.py").write_text("from . import a\n")
    assert circles(import_graph(tmp_path)) == [["magrod.orbits.a", "magrod.orbits.b"]]
