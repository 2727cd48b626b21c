"""Bring your own rod (issue 26): a model file through `magrod check --model ./file.py`, the content-hash cache,
and the table of bad model files (exit 2, one stderr line naming the check, one JSON object, nothing written)."""
from __future__ import annotations

import json

import pytest

from magrod import cli

GOOD = '''
import sympy as sp
m1, m2, m3, n1, n2, n3 = sp.symbols("m1 m2 m3 n1 n2 n3", real=True)
u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
v1, v2, v3 = sp.symbols("v1 v2 v3", real=True)
A, C = sp.symbols("A C", positive=True)

def hat(a):
    return sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])

m, n = sp.Matrix([m1, m2, m3]), sp.Matrix([n1, n2, n3])
NAME = "my-rod"
STATE = [m1, m2, m3, n1, n2, n3]
PARAMETERS = {A: ("bending stiffness", (0, sp.oo), 1), C: ("torsional stiffness", (0, sp.oo), 2)}
J = sp.Matrix.vstack(sp.Matrix.hstack(hat(m), hat(n)), sp.Matrix.hstack(hat(n), sp.zeros(3, 3)))
W = (A * (u1**2 + u2**2) + C * u3**2) / 2
STRAINS = [(u1, m1), (u2, m2), (u3, m3), (v1, n1), (v2, n2), (v3, n3)]
FIXED = {v1: 0, v2: 0, v3: 1}
CANDIDATES = {"I1": (m3, "Kehrbaum97b")}
'''

# (name, how GOOD is broken, the check the one error line must name)
BAD = [
    ("J not skew", ("J = sp.Matrix.vstack(", "J = sp.diag(1, 0, 0, 0, 0, 0) + sp.Matrix.vstack("), "skew"),
    ("Jacobi fails", ("W = (A", "J[0, 1] += n1\nJ[1, 0] -= n1\nW = (A"), "jacobi"),
    ("W not polynomial", ("W = (A * (u1**2", "W = sp.sqrt(1 + u1**2) + (A * (u1**2"), "W polynomial"),
    ("W not convex", ("W = (A * (u1**2 + u2**2)", "W = (A * (u1**2 - 3 * u2**2)"), "W convex"),
    ("W of degree 4", ("W = (A * (u1**2", "W = u1**4 + (A * (u1**2"), "W polynomial"),
    ("parameter named like a state variable", ('PARAMETERS = {A: ("bending stiffness", (0, sp.oo), 1), ',
                                               'PARAMETERS = {m1: ("x", (0, sp.oo), 1), A: ("bending stiffness", (0, sp.oo), 1), '),
     "name clash"),
    ("two symbols one name", ("CANDIDATES = {", "CANDIDATES = {'I9': (sp.Symbol('A') * m3, 'x'), "), "name clash"),
    ("registered NAME", ('NAME = "my-rod"', 'NAME = "kirchhoff"'), "name clash"),
    ("keyword name", ('A, C = sp.symbols("A C", positive=True)', 'A, C = sp.symbols("A lambda", positive=True)'),
     "name clash"),
    ("missing parameter", ('PARAMETERS = {A: ("bending stiffness", (0, sp.oo), 1), C: ("torsional stiffness", (0, sp.oo), 2)}',
                           'PARAMETERS = {A: ("bending stiffness", (0, sp.oo), 1)}'), "parameters"),
    ("default outside its range", ('C: ("torsional stiffness", (0, sp.oo), 2)', 'C: ("torsional stiffness", (0, sp.oo), -2)'),
     "parameters"),
    ("no STATE", ("STATE = [m1, m2, m3, n1, n2, n3]", "STATE_ = [m1, m2, m3, n1, n2, n3]"), "missing"),
    ("syntax error", ("import sympy as sp", "import sympy as sp\nthis is not python"), "import"),
    ("raises on import", ("import sympy as sp", "import sympy as sp\nraise RuntimeError('boom')"), "import"),
    # a string is never parsed (sympify would evaluate it as code a second time): data, not code
    ("W as a string", ("W = (A * (u1**2 + u2**2) + C * u3**2) / 2", "W = '(A * (u1**2 + u2**2) + C * u3**2) / 2'"),
     "W polynomial"),
    ("default as a string", ('C: ("torsional stiffness", (0, sp.oo), 2)', 'C: ("torsional stiffness", (0, sp.oo), "2")'),
     "parameters"),
]


@pytest.fixture()
def cache(tmp_path, monkeypatch):
    d = tmp_path / "cache"
    monkeypatch.setenv("MAGROD_MODEL_CACHE", str(d))
    from magrod.core import models

    models._LOADED.clear()
    return d


def test_good_file_check_and_section(cache, tmp_path, capsys):
    f = tmp_path / "my_rod.py"
    f.write_text(GOOD)
    assert cli.main(["check", "--model", str(f), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    st = {r["key"]: r["status"] for r in out["results"]}
    assert out["model"] == "my-rod" and st["jacobi"] == "holds" and st["s1_symmetry"] == "holds"
    entries = list(cache.iterdir())
    assert len(entries) == 1 and (entries[0] / "body.py").is_file()  # in the cache, keyed by content
    assert cli.main(["check", "--model", str(f), "--integrals", "--degree", "3", "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["certified"] and "I1" in r["known"]
    import magrod as mr

    sec = mr.poincare_section(str(f), iterates=20)
    assert sec.success and sec.system.code.name == "my-rod" and sec.max_abs_dH <= 1e-12
    from magrod.core import models

    f.write_text(GOOD + "\n# an edited comment: the same evaluated model, the same entry\n")
    models._LOADED.clear()
    assert cli.main(["check", "--model", str(f), "--json"]) == 0
    assert len(list(cache.iterdir())) == 1
    f.write_text(GOOD.replace('"torsional stiffness", (0, sp.oo), 2)', '"torsional stiffness", (0, sp.oo), 3)'))
    models._LOADED.clear()
    assert cli.main(["check", "--model", str(f), "--json"]) == 0
    capsys.readouterr()
    assert len(list(cache.iterdir())) == 2  # a new model, a new entry


@pytest.mark.parametrize("name,edit,check", BAD, ids=[b[0] for b in BAD])
def test_bad_model_files(name, edit, check, cache, tmp_path, capsys):
    old, new = edit
    assert old in GOOD, name
    f = tmp_path / "bad_rod.py"
    f.write_text(GOOD.replace(old, new, 1))
    rc = cli.main(["check", "--model", str(f), "--json"])
    cap = capsys.readouterr()
    assert rc == 2, cap
    obj = json.loads(cap.out)
    assert obj["ok"] is False and obj["parameter"] == "model"
    lines = [ln for ln in cap.err.splitlines() if ln.strip()]
    assert len(lines) == 1 and f"{check}:" in lines[0] and "Traceback" not in cap.err, lines
    assert not cache.exists() or not any(cache.iterdir())  # nothing written


def test_the_unbroken_file_passes_every_check_of_the_table(tmp_path):
    """The table's control: GOOD itself passes (so each failure above is the edit's)."""
    from magrod.derive.models.spec import load_file

    f = tmp_path / "good.py"
    f.write_text(GOOD)
    assert load_file(f).name == "my-rod"


def test_models_lists_every_model_with_its_parameters(capsys):
    assert cli.main(["models", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    names = [m["name"] for m in out["models"]]
    assert names == ["kirchhoff", "anisotropic", "curved", "extensible", "magnetic", "magnetic-extensible"]
    aniso = out["models"][1]
    assert [p["name"] for p in aniso["parameters"]] == ["B1", "B2", "C"] and not aniso["s1_symmetric"]


EULER_TOP = '''
import sympy as sp
m1, m2, m3 = sp.symbols("m1 m2 m3", real=True)
I1, I2, I3 = sp.symbols("I1 I2 I3", positive=True)
NAME = "euler-top"
STATE = [m1, m2, m3]
PARAMETERS = {I1: ("moment 1", (0, sp.oo), 1), I2: ("moment 2", (0, sp.oo), 2), I3: ("moment 3", (0, sp.oo), 3)}
J = sp.Matrix([[0, -m3, m2], [m3, 0, -m1], [-m2, m1, 0]])
H = m1**2 / (2 * I1) + m2**2 / (2 * I2) + m3**2 / (2 * I3)
REFERENCE = {m1: 0.3, m2: 0.2, m3: 0.9}
'''


def test_a_model_given_by_H_on_another_algebra(cache, tmp_path):
    """Not only rods: the free rigid body on so(3)* given by H directly; the pipeline finds |m|^2 as the one Casimir,
    no S^1 symmetry (I1 != I2), nothing beyond H and |m|^2 up to degree 4, and a section that conserves both."""
    import magrod as mr

    f = tmp_path / "euler_top.py"
    f.write_text(EULER_TOP)
    rep = mr.integrability_report(model=str(f))
    assert rep.row("hamiltonian")["title"] == "H as given"
    assert rep.row("casimirs")["details"]["basis_found"] == {"C1": "m1**2 + m2**2 + m3**2"}
    assert rep.statuses["s1_symmetry"] == "absent"
    from magrod.integrability.model_search import model_search

    r = model_search(str(f), 4)
    assert r.certified and r.known == ["C1", "H"]
    sec = mr.poincare_section(str(f), iterates=10)
    assert sec.success and sec.max_abs_dH <= 1e-12 and sec.casimir_drift <= 1e-12


def test_check_model_imports_neither_heyoka_nor_matplotlib(tmp_path):
    """`magrod check --model NAME [--integrals]` stays light, as `magrod check` does (the body code is imported on
    first use, by the numerics)."""
    import subprocess
    import sys

    code = ("import sys, io, contextlib\nfrom magrod import cli\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    assert cli.main(['check', '--model', 'curved', '--json']) == 0\n"
            "    assert cli.main(['check', '--model', 'curved', '--integrals', '--degree', '2', '--json']) == 0\n"
            "print(sorted({m.split('.')[0] for m in sys.modules} & {'heyoka', 'matplotlib'}))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[]", r.stdout
