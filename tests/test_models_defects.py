"""Defects found with users' own model files (tests/model_files/): a legal parameter value that the generated code
could not take, the cache blind to a helper module, products of known integrals reported as new, the S^1 test tied
to the order of the state, report lines written for the paper's rod, and the check/scan workflow on a model file."""
from __future__ import annotations

import json
import os
from fractions import Fraction
from pathlib import Path

import pytest

from magrod import cli
from magrod.core.errors import ParameterError

FILES = Path(__file__).parent / "model_files"
SO4 = FILES / "so4_rod.py"


@pytest.fixture()
def cache(tmp_path, monkeypatch):
    d = tmp_path / "cache"
    monkeypatch.setenv("MAGROD_MODEL_CACHE", str(d))
    monkeypatch.delenv("MAGROD_NO_MODEL_CACHE", raising=False)
    from magrod.core import models

    models._LOADED.clear()
    return d


def _edited(tmp_path, old, new, name="rod.py", src=SO4):
    text = src.read_text()
    assert old in text
    f = tmp_path / name
    f.write_text(text.replace(old, new))
    return f


# -- a legal parameter value works, or the model's own singularity is a clear error ------------------------------
def test_found_casimirs_carry_no_parameter_denominators(cache):
    from magrod.core.models import resolve

    mc = resolve(SO4)
    found = mc.report["results"][3]["details"]["basis_found"]
    assert sorted(found.values()) == sorted(["m1*n1 + m2*n2 + m3*n3",
                                             "kappa*m1**2 + kappa*m2**2 + kappa*m3**2 + n1**2 + n2**2 + n3**2"])


@pytest.mark.parametrize("kappa", ["0", "1e-8", "-3"])
def test_every_kappa_the_file_declares_legal_is_searched(cache, kappa, capsys):
    """kappa = 0 is e(3)*, the Kirchhoff bracket: no division by zero anywhere (it raised ZeroDivisionError)."""
    assert cli.main(["check", "--model", str(SO4), "--integrals", "--degree", "2", "--model-params",
                     f"kappa={kappa}", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert Fraction(out["values"]["kappa"]) == Fraction(kappa)
    assert out["certified"] and out["new_integrals"] == ["m3"]  # the Lagrange rod: A1 = A2 = A


def test_the_so4_casimirs_are_those_of_e3_at_kappa_zero(cache):
    from magrod.core.models import resolve
    from magrod.integrability.model_search import polynomial

    mc = resolve(SO4)
    vals = {"A": Fraction(1), "C": Fraction(2), "kappa": Fraction(0)}
    two = [polynomial(mc, c, vals) for c in mc.names.CASIMIRS]
    n2 = {(0, 0, 0, 2, 0, 0): 1, (0, 0, 0, 0, 2, 0): 1, (0, 0, 0, 0, 0, 2): 1}
    assert n2 in two  # |n|^2, the Casimir of e(3)*
    assert mc.parameters({"kappa": 0.0})[2] == 0.0


def test_a_model_singular_at_a_legal_value_says_so(cache, tmp_path, capsys):
    """H = ... + n3/kappa is the user's own singularity at kappa = 0: one line naming kappa, exit 2."""
    f = _edited(tmp_path, "H = (m1**2 + m2**2) / (2 * A) + m3**2 / (2 * C) + n3",
                "H = (m1**2 + m2**2) / (2 * A) + m3**2 / (2 * C) + n3 / kappa")
    from magrod.core.models import resolve

    mc = resolve(f)
    with pytest.raises(ParameterError) as e:
        mc.parameters({"kappa": 0})
    assert e.value.name == "kappa" and "singular" in str(e.value)
    assert mc.parameters({"kappa": 1e-8})[2] == 1e-8
    rc = cli.main(["check", "--model", str(f), "--integrals", "--degree", "2", "--model-params", "kappa=0"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "kappa" in err[0] and "Traceback" not in err[0]


def test_conservation_is_measured_against_the_size_of_the_terms(cache):
    """The scale of H and of each Casimir is the sum of the absolute values of its terms at the state: positive on
    the level m.n = 0 where the Casimir itself is 0, and it follows a parameter that multiplies a Casimir."""
    import numpy as np

    from magrod.core.models import resolve

    mc = resolve(SO4)
    x = np.array([[0.3, 0.2, 0.5, 0.4, 0.9, -0.6]])  # m.n = 0.12 + 0.18 - 0.3 = 0
    s = mc.conservation_scales(x, {"kappa": 1e-8})
    assert s.shape == (1, 3)
    h = (0.3**2 + 0.2**2) / 2 + 0.5**2 / 4 + 0.6
    assert s[0, 0] == pytest.approx(h, rel=1e-15)
    names = list(mc.names.CASIMIRS)
    mn = names.index(next(k for k in names if mc.fi.POLYNOMIALS and len(getattr(mc.fi, f"{k}_MONOMIALS")) == 3))
    assert s[0, 1 + mn] == pytest.approx(0.12 + 0.18 + 0.3, rel=1e-15)
    big = mc.conservation_scales(x, {"kappa": 1e8})[0, 2 - mn]
    assert big == pytest.approx(1e8 * 0.38 + 0.4**2 + 0.9**2 + 0.6**2, rel=1e-15)


# -- the cache: keyed by the evaluated model, bypassable -----------------------------------------------------------
HELPER_FILE = '''
import sympy as sp
from rod_helper import RATIO
m1, m2, m3, n1, n2, n3 = sp.symbols("m1 m2 m3 n1 n2 n3", real=True)
B = sp.Symbol("B", positive=True)

def hat(a):
    return sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])

m, n = sp.Matrix([m1, m2, m3]), sp.Matrix([n1, n2, n3])
NAME = "helper-rod"
STATE = [m1, m2, m3, n1, n2, n3]
PARAMETERS = {B: ("stiffness scale", (0, sp.oo), 1)}
J = sp.Matrix.vstack(sp.Matrix.hstack(hat(m), hat(n)), sp.Matrix.hstack(hat(n), sp.zeros(3, 3)))
H = (m1**2 / RATIO[0] + m2**2 / RATIO[1] + m3**2 / RATIO[2]) / (2 * B) + n3
'''


def test_an_edited_helper_module_is_a_new_model(cache, tmp_path, monkeypatch):
    """1:2:2 is the Kovalevskaya rod (an integral of degree 4 beyond H and the Casimirs); 1:2:3 is not."""
    from magrod.core.models import resolve
    from magrod.integrability.model_search import model_search

    monkeypatch.syspath_prepend(str(tmp_path))
    helper = tmp_path / "rod_helper.py"
    helper.write_text("RATIO = (1, 2, 2)\n")
    f = tmp_path / "kov.py"
    f.write_text(HELPER_FILE)
    a = resolve(f)
    assert model_search(a, 4).new_integrals
    helper.write_text("RATIO = (1, 2, 3)\n")
    os.utime(helper, ns=(helper.stat().st_mtime_ns + 10**9,) * 2)
    b = resolve(f)
    assert b.directory != a.directory and not model_search(b, 4).new_integrals
    assert len(list(cache.iterdir())) == 2


def test_the_cache_can_be_bypassed(cache, tmp_path, monkeypatch, capsys):
    from magrod.core.models import resolve

    a = resolve(SO4, cache=False)
    assert not cache.exists() or not list(cache.iterdir())
    assert a.names.NAME == "so4-rod"
    monkeypatch.setenv("MAGROD_NO_MODEL_CACHE", "1")
    assert cli.main(["check", "--model", str(SO4), "--degree", "1", "--json"]) == 0
    assert not cache.exists() or not list(cache.iterdir())
    monkeypatch.delenv("MAGROD_NO_MODEL_CACHE")
    assert cli.main(["check", "--model", str(SO4), "--degree", "1", "--no-cache", "--json"]) == 0
    assert not cache.exists() or not list(cache.iterdir())
    capsys.readouterr()


def test_a_cached_models_code_does_not_point_at_the_derive_command(cache):
    from magrod.core.models import resolve

    d = Path(resolve(SO4).directory)
    for name in ("names.py", "body.py", "first_integrals.py"):
        text = (d / name).read_text()
        assert "python -m derive" not in text and "DO NOT EDIT" in text


# -- what is found, what is new, what is certified -----------------------------------------------------------------
def test_products_of_known_and_found_integrals_are_not_new(cache, capsys):
    """The so(4)* Lagrange rod: m3 is found; m3^2, m3 H, m3 C1, ... are in the algebra it generates."""
    from magrod.integrability.model_search import model_search

    r = model_search(SO4, 4)
    assert r.new_integrals == ["m3"] and r.new_verified == [True]
    assert r.certified and r.success
    assert cli.main(["check", "--model", str(SO4), "--integrals", "--degree", "3"]) == 0
    text = capsys.readouterr().out
    assert "NOT certified" not in text and "found" in text


def test_the_S1_test_does_not_depend_on_the_order_of_the_state():
    import sympy as sp

    from magrod.derive.models import pipeline, spec

    ns = {}
    exec(compile(SO4.read_text(), str(SO4), "exec"), ns)  # noqa: S102  (the test's own model file)
    m1, m2, m3, n1, n2, n3 = ns["STATE"]
    order = [m1, n1, m2, n2, m3, n3]
    perm = [ns["STATE"].index(x) for x in order]
    ns["STATE"] = order
    ns["J"] = sp.Matrix(6, 6, lambda i, j: ns["J"][perm[i], perm[j]])
    model = spec.build_model(ns, "interleaved")
    assert pipeline.s1_symmetric(model)
    ns["H"] = ns["H"] + m1 * n2  # not invariant under rotations about d3
    assert not pipeline.s1_symmetric(spec.build_model(ns, "interleaved"))


# -- the report fits a user's rod ----------------------------------------------------------------------------------
def test_a_user_rods_report_is_written_for_it(cache, capsys):
    assert cli.main(["check", "--model", str(SO4)]) == 0
    text = capsys.readouterr().out
    assert text.count("a user's rod (tests)") == 1  # SOURCE once, in the header
    assert "printed paper" not in text
    lines = text.splitlines()
    cand = [ln for ln in lines if "candidate" in ln.lower()]
    assert all(ln.split(":", 1)[-1].strip() for ln in cand), cand
    # the full report: the exact search to degree 4 at the file's defaults, with the integral m3 it finds
    assert "degree <= 4" in text and "m3" in text


def test_a_user_rods_report_from_the_api_has_no_paper_line(cache):
    import magrod as mr

    text = mr.integrability_report(model=str(SO4)).text()
    assert "printed paper" not in text and "so4-rod" in text.splitlines()[0]
    assert "none declared" in text  # the file declares no candidates: said so, not an empty line


def test_coordinate_integrals_count_whatever_the_candidates_are_named(cache, tmp_path):
    from magrod.core.models import resolve

    f = _edited(tmp_path, 'REFERENCE =', 'CANDIDATES = {"twist": (m3, "the symmetric top")}\nREFERENCE =')
    row = next(r for r in resolve(f).report["results"] if r["key"] == "integrals_found")["details"]
    assert row["candidate beyond H, Casimirs, coordinate integrals"] == {"twist": False}
    assert row["beyond_the_algebra"] == []


# -- the workflow on a model file ----------------------------------------------------------------------------------
def test_check_model_uses_the_files_defaults_and_takes_model_params_alone(cache, capsys):
    assert cli.main(["check", "--model", str(SO4), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["search"]["values"] == {"A": "1", "C": "2", "kappa": "1"}
    assert out["search"]["degree"] == 4
    assert cli.main(["check", "--model", str(SO4), "--model-params", "kappa=-1/2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["search"]["values"] == {"A": "1", "C": "2", "kappa": "-1/2"}


def test_the_stiffness_scan_runs_on_a_model_file_over_a_grid(cache, tmp_path, capsys):
    """A Kirchhoff rod of the user's with three stiffnesses: over {1, 2}^3 the scan finds Lagrange (B1 = B2) and
    Kovalevskaya (B2 = C = 2 B1: 1:2:2), and nothing at 2:1:1 or 1:1:... beyond them."""
    f = _edited(tmp_path, "H = (m1**2 + m2**2) / (2 * A) + m3**2 / (2 * C) + n3",
                "H = m1**2 / (2 * A) + m2**2 / (2 * A2) + m3**2 / (2 * C) + n3")
    f.write_text(f.read_text().replace("PARAMETERS = {", 'PARAMETERS = {A2: ("second bending stiffness", '
                                       '(0, sp.oo), 2), ').replace('A, C = sp.symbols("A C", positive=True)',
                                                                   'A, A2, C = sp.symbols("A A2 C", positive=True)'))
    assert cli.main(["landscape", "--model", str(f), "--grid", "A=1,2", "--grid", "A2=1,2", "--grid", "C=1,2",
                     "--model-params", "kappa=0", "--degree", "4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    rows = {(r["values"]["A"], r["values"]["A2"], r["values"]["C"]): r for r in out["rows"]}
    assert len(out["points"]) == 8
    lagrange = {("1", "1", "1"), ("1", "1", "2"), ("2", "2", "1"), ("2", "2", "2")}
    kovalevskaya = {("1", "2", "2"), ("2", "1", "2")}
    assert set(rows) == lagrange | kovalevskaya  # not 1:2:1 nor 2:1:1
    assert all(rows[k]["integrals"] == ["m3"] for k in lagrange)
    assert all(len(rows[k]["integrals"]) == 1 and "m1^4" in rows[k]["integrals"][0].replace("m2^4", "m1^4")
               for k in kovalevskaya)
    assert all(all(r["verified"]) and r["certified"] for r in rows.values())


def test_every_benchmark_the_library_cites_exists():
    import re

    root = Path(__file__).parents[1]
    cited = set()
    for p in (root / "magrod").rglob("*.py"):
        cited |= set(re.findall(r"benchmarks/([A-Za-z0-9_]+\.py)", p.read_text()))
    assert cited and all((root / "benchmarks" / c).is_file() for c in cited), sorted(
        c for c in cited if not (root / "benchmarks" / c).is_file())
