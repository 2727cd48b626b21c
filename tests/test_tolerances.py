"""Every tolerance is defined once, in magrod/core/tolerances.py, with its reason (issue 25): no numeric literal
is given to a tolerance anywhere else -- a keyword (tol=, xtol=, rtol=, atol=, tail_tol= ...), a default of a
parameter so named, or an assignment to such a name.  Read from the source (AST).  Multiples of machine epsilon
written in place (`4 * np.finfo(float).eps`) are a method's statement, not a literal, and pass."""
import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TOL = re.compile(r"tol", re.I)
WINGS = ("core", "orbits", "chaos", "separatrix", "integrability", "proof", "figures", "cli", "explorer")


def _literal(v):
    if isinstance(v, ast.Constant) and isinstance(v.value, (int, float)) and not isinstance(v.value, bool):
        return v.value
    if isinstance(v, ast.Constant) and isinstance(v.value, str) and re.fullmatch(r"[0-9.]+e-?[0-9]+", v.value):
        return v.value
    if isinstance(v, ast.UnaryOp) and isinstance(v.op, ast.USub):
        return _literal(v.operand)
    if isinstance(v, ast.IfExp):
        return _literal(v.body) if _literal(v.body) is not None else _literal(v.orelse)
    return None


def tolerance_literals(root: Path = ROOT) -> list:
    out = []
    for wing in WINGS:
        for p in sorted((root / "magrod" / wing).rglob("*.py")):
            if p.name == "tolerances.py":
                continue
            for node in ast.walk(ast.parse(p.read_text())):
                pairs = []
                if isinstance(node, ast.keyword) and node.arg and TOL.search(node.arg):
                    pairs.append((node.arg, node.value))
                elif isinstance(node, (ast.Assign, ast.AnnAssign)):
                    for t in (node.targets if isinstance(node, ast.Assign) else [node.target]):
                        if isinstance(t, ast.Name) and TOL.search(t.id):
                            pairs.append((t.id, node.value))
                elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    a = node.args
                    pos = a.args[len(a.args) - len(a.defaults):]
                    pairs += [(x.arg, d) for x, d in zip(pos, a.defaults) if TOL.search(x.arg)]
                    pairs += [(x.arg, d) for x, d in zip(a.kwonlyargs, a.kw_defaults) if d is not None and
                              TOL.search(x.arg)]
                for name, v in pairs:
                    val = _literal(v)
                    if val is not None and val != 0:  # 0 means "the method's default" (machine epsilon)
                        out.append(f"{p.relative_to(root)}:{v.lineno}: {name} = {val!r}")
    return out


PENDING: set = set()  # issue 27 moved the proof's and the enclosure's step controls into tolerances.py


def test_no_tolerance_literals_outside_tolerances_py():
    found = [f for f in tolerance_literals() if (f.split(":")[0], f.split(": ")[1].split(" =")[0]) not in PENDING]
    assert found == [], "define these in magrod/core/tolerances.py with their reason: " + "; ".join(found)


def test_the_scan_finds_a_literal(tmp_path):
    d = tmp_path / "magrod" / "orbits"
    d.mkdir(parents=True)
    (d / "x.py").write_text("def f(a, tol=1e-9, *, xtol=4 * EPS):\n    g(rtol=1e-12)\n    step_tol = '1e-32'\n")
    got = tolerance_literals(tmp_path)
    assert sorted(g.split(": ")[1] for g in got) == ["rtol = 1e-12", "step_tol = '1e-32'", "tol = 1e-09"]
